//! The dynamics learnt from simulated demonstrations, against the simulator's truth: φ from
//! instrumented and direct topples at clean and real noise, and the CoM of the box with a
//! weight inside from its topples over four edges.

use nalgebra::Vector3;
use objmodel::classify::{Config, Kind};
use objmodel::learn::{Learner, Source};
use objmodel::observation::Observation;
use objmodel::tree::Tree;
use objmodel::Demonstration;
use objmodel_sim::dataset::standard_boxes;
use objmodel_sim::{simulate, SceneKind, TrackerNoise};

type Learnt = (Observation, objmodel_sim::Truth);

fn learn(kind: SceneKind, box_name: &str, noise: &TrackerNoise, seed: u64) -> Learnt {
    let l = try_learn(kind, box_name, noise, seed);
    assert_eq!(
        l.0.classification.kind,
        Kind::Topple,
        "{box_name} {kind:?} seed {seed}"
    );
    l
}

fn try_learn(kind: SceneKind, box_name: &str, noise: &TrackerNoise, seed: u64) -> Learnt {
    let spec = standard_boxes()
        .into_iter()
        .find(|b| b.name == box_name)
        .unwrap();
    let d = simulate(kind, &spec, noise, seed).unwrap();
    let demo = Demonstration {
        name: format!("{box_name}_{kind:?}_{seed}"),
        object: d.object.clone(),
        palm: d.palm.clone(),
    };
    let o = Learner::new(Config::default())
        .observe(&Source::Memory(&demo))
        .unwrap();
    (o, d.truth)
}

fn phi_error_deg(dy: &[objmodel::dynamics::ToppleDynamics], truth: &objmodel_sim::Truth) -> f64 {
    (dy[0].phi.expect("phi") - truth.phi.expect("true phi"))
        .to_degrees()
        .abs()
}

#[test]
fn phi_from_instrumented_topples() {
    for (noise, limit) in [(TrackerNoise::clean(), 0.2), (TrackerNoise::real(), 1.0)] {
        for seed in 1..=3 {
            let (o, truth) = learn(SceneKind::InstrumentedTopple, "weighted", &noise, seed);
            let dy = o.dynamics;
            let err = phi_error_deg(&dy, &truth);
            eprintln!(
                "instrumented, {} noise, seed {seed}: phi error {err:.3} deg (onset-only {:?})",
                noise.name,
                dy[0]
                    .phi_onset
                    .map(|p| (p - truth.phi.unwrap()).to_degrees())
            );
            assert!(err < limit, "phi error {err} deg");
            assert!(dy[0].onset.is_some());
        }
    }
}

/// The paper's φ, the palm's tilt at the onset, against the truth with its σ: over the five
/// boxes' instrumented topples, exact and at motion-capture noise, no error beyond 3.5 σ and
/// no bias (mean error / σ within ±1). Measured on the rotation's absolute value, the onset
/// came late and φ high: median |error|/σ 15.6 (max 33.7) on exact poses.
#[test]
fn the_onset_phi_is_unbiased_within_its_sigma() {
    for noise in [TrackerNoise::clean(), TrackerNoise::mocap()] {
        let mut z = Vec::new();
        for spec in standard_boxes() {
            for seed in 1..=2 {
                let (o, truth) = learn(SceneKind::InstrumentedTopple, &spec.name, &noise, seed);
                let dy = &o.dynamics[0];
                let (Some(phi), Some(sigma)) = (dy.phi_onset, dy.phi_onset_sigma) else {
                    continue;
                };
                z.push((phi - truth.phi.expect("true phi")) / sigma);
            }
        }
        assert!(z.len() >= 8, "{}: {} onsets", noise.name, z.len());
        let mean = z.iter().sum::<f64>() / z.len() as f64;
        let worst = z.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        eprintln!("onset φ at {}: error/σ {z:.2?}", noise.name);
        assert!(mean.abs() < 1.0, "{}: mean error/σ {mean:.2}", noise.name);
        assert!(worst < 3.5, "{}: worst |error|/σ {worst:.2}", noise.name);
    }
}

#[test]
fn phi_from_direct_topples_by_the_fall() {
    // Clean: within 0.1°. A fall fitted from before the balance point takes in frames in which
    // the finger still drives the box, and came out 0.4-0.6° low here.
    for (noise, limit) in [(TrackerNoise::clean(), 0.1), (TrackerNoise::real(), 7.0)] {
        for seed in 1..=2 {
            let (o, truth) = learn(SceneKind::Topple, "tall", &noise, seed);
            let dy = o.dynamics;
            let Some(f) = dy[0].fall else {
                panic!("no fall fit")
            };
            let err = phi_error_deg(&dy, &truth);
            eprintln!(
                "direct, {} noise, seed {seed}: phi error {err:.3} deg, k {:.1}/s², {} frames",
                noise.name, f.k, f.frames
            );
            assert!(err < limit, "phi error {err} deg");
        }
    }
}

#[test]
fn centre_of_mass_of_the_weighted_box_from_its_topples() {
    let mut tree = Tree::default();
    let mut truth_com = None;
    for (kind, seed) in [
        (SceneKind::InstrumentedTopple, 1),
        (SceneKind::InstrumentedTopple, 2),
        (SceneKind::InstrumentedTopple, 3),
        (SceneKind::Topple, 1),
        (SceneKind::Topple, 2),
        (SceneKind::Topple, 3),
    ] {
        let (o, truth) = try_learn(kind, "weighted", &TrackerNoise::clean(), seed);
        let c = &o.classification;
        if c.kind != Kind::Topple {
            // Known: one direct topple of this box is classified "general" (see docs/learner-table.md).
            eprintln!(
                "{kind:?} seed {seed}: classified {}, skipped",
                c.kind.as_str()
            );
            continue;
        }
        tree.add(&o);
        truth_com = Some(Vector3::from(truth.com));
    }
    let com = tree
        .com
        .as_ref()
        .expect("the pendulums of several edges fix the CoM");
    let err = (com.point - truth_com.unwrap()).norm() * 1e3;
    eprintln!("CoM error {err:.2} mm from {} pendulums", com.pendulums);
    assert!(err < 3.0, "CoM error {err} mm");
}
