//! A completed topple's rests measure its edge (`classify::parts::edge_on_support`,
//! `EdgeObservation::condition_on`), on the kinematic generator against exact truth.

use nalgebra::{UnitQuaternion, Vector3};
use objmodel::classify::{height_difference_var, Config};
use objmodel::landing::RestPlace;
use objmodel::learn::{Learner, Source};
use objmodel::synth::{self, SynthBox, SynthNoise, ToppleParams};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// A completed topple's edge lies on the support in the rest before and in the rest after, so
/// the rests measure it: the difference of its heights there is zero within what the support
/// and the contact allow between the places it touched (`classify::height_difference_var`),
/// and the rests' noise (each rest's mean known to the tracker's accuracy, taken as its
/// per-frame noise). At 2 mm and 1° and 15 Hz, where a fall has a few frames, the taught edge
/// is then known along the direction the rests measure it at least to that (without the
/// measurement, the first demonstration fails this), and its error along that direction is
/// not beyond what its σ there says. Direct topples in the world and topples on a palm (the
/// palm's frame, whose support is the palm).
#[test]
fn the_rests_measure_a_completed_topples_edge() {
    let noise = SynthNoise {
        sigma_position: 2e-3,
        sigma_rotation: 1f64.to_radians(),
        ..SynthNoise::REAL
    };
    let contact = Config::default().robust.edge_tolerance_m;
    for instrumented in [false, true] {
        let (mut z2, mut shrink, mut n) = (0.0, 0.0, 0);
        for seed in 0..40u64 {
            let mut rng = StdRng::seed_from_u64(500 + seed);
            let b = SynthBox::random(&mut rng);
            let side = rng.random_range(0..4);
            let d = if instrumented {
                let rate = rng.random_range(0.12..0.3);
                synth::instrumented_topple(&b, side, rate, &noise, 15.0, seed)
            } else {
                let p = ToppleParams {
                    side,
                    push_s: rng.random_range(0.8..2.5),
                    ..Default::default()
                };
                synth::topple(&b, &p, &noise, 15.0, seed)
            };
            let c = Learner::new(Config::default())
                .observe(&Source::Memory(&d.demo))
                .unwrap()
                .classification;
            let truth = d.truth.edge.unwrap();
            for s in &c.segments {
                let (Some(e), Some(rb), Some(ra), Some(pb), Some(pa)) = (
                    &s.edge,
                    s.resting_rotation_before,
                    s.resting_rotation_after,
                    s.resting_place_before,
                    s.resting_place_after,
                ) else {
                    continue;
                };
                let (nb, na) = (
                    s.resting_frames_before as f64,
                    s.resting_frames_after as f64,
                );
                if nb < 9.0 || na < 9.0 {
                    continue;
                }
                // The rests' "up": world z, or the palm's normal (level at the start).
                let up = Vector3::z();
                let g = (rb.to_rotation_matrix().matrix() - ra.to_rotation_matrix().matrix())
                    .transpose()
                    * up;
                let u = e.line.direction;
                let g = g - u * u.dot(&g);
                let along = g.normalize();
                let sigma = along.dot(&(e.point_cov * along)).sqrt();
                // What the support, the contact and the rests allow the heights to differ by
                // (the rests' noise as the learner estimated it, relative to the palm on a
                // palm, with the tag within 0.3 m of the edge; each rest's mean known to the
                // tracker's accuracy, taken as its per-frame noise).
                let at = |r: UnitQuaternion<f64>, place: RestPlace| {
                    r * e.line.point + place.position(&-up)
                };
                let moved = at(rb, pb) - at(ra, pa);
                let distance = (moved - up * up.dot(&moved)).norm();
                let est = c.noise.unwrap();
                let rests = (est.sigma_position.powi(2) + (est.sigma_rotation * 0.3).powi(2))
                    * (2.0 + 1.0 / nb + 1.0 / na);
                let allowed = (height_difference_var(distance, contact) + rests).sqrt();
                assert!(
                    sigma * g.norm() <= allowed * 1.001,
                    "seed {seed} instrumented {instrumented}: σ {:.2} mm along the rests' \
                     direction (|g| {:.2}), the support allows {:.2} mm",
                    sigma * 1e3,
                    g.norm(),
                    allowed * 1e3
                );
                z2 += (along.dot(&(e.line.point - truth.point)) / sigma).powi(2);
                shrink += sigma * g.norm() / allowed;
                n += 1;
            }
        }
        let rms = (z2 / n as f64).sqrt();
        let shrink = shrink / n as f64;
        eprintln!("instrumented {instrumented}: {n} edges, rms error/σ along the rests' direction {rms:.2}, mean σ|g| / allowed {shrink:.2}");
        assert!(n >= 12, "{n} completed topples with both rests");
        assert!(
            (0.5..1.5).contains(&rms),
            "rms error/σ {rms:.2} over {n} edges"
        );
    }
}
