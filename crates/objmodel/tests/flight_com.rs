//! A model learnt from tosses alone has the centre of mass that their flights agree on
//! (`tree/flights.rs`, `shared_com`): no pendulum needed. Data: `objmodel dataset` (rapier),
//! eleven tosses each of the brick and of the box with a weight inside, at motion-capture noise
//! (0.1-0.5 mm, 0.05-0.3° per axis, 100-250 Hz); the truth is the simulator's centre of mass.

mod common;

use nalgebra::Vector3;
use objmodel::learn::Config;
use objmodel::tree::Tree;

const DIR: &str = "rapier_tosses/shared_com";

/// χ²₃ at 10⁻⁴: beyond it an error is not the covariance's.
const CHI2_3: f64 = 21.1;

fn true_com(b: &str) -> Vector3<f64> {
    let truth: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(common::data(&format!("{DIR}/{b}.truth.json"))).unwrap(),
    )
    .unwrap();
    common::vec3(&truth["com"])
}

/// The tree's CoM against the truth: its error and χ²₃ under its covariance.
fn error(tree: &Tree, truth: &Vector3<f64>) -> (f64, f64) {
    let com = tree.com.as_ref().expect("a centre of mass");
    let d = com.point - truth;
    let w = com.covariance_matrix().unwrap().try_inverse().unwrap();
    (d.norm(), d.dot(&(w * d)))
}

#[test]
fn a_model_from_tosses_alone_has_the_centre_of_mass_its_flights_agree_on() {
    for b in ["brick", "weighted"] {
        let (tree, _) = common::learn_files(&common::tum_files(&format!("{DIR}/{b}")));
        let com = tree
            .com
            .as_ref()
            .expect("the flights fix the centre of mass");
        assert_eq!(com.pendulums, 0, "{b}");
        assert!(com.flight_demonstrations >= 3, "{b}: {com:?}");
        assert!(com.learnt_from().contains("flights"), "{b}");
        let (err, chi2) = error(&tree, &true_com(b));
        assert!(err < 1e-3 && chi2 < CHI2_3, "{b}: {err} m, χ²₃ {chi2}");
        // The file keeps the flights, and the model read back is the same.
        let json = serde_json::to_string(&tree).unwrap();
        let back: Tree = serde_json::from_str(&json).unwrap();
        assert_eq!(back, tree, "{b}");
        assert!(json.contains("\"flights\""), "{b}");
    }
}

/// Tosses learnt in two sessions into one model pool all their flights: the centre of mass
/// is the one of learning them at once; and a model that keeps the flights of only two
/// demonstrations has none (three must agree).
#[test]
fn flights_learnt_in_two_sessions_pool_and_two_demonstrations_are_too_few() {
    let all = common::tum_files(&format!("{DIR}/weighted"));
    let (at_once, _) = common::learn_files(&all);
    let mut tree = Tree::default();
    let (first, second) = all.split_at(all.len() / 2);
    common::learn_into(Config::default(), &mut tree, first);
    common::learn_into(Config::default(), &mut tree, second);
    let (a, b) = (at_once.com.unwrap(), tree.com.clone().unwrap());
    assert_eq!(a.flights, b.flights);
    assert!((a.point - b.point).norm() < 1e-9, "{a:?} {b:?}");
    let mut with_flights: Vec<String> = tree.flights.iter().map(|f| f.demo.clone()).collect();
    with_flights.dedup();
    assert!(with_flights.len() >= 3);
    for demo in &with_flights[2..] {
        tree.remove_demo(demo);
    }
    assert!(tree
        .flights
        .iter()
        .all(|f| with_flights[..2].contains(&f.demo)));
    assert_eq!(tree.com, None);
}

/// Learnt under a gravity tilted 2° from the simulator's (a tracking frame off level), the
/// flights still agree on the centre of mass within its covariance: each flight's point moves
/// with gravity by its own sensitivity, and the pooling estimates gravity's error with the
/// point (`shared_com`): the gravity given less the simulator's, to a fifth of it.
#[test]
fn a_gravity_off_by_two_degrees_is_estimated_with_the_centre_of_mass() {
    let all = common::tum_files(&format!("{DIR}/brick"));
    let tilt = 2f64.to_radians();
    let given = Vector3::new(tilt.sin(), 0.0, -tilt.cos());
    let mut tree = Tree::default();
    let config = Config {
        gravity: Some(given),
        ..Config::default()
    };
    common::learn_into(config, &mut tree, &all);
    let (err, chi2) = error(&tree, &true_com("brick"));
    assert!(err < 1e-3 && chi2 < CHI2_3, "{err} m, χ²₃ {chi2}");
    let said = tree.com.unwrap().flights_gravity_error.unwrap();
    // The truth: the gravity given minus the simulator's (both 9.81 m/s²).
    let truth = (given - Vector3::new(0.0, 0.0, -1.0)) * objmodel::pendulum::G;
    assert!(
        (said - truth).norm() < 0.2 * truth.norm(),
        "said {said:?}, truth {truth:?}"
    );
}

/// A demonstration that teaches nothing (here made so with `withhold_all`, as a file whose
/// noise cannot be resolved or whose lengths are not metres is) keeps its flights among its
/// parts, each saying why it taught nothing, and gives the tree no centre of mass.
#[test]
fn a_demonstration_that_teaches_nothing_keeps_its_flights_but_gives_no_centre_of_mass() {
    let (_, reports) = common::learn_files(&common::tum_files(&format!("{DIR}/brick")));
    let mut o = reports
        .into_iter()
        .find(|o| !o.classification.flight_coms_taught().is_empty())
        .expect("a flight that measured its centre of mass");
    let flights = |c: &objmodel::classify::Classification| {
        c.parts
            .iter()
            .filter(|p| p.kind == objmodel::classify::Label::Flight)
            .count()
    };
    let before = flights(&o.classification);
    o.classification.withhold_all("a reason");
    let c = &o.classification;
    assert_eq!(flights(c), before, "{:?}", c.parts);
    assert!(c.parts.iter().all(|p| p.taught.is_empty()));
    assert!(c
        .parts
        .iter()
        .filter(|p| p.com_estimate.is_some())
        .all(|p| p.withheld.as_deref() == Some("a reason")));
    assert!(c.flight_coms_taught().is_empty());
    let mut tree = Tree::default();
    tree.add(&o);
    assert!(tree.flights.is_empty() && tree.com.is_none());
}
