//! The messy scenes (toss, compounds, session) and their per-interval contact-mode truth,
//! checked against rigid-body facts on the full-rate record: in flight the centre of mass
//! falls with gravity, at rest nothing moves, on a face that face points down the support, in
//! a topple the edge stays on the support.

use nalgebra::{Point3, Vector3};
use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::demo::{clean_demo, run_scene};
use objmodel_sim::events::support_from_box;
use objmodel_sim::scenes::{Sample, SceneOutput};
use objmodel_sim::truth::ModeTruth;
use objmodel_sim::{BoxSpec, SceneKind, SimOptions, Truth};

fn scene(kind: SceneKind, b: usize, seed: u64) -> (BoxSpec, SceneOutput, Truth) {
    let spec = standard_boxes()[b].clone();
    let opts = SimOptions::default();
    let out = run_scene(kind, &spec, seed, &opts).expect("the scene runs");
    let truth = clean_demo(kind, &spec, seed, &out, &opts)
        .expect("its truth")
        .truth;
    (spec, out, truth)
}

fn inside<'a>(out: &'a SceneOutput, m: &ModeTruth) -> impl Iterator<Item = (usize, &'a Sample)> {
    let (t0, t1) = (m.t0, m.t1);
    out.samples
        .iter()
        .enumerate()
        .filter(move |(_, s)| s.t >= t0 && s.t <= t1)
}

/// Box-frame coordinates of a tag-frame point of the truth.
fn to_box(spec: &BoxSpec, p: [f64; 3]) -> Point3<f64> {
    spec.box_from_tag() * Point3::from(p)
}

/// The rigid-body facts every labelled interval must satisfy (see the module doc).
fn check_modes(spec: &BoxSpec, out: &SceneOutput, truth: &Truth) {
    let s = &out.samples;
    let dt = s[1].t - s[0].t;
    let com = |i: usize| s[i].world_from_box * spec.com_box();
    assert_eq!(truth.modes[0].t0, 0.0);
    assert!((truth.modes.last().unwrap().t1 - truth.duration).abs() < 1e-9);
    for w in truth.modes.windows(2) {
        assert_eq!(w[0].t1, w[1].t0, "modes leave no gap");
    }
    for m in &truth.modes {
        let at: Vec<usize> = inside(out, m).map(|(i, _)| i).collect();
        match m.mode.as_str() {
            "flight" => {
                assert!(m.face.is_none() && m.edge.is_none() && m.contact == "none");
                // Interior samples: the CoM's acceleration is gravity.
                for w in at.windows(3).skip(2).take(at.len().saturating_sub(6)) {
                    let a =
                        (com(w[2]).coords - 2.0 * com(w[1]).coords + com(w[0]).coords) / (dt * dt);
                    assert!(
                        (a - Vector3::new(0.0, 0.0, -9.81)).norm() < 0.05,
                        "flight {:.3}-{:.3} s accelerates at {a:?} at {:.4} s",
                        m.t0,
                        m.t1,
                        s[w[1]].t
                    );
                }
            }
            "rest" | "slide" => {
                let f = m.face.as_ref().expect("a face");
                let n_box = spec.box_from_tag().rotation * Vector3::from(f.normal);
                for &i in &at {
                    let n = support_from_box(&s[i]).rotation * n_box;
                    assert!(n.angle(&-Vector3::z()) < 1f64.to_radians(), "{m:?}");
                }
                if m.mode == "rest" {
                    assert!(m.travel < 1e-3 && m.turn_deg < 0.2, "{m:?}");
                }
            }
            "topple" => {
                let e = m.edge.as_ref().expect("an edge");
                let (p0, p1) = (to_box(spec, e.line.p0), to_box(spec, e.line.p1));
                for &i in &at {
                    let sfb = support_from_box(&s[i]);
                    assert!(
                        (sfb * p0).z.abs() < 1e-3 && (sfb * p1).z.abs() < 1e-3,
                        "{m:?}"
                    );
                }
            }
            "carried" => assert_eq!(m.contact, "hand"),
            "impact" | "general" => {}
            other => panic!("unknown mode {other}"),
        }
    }
}

#[test]
fn toss_flies_lands_and_rests_with_its_modes_true() {
    let mut short_tails = 0;
    let mut seen = std::collections::BTreeSet::new();
    for seed in 1..=8 {
        let (spec, out, truth) = scene(SceneKind::Toss, (seed as usize) % 5, seed);
        check_modes(&spec, &out, &truth);
        let kinds: Vec<&str> = truth.modes.iter().map(|m| m.mode.as_str()).collect();
        seen.extend(kinds.iter().map(|k| k.to_string()));
        assert_eq!(kinds[0], "carried", "the record starts in the hand");
        assert_eq!(kinds[1], "flight", "then the box flies");
        assert!(kinds.contains(&"impact"));
        let last = truth.modes.last().unwrap();
        assert_eq!(last.mode, "rest");
        // The last rest is the tail the script asked for (to a few physics steps).
        let tail = truth.script["tail"];
        assert!(
            (last.t1 - last.t0 - tail).abs() < 0.03,
            "rest {:.3} s, tail {tail:.3} s",
            last.t1 - last.t0
        );
        if tail < 0.2 {
            short_tails += 1;
        }
        assert!(truth.edge.is_none() && truth.face.is_none());
    }
    assert!(short_tails >= 1, "some tosses stop soon after the box does");
    for k in ["carried", "flight", "impact", "slide", "rest"] {
        assert!(seen.contains(k), "no {k} in 8 tosses");
    }
}

#[test]
fn box_features_are_the_faces_and_edges_of_the_box() {
    let spec = standard_boxes()[3].clone();
    let f = objmodel_sim::modes::box_features(&spec);
    assert_eq!((f.faces.len(), f.edges.len()), (6, 12));
    let h = spec.half_extents();
    for face in &f.faces {
        // The plane passes at the half extent from the box centre.
        let n = Vector3::from(face.normal);
        let centre = spec.tag_from_box() * Point3::origin();
        let d = face.offset - n.dot(&centre.coords);
        assert!(h.iter().any(|x| (x - d).abs() < 1e-12), "{face:?}");
    }
    for e in &f.edges {
        // Both end points lie on both faces of the edge.
        for id in &e.faces {
            let face = f.faces.iter().find(|x| &x.id == id).unwrap();
            let n = Vector3::from(face.normal);
            for p in [e.line.p0, e.line.p1] {
                assert!((n.dot(&Vector3::from(p)) - face.offset).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn topple_then_slide_topples_about_an_edge_then_slides_on_the_adjacent_face() {
    for (b, seed) in [(0, 1), (2, 2), (4, 3)] {
        let (spec, out, truth) = scene(SceneKind::ToppleSlide, b, seed);
        check_modes(&spec, &out, &truth);
        let big: Vec<&ModeTruth> = truth
            .modes
            .iter()
            .filter(|m| {
                (m.mode == "topple" && m.turn_deg > 30.0) || (m.mode == "slide" && m.travel > 0.02)
            })
            .collect();
        assert_eq!(big.len(), 2, "{:?}", truth.modes);
        let (topple, slide) = (big[0], big[1]);
        assert_eq!(
            (topple.mode.as_str(), slide.mode.as_str()),
            ("topple", "slide")
        );
        // The box slides on the face it toppled onto: one of the edge's two faces, not the
        // face it stood on first.
        let e = topple.edge.as_ref().unwrap();
        let f = slide.face.as_ref().unwrap();
        assert!(e.faces.contains(&f.id), "{e:?} {f:?}");
        assert_ne!(truth.modes[0].face.as_ref().unwrap().id, f.id);
        assert!(slide.t0 > topple.t1);
    }
}

#[test]
fn session_holds_topples_slides_and_carries_with_rests_between() {
    let (spec, out, truth) = scene(SceneKind::Session, 1, 1);
    check_modes(&spec, &out, &truth);
    let count = |k: &str, keep: &dyn Fn(&ModeTruth) -> bool| {
        truth
            .modes
            .iter()
            .filter(|m| m.mode == k && keep(m))
            .count()
    };
    assert!(count("topple", &|m| m.turn_deg > 30.0) >= 1);
    assert!(count("slide", &|m| m.travel > 0.02) >= 1);
    assert!(count("carried", &|_| true) >= 1);
    assert!(count("rest", &|m| m.t1 - m.t0 > 0.4) >= 5);
    assert!(truth.duration > 10.0);
}
