//! MuJoCo's palm topples: on its soft, sticky contact the box lags the palm as it starts to
//! tilt, creeps down it, and only then falls (`bench/mujoco_probe.py`). Their edges are
//! measured from the stop before the fall (`tests/parts.rs`); their pendulums were not fitted
//! at all (a re-measured topple taught no φ), and at a precise tracker's rate every palm
//! topple creeps. A creep down the palm leaves the object at rest relative to the palm's
//! tilt, so the onset and the pendulum on the palm still hold: each of these scenes now
//! teaches φ within 3 σ of the box's (and the paper's onset φ too), or none.

mod common;

use objmodel::learn::{Config, Learner, Source};

#[test]
fn a_palm_topple_after_a_creep_teaches_phi_within_its_sigma() {
    let learner = Learner::new(Config::default());
    let mut taught = 0;
    let names = [
        "mujoco_palm_120hz_exact",
        "mujoco_palm_120hz_0.1mm",
        "mujoco_palm_creep_exact",
        "mujoco_palm_creep_0.3mm_7",
        "mujoco_palm_creep_0.3mm_15",
        "mujoco_palm_tilt_0.1mm",
    ];
    for name in names {
        let obs = learner
            .observe(&Source::Files {
                object: &common::data(&format!("{name}.tum")),
                palm: Some(&common::data(&format!("{name}.palm.tum"))),
            })
            .unwrap();
        let truth = common::truth_phi(name).to_degrees();
        for d in &obs.dynamics {
            let deg = |x: Option<f64>| x.map(f64::to_degrees);
            if let (Some(phi), Some(sigma)) = (deg(d.phi), deg(d.phi_sigma)) {
                taught += 1;
                assert!(
                    (phi - truth).abs() < 3.0 * sigma,
                    "{name}: φ {phi:.2}° ± {sigma:.2}° for {truth:.2}°"
                );
            }
            if let (Some(phi), Some(sigma)) = (deg(d.phi_onset), deg(d.phi_onset_sigma)) {
                assert!(
                    (phi - truth).abs() < 3.0 * sigma,
                    "{name}: φ at the onset {phi:.2}° ± {sigma:.2}° for {truth:.2}°"
                );
            }
        }
    }
    // Not bought by silence: 5 of the 6 teach φ (none did before).
    assert!(taught >= 5, "{taught} of {} taught φ", names.len());
}
