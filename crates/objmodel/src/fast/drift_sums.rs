//! The sums of a rest's drift fit and mean pose (`crate::classify`'s rest statistics), kept in
//! whole four-lane rows.
//!
//! A frame is seven four-lane additions, whose loads and stores are the same from frame to
//! frame. With the sums in separate fields, the compiler combined fields into vectors
//! differently for loads and stores, and one load straddled a store of the frame before: the
//! processor could not forward it, and each call waited for the store (half of the time of
//! adding a frame, which the 10^6-pose benchmark does for nearly every frame, its whole topple
//! being a slow motion).

use super::lanes::F4;
use nalgebra::{Vector3, Vector4};

/// Σx (two lanes), Σ dt·x (two), Σq (sign-aligned, `(x, y, z, w)`), `(Σp, 0)` and
/// `(n, Σdt, Σdt², 0)`, with `x` the fitted coordinates about the first frame's (see
/// [`fitted`]) and `dt` the time since the first frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct DriftSums {
    sums: [F4; 7],
    /// The fitted coordinates at the first frame.
    origin: [F4; 2],
}

/// Where [`DriftSums`] keeps Σx (two groups of lanes),
const SUM_X: usize = 0;
/// Σ dt·x (two groups),
const SUM_TX: usize = 2;
/// Σq,
const SUM_Q: usize = 4;
/// `(Σp, 0)`
const SUM_P: usize = 5;
/// and `(n, Σdt, Σdt², 0)`.
const SUM_N: usize = 6;

/// The six coordinates whose drift a [`DriftSums`] fits, the accumulated rotation `r` \[rad\]
/// and the position `p` \[m\], in two groups of four lanes: `(r, p_x)` and `(p_y, p_z, 0, 0)`.
#[inline(always)]
fn fitted(r: &Vector3<f64>, p: &Vector3<f64>) -> [F4; 2] {
    [F4([r.x, r.y, r.z, p.x]), F4([p.y, p.z, 0.0, 0.0])]
}

impl DriftSums {
    /// Number of frames.
    #[inline(always)]
    pub fn n(&self) -> f64 {
        self.sums[SUM_N].0[0]
    }

    /// `[n, Σdt, Σdt²]`.
    #[inline(always)]
    pub fn time_sums(&self) -> [f64; 3] {
        let [n, st, stt, _] = self.sums[SUM_N].0;
        [n, st, stt]
    }

    /// `(Σx_j, Σ dt·x_j)` of fitted coordinate `j` (0..3 the accumulated rotation, 3..6 the
    /// position), about the first frame's.
    #[inline(always)]
    pub fn x_sums(&self, j: usize) -> (f64, f64) {
        (
            self.sums[SUM_X + j / 4].0[j % 4],
            self.sums[SUM_TX + j / 4].0[j % 4],
        )
    }

    /// Σq, sign-aligned.
    #[inline(always)]
    pub fn sum_q(&self) -> Vector4<f64> {
        Vector4::from(self.sums[SUM_Q].0)
    }

    /// Σp \[m\].
    #[inline(always)]
    pub fn sum_p(&self) -> Vector3<f64> {
        let p = self.sums[SUM_P].0;
        Vector3::new(p[0], p[1], p[2])
    }

    /// Add a frame `dt` \[s\] after the first, of accumulated rotation `rot` \[rad\], position
    /// `p` \[m\] and orientation `q` (`(x, y, z, w)`, sign-aligned with the sum).
    #[inline(always)]
    pub fn add(&mut self, dt: f64, rot: &Vector3<f64>, p: &Vector3<f64>, q: &Vector4<f64>) {
        let x = fitted(rot, p);
        if self.n() == 0.0 {
            self.origin = x;
        }
        let (xa, xb) = (x[0] - self.origin[0], x[1] - self.origin[1]);
        let terms = [
            xa,
            xb,
            dt * xa,
            dt * xb,
            F4([q.x, q.y, q.z, q.w]),
            F4([p.x, p.y, p.z, 0.0]),
            F4([1.0, dt, dt * dt, 0.0]),
        ];
        for (s, t) in self.sums.iter_mut().zip(terms) {
            *s = *s + t;
        }
    }
}
