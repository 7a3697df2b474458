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

/// Smallest position noise [m] the tests assume (50 µm). Below it, pose changes are not
/// demonstrations: rigid contacts comply and settle at this scale (a box on a tilting palm
/// shifts by micrometres as the load moves), and no camera tracker resolves them.
pub const MIN_SIGMA_POSITION_M: f64 = 5e-5;
/// Smallest rotation noise [rad] the tests assume (2e-4 rad, 0.011°), for the same reason.
pub const MIN_SIGMA_ROTATION_RAD: f64 = 2e-4;

/// Per-axis standard deviations of the tracking noise.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct NoiseModel {
    /// Position noise per axis [m].
    pub sigma_position: f64,
    /// Orientation noise per axis [rad] (of the rotation vector of the error).
    pub sigma_rotation: f64,
}

impl NoiseModel {
    /// The model with both sigmas raised to at least their floors.
    pub fn floored(self) -> Self {
        Self {
            sigma_position: self.sigma_position.max(MIN_SIGMA_POSITION_M),
            sigma_rotation: self.sigma_rotation.max(MIN_SIGMA_ROTATION_RAD),
        }
    }
}

/// One sample for the estimator: time [s], orientation, position [m].
pub type PoseSample = (f64, UnitQuaternion<f64>, Vector3<f64>);

/// Estimate the noise from consecutive samples (at least 3; sign continuity not required).
/// Returns `None` with fewer than 3 samples.
pub fn estimate(samples: &[PoseSample]) -> Option<NoiseModel> {
    if samples.len() < 3 {
        return None;
    }
    let mut pos = Vec::with_capacity(3 * samples.len());
    let mut rot = Vec::with_capacity(3 * samples.len());
    for w in samples.windows(3) {
        let (t0, q0, p0) = &w[0];
        let (t1, q1, p1) = &w[1];
        let (t2, q2, p2) = &w[2];
        let s = ((t1 - t0) / (t2 - t0)).clamp(0.0, 1.0);
        // Interpolate on the geodesic from q0 to q2 (sign-aligned), and linearly in position.
        let d = so3_log(&(q0.inverse() * q2));
        let mid = q0 * crate::se3::so3_exp(&(d * s));
        let rr = so3_log(&(mid.inverse() * q1));
        let rp = p1 - (p0 * (1.0 - s) + p2 * s);
        // Residual variance factor for unequal spacing: 1 + (1-s)² + s².
        let k = (1.0 + (1.0 - s).powi(2) + s * s).sqrt();
        for i in 0..3 {
            pos.push(rp[i].abs() / k);
            rot.push(rr[i].abs() / k);
        }
    }
    let sp = crate::stats::robust_sigma_zero_mean(&mut pos)?;
    let sr = crate::stats::robust_sigma_zero_mean(&mut rot)?;
    Some(
        NoiseModel {
            sigma_position: sp,
            sigma_rotation: sr,
        }
        .floored(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};
    use rand_distr::StandardNormal;

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
}
