//! The tracker's noise for a demonstration whose own frames cannot measure it, from the
//! demonstrations learnt with it.
//!
//! A box thrown past a tracker at 30 Hz moves more between two frames than the tracker's noise,
//! from its first frame to its last, and rests too briefly for a rest to measure the noise
//! (`learn`'s noise check): alone, it teaches nothing. Learnt with other demonstrations at its
//! frame rate, it takes the noise that the rests of all of them measure together
//! ([`crate::noise_correlation::measure_pooled`] over windows of ten frames counted back from
//! each rest's end, [`crate::noise_correlation::NoiseWindows::of_rests`]), as a demonstration
//! long enough measures its own: the long-run noise where it is correlated from frame to frame,
//! else the white noise. The demonstrations of one call at one frame rate are taken to be one
//! tracker's. Why not the noise each demonstration used: a short one's estimate from its first
//! frames holds some of its motion (the 500 simulated tosses at 1 mm, 0.5°: a median of
//! 1.52 mm, 0.63° over those estimates, against 1.08 mm, 0.55° over those measured on a rest,
//! and 0.99-1.06 mm, 0.49-0.54° over each box's pooled rests); and a camera's correlated noise
//! shows only in many windows, which one toss does not have (the camera set's tosses, ρ 0.5:
//! 0.44-0.58 pooled per box). `learn` then checks the noise against the demonstration's own
//! frames as it checks a noise the user gives, and uses the larger where they show more.

use crate::noise::NoiseModel;
use crate::noise_correlation::{measure_pooled, Correlation, NoiseWindows};
use serde::{Deserialize, Serialize};

/// The fewest demonstrations whose windows are pooled: the rests of one or two short
/// demonstrations are too few to stand for a tracker.
pub const MIN_DEMONSTRATIONS: usize = 3;

/// How far apart (relative) two demonstrations' median frame intervals may be for their
/// frame rates to be the same: a tracker's frames come at a fixed rate, and dropped frames
/// move the median interval by far less.
pub const SAME_RATE: f64 = 0.05;

/// The most windows one demonstration gives the pool (evenly spread over it), so that a long
/// demonstration does not outweigh the others, and memory stays small.
pub const MAX_WINDOWS: usize = 256;

/// The noise a demonstration was learnt with, measured on the rests of those learnt with it at
/// its frame rate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SharedNoise {
    /// The noise the tests use: the long-run noise where the correlation matters
    /// ([`Correlation::matters`]), else the white noise.
    pub noise: NoiseModel,
    /// What the pooled windows measured.
    pub measured: Correlation,
    /// How many demonstrations gave windows.
    pub demonstrations: usize,
}

/// The noise that the windows of the demonstrations `learnt` (each its median frame interval
/// \[s\] and its windows) give one whose median frame interval is `interval`: pooled over
/// those at its frame rate ([`SAME_RATE`]) if there are [`MIN_DEMONSTRATIONS`] of them with
/// windows, and the pooled correlation within what the windows resolve
/// ([`Correlation::beyond_resolution`] at `alpha`). `tolerance` (position \[m\], rotation
/// \[rad\]) is the model tolerance the tests add to the noise.
pub fn shared_noise<'a>(
    interval: f64,
    learnt: impl IntoIterator<Item = (f64, &'a NoiseWindows)>,
    tolerance: (f64, f64),
    alpha: f64,
) -> Option<SharedNoise> {
    let at_rate: Vec<&NoiseWindows> = learnt
        .into_iter()
        .filter(|&(dt, w)| same_rate(interval, dt) && !w.is_empty())
        .map(|(_, w)| w)
        .collect();
    if at_rate.len() < MIN_DEMONSTRATIONS {
        return None;
    }
    let measured = measure_pooled(at_rate.iter().copied())?;
    if measured.beyond_resolution(alpha) {
        return None;
    }
    Some(SharedNoise {
        noise: if measured.matters(tolerance) {
            measured.long_run
        } else {
            measured.white
        },
        measured,
        demonstrations: at_rate.len(),
    })
}

/// Whether two median frame intervals \[s\] are one frame rate's.
fn same_rate(a: f64, b: f64) -> bool {
    a > 0.0 && b > 0.0 && (a - b).abs() <= SAME_RATE * a.min(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::PoseSample;
    use nalgebra::{UnitQuaternion, Vector3};
    use rand::{rngs::StdRng, Rng, SeedableRng};
    use rand_distr::{Distribution, Normal};

    const TOLERANCE: (f64, f64) = (3e-4, 1e-3);

    /// The rest that ends a toss at 30 Hz as a tracker sees it: `n` frames, with AR(1) noise
    /// of marginal σ (1 mm, 0.5°) and lag-one correlation `rho`, and a settling wobble (up to
    /// 0.6°, as large as the noise) decaying over its first frames.
    fn rest(rng: &mut StdRng, n: usize, rho: f64) -> Vec<PoseSample> {
        let unit = Normal::new(0.0, 1.0).unwrap();
        let (sp, sr, dt) = (1e-3, 0.5f64.to_radians(), 1.0 / 30.0);
        let innovation = (1.0 - rho * rho).sqrt();
        let mut e: [f64; 6] = std::array::from_fn(|_| unit.sample(rng));
        let wobble = rng.random_range(0.0..0.01);
        (0..n)
            .map(|k| {
                for x in &mut e {
                    *x = rho * *x + innovation * unit.sample(rng);
                }
                let t = k as f64 * dt;
                let settle = wobble * (-t / 0.05).exp() * (40.0 * t).cos();
                let q = UnitQuaternion::from_scaled_axis(Vector3::new(
                    e[0] * sr + settle,
                    e[1] * sr,
                    e[2] * sr,
                ));
                (t, q, Vector3::new(e[3], e[4], e[5]) * sp)
            })
            .collect()
    }

    fn shared(rho: f64, seed: u64, n: usize) -> Option<SharedNoise> {
        let mut rng = StdRng::seed_from_u64(seed);
        let windows: Vec<NoiseWindows> = (0..n)
            .map(|_| {
                let len = rng.random_range(8..25);
                NoiseWindows::of_rests([rest(&mut rng, len, rho).as_slice()])
            })
            .collect();
        shared_noise(
            1.0 / 30.0,
            windows.iter().map(|w| (1.0 / 30.0, w)),
            TOLERANCE,
            1e-3,
        )
    }

    #[test]
    fn short_rests_together_measure_their_trackers_noise() {
        // Sixty rests of 8-24 frames, each too short to measure its noise's correlation, over
        // 50 draws: the white noise's σ, and a camera's correlated noise's long-run σ (√3
        // times the marginal σ at ρ 0.5), near the truth in the median and within the
        // sampling error of ρ in every draw (its long-run factor is steep: ρ 0.58 for 0.5
        // gives 1.12 times the truth).
        for (rho, factor, within) in [(0.0, 1.0, 0.15), (0.5, 3f64.sqrt(), 0.4)] {
            let mut ratios = Vec::new();
            for seed in 0..50 {
                let s = shared(rho, seed, 60).expect("measured");
                let p = s.noise.sigma_position / (1e-3 * factor);
                let r = s.noise.sigma_rotation / (0.5f64.to_radians() * factor);
                assert!(
                    (p - 1.0).abs() < within && (r - 1.0).abs() < within,
                    "ρ {rho}, seed {seed}: {p:.3} {r:.3} of the truth ({s:?})"
                );
                ratios.extend([p, r]);
            }
            let median = crate::stats::median(&mut ratios).unwrap();
            assert!((median - 1.0).abs() < 0.05, "ρ {rho}: median {median:.3}");
        }
    }

    #[test]
    fn only_demonstrations_at_the_frame_rate_share_their_noise() {
        let mut rng = StdRng::seed_from_u64(7);
        let w: Vec<NoiseWindows> = (0..4)
            .map(|_| NoiseWindows::of_rests([rest(&mut rng, 30, 0.0).as_slice()]))
            .collect();
        let at = |dts: [f64; 4]| {
            shared_noise(1.0 / 30.0, dts.into_iter().zip(&w), TOLERANCE, 1e-3)
                .map(|s| s.demonstrations)
        };
        let (a, b) = (1.0 / 30.0, 1.0 / 120.0);
        assert_eq!(at([a, a, a, a]), Some(4));
        assert_eq!(at([a, a, a, b]), Some(3));
        assert_eq!(at([a, a, b, b]), None);
        // 5% either way is another rate; 1.6% is the same.
        assert_eq!(at([1.0 / 28.0, 1.0 / 32.0, a, a]), None);
        assert_eq!(at([1.0 / 30.5, 1.0 / 29.5, a, a]), Some(4));
    }
}
