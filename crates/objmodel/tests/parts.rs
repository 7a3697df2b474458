//! The parts of a demonstration (`Classification::parts`) and the later parts measured from
//! their own onset (`objmodel::onset`), through the learning pipeline.

use nalgebra::Vector3;
use objmodel::classify::{Config, Label};
use objmodel::learn::{Learner, Source};
use objmodel::synth::{self, SynthBox, SynthNoise};
use rand::{rngs::StdRng, Rng, SeedableRng};

fn line_angle_deg(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.cross(b).norm().atan2(a.dot(b).abs()).to_degrees()
}

/// A slide, then a topple, with no rest between: the parts are in time order (touching at most),
/// start with the rest, and hold a topple (a slide's first frames that a rotation about the
/// edge explains too are labelled topple); every edge the pipeline reports (a
/// topple re-measured from its onset included) is the demonstration's edge within 5 mm and 3°,
/// and the part that taught it is a topple.
#[test]
fn slide_then_topple_parts_and_edges() {
    let learner = Learner::new(Config::default());
    let (mut edges, mut remeasured) = (0, 0);
    for noise in [SynthNoise::CLEAN, SynthNoise::REAL] {
        for seed in 0..20u64 {
            let mut rng = StdRng::seed_from_u64(7000 + seed);
            let b = SynthBox::random(&mut rng);
            let side = rng.random_range(0..4);
            let slide = rng.random_range(0.02..0.12);
            let d = synth::slide_then_topple(&b, side, slide, &noise, 30.0, seed);
            let c = learner.classify(&Source::Memory(&d.demo)).unwrap();
            let parts = &c.parts;
            assert_eq!(parts[0].kind, Label::Rest, "{}: {parts:?}", d.demo.name);
            // (The classifier's label runs may share a boundary frame.)
            for w in parts.windows(2) {
                assert!(
                    w[0].t_end <= w[1].t_start && w[0].last <= w[1].first,
                    "{parts:?}"
                );
            }
            assert!(parts.iter().any(|p| p.kind == Label::Topple), "{parts:?}");
            let truth = d.truth.edge.unwrap();
            for e in c.edges() {
                edges += 1;
                let angle = line_angle_deg(&e.line.direction, &truth.direction);
                let dist = truth.distance_to(&e.line.point) * 1e3;
                assert!(
                    angle < 3.0 && dist < 5.0,
                    "{}: wrong edge ({dist:.1} mm, {angle:.1}°)",
                    d.demo.name
                );
            }
            remeasured += c.segments.iter().filter(|s| s.remeasured.is_some()).count();
            for p in parts
                .iter()
                .filter(|p| p.taught.iter().any(|t| t == "edge"))
            {
                assert_eq!(p.kind, Label::Topple, "{parts:?}");
            }
        }
    }
    eprintln!("slide then topple: {edges} edges (all true), {remeasured} from a later part");
}

/// A plain topple: rest, topple (taught the edge), and the rests beside it taught their faces.
#[test]
fn a_topple_s_parts_say_what_they_taught() {
    let mut rng = StdRng::seed_from_u64(5);
    let b = SynthBox::random(&mut rng);
    let p = synth::ToppleParams {
        side: 1,
        ..Default::default()
    };
    let d = synth::topple(&b, &p, &SynthNoise::REAL, 30.0, 5);
    let c = Learner::new(Config::default())
        .classify(&Source::Memory(&d.demo))
        .unwrap();
    let kinds: Vec<Label> = c.parts.iter().map(|p| p.kind).collect();
    assert_eq!(kinds.first(), Some(&Label::Rest), "{:?}", c.parts);
    let topple = c.parts.iter().find(|p| p.kind == Label::Topple).unwrap();
    assert_eq!(topple.taught, vec!["edge".to_string()], "{:?}", c.parts);
    assert!(
        c.parts[0].taught.contains(&"resting face".to_string()),
        "{:?}",
        c.parts
    );
    let json = serde_json::to_value(&c).unwrap();
    assert_eq!(json["parts"][0]["kind"], "rest");
}
