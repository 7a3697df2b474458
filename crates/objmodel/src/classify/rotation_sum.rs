//! The accumulated rotation of a stream of frames (what rest detection fits for the
//! orientation: continuous, unlike a rotation vector from a fixed reference, which wraps at π).

use crate::se3::so3_log;
use nalgebra::{UnitQuaternion, Vector3};

/// `sin²(θ/2)` below which [`step_log`] uses its series (rotations below 1.15°).
const STEP_SERIES_S2: f64 = 1e-4;

/// The rotation vector ω \[rad\] of `q0⁻¹ q`, the rotation from one frame to the next: nearly
/// always tiny, so computed without a division or `atan2`.
///
/// For a unit quaternion `(w, v)` with `w >= 0` and `s = |v| = sin(θ/2)`, `θ = 2 asin(s)`, so
/// `ω = v · 2 asin(s)/s` with `asin(s)/s = 1 + s²/6 + 3s⁴/40 + 5s⁶/112 + 35s⁸/1152 + …`; for
/// `s² <` [`STEP_SERIES_S2`] the series truncated after s⁸ is exact to 3e-22 (and `w < 0` only
/// flips the sign). It equals [`so3_log`] up to rounding and the quaternion's norm (`|q|² = 1 + δ`
/// changes ω by `δ/2` relative, ~1e-16 for normalised inputs); larger rotations go to
/// [`so3_log`].
#[inline(always)]
pub(super) fn step_log(q0: &UnitQuaternion<f64>, q: &UnitQuaternion<f64>) -> Vector3<f64> {
    let d = q0.inverse() * q;
    let v = d.imag();
    let s2 = v.norm_squared();
    if s2 < STEP_SERIES_S2 {
        let half_k =
            1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0 + s2 * (5.0 / 112.0 + s2 * (35.0 / 1152.0))));
        let k = if d.w < 0.0 { -2.0 } else { 2.0 } * half_k;
        v * k
    } else {
        so3_log(&d)
    }
}

/// The accumulated rotation \[rad\] of a stream of frames: the sum of the logs of the
/// frame-to-frame rotations since the first frame (`step_log`). A stage of its own, so that
/// it can run on another thread than the rest detector that fits it
/// (`RestDetector`).
#[derive(Clone, Copy, Debug, Default)]
pub struct RotationSum {
    sum: Vector3<f64>,
    last: Option<UnitQuaternion<f64>>,
}

impl RotationSum {
    /// The accumulated rotation at the next frame, of orientation `q`.
    #[inline(always)]
    pub fn next(&mut self, q: &UnitQuaternion<f64>) -> Vector3<f64> {
        if let Some(q0) = self.last {
            self.sum += step_log(&q0, q);
        }
        self.last = Some(*q);
        self.sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_log_is_the_log() {
        let mut seed =
            <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x1234_5678_9abc_def1);
        let mut rnd = move || rand::Rng::random::<f64>(&mut seed) - 0.5;
        for k in 0..20000 {
            let scale = [1e-9, 1e-5, 1e-3, 0.019, 0.021, 0.3, 3.0][k % 7];
            let q0 = UnitQuaternion::from_scaled_axis(Vector3::new(rnd(), rnd(), rnd()) * 6.0);
            let w = Vector3::new(rnd(), rnd(), rnd()) * scale;
            let mut q = q0 * UnitQuaternion::from_scaled_axis(w);
            if k % 3 == 0 {
                q = UnitQuaternion::new_unchecked(-q.into_inner());
            }
            let exact = so3_log(&(q0.inverse() * q));
            let err = (step_log(&q0, &q) - exact).norm();
            assert!(err <= 2e-15 * exact.norm(), "{w} {exact} {err:e}");
        }
    }
}
