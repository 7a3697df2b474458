//! Landings on the rapier tosses: one box's tosses learnt together, at motion-capture noise
//! and at the "real" camera preset. Their final rests, reached after a flight and confirmed by
//! another toss's landing in the same down and place, teach the faces the box rested on
//! (`objmodel::landing`); every face learnt must be one of the box's.

use objmodel::classify::Config;
use objmodel::learn::{Learner, Source};
use objmodel::tree::Tree;
use objmodel::Demonstration;
use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::demo::{clean_demo, run_scene};
use objmodel_sim::eval_precision::face_is_true;
use objmodel_sim::noise::TrackerNoise;
use objmodel_sim::{SceneKind, SimOptions};
use rand::{rngs::StdRng, SeedableRng};

/// Tosses of the first standard box at one noise level, learnt together: the tree and the
/// box's features.
fn learn_tosses(level: &str, n: u64) -> (Tree, objmodel_sim::truth::BoxFeatures) {
    let spec = &standard_boxes()[0];
    let mut demos = Vec::new();
    let mut features = None;
    for seed in 1..=n {
        let out = run_scene(SceneKind::Toss, spec, seed, &SimOptions::default()).expect("runs");
        let mut rng = StdRng::seed_from_u64(seed);
        let (noise, rate) = match level {
            "mocap" => (TrackerNoise::mocap_drawn(&mut rng), 240.0),
            _ => (TrackerNoise::real(), 30.0),
        };
        let opts = SimOptions {
            rate_hz: rate,
            ..SimOptions::default()
        };
        let clean = clean_demo(SceneKind::Toss, spec, seed, &out, &opts).expect("truth");
        let sim = clean.with_noise(&noise);
        features = Some(sim.truth.features.clone());
        demos.push(Demonstration {
            name: format!("toss_{level}_{seed}"),
            object: sim.object.clone(),
            palm: None,
        });
    }
    let sources: Vec<Source> = demos.iter().map(Source::Memory).collect();
    let mut tree = Tree::default();
    Learner::new(Config::default())
        .learn(&mut tree, &sources)
        .expect("learns");
    (tree, features.expect("at least one toss"))
}

#[test]
fn confirmed_landings_teach_only_true_faces() {
    for level in ["mocap", "real"] {
        let (tree, features) = learn_tosses(level, 16);
        let from_landings: Vec<_> = tree
            .faces
            .iter()
            .filter(|f| f.evidence.landing > 0)
            .collect();
        println!(
            "{level}: {} landings, {} confirmed; {} faces, {} from landings",
            tree.landings.len(),
            tree.landings.iter().filter(|l| l.confirmed).count(),
            tree.faces.len(),
            from_landings.len()
        );
        for f in &tree.faces {
            assert!(
                face_is_true(f, &features),
                "{level}: face {} ({:?}, evidence {:?}) is not on the box",
                f.id,
                f.normal,
                f.evidence
            );
        }
        // 16 tosses of a box with six faces come to rest on some face more than once.
        assert!(
            from_landings.len() >= 2,
            "{level}: {} faces from landings",
            from_landings.len()
        );
        // Every confirmed landing taught a face (its observation is in one).
        for l in tree.landings.iter().filter(|l| l.confirmed) {
            assert!(
                tree.faces
                    .iter()
                    .any(|f| f.observations.iter().any(
                        |o| o.demo == l.demo && o.source == objmodel::face::FaceSource::Landing
                    )),
                "{level}: {} confirmed but taught nothing",
                l.demo
            );
        }
    }
}
