//! The SE(3) logarithm of four rigid motions and their screws, lane by lane: each lane has the
//! bits of the scalar original ([`Twist::log_quat`], [`Screw::from_twist`]), and four frames
//! share each division and square root of the logarithm's long dependent chain; and the buffer
//! of four motions the paper's method fills ([`FourMotions`]).

use super::lanes::{cross, dot, lane, scale, F4, M4, V4};
use crate::screw::{moments, Screw, ZERO_ROTATION_RAD};
use crate::se3::{coef_vinv_series, Twist, SERIES_THRESHOLD_RAD};
use nalgebra::{Unit, UnitQuaternion, Vector3};

/// [`crate::se3::so3_log_parts`] of four quaternions `(w, v)`, lane by lane, each rounded as the scalar one
/// (the series and the arctangent are both taken only when the lanes need both).
#[inline(always)]
fn so3_log_parts4(qw: F4, qv: &V4) -> (V4, F4, F4) {
    let neg = qw.lt(F4::splat(0.0));
    let w = neg.select(-qw, qw);
    let v: V4 = [
        neg.select(-qv[0], qv[0]),
        neg.select(-qv[1], qv[1]),
        neg.select(-qv[2], qv[2]),
    ];
    let s2 = dot(&v, &v);
    let series = s2.lt((w * w) * 1e-4);
    let k = if series.all() {
        so3_log_k_series(s2, w)
    } else if !series.any() {
        so3_log_k_atan(s2, w)
    } else {
        series.select(so3_log_k_series(s2, w), so3_log_k_atan(s2, w))
    };
    (scale(&v, k), k, w)
}

/// `θ/|q_v|` of [`crate::se3::so3_log_parts`] by its series (`|q_v|² = s2`, scalar part `w`).
#[inline(always)]
fn so3_log_k_series(s2: F4, w: F4) -> F4 {
    let inv_w = 1.0 / w;
    let x2 = s2 * inv_w * inv_w;
    2.0 * inv_w * (1.0 - x2 * (1.0 / 3.0 - x2 * (1.0 / 5.0 - x2 / 7.0)))
}

/// `θ/|q_v|` of [`crate::se3::so3_log_parts`] by the arctangent.
#[inline(always)]
fn so3_log_k_atan(s2: F4, w: F4) -> F4 {
    let s = s2.sqrt();
    2.0 * super::atan::atan2_nonneg4(s, w) / s
}

/// Four twists, lane by lane (see [`super::lanes`]): lane `k` of each coordinate is the `k`-th
/// twist.
#[derive(Clone, Copy, Debug)]
pub struct Twist4 {
    /// Linear parts v \[m\].
    pub v: V4,
    /// Angular parts ω \[rad\].
    pub omega: V4,
}

impl Twist4 {
    /// [`Twist::log_quat`] of four rigid motions: quaternions by their scalar parts `qw` and
    /// vector parts `qv`, translations `t`. Each lane has the bits of the scalar logarithm.
    #[inline(always)]
    pub fn log_quat(qw: F4, qv: &V4, t: &V4) -> Self {
        let (omega, k, w) = so3_log_parts4(qw, qv);
        let theta2 = dot(&omega, &omega);
        let small = theta2.lt(F4::splat(SERIES_THRESHOLD_RAD * SERIES_THRESHOLD_RAD));
        let c = if small.all() {
            coef_vinv_series(theta2)
        } else if !small.any() {
            (1.0 - 0.5 * k * w) / theta2
        } else {
            small.select(coef_vinv_series(theta2), (1.0 - 0.5 * k * w) / theta2)
        };
        let wxt = cross(&omega, t);
        let wwxt = cross(&omega, &wxt);
        let v = [
            t[0] - 0.5 * wxt[0] + c * wwxt[0],
            t[1] - 0.5 * wxt[1] + c * wwxt[1],
            t[2] - 0.5 * wxt[2] + c * wwxt[2],
        ];
        Self { v, omega }
    }

    /// Lane `k` as a [`Twist`].
    #[inline(always)]
    pub fn lane(&self, k: usize) -> Twist {
        Twist {
            v: lane(&self.v, k),
            omega: lane(&self.omega, k),
        }
    }

    /// [`Screw::from_twist`] of the four twists: lane `k` is the screw of twist `k`, with its
    /// bits; `None` in the lanes whose rotation is at or below [`ZERO_ROTATION_RAD`] (a
    /// translation or nothing: take [`Screw::from_twist`] of that twist).
    #[inline(always)]
    pub fn screws(&self) -> [Option<Screw>; 4] {
        let m = moments(&self.omega, &self.v);
        let theta = m.theta2.sqrt();
        let inv = 1.0 / theta;
        let inv2 = inv * inv;
        let direction = scale(&self.omega, inv);
        let point = scale(&m.moment, inv2);
        let pitch = m.omega_v * inv2;
        let screw = |k: usize| {
            (theta.0[k] > ZERO_ROTATION_RAD).then(|| Screw {
                direction: Unit::new_unchecked(lane(&direction, k)),
                point: lane(&point, k),
                pitch: pitch.0[k],
                magnitude: theta.0[k],
            })
        };
        [screw(0), screw(1), screw(2), screw(3)]
    }
}

/// Up to four frames' motions waiting for their logarithms (the paper's `g(0)⁻¹ g(t)`, see
/// `crate::classify`'s paper method), which are taken
/// together in four lanes ([`Twist4::log_quat`], in AVX2 code when the processor has it): each
/// logarithm is a long chain of square roots and divisions, and four share each instruction.
/// Every lane has the bits of the frame-by-frame logarithm.
#[derive(Default)]
pub struct FourMotions {
    n: usize,
    /// Frame index and time \[s\].
    index: [usize; 4],
    t: [f64; 4],
    /// The motion's rotation `(w, x, y, z)` and translation \[m\], by coordinate.
    qw: F4,
    qv: V4,
    tr: V4,
}

impl FourMotions {
    /// Add frame `index` at time `t` \[s\], its motion's rotation `q` and translation `tr`
    /// \[m\]; true when there are four.
    #[inline(always)]
    pub fn push(
        &mut self,
        index: usize,
        t: f64,
        q: &UnitQuaternion<f64>,
        tr: &Vector3<f64>,
    ) -> bool {
        let k = self.n;
        (self.index[k], self.t[k]) = (index, t);
        self.qw.0[k] = q.w;
        for i in 0..3 {
            self.qv[i].0[k] = q.imag()[i];
            self.tr[i].0[k] = tr[i];
        }
        self.n += 1;
        self.n == 4
    }

    /// Whether no frame waits.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Each waiting frame's index, time, twist and screw (`None` for the zero twist), in
    /// order: the logarithms and the screws of rotations taken four at a time.
    #[inline(always)]
    pub fn twists_and_screws(self, mut each: impl FnMut(usize, f64, Twist, Option<Screw>)) {
        // Identities after the last frame.
        let valid = M4([self.n > 0, self.n > 1, self.n > 2, self.n > 3]);
        let qw = valid.select(self.qw, F4::splat(1.0));
        let xi = Twist4::log_quat(qw, &self.qv, &self.tr);
        let screws = xi.screws();
        for (k, screw) in screws.into_iter().enumerate().take(self.n) {
            let x = xi.lane(k);
            let screw = screw.or_else(|| Screw::from_twist(&x));
            each(self.index[k], self.t[k], x, screw);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_lane_log_has_the_scalar_bits() {
        // Angles from 1e-12 to π - 1e-7, across both series thresholds, both quaternion
        // signs, lanes of mixed cases.
        let mut state =
            <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x5851_f42d_4c95_7f2d);
        let mut r = || rand::Rng::random::<f64>(&mut state);
        let angles = [
            0.0, 1e-12, 1e-6, 0.0199, 0.02, 0.0201, 0.0999, 0.1, 0.1001, 1.0, 3.0,
        ];
        let mut motions = Vec::new();
        for i in 0..4000 {
            let axis = Vector3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize();
            let angle = match i % 3 {
                0 => angles[i / 3 % angles.len()],
                1 => r() * std::f64::consts::PI,
                _ => std::f64::consts::PI - 1e-7 * r(),
            };
            let mut q = UnitQuaternion::from_scaled_axis(axis * angle);
            if r() < 0.5 {
                q = UnitQuaternion::new_unchecked(-q.into_inner());
            }
            motions.push((q, Vector3::new(r() - 0.5, r() - 0.5, r() - 0.5)));
        }
        for c in motions.chunks(4) {
            let qw = F4::from_fn(|k| c[k].0.w);
            let qv: V4 = std::array::from_fn(|i| F4::from_fn(|k| c[k].0.imag()[i]));
            let t: V4 = std::array::from_fn(|i| F4::from_fn(|k| c[k].1[i]));
            let four = Twist4::log_quat(qw, &qv, &t);
            for (k, (q, t)) in c.iter().enumerate() {
                let one = Twist::log_quat(q, t);
                let lane = four.lane(k);
                for i in 0..3 {
                    assert_eq!(lane.omega[i].to_bits(), one.omega[i].to_bits(), "{q:?}");
                    assert_eq!(lane.v[i].to_bits(), one.v[i].to_bits(), "{q:?}");
                }
            }
        }
    }

    #[test]
    fn four_lane_screws_have_the_scalar_bits() {
        let mut state =
            <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(0x1234_5678_9abc_def1);
        let mut r = || rand::Rng::random::<f64>(&mut state) - 0.5;
        for _ in 0..500 {
            // Rotations of all sizes, down to none (a pure translation) and the zero twist.
            let twists: [Twist; 4] = std::array::from_fn(|k| {
                let scale = [1.0, 1e-6, 1e-13, 0.0][k];
                Twist::new(
                    Vector3::new(r(), r(), r()) * if k == 3 { 0.0 } else { 1.0 },
                    Vector3::new(r(), r(), r()) * scale,
                )
            });
            let v4 = |f: &dyn Fn(&Twist) -> Vector3<f64>| -> V4 {
                std::array::from_fn(|i| F4::from_fn(|k| f(&twists[k])[i]))
            };
            let four = Twist4 {
                v: v4(&|x| x.v),
                omega: v4(&|x| x.omega),
            };
            let screws = four.screws();
            for (k, x) in twists.iter().enumerate() {
                let one = Screw::from_twist(x);
                match screws[k] {
                    Some(s) => assert_eq!(Some(s), one),
                    None => assert!(x.omega.norm() <= ZERO_ROTATION_RAD),
                }
            }
        }
    }
}
