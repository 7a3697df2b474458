//! Tracking noise, estimated from the data itself.
//!
//! The learner's tests normalise residuals by the tracker's noise, so it must know that noise.
//! Rather than trust a datasheet, it is estimated from the second differences of the poses:
//! for a smooth motion sampled at time steps where the pose changes little between frames, the
//! residual of frame k from the geodesic midpoint of frames k-1 and k+1 is dominated by noise,
//! with variance `σ² (1 + ½)` per axis for i.i.d. noise of variance σ². A median of absolute
//! residuals (scaled by 1.4826) ignores the few frames where acceleration, impacts or tag flips
//! dominate.

use crate::se3::so3_log;
use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// Smallest position noise \[m\] the tests assume (50 µm). Below it, pose changes are not
/// demonstrations: rigid contacts comply and settle at this scale (a box on a tilting palm
/// shifts by micrometres as the load moves), and no camera tracker resolves them.
pub const MIN_SIGMA_POSITION_M: f64 = 5e-5;
/// Smallest rotation noise \[rad\] the tests assume (2e-4 rad, 0.011°), for the same reason.
pub const MIN_SIGMA_ROTATION_RAD: f64 = 2e-4;

/// Per-axis standard deviations of the tracking noise.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct NoiseModel {
    /// Position noise per axis \[m\].
    pub sigma_position: f64,
    /// Orientation noise per axis \[rad\] (of the rotation vector of the error).
    pub sigma_rotation: f64,
}

impl NoiseModel {
    /// The noise assumed where none was given and none could be estimated (too few frames):
    /// 1 mm and 0.01 rad per axis.
    pub const FALLBACK: NoiseModel = NoiseModel {
        sigma_position: 1e-3,
        sigma_rotation: 1e-2,
    };

    /// The noise model from options that give the position \[m\] and rotation \[rad\]
    /// standard deviations, each as (its name as the user wrote it, its value): both or
    /// neither, each zero or positive.
    pub fn from_options(
        position: (&str, Option<f64>),
        rotation: (&str, Option<f64>),
    ) -> Result<Option<Self>, String> {
        for ((name, v), unit) in [(position, "metres"), (rotation, "radians")] {
            if let Some(v) = v {
                if !(v >= 0.0 && v.is_finite()) {
                    return Err(format!("{name} must be zero or positive ({unit}), got {v}"));
                }
            }
        }
        match (position.1, rotation.1) {
            (Some(p), Some(r)) => Ok(Some(Self {
                sigma_position: p,
                sigma_rotation: r,
            })),
            (None, None) => Ok(None),
            _ => Err(format!(
                "give both {} and {}, or neither",
                position.0, rotation.0
            )),
        }
    }

    /// The model with both sigmas raised to at least their floors.
    pub fn floored(self) -> Self {
        Self {
            sigma_position: self.sigma_position.max(MIN_SIGMA_POSITION_M),
            sigma_rotation: self.sigma_rotation.max(MIN_SIGMA_ROTATION_RAD),
        }
    }
}

/// The per-axis noise of the motion relative to a palm (`palm_from_object = palm_from_world ·
/// world_from_object`) from each tracker's: the orientation errors add; the position error is
/// the object's, the palm's, and the palm's orientation error `δθ` turning the object's
/// position in the palm frame `r` (`δθ × r`, of per-axis variance `σ_θ² (|r|² − r_i²)`, on
/// average over the axes `⅔ σ_θ² |r|²`) at `lever_m = |r|`. A palm `palm_slower` times slower
/// than the object (1 when as fast or faster) counts `palm_slower` times: one palm error is
/// interpolated over that many object frames (`classify::palm`).
pub fn relative(
    object: NoiseModel,
    palm: NoiseModel,
    lever_m: f64,
    palm_slower: f64,
) -> NoiseModel {
    let k = palm_slower.max(1.0);
    let palm_position_var =
        palm.sigma_position.powi(2) + 2.0 / 3.0 * (palm.sigma_rotation * lever_m).powi(2);
    NoiseModel {
        sigma_position: (object.sigma_position.powi(2) + k * palm_position_var).sqrt(),
        sigma_rotation: (object.sigma_rotation.powi(2) + k * palm.sigma_rotation.powi(2)).sqrt(),
    }
}

/// One sample for the estimator: time \[s\], orientation, position \[m\].
pub type PoseSample = (f64, UnitQuaternion<f64>, Vector3<f64>);

/// Estimate the noise from consecutive samples (at least 3; sign continuity not required).
/// Returns `None` with fewer than 3 samples.
pub fn estimate(samples: &[PoseSample]) -> Option<NoiseModel> {
    let (sp, sr) = midpoint_sigmas(samples, 1)?;
    // Trackers often filter their output, and filtered noise is correlated from frame to
    // frame: second differences then understate it. The scatter about a straight line over
    // short windows does not; take the larger of the two (they agree for white noise).
    let (wp, wr) = window_scatter(samples).unwrap_or((0.0, 0.0));
    Some(
        NoiseModel {
            sigma_position: sp.max(wp),
            sigma_rotation: sr.max(wr),
        }
        .floored(),
    )
}

/// Whether [`estimate`] measured the motion rather than the noise: a thrown box filmed at
/// 30 Hz gave 2-12 mm for 1 mm noise (its straight-line windows hold the flight's curvature),
/// and every test then passed everything.
///
/// The residual of a frame from the midpoint of its neighbours `lag` frames away holds the
/// noise (the same variance at every lag) and the acceleration, whose variance grows as
/// `lag⁴`: from the robust sigmas at lags 1 and 2, `σ² = (16 s₁² - s₂²) / 15` is the noise
/// with the acceleration removed (Richardson). The estimate measured the motion when it
/// exceeds that σ by more than the sampling error allows: one-sided, at the normal quantile
/// of `alpha`, with the relative standard error of σ about `1.17 · 2 / √m` for `m` residuals
/// (the median-based sigma's 1.17/√m, inflated for the extrapolation), and when the excess
/// variance is more than the model tolerance `tolerance` (position \[m\], rotation \[rad\])
/// that the tests add to the noise anyway (exact poses of a smooth motion "estimate" its
/// curvature, harmlessly small). Per position and rotation; never below the noise floors.
pub fn motion_dominated(samples: &[PoseSample], alpha: f64, tolerance: (f64, f64)) -> bool {
    let (Some(est), Some(noise)) = (estimate(samples), motion_free(samples)) else {
        return false;
    };
    let m = 3.0 * (samples.len() as f64 - 4.0).max(1.0);
    let limit = 1.0 + crate::stats::normal_quantile(1.0 - alpha) * 1.17 * 2.0 / m.sqrt();
    let floor = NoiseModel {
        sigma_position: 0.0,
        sigma_rotation: 0.0,
    }
    .floored();
    let inflated = |est: f64, noise: f64, tol: f64| {
        est > limit * noise && est * est - noise * noise > tol * tol
    };
    inflated(
        est.sigma_position,
        noise.sigma_position.max(floor.sigma_position),
        tolerance.0,
    ) || inflated(
        est.sigma_rotation,
        noise.sigma_rotation.max(floor.sigma_rotation),
        tolerance.1,
    )
}

/// The per-axis noise of consecutive samples with a smooth motion's acceleration removed
/// (Richardson, see [`motion_dominated`]), unfloored: zero for the exact poses of a smooth
/// motion, the noise for a tracker's. `None` with fewer than 5 samples.
pub fn motion_free(samples: &[PoseSample]) -> Option<NoiseModel> {
    let ((p1, r1), (p2, r2)) = (midpoint_sigmas(samples, 1)?, midpoint_sigmas(samples, 2)?);
    // σ² = (16 s₁² - s₂²) / 15 from the robust sigmas s₁, s₂ at lags 1 and 2.
    let richardson = |s1: f64, s2: f64| ((16.0 * s1 * s1 - s2 * s2) / 15.0).max(0.0).sqrt();
    Some(NoiseModel {
        sigma_position: richardson(p1, p2),
        sigma_rotation: richardson(r1, r2),
    })
}

/// Whether the estimate `a` (from `n_a` consecutive samples) exceeds `b` (from `n_b`), in
/// position or rotation, by more than their sampling errors allow: one-sided at the normal
/// quantile of `alpha`, on the log scale, with the relative standard error of each about
/// `1.17 / √m` for its `m = 3 (n - 2)` residuals (the median-based sigma's).
pub fn exceeds(a: &NoiseModel, n_a: usize, b: &NoiseModel, n_b: usize, alpha: f64) -> bool {
    let m = |n: usize| 3.0 * (n as f64 - 2.0).max(1.0);
    let se = 1.17 * (1.0 / m(n_a) + 1.0 / m(n_b)).sqrt();
    let limit = (crate::stats::normal_quantile(1.0 - alpha) * se).exp();
    a.sigma_position > limit * b.sigma_position || a.sigma_rotation > limit * b.sigma_rotation
}

/// Robust per-axis sigmas (position, rotation) of the residuals of each frame from the
/// geodesic midpoint of the frames `lag` before and after it, scaled by their variance factor
/// for white noise. `None` with fewer than `2 lag + 1` samples.
fn midpoint_sigmas(samples: &[PoseSample], lag: usize) -> Option<(f64, f64)> {
    if samples.len() < 2 * lag + 1 {
        return None;
    }
    let mut pos = Vec::with_capacity(3 * samples.len());
    let mut rot = Vec::with_capacity(3 * samples.len());
    for k in lag..samples.len() - lag {
        let (t0, q0, p0) = &samples[k - lag];
        let (t1, q1, p1) = &samples[k];
        let (t2, q2, p2) = &samples[k + lag];
        let s = ((t1 - t0) / (t2 - t0)).clamp(0.0, 1.0);
        // Interpolate on the geodesic from q0 to q2 (sign-aligned), and linearly in position.
        let d = so3_log(&(q0.inverse() * q2));
        let mid = q0 * crate::se3::so3_exp(&(d * s));
        let rr = so3_log(&(mid.inverse() * q1));
        let rp = p1 - (p0 * (1.0 - s) + p2 * s);
        // Residual variance factor for unequal spacing: 1 + (1-s)² + s².
        let factor = (1.0 + (1.0 - s).powi(2) + s * s).sqrt();
        for i in 0..3 {
            pos.push(rp[i].abs() / factor);
            rot.push(rr[i].abs() / factor);
        }
    }
    Some((
        crate::stats::robust_sigma_zero_mean(&mut pos)?,
        crate::stats::robust_sigma_zero_mean(&mut rot)?,
    ))
}

/// Frames per window of [`window_scatter`].
pub const SCATTER_WINDOW: usize = 9;

/// Median over non-overlapping windows of [`SCATTER_WINDOW`] samples of the robust scale of the
/// residuals about a least-squares straight line in time, per axis (corrected for the line's two
/// parameters): the noise level including its correlation over a window. Motion that is not
/// uniform within a window inflates only those windows, which the median ignores.
pub fn window_scatter(samples: &[PoseSample]) -> Option<(f64, f64)> {
    let k = SCATTER_WINDOW;
    let (mut pos, mut rot) = (Vec::new(), Vec::new());
    for w in samples.chunks_exact(k) {
        let tm = w.iter().map(|s| s.0).sum::<f64>() / k as f64;
        let stt: f64 = w.iter().map(|s| (s.0 - tm).powi(2)).sum();
        if stt <= 0.0 {
            continue;
        }
        let qc = w[k / 2].1;
        let xs: Vec<[f64; 6]> = w
            .iter()
            .map(|(_, q, p)| {
                let r = so3_log(&(qc.inverse() * q));
                [r.x, r.y, r.z, p.x, p.y, p.z]
            })
            .collect();
        let (mut rr, mut pr) = (Vec::with_capacity(3 * k), Vec::with_capacity(3 * k));
        for j in 0..6 {
            let m = xs.iter().map(|x| x[j]).sum::<f64>() / k as f64;
            let slope = w
                .iter()
                .zip(&xs)
                .map(|(s, x)| (s.0 - tm) * (x[j] - m))
                .sum::<f64>()
                / stt;
            let res = w
                .iter()
                .zip(&xs)
                .map(|(s, x)| (x[j] - m - slope * (s.0 - tm)).abs());
            if j < 3 {
                rr.extend(res)
            } else {
                pr.extend(res)
            }
        }
        // Robust per window (a tag flip in it must not count): median |residual|, scaled to σ
        // and corrected for the two parameters of the line.
        let dof = (k as f64 / (k - 2) as f64).sqrt();
        rot.push(crate::stats::robust_sigma_zero_mean(&mut rr)? * dof);
        pos.push(crate::stats::robust_sigma_zero_mean(&mut pr)? * dof);
    }
    Some((
        crate::stats::median(&mut pos)?,
        crate::stats::median(&mut rot)?,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};
    use rand_distr::StandardNormal;

    /// The relative motion's noise that [`relative`] propagates is the one that the trackers'
    /// noise gives `palm_from_object`, drawn (per-axis variances averaged over the axes, within
    /// their sampling error), for several poses, levers and noise levels.
    #[test]
    fn relative_noise_is_what_two_noisy_trackers_give() {
        let mut rng = StdRng::seed_from_u64(7);
        let n = |rng: &mut StdRng, s: f64| {
            Vector3::new(
                rng.sample::<f64, _>(StandardNormal) * s,
                rng.sample::<f64, _>(StandardNormal) * s,
                rng.sample::<f64, _>(StandardNormal) * s,
            )
        };
        for case in 0..6 {
            let object = NoiseModel {
                sigma_position: rng.random_range(1e-4..3e-3),
                sigma_rotation: rng.random_range(1e-3..3e-2),
            };
            let palm = NoiseModel {
                sigma_position: rng.random_range(1e-4..3e-3),
                sigma_rotation: rng.random_range(1e-3..3e-2),
            };
            let world_from_palm = (
                UnitQuaternion::from_scaled_axis(n(&mut rng, 1.0)),
                n(&mut rng, 0.5),
            );
            let palm_from_object = (
                UnitQuaternion::from_scaled_axis(n(&mut rng, 1.0)),
                n(&mut rng, 0.1),
            );
            let world_from_object = (
                world_from_palm.0 * palm_from_object.0,
                world_from_palm.1 + world_from_palm.0 * palm_from_object.1,
            );
            let draws = 20_000;
            let (mut var_p, mut var_r) = (0.0, 0.0);
            for _ in 0..draws {
                let (qp, pp) = (
                    world_from_palm.0
                        * UnitQuaternion::from_scaled_axis(n(&mut rng, palm.sigma_rotation)),
                    world_from_palm.1 + n(&mut rng, palm.sigma_position),
                );
                let (qo, po) = (
                    world_from_object.0
                        * UnitQuaternion::from_scaled_axis(n(&mut rng, object.sigma_rotation)),
                    world_from_object.1 + n(&mut rng, object.sigma_position),
                );
                let p = qp.inverse() * (po - pp) - palm_from_object.1;
                let r = so3_log(&(palm_from_object.0.inverse() * (qp.inverse() * qo)));
                var_p += p.norm_squared() / 3.0;
                var_r += r.norm_squared() / 3.0;
            }
            let want = relative(object, palm, palm_from_object.1.norm(), 1.0);
            // Sampling error of a variance from 3 × 20 000 squares: √(2 / 60 000) ≈ 0.6%.
            for (got, want) in [
                (var_p / draws as f64, want.sigma_position.powi(2)),
                (var_r / draws as f64, want.sigma_rotation.powi(2)),
            ] {
                assert!(
                    (got / want - 1.0).abs() < 0.03,
                    "case {case}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn recovers_known_noise_on_a_moving_object() {
        let mut rng = StdRng::seed_from_u64(1);
        let mut v = Vec::new();
        for k in 0..600 {
            let t = k as f64 / 30.0;
            let n = |rng: &mut StdRng, s: f64| {
                Vector3::new(
                    rng.sample::<f64, _>(StandardNormal) * s,
                    rng.sample::<f64, _>(StandardNormal) * s,
                    rng.sample::<f64, _>(StandardNormal) * s,
                )
            };
            let q = UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.3 * t, 0.0))
                * UnitQuaternion::from_scaled_axis(n(&mut rng, 0.0087));
            let p = Vector3::new(0.1 * t, 0.0, 0.0) + n(&mut rng, 0.001);
            // Quaternion sign flips must not matter.
            let q = if k % 7 == 0 {
                UnitQuaternion::new_unchecked(-q.into_inner())
            } else {
                q
            };
            v.push((t, q, p));
        }
        let m = estimate(&v).unwrap();
        assert!((m.sigma_position / 0.001 - 1.0).abs() < 0.1, "{m:?}");
        assert!((m.sigma_rotation / 0.0087 - 1.0).abs() < 0.1, "{m:?}");
    }

    /// No false alarm at 1 mm / 0.5° noise: a slow motion over 20 s at 30 Hz, and a box shaken
    /// at 4 Hz by 3 cm and 0.5 rad at 240 Hz, are measured.
    #[test]
    fn tells_when_the_motion_not_the_noise_was_measured() {
        let mut rng = StdRng::seed_from_u64(3);
        let mut n = |s: f64| {
            Vector3::new(
                rng.sample::<f64, _>(StandardNormal) * s,
                rng.sample::<f64, _>(StandardNormal) * s,
                rng.sample::<f64, _>(StandardNormal) * s,
            )
        };
        let tol = (3e-4, 0.5f64.to_radians());
        let mut samples = |rate: f64, frames: usize, shake: f64| -> Vec<PoseSample> {
            (0..frames)
                .map(|k| {
                    let t = k as f64 / rate;
                    let w = (std::f64::consts::TAU * 4.0 * t).sin() * shake;
                    let q = UnitQuaternion::from_scaled_axis(Vector3::new(0.5 * w, 0.05 * t, 0.0))
                        * UnitQuaternion::from_scaled_axis(n(0.0087));
                    let p = Vector3::new(0.03 * w + 0.01 * t, 0.0, 0.0) + n(0.001);
                    (t, q, p)
                })
                .collect()
        };
        assert!(!motion_dominated(&samples(30.0, 600, 0.0), 1e-3, tol));
        // (A flight whose estimate was its curvature: tests/compound.rs, on a rapier toss.)
        assert!(!motion_dominated(&samples(240.0, 240, 1.0), 1e-3, tol));
    }

    /// Two estimates of the same noise at rest, each from its own samples, do not exceed each
    /// other beyond the level (rarely, over 400 pairs); twice the noise does, with enough
    /// samples, and not with too few to tell.
    #[test]
    fn one_estimate_exceeds_another_only_beyond_sampling_error() {
        let mut rng = StdRng::seed_from_u64(4);
        let at_rest = |n: usize, sp: f64, sr: f64, rng: &mut StdRng| {
            let v: Vec<PoseSample> = (0..n)
                .map(|k| {
                    let g = |rng: &mut StdRng, s: f64| {
                        Vector3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal) * s)
                    };
                    let q = UnitQuaternion::from_scaled_axis(g(rng, sr));
                    (k as f64 / 30.0, q, g(rng, sp))
                })
                .collect();
            estimate(&v).unwrap()
        };
        let mut false_alarms = 0;
        for _ in 0..400 {
            let n_a = rng.random_range(20..300);
            let n_b = rng.random_range(15..60);
            let a = at_rest(n_a, 1e-3, 8.7e-3, &mut rng);
            let b = at_rest(n_b, 1e-3, 8.7e-3, &mut rng);
            false_alarms += exceeds(&a, n_a, &b, n_b, 1e-3) as usize;
        }
        assert!(false_alarms <= 4, "{false_alarms} of 400");
        let twice = at_rest(200, 2e-3, 8.7e-3, &mut rng);
        let once = at_rest(30, 1e-3, 8.7e-3, &mut rng);
        assert!(exceeds(&twice, 200, &once, 30, 1e-3));
        assert!(!exceeds(&twice, 4, &once, 4, 1e-3));
    }
}
