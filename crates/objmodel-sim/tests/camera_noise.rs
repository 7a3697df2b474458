//! A camera's noise (`TrackerNoise::camera`: larger along the line of sight, correlated from
//! frame to frame at 0.5) on rapier topples and compounds at 30 Hz: correlated first frames look
//! like motion to the check that the first frames measured the noise (correlated noise grows
//! with the lag as a motion does), and where the first classification, made with their
//! short-lag noise, found no rest long enough to measure it, a demonstration taught nothing
//! ("the tracking noise cannot be estimated"; 13 of the camera set's 221 demonstrations that are
//! not tosses). The long-run noise measured on the quiet windows of every frame is the noise to
//! test with: every such demonstration is analysed, and each box's tree holds only its own
//! features.

use objmodel::learn::{Config, Learner, Source};
use objmodel::tree::Tree;
use objmodel::{Demonstration, StampedPose};
use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::demo::simulate_clean;
use objmodel_sim::eval_precision::{edge_is_true, face_is_true};
use objmodel_sim::noise::TrackerNoise;
use objmodel_sim::truth::BoxFeatures;
use objmodel_sim::{SceneKind, SimOptions};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

#[test]
fn camera_topples_are_analysed_and_teach_only_the_box() {
    let learner = Learner::new(Config::default());
    let noise = TrackerNoise::camera();
    let opts = SimOptions::default();
    let scenes = [
        (SceneKind::Topple, 3),
        (SceneKind::Compound, 3),
        (SceneKind::ToppleSlide, 2),
    ];
    let (mut unmeasurable, mut off, mut edges) = (vec![], vec![], 0);
    for spec in standard_boxes() {
        let mut demos = vec![];
        let mut features = None;
        for (kind, seeds) in scenes {
            for seed in 1..=seeds {
                let clean = simulate_clean(kind, &spec, seed, &opts).expect("the scene runs");
                let sim = clean.with_noise(&noise);
                features = Some(sim.truth.features.clone());
                demos.push(Demonstration {
                    name: format!("{}_{kind:?}_{seed}", spec.name),
                    object: sim.object.clone(),
                    palm: None,
                });
            }
        }
        let features = features.expect("scenes ran");
        let sources: Vec<Source> = demos.iter().map(Source::Memory).collect();
        let mut tree = Tree::default();
        let reports = learner.learn(&mut tree, &sources).expect("learns");
        for r in &reports {
            let c = &r.classification;
            if c.warnings.iter().any(|w| w.contains("cannot be estimated")) {
                unmeasurable.push(c.name.clone());
            }
        }
        edges += tree.edges.len();
        off.extend(
            off_the_box(&tree, &features)
                .into_iter()
                .map(|o| format!("{}: {o}", spec.name)),
        );
    }
    eprintln!("{edges} edges; unmeasurable {unmeasurable:?}; off the box {off:?}");
    assert!(unmeasurable.is_empty(), "taught nothing: {unmeasurable:?}");
    assert!(off.is_empty(), "features off the box: {off:?}");
    assert!(edges >= 15, "{edges} edges learnt");
}

/// Each stamp moved by up to a quarter of the spacing (uniform, order kept), as a camera
/// driver's stamps are when it stamps a frame on arrival: the frames stay one apart.
fn jittered(poses: &[StampedPose], rng: &mut StdRng) -> Vec<StampedPose> {
    let spacing = 1.0 / 30.0;
    poses
        .iter()
        .map(|p| StampedPose {
            t: p.t + rng.random_range(-0.25..0.25) * spacing,
            ..*p
        })
        .collect()
}

/// What the demonstrations teach learnt together: the features off the box (as "kind at
/// point"), and how many edges they measure (taught, or held back as too loose), and of how
/// many demonstrations the correlation was measured.
fn learnt_off_the_box(
    demos: &[Demonstration],
    features: &BoxFeatures,
) -> (Vec<String>, usize, usize) {
    let learner = Learner::new(Config::default());
    let sources: Vec<Source> = demos.iter().map(Source::Memory).collect();
    let mut tree = Tree::default();
    let reports = learner.learn(&mut tree, &sources).expect("learns");
    let correlated = reports
        .iter()
        .filter(|r| r.classification.noise_correlation.is_some())
        .count();
    (
        off_the_box(&tree, features),
        tree.edge_estimates().count(),
        correlated,
    )
}

/// The tree's features that are not the box's, as "edge at point" or "face normal".
fn off_the_box(tree: &Tree, features: &BoxFeatures) -> Vec<String> {
    let edges = tree
        .edges
        .iter()
        .filter(|e| !edge_is_true(e, features))
        .map(|e| format!("edge at {:?}", e.point));
    let faces = tree
        .faces
        .iter()
        .filter(|f| !face_is_true(f, features))
        .map(|f| format!("face {:?}", f.normal));
    edges.chain(faces).collect()
}

#[test]
fn jittered_camera_stamps_teach_what_even_ones_do() {
    // The correlation of a camera's noise is measured over windows of consecutive frames; with
    // stamps jittered by ±25% of the spacing, those windows were taken for ones with a missing
    // frame and the correlation went unmeasured: the tests took the noise as independent, too
    // strict, and palm topples taught edges 5-13 mm off the box at σ 2 mm (the camera data set
    // with jittered stamps: 9 of the 21 edges its palm topples taught). Jitter must change
    // nothing: the same demonstrations with even and with jittered stamps teach as many features
    // off the box (at this noise a single palm topple's edge is located to ±3 mm, and two of the
    // 15 below lay 6 mm from the brick's edge, at 2σ, with even stamps too, until edges so
    // loose were held back: `tree/unlocated.rs`).
    let noise = TrackerNoise::camera();
    let opts = SimOptions::default();
    let mut rng = StdRng::seed_from_u64(53);
    let (mut off_even, mut off_jittered, mut edges, mut correlated) = (vec![], vec![], 0, 0);
    for spec in standard_boxes() {
        let (mut even, mut jitter) = (vec![], vec![]);
        let mut features = None;
        for seed in 1..=3 {
            let clean = simulate_clean(SceneKind::InstrumentedTopple, &spec, seed, &opts)
                .expect("the scene runs");
            let sim = clean.with_noise(&noise);
            features = Some(sim.truth.features.clone());
            let name = format!("{}_palm_topple_{seed}", spec.name);
            even.push(Demonstration {
                name: name.clone(),
                object: sim.object.clone(),
                palm: sim.palm.clone(),
            });
            jitter.push(Demonstration {
                name,
                object: jittered(&sim.object, &mut rng),
                palm: sim.palm.as_deref().map(|p| jittered(p, &mut rng)),
            });
        }
        let features = features.expect("scenes ran");
        let (off, _, _) = learnt_off_the_box(&even, &features);
        off_even.extend(off.into_iter().map(|o| format!("{}: {o}", spec.name)));
        let (off, n, c) = learnt_off_the_box(&jitter, &features);
        off_jittered.extend(off.into_iter().map(|o| format!("{}: {o}", spec.name)));
        edges += n;
        correlated += c;
    }
    eprintln!(
        "jittered: {edges} edges, correlation measured in {correlated} of 15; off the box: \
         even stamps {off_even:?}, jittered {off_jittered:?}"
    );
    assert!(
        correlated >= 12,
        "correlation measured in {correlated} of 15"
    );
    assert!(
        off_jittered.len() <= off_even.len(),
        "jittered stamps teach more off the box: {off_jittered:?} against {off_even:?}"
    );
    assert!(edges >= 8, "{edges} edges learnt");
}
