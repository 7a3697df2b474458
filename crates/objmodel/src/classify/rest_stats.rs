//! The statistics of a rest: its mean pose, and the least-squares drift of the pose over it,
//! which tells a real rest from a motion too slow for the windowed rest test (see
//! [`super::segments`], which keeps one for the current rest, one for its latest part, and one
//! to probe a slow motion for its end).

use super::frame_model::FrameModel;
use crate::clean::RawFrame;
use crate::fast::avx2_or_baseline;
use crate::fast::drift_sums::DriftSums;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// Mean pose over a rest, and the least-squares drift of the pose over the whole rest (to tell
/// a real rest from a motion too slow for the windowed rest test).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct RestStats {
    /// Σx, Σ dt·x, Σq (sign-aligned), Σp and `(n, Σdt, Σdt²)`, with `x` the fitted coordinates
    /// (accumulated rotation and position) about the first frame's and `dt = t - t0`.
    sums: DriftSums,
    /// Time \[s\] of the first frame.
    pub(super) t0: f64,
    /// Time \[s\] of the latest frame.
    pub(super) t1: f64,
    /// Mean pose and frame count over the rest's first `head_s` seconds (taken when a frame
    /// beyond them arrives): the pose a slow motion started from.
    head: Option<(UnitQuaternion<f64>, Vector3<f64>, f64)>,
}

impl RestStats {
    /// Number of frames.
    #[inline(always)]
    pub(super) fn n(&self) -> f64 {
        self.sums.n()
    }

    /// χ²₆ statistic of the pose's drift (least-squares slope) over the whole rest. The slope's
    /// variance is the noise's, `σ²/S_tt`, plus the model tolerance spread over the rest,
    /// `(tol/T)²`: contacts settle by that much without the object being moved.
    pub(super) fn drift_chi2(&self, m: &FrameModel) -> f64 {
        let [n, st, stt] = self.sums.time_sums();
        let den = n * stt - st * st;
        let duration = self.t1 - self.t0;
        if n < 3.0 || den <= 0.0 || duration <= 0.0 {
            return 0.0;
        }
        let stt_c = den / n;
        (0..6)
            .map(|j| {
                let (sx, stx) = self.sums.x_sums(j);
                let beta = (n * stx - st * sx) / den;
                let (var, tol2) = if j < 3 {
                    (m.var_r, m.tol_r2)
                } else {
                    (m.var_p, m.tol_p2)
                };
                beta * beta / (var / stt_c + tol2 / (duration * duration))
            })
            .sum()
    }

    /// Add a frame; `rot` is its accumulated rotation (sum of the logs of the frame-to-frame
    /// rotations, [`super::rotation_sum::RotationSum`]): over a rest it differs from the log of the rotation
    /// from the first frame only at second order in the (small) angles, and it stays linear in
    /// time for a slow turn about a fixed axis, which the drift test is about.
    #[inline(always)]
    pub(super) fn add(&mut self, f: &RawFrame, rot: &Vector3<f64>, head_s: f64) {
        avx2_or_baseline!(#[inline(never)] fn(
            this: &mut RestStats = self,
            f: &RawFrame = f,
            rot: &Vector3<f64> = rot,
            head_s: f64 = head_s,
        ) {
            this.add_with(f, rot, head_s)
        })
    }

    #[inline(always)]
    fn add_with(&mut self, f: &RawFrame, rot: &Vector3<f64>, head_s: f64) {
        let n = self.n();
        if n == 0.0 {
            self.t0 = f.t;
        }
        self.t1 = f.t;
        let dt = f.t - self.t0;
        if dt > head_s && self.head.is_none() {
            self.head = self.mean().map(|(q, p)| (q, p, n));
        }
        let mut q = f.q.into_inner().coords;
        if n > 0.0 && q.dot(&self.sums.sum_q()) < 0.0 {
            q = -q;
        }
        self.sums.add(dt, rot, &f.p, &q);
    }

    pub(super) fn mean(&self) -> Option<(UnitQuaternion<f64>, Vector3<f64>)> {
        let n = self.n();
        (n > 0.0).then(|| {
            (
                UnitQuaternion::from_quaternion(Quaternion::from(self.sums.sum_q())),
                self.sums.sum_p() / n,
            )
        })
    }

    /// χ²₆ statistic of frame `f`'s pose against the rest's mean pose, under the per-frame
    /// noise and model tolerance of `m`, the mean's own noise included: small for a frame of
    /// the same rest, large for one the object reached while the tracker did not see it.
    pub(super) fn departure_chi2(&self, f: &RawFrame, m: &FrameModel) -> f64 {
        let Some((q, p)) = self.mean() else {
            return 0.0;
        };
        let k = 1.0 + 1.0 / self.n();
        let r = crate::se3::so3_log(&(q.inverse() * f.q));
        r.norm_squared() / (m.var_r * k + m.tol_r2)
            + (f.p - p).norm_squared() / (m.var_p * k + m.tol_p2)
    }

    /// The pose a slow motion through this "rest" started from: the mean over the rest's head
    /// (or over all of it while it is short), and the number of frames averaged.
    pub(super) fn start(&self) -> Option<(UnitQuaternion<f64>, Vector3<f64>, f64)> {
        self.head
            .or_else(|| self.mean().map(|(q, p)| (q, p, self.n())))
    }

    /// "Down" in object coordinates at the mean pose, given it (`down`) in the frame the poses
    /// are relative to.
    pub(super) fn down(&self, down: Option<Vector3<f64>>) -> Option<Vector3<f64>> {
        let (q, _) = self.mean()?;
        Some((q.inverse() * down?).normalize())
    }
}
