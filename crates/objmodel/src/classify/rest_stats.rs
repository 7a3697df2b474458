//! The statistics of a rest: its mean pose, and the least-squares drift of the pose over it,
//! which tells a real rest from a motion too slow for the windowed rest test (see
//! [`super::segments`], which keeps one for the current rest, one for its latest part, and one
//! to probe a slow motion for its end).

use super::frame_model::FrameModel;
use crate::clean::RawFrame;
use crate::fast::avx2_or_baseline;
use crate::fast::lanes::F4;
use nalgebra::{Quaternion, UnitQuaternion, Vector3, Vector4};

/// Mean pose over a rest, and the least-squares drift of the pose over the whole rest (to tell
/// a real rest from a motion too slow for the windowed rest test).
///
/// The sums that every frame adds to are kept in whole lanes ([`RestStats::sums`]): a frame is
/// seven four-lane additions, whose loads and stores are the same from frame to frame. With
/// the sums in separate fields, the compiler combined fields into vectors differently for
/// loads and stores, and one load straddled a store of the frame before: the processor could
/// not forward it, and each call waited for the store (half of the time of `RestStats::add`, which
/// the 10^6-pose benchmark calls for nearly every frame, its whole topple being a slow motion).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct RestStats {
    /// Σx (two lanes), Σ dt·x (two), Σq (sign-aligned, `(x, y, z, w)`), `(Σp, 0)` and
    /// `(n, Σdt, Σdt², 0)`, with `x` the fitted coordinates about [`RestStats::origin`] (see
    /// [`fitted`]) and `dt = t - t0`.
    sums: [F4; 7],
    /// Time \[s\] of the first frame.
    pub(super) t0: f64,
    /// Time \[s\] of the latest frame.
    pub(super) t1: f64,
    /// The fitted coordinates at the first frame.
    origin: [F4; 2],
    /// Mean pose and frame count over the rest's first `head_s` seconds (taken when a frame
    /// beyond them arrives): the pose a slow motion started from.
    head: Option<(UnitQuaternion<f64>, Vector3<f64>, f64)>,
}

/// Where [`RestStats::sums`] keeps Σx (two groups of lanes),
const SUM_X: usize = 0;
/// Σ dt·x (two groups),
const SUM_TX: usize = 2;
/// Σq,
const SUM_Q: usize = 4;
/// `(Σp, 0)`
const SUM_P: usize = 5;
/// and `(n, Σdt, Σdt², 0)`.
const SUM_N: usize = 6;

/// The six coordinates whose drift a [`RestStats`] fits, the accumulated rotation `r` \[rad\]
/// and the position `p` \[m\], in two groups of four lanes: `(r, p_x)` and `(p_y, p_z, 0, 0)`.
#[inline(always)]
fn fitted(r: &Vector3<f64>, p: &Vector3<f64>) -> [F4; 2] {
    [F4([r.x, r.y, r.z, p.x]), F4([p.y, p.z, 0.0, 0.0])]
}

impl RestStats {
    /// Number of frames.
    #[inline(always)]
    pub(super) fn n(&self) -> f64 {
        self.sums[SUM_N].0[0]
    }

    /// Σq, sign-aligned.
    #[inline(always)]
    fn sum_q(&self) -> Vector4<f64> {
        Vector4::from(self.sums[SUM_Q].0)
    }

    /// Σp \[m\].
    #[inline(always)]
    fn sum_p(&self) -> Vector3<f64> {
        let p = self.sums[SUM_P].0;
        Vector3::new(p[0], p[1], p[2])
    }

    /// χ²₆ statistic of the pose's drift (least-squares slope) over the whole rest. The slope's
    /// variance is the noise's, `σ²/S_tt`, plus the model tolerance spread over the rest,
    /// `(tol/T)²`: contacts settle by that much without the object being moved.
    pub(super) fn drift_chi2(&self, m: &FrameModel) -> f64 {
        let [n, st, stt, _] = self.sums[SUM_N].0;
        let den = n * stt - st * st;
        let duration = self.t1 - self.t0;
        if n < 3.0 || den <= 0.0 || duration <= 0.0 {
            return 0.0;
        }
        let stt_c = den / n;
        (0..6)
            .map(|j| {
                let sx = self.sums[SUM_X + j / 4].0[j % 4];
                let stx = self.sums[SUM_TX + j / 4].0[j % 4];
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
        let x = fitted(rot, &f.p);
        let n = self.n();
        if n == 0.0 {
            self.t0 = f.t;
            self.origin = x;
        }
        self.t1 = f.t;
        let dt = f.t - self.t0;
        if dt > head_s && self.head.is_none() {
            self.head = self.mean().map(|(q, p)| (q, p, n));
        }
        let mut q = f.q.into_inner().coords;
        if n > 0.0 && q.dot(&self.sum_q()) < 0.0 {
            q = -q;
        }
        let (xa, xb) = (x[0] - self.origin[0], x[1] - self.origin[1]);
        let terms = [
            xa,
            xb,
            dt * xa,
            dt * xb,
            F4([q.x, q.y, q.z, q.w]),
            F4([f.p.x, f.p.y, f.p.z, 0.0]),
            F4([1.0, dt, dt * dt, 0.0]),
        ];
        for (s, t) in self.sums.iter_mut().zip(terms) {
            *s = *s + t;
        }
    }

    pub(super) fn mean(&self) -> Option<(UnitQuaternion<f64>, Vector3<f64>)> {
        let n = self.n();
        (n > 0.0).then(|| {
            (
                UnitQuaternion::from_quaternion(Quaternion::from(self.sum_q())),
                self.sum_p() / n,
            )
        })
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
