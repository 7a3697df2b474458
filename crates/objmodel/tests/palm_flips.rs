//! φ of instrumented topples whose palm tag flips: the tilt angles come from the palm's poses,
//! and a flipped palm pose (the tag's mirror solution, tens of degrees off for a frame) near
//! the onset must not move φ (before the palm stream was cleaned in the dynamics, one such
//! pose at 30 Hz put φ 3.8° off at 7.6 σ in the standard data set).

use nalgebra::{UnitQuaternion, Vector3};
use objmodel::learn::{Config, Learner, Source};
use objmodel::synth::{self, SynthBox, SynthNoise};
use rand::{rngs::StdRng, Rng, SeedableRng};

fn phi_of(demo: &objmodel::trajectory::Demonstration) -> Option<(f64, f64)> {
    let learner = Learner::new(Config::default());
    let obs = learner.observe(&Source::Memory(demo)).unwrap();
    let d = obs.dynamics.first()?;
    Some((d.phi?, d.phi_sigma?))
}

#[test]
fn flipped_palm_poses_do_not_move_phi() {
    let mut rng = StdRng::seed_from_u64(11);
    let mut checked = 0;
    for seed in 0..6u64 {
        let b = SynthBox::random(&mut rng);
        let side = (seed % 4) as usize;
        let d = synth::instrumented_topple(&b, side, 0.2, &SynthNoise::REAL, 30.0, 100 + seed);
        let truth = d.truth.phi.unwrap();
        let Some((phi, sigma)) = phi_of(&d.demo) else {
            continue;
        };
        // Flip palm poses around the onset (the tilt reaches φ at rest + φ / rate).
        let onset = d.demo.palm.as_ref().unwrap()[0].t + 1.0 + truth / 0.2;
        let mut flipped = d.demo.clone();
        let palm = flipped.palm.as_mut().unwrap();
        let near: Vec<usize> = (0..palm.len())
            .filter(|&i| (palm[i].t - onset).abs() < 0.5)
            .collect();
        for _ in 0..2 {
            let i = near[rng.random_range(0..near.len())];
            let axis = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                0.3,
            );
            let mirror = UnitQuaternion::from_scaled_axis(axis.normalize() * 1.4);
            palm[i].pose.rotation = mirror * palm[i].pose.rotation;
        }
        let (phi_f, sigma_f) = phi_of(&flipped).expect("φ with flipped palm poses");
        assert!(
            (phi_f - phi).abs() < sigma.max(sigma_f),
            "seed {seed}: the flips moved φ from {:.2}° ± {:.2}° to {:.2}° ± {:.2}° (truth {:.2}°)",
            phi.to_degrees(),
            sigma.to_degrees(),
            phi_f.to_degrees(),
            sigma_f.to_degrees(),
            truth.to_degrees()
        );
        checked += 1;
    }
    assert!(checked >= 4, "only {checked} demonstrations had a φ");
}
