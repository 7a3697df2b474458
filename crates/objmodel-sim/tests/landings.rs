//! Landings on the rapier tosses: one box's tosses learnt together, at motion-capture noise
//! and at the "real" camera preset (its noise given: a 30 Hz toss cannot measure it). Their final rests, reached after a flight and confirmed by
//! another toss's landing in the same down and place, teach the faces the box rested on
//! (`objmodel::landing`); every face learnt must be one of the box's. At motion-capture rates
//! the rolls' edges measure the table's height, which gives those faces their offsets
//! (`objmodel::support`).

use objmodel::classify::Config;
use objmodel::learn::{Learner, Source};
use objmodel::tree::Tree;
use objmodel_sim::eval_precision::face_is_true;

mod common;

/// Tosses of the first standard box at one noise level, learnt together: the tree and the
/// box's features.
fn learn_tosses(level: &str, n: u64) -> (Tree, objmodel_sim::truth::BoxFeatures) {
    // At 30 Hz a toss's short rests cannot measure the noise: such a file teaches nothing
    // unless the tracker's noise is given, as a user of a camera tracker gives it
    // (`--noise-position`, `--noise-rotation`).
    let (demos, features, given) = common::tosses(level, n);
    let sources: Vec<Source> = demos.iter().map(Source::Memory).collect();
    let mut tree = Tree::default();
    let mut config = Config::default();
    config.robust.noise = given;
    Learner::new(config)
        .learn(&mut tree, &sources)
        .expect("learns");
    (tree, features)
}

#[test]
fn confirmed_landings_teach_only_true_faces() {
    for (level, n) in [("mocap", 48), ("real", 16)] {
        let (tree, features) = learn_tosses(level, n);
        let from_landings: Vec<_> = tree
            .faces
            .iter()
            .filter(|f| f.evidence.landing > 0)
            .collect();
        println!(
            "{level}: {} landings, {} confirmed; {} faces, {} from landings, {} with offsets; \
             support {:?} from {} edges",
            tree.landings.len(),
            tree.landings.iter().filter(|l| l.confirmed).count(),
            tree.faces.len(),
            from_landings.len(),
            tree.faces.iter().filter(|f| f.offset.is_some()).count(),
            tree.support.as_ref().map(|s| (s.height, s.sigma_m)),
            tree.supports.len()
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
        // At motion-capture rates rolls locate their edges, which lie on the table (its top is
        // the world's z = 0): the support's height is known, and every face of a landing gets
        // its offset, within its σ of the box's (and within the 5 mm `face_is_true` asked).
        if level == "mocap" {
            let support = tree.support.as_ref().expect("rolls measured the support");
            assert!(
                support.height.abs() < 4.0 * support.sigma_m,
                "support at {} ± {} m",
                support.height,
                support.sigma_m
            );
            let with_offsets: Vec<_> = tree.faces.iter().filter(|f| f.offset.is_some()).collect();
            assert!(
                with_offsets.len() >= 3,
                "{} faces with offsets",
                with_offsets.len()
            );
            for f in with_offsets {
                let truth = features
                    .faces
                    .iter()
                    .max_by(|a, b| {
                        let n = |t: &objmodel_sim::truth::FaceFeature| {
                            f.normal.dot(&nalgebra::Vector3::from(t.normal))
                        };
                        n(a).total_cmp(&n(b))
                    })
                    .unwrap();
                let err = f.offset.unwrap() - truth.offset;
                let sigma = f.offset_sigma_m.unwrap();
                assert!(
                    err.abs() < 4.0 * sigma,
                    "face {}: offset {:.4} m for {:.4} (σ {:.2} mm)",
                    f.id,
                    f.offset.unwrap(),
                    truth.offset,
                    sigma * 1e3
                );
            }
        }
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
