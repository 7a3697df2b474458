//! The tree's mass properties and predictions on the kinematic generator's exact topples: the
//! CoM with its covariance, the predicted pendulum of every (face, edge) pair against the true
//! box's, the observed ones beside them, and the friction bound of an instrumented topple.

use nalgebra::{Point3, Vector3};
use objmodel::learn::{Config, Learner, Source};
use objmodel::prediction::pendulums;
use objmodel::shape::{reconstruct, LearntFace};
use objmodel::synth::{self, SynthBox, SynthNoise};
use objmodel::tree::Tree;
use rand::{rngs::StdRng, SeedableRng};

/// The true box's faces in the tag (object) frame.
fn true_faces(b: &SynthBox) -> Vec<LearntFace> {
    let tag_from_box = b.box_from_tag.inverse();
    let centre = (tag_from_box * Point3::origin()).coords;
    let mut out = Vec::new();
    for k in 0..3 {
        for s in [1.0, -1.0] {
            let n = tag_from_box.rotation * Vector3::ith(k, s);
            out.push(LearntFace {
                id: format!("t{}", out.len()),
                normal: n,
                outward: true,
                offset: Some(n.dot(&centre) + b.half[k]),
                offset_sigma_m: 0.0,
                normal_sigma_rad: 0.0,
            });
        }
    }
    out
}

fn learn(b: &SynthBox, noise: &SynthNoise, seed: u64) -> Tree {
    let learner = Learner::new(Config::default());
    let mut tree = Tree::default();
    for d in synth::topples_over_every_face(b, noise, seed) {
        learner
            .learn(&mut tree, &[Source::Memory(&d.demo)])
            .unwrap();
    }
    // The direct topples' kinematic falls are not pendulums (their φ is rightly undetermined,
    // see `pendulum::jackknife`): instrumented topples over the four bottom edges give φ.
    for side in 0..4 {
        let mut d = synth::instrumented_topple(b, side, 0.2, noise, 30.0, seed * 10 + side as u64);
        d.demo.name = format!("instrumented{side}");
        learner
            .learn(&mut tree, &[Source::Memory(&d.demo)])
            .unwrap();
    }
    tree
}

/// Topples over every face of a box: the CoM has a covariance whose sigma is not zero and which
/// covers its error; the shape predicts 24 pendulums, each within 5 of its sigmas of the true
/// box's (φ and l_p), and every observed pendulum is beside its prediction.
#[test]
fn predictions_and_the_centre_of_mass_cover_the_truth() {
    // (Exact poses give no pendulum: their noise cannot be measured.)
    for seed in 1..=6 {
        let b = SynthBox::random(&mut StdRng::seed_from_u64(seed));
        let truth_com = (b.box_from_tag.inverse() * Point3::origin()).coords;
        let truth_shape = reconstruct(&true_faces(&b)).unwrap();
        let truth = pendulums(&truth_shape, &truth_com);
        let tree = learn(&b, &SynthNoise::REAL, seed);
        let planes = tree.com_planes();
        let com = tree.com.as_ref().unwrap_or_else(|| {
            panic!(
                "no CoM from {} planes: {:?}",
                planes.len(),
                planes.iter().map(|p| (p.phi, p.axis)).collect::<Vec<_>>()
            )
        });
        assert!(com.sigma_m.unwrap() > 0.0);
        let z = com.standardised_error(&truth_com).expect("a covariance");
        assert!(z.amax() < 5.0, "CoM {} off by {z} sigmas", com.point);
        assert_eq!(tree.predictions.len(), 24);
        let observed = tree
            .predictions
            .iter()
            .filter(|p| p.observed.is_some())
            .count();
        let with_phi = tree
            .edges
            .iter()
            .flat_map(|e| &e.pendulums)
            .filter(|p| p.phi.is_some())
            .count();
        assert!(with_phi >= 4);
        assert_eq!(observed, with_phi, "observed beside their prediction");
        for p in &tree.predictions {
            let t = truth
                .iter()
                .min_by(|a, c| {
                    let d = |q: &objmodel::prediction::PredictedPendulum| {
                        (q.resting_normal - p.resting_normal).norm()
                            + (q.edge_direction - p.edge_direction).norm()
                            + (q.edge_point - p.edge_point).norm()
                    };
                    d(a).total_cmp(&d(c))
                })
                .unwrap();
            let zphi = (p.phi - t.phi) / p.phi_sigma.unwrap();
            let zl = (p.l_p - t.l_p) / p.l_p_sigma.unwrap();
            assert!(
                zphi.abs() < 5.0 && zl.abs() < 5.0,
                "{zphi} {zl}: {p:?} vs {t:?}"
            );
        }
        // The instrumented topples bound the friction from below; nothing estimates it.
        let f = tree.friction.as_ref().expect("a bound");
        assert!(f.estimate.is_none() && f.lower_bound.is_some());
        assert!(tree.inertia.is_some());
    }
}

/// An instrumented topple held on the palm up to its tipping angle: μ is above a bound just
/// below tan φ, and there is no estimate.
#[test]
fn an_instrumented_topple_bounds_the_friction() {
    let b = SynthBox::new(Vector3::new(0.05, 0.04, 0.09), (0.01, -0.005), 0.4);
    let learner = Learner::new(Config::default());
    let mut tree = Tree::default();
    let d = synth::instrumented_topple(&b, 1, 0.2, &SynthNoise::REAL, 30.0, 3);
    learner
        .learn(&mut tree, &[Source::Memory(&d.demo)])
        .unwrap();
    let phi = d.truth.phi.expect("a tipping angle");
    let f = tree.friction.expect("a bound");
    assert!(f.estimate.is_none());
    let bound = f.lower_bound.unwrap();
    assert!(
        bound < phi.tan() && bound > (phi / 2.0).tan(),
        "{bound} vs tan φ {}",
        phi.tan()
    );
}
