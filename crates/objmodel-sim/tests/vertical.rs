//! The gravity given, checked against the vertical the rests turn about
//! (`objmodel::vertical`), on rapier tosses: learnt as tracked (z up), nothing is said; tracked
//! in a frame with y up (as motion-capture systems often are) and learnt with the default
//! gravity (z up), the learner says which vertical the rests show and which way along it the
//! flights fall, and learns nothing; given the right gravity, it learns what it learns from the
//! z-up poses. Given gravity upside down, the rests agree with its line and
//! the flights fall against it: that is caught too.

use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use objmodel::classify::Config;
use objmodel::learn::{Learner, Source};
use objmodel::tree::Tree;
use objmodel::Demonstration;
use objmodel_sim::eval_precision::face_is_true;

mod common;

/// Learn `demos` together with `gravity`: the tree and each report's warnings.
fn learn(demos: &[Demonstration], gravity: Vector3<f64>) -> (Tree, Vec<Vec<String>>) {
    let sources: Vec<Source> = demos.iter().map(Source::Memory).collect();
    let config = Config {
        gravity: Some(gravity),
        ..Config::default()
    };
    let mut tree = Tree::default();
    let reports = Learner::new(config)
        .learn(&mut tree, &sources)
        .expect("learns");
    let warnings = reports
        .into_iter()
        .map(|r| r.classification.warnings)
        .collect();
    (tree, warnings)
}

const CHECKED: &str = objmodel::learn::NOT_LEARNT;

#[test]
fn a_tracker_with_y_up_learnt_as_z_up_is_caught_and_teaches_nothing_from_gravity() {
    let (demos, features, _) = common::tosses("mocap", 40);
    let z_up = Vector3::new(0.0, 0.0, -1.0);

    let (tree, warnings) = learn(&demos, z_up);
    assert!(
        warnings.iter().flatten().all(|w| !w.contains(CHECKED)),
        "the right gravity was doubted"
    );
    let faces = tree.faces.len();
    assert!(faces >= 3, "{faces} faces from the z-up tosses");

    // The same poses in a tracker frame whose y axis is up: tracker_from_world turns z to y.
    let tracker_from_world = Isometry3::from_parts(
        Default::default(),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -std::f64::consts::FRAC_PI_2),
    );
    assert!((tracker_from_world * Vector3::z() - Vector3::y()).norm() < 1e-12);
    let y_up: Vec<Demonstration> = demos
        .iter()
        .map(|d| d.in_frame(&tracker_from_world))
        .collect();

    let (wrong, warnings) = learn(&y_up, z_up);
    assert!(wrong.demos.is_empty(), "nothing is learnt");
    for w in &warnings {
        let said = w
            .iter()
            .find(|w| w.contains(CHECKED))
            .expect("every report says it");
        // The rests show the line; the flights, which way along it things fall.
        assert!(said.contains("turn about (0.000,"), "{said}");
        assert!(
            said.ends_with("give --gravity 0.000,-1.000,0.000"),
            "{said}"
        );
    }

    let (right, warnings) = learn(&y_up, Vector3::new(0.0, -1.0, 0.0));
    assert!(warnings.iter().flatten().all(|w| !w.contains(CHECKED)));
    assert_eq!(
        right.faces.len(),
        faces,
        "the y-up poses with their gravity"
    );
    for f in &right.faces {
        assert!(face_is_true(f, &features), "face {} off the box", f.id);
    }
}

#[test]
fn a_gravity_given_upside_down_is_caught_by_the_flights() {
    let (demos, _, _) = common::tosses("mocap", 24);
    let (tree, warnings) = learn(&demos, Vector3::new(0.0, 0.0, 1.0));
    assert!(tree.demos.is_empty(), "nothing is learnt");
    for w in &warnings {
        let said = w
            .iter()
            .find(|w| w.contains(CHECKED))
            .expect("every report says it");
        assert!(said.contains("points up"), "{said}");
        assert!(
            said.ends_with("give --gravity 0.000,0.000,-1.000"),
            "{said}"
        );
    }
}
