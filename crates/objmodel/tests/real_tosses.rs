//! Real tosses from another lab (`tests/data/contactnets_tosses`: 58 tosses of the ContactNets
//! cube, AprilTag tracking at 148 Hz; see its README). Learnt together as a user would learn
//! them, every feature of the tree must be the cube's, and the rests at the ends of the files
//! (a tenth of a second each) must find its faces. Real contacts, not a simulator's: the cube's
//! edges are rounded, the board's friction is low (μ ≈ 0.18, its edges slide as it tumbles),
//! and each file starts in flight.

mod common;

use objmodel::learn::{Config, Learner, Source};
use objmodel::observation::Observation;
use objmodel::tree::Tree;
use std::path::PathBuf;

const DIR: &str = "contactnets_tosses";

/// The tosses' files, sorted by name.
fn tosses() -> Vec<PathBuf> {
    common::tum_files(DIR)
}

/// The 58 tosses learnt together by `learner`: the tree and each toss's report, in the order
/// of [`tosses`].
fn learnt(learner: Learner) -> (Tree, Vec<Observation>) {
    let paths = tosses();
    assert_eq!(paths.len(), 58);
    let sources: Vec<Source> = paths.iter().map(Source::file).collect();
    let mut tree = Tree::default();
    let reports = learner.learn(&mut tree, &sources).unwrap();
    (tree, reports)
}

#[test]
fn every_feature_learnt_from_real_tosses_is_the_cubes_and_the_rests_find_its_faces() {
    let (tree, _) = learnt(Learner::new(Config::default()));
    let truth = common::box_truth(&format!("{DIR}/cube.truth.json"));
    common::assert_tree_on_box(&tree, &truth, DIR);
    // Each of the six faces, found by one face of the tree.
    for (n, _) in &truth.faces {
        let found = tree
            .faces
            .iter()
            .filter(|f| f.normal.angle(n) < 5f64.to_radians())
            .count();
        assert_eq!(found, 1, "face {n:?} found {found} times: {:?}", tree.faces);
    }
}

/// Each file starts at the release, in flight (7 mm between its first two frames at 0.15 mm
/// of noise): no file starts with a rest, although the rest test, with no window before a
/// file's first frames, cannot tell them moving (`start_rest::unlabel_moving_start`).
#[test]
fn a_toss_tracked_from_its_release_does_not_start_with_a_rest() {
    let (_, reports) = learnt(Learner::new(Config::default()));
    for (path, r) in tosses().iter().zip(&reports) {
        let parts = &r.classification.parts;
        assert_ne!(
            parts[0].kind,
            objmodel::classify::Label::Rest,
            "{}: {:?}",
            path.display(),
            parts[0]
        );
        // And each ends at rest, as its last frames show.
        assert_eq!(
            parts.last().unwrap().kind,
            objmodel::classify::Label::Rest,
            "{}",
            path.display()
        );
    }
}

/// With the board's height given (its surface is the board frame's z = 0, to about a
/// millimetre: the cube rests 0.9 mm lower than its stated half-width), the rests after the
/// flights give the six faces their offsets, within their σ of the cube's, and the tree the
/// cube's shape: its corners within 5 mm, and no more vertices than a cube's.
#[test]
fn with_the_boards_height_given_the_rests_give_the_cube_its_shape() {
    let (tree, _) = learnt(
        Learner::new(Config::default())
            .with_support(0.0, 1e-3)
            .unwrap(),
    );
    let truth = common::box_truth(&format!("{DIR}/cube.truth.json"));
    common::assert_tree_on_box(&tree, &truth, DIR);
    assert_eq!(tree.faces.len(), 6, "{:?}", tree.faces);
    for f in &tree.faces {
        let (Some(d), Some(sigma)) = (f.offset, f.offset_sigma_m) else {
            panic!("face {} has no offset: {f:?}", f.id);
        };
        let (_, truth_d) = truth
            .faces
            .iter()
            .find(|(n, _)| f.normal.angle(n) < 5f64.to_radians())
            .unwrap();
        assert!(
            (d - truth_d).abs() < 5.0 * sigma,
            "face {}: offset {d} at ±{sigma}, the cube's {truth_d}",
            f.id
        );
    }
    let shape = tree
        .shape
        .as_ref()
        .expect("a shape from six faces with offsets");
    assert_eq!(shape.vertices.len(), 8);
    let half = 0.0524;
    for v in &shape.vertices {
        let corner = v.map(|x| half * x.signum());
        assert!((v - corner).norm() < 5e-3, "vertex {v:?}");
    }
}

/// A flight reports the centre of mass it measured only where it is the cube's (its centre,
/// the tracked origin: χ²₃ of the error under the reported covariance at 10⁻³). In toss 334
/// the cube's corner stays on the board while it turns, its spin reversed by the contact, for
/// two windows a point 70 mm from the centre fell with gravity; the rotation test
/// ([`objmodel::flight::torque_free`]) tells that no free body turns so.
#[test]
fn a_flight_of_a_real_toss_reports_no_centre_of_mass_but_the_cubes() {
    let (_, reports) = learnt(Learner::new(Config::default()));
    for (path, r) in tosses().iter().zip(&reports) {
        for p in &r.classification.parts {
            let Some(c) = &p.com_estimate else { continue };
            let chi2 = c
                .covariance
                .try_inverse()
                .map_or(f64::INFINITY, |w| c.point.dot(&(w * c.point)));
            assert!(
                chi2 < objmodel::stats::chi2_threshold(3.0, 1e-3),
                "{} frames {}-{}: centre of mass {:?} (χ² {chi2})",
                path.display(),
                p.first,
                p.last,
                c.point
            );
        }
    }
}
