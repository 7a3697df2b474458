//! The Lie groups SO(3) and SE(3): exact exponential and logarithm, and twists.
//!
//! A twist ξ = (v, ω) ∈ se(3) ≅ R⁶ generates the rigid motion `exp(ξ)`; for a rotation vector
//! ω with θ = |ω| and Ω = \[ω\]ₓ:
//!
//! ```text
//! exp(ξ) = (R, t),  R = I + sinθ/θ Ω + (1 - cosθ)/θ² Ω²,   t = V v,
//! V  = I + B(θ) Ω + C(θ) Ω²,            B = (1 - cosθ)/θ² = 2 sin²(θ/2)/θ²,  C = (θ - sinθ)/θ³,
//! V⁻¹ = I - ½ Ω + c(θ) Ω²,              c = (1 - (θ/2) cot(θ/2)) / θ².
//! ```
//!
//! Numerics. Rotations are handled as unit quaternions. The logarithm takes the quaternion with
//! w ≥ 0 (q and -q are one rotation), so θ ∈ [0, π] and θ = 2·atan2(|q_v|, w), which is accurate
//! both near 0 and near π (no `acos`). `C` and `c` lose digits to cancellation for small θ, so
//! below [`SERIES_THRESHOLD_RAD`] they are evaluated from their Taylor series, truncated where the
//! next term is below 1e-17 relative. At exactly θ = π the rotation axis sign is arbitrary
//! (both logs are valid); this module returns the one with the quaternion's vector part.

use crate::fast::Real;
use nalgebra::{Isometry3, Matrix3, Quaternion, Translation3, UnitQuaternion, Vector3, Vector6};

/// Rotation angle \[rad\] below which the coefficients `C(θ)` and `c(θ)` come from their Taylor
/// series instead of the closed forms (which cancel catastrophically near 0). At 0.1 rad the
/// series, truncated after the θ⁸ (resp. θ⁶) term, is exact to 2e-16 relative.
pub const SERIES_THRESHOLD_RAD: f64 = 0.1;

/// `[w]ₓ`, the cross-product matrix: `hat(w) * x = w × x`.
pub fn hat(w: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0)
}

/// `B(θ) = (1 - cos θ)/θ²`, from `2 sin²(θ/2)/θ²` (no cancellation); `1/2` at 0.
fn coef_b(theta: f64) -> f64 {
    if theta < 1e-4 {
        0.5 - theta * theta / 24.0
    } else {
        let s = (0.5 * theta).sin();
        2.0 * s * s / (theta * theta)
    }
}

/// `C(θ) = (θ - sin θ)/θ³`.
fn coef_c(theta: f64) -> f64 {
    if theta < SERIES_THRESHOLD_RAD {
        let t2 = theta * theta;
        1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0 * (1.0 - t2 / 110.0)))
    } else {
        (theta - theta.sin()) / (theta * theta * theta)
    }
}

/// `c(θ) = (1 - (θ/2) cot(θ/2))/θ²`, the Ω² coefficient of `V⁻¹`.
fn coef_vinv(theta: f64) -> f64 {
    if theta < SERIES_THRESHOLD_RAD {
        coef_vinv_series(theta * theta)
    } else {
        let h = 0.5 * theta;
        (1.0 - h * h.cos() / h.sin()) / (theta * theta)
    }
}

/// The Taylor series of `c(θ)` in `θ²` (see [`coef_vinv`]), exact to 2e-16 below
/// [`SERIES_THRESHOLD_RAD`].
#[inline(always)]
pub(crate) fn coef_vinv_series<T: Real>(t2: T) -> T {
    t2 / 720.0 + 1.0 / 12.0 + t2 * t2 / 30240.0 + t2 * t2 * t2 / 1_209_600.0
}

/// Exponential of SO(3): the rotation by `|omega|` \[rad\] about `omega`.
pub fn so3_exp(omega: &Vector3<f64>) -> UnitQuaternion<f64> {
    let theta = omega.norm();
    let h = 0.5 * theta;
    // sin(θ/2)/θ, with its series below 1e-4 rad (error < 1e-18).
    let k = if theta < 1e-4 {
        0.5 - theta * theta / 48.0
    } else {
        h.sin() / theta
    };
    UnitQuaternion::new_unchecked(Quaternion::new(
        h.cos(),
        k * omega.x,
        k * omega.y,
        k * omega.z,
    ))
}

/// Logarithm of SO(3): the rotation vector ω (axis · angle, angle in [0, π]) of `q`.
///
/// Works for either sign of the quaternion (q and -q give the same ω, except at exactly π
/// where the axis sign is arbitrary).
#[inline]
pub fn so3_log(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    so3_log_parts(q).0
}

/// [`so3_log`] with the parts the SE(3) logarithm reuses: `(ω, θ/|q_v|, |w|)` for the
/// quaternion taken with `w ≥ 0` (`θ/|q_v|` is `2` at the identity).
#[inline(always)]
pub(crate) fn so3_log_parts(q: &UnitQuaternion<f64>) -> (Vector3<f64>, f64, f64) {
    let q = q.quaternion();
    let (w, v) = if q.w < 0.0 {
        (-q.w, -q.imag())
    } else {
        (q.w, q.imag())
    };
    let s2 = v.norm_squared();
    // θ/s = 2·atan2(s, w)/s = (2/w)·atan(x)/x with x = s/w. For x < 1e-2 (rotations below
    // 1.15°, the common case between consecutive frames) the series
    // atan(x)/x = 1 - x²/3 + x⁴/5 - x⁶/7 is exact to 1.2e-17 and spares the arctangent.
    let k = if s2 < 1e-4 * (w * w) {
        let inv_w = 1.0 / w; // One division; w > 0.99995 here.
        let x2 = s2 * inv_w * inv_w;
        2.0 * inv_w * (1.0 - x2 * (1.0 / 3.0 - x2 * (1.0 / 5.0 - x2 / 7.0)))
    } else {
        let s = s2.sqrt();
        2.0 * crate::fast::atan::atan2_nonneg(s, w) / s
    };
    (v * k, k, w)
}

/// A twist ξ = (v, ω) ∈ se(3): `omega` \[rad\] is the rotation vector, `v` \[m\] the linear part.
/// `exp(ξ)` is the rigid motion obtained by following ξ for unit time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Twist {
    /// Linear part v \[m\].
    pub v: Vector3<f64>,
    /// Angular part ω \[rad\].
    pub omega: Vector3<f64>,
}

impl Twist {
    /// A twist from its linear and angular parts.
    pub fn new(v: Vector3<f64>, omega: Vector3<f64>) -> Self {
        Self { v, omega }
    }

    /// The twist as a 6-vector `(v, ω)`.
    pub fn to_vector(&self) -> Vector6<f64> {
        Vector6::new(
            self.v.x,
            self.v.y,
            self.v.z,
            self.omega.x,
            self.omega.y,
            self.omega.z,
        )
    }

    /// Logarithm of SE(3): the twist ξ with `exp(ξ) = g`, with rotation angle in [0, π].
    pub fn log(g: &Isometry3<f64>) -> Self {
        let omega = so3_log(&g.rotation);
        Self::log_with_omega(omega, &g.translation.vector)
    }

    /// Logarithm of the rigid motion `(q, t)`, computed from the quaternion's parts: with
    /// `q = (cos(θ/2), sin(θ/2) u)`, `(θ/2) cot(θ/2) = (θ/2) w / |v|` needs no trigonometry
    /// beyond the one `atan2` of the angle (and none below 1.15°, see [`so3_log`]). The same
    /// result as [`Twist::log`]; the fast path of the classifiers' per-frame loops.
    #[inline]
    pub fn log_quat(q: &UnitQuaternion<f64>, t: &Vector3<f64>) -> Self {
        let (omega, k, w) = so3_log_parts(q);
        let theta2 = omega.norm_squared();
        // c(θ) = (1 - (θ/2) cot(θ/2))/θ² with (θ/2) cot(θ/2) = (θ/2) w/|v| = k w / 2.
        let c = if theta2 < SERIES_THRESHOLD_RAD * SERIES_THRESHOLD_RAD {
            coef_vinv_series(theta2)
        } else {
            (1.0 - 0.5 * k * w) / theta2
        };
        let wxt = omega.cross(t);
        Self {
            v: t - 0.5 * wxt + c * omega.cross(&wxt),
            omega,
        }
    }

    /// Logarithm when the rotation vector ω of g's rotation is already known: `v = V⁻¹(ω) t`.
    #[inline]
    pub fn log_with_omega(omega: Vector3<f64>, t: &Vector3<f64>) -> Self {
        let theta = omega.norm();
        let wxt = omega.cross(t);
        let v = t - 0.5 * wxt + coef_vinv(theta) * omega.cross(&wxt);
        Self { v, omega }
    }

    /// Exponential of SE(3).
    pub fn exp(&self) -> Isometry3<f64> {
        let theta = self.omega.norm();
        let wxv = self.omega.cross(&self.v);
        let t = self.v + coef_b(theta) * wxv + coef_c(theta) * self.omega.cross(&wxv);
        Isometry3::from_parts(Translation3::from(t), so3_exp(&self.omega))
    }

    /// Rotation angle θ = |ω| \[rad\].
    pub fn angle(&self) -> f64 {
        self.omega.norm()
    }
}

/// The geodesic distance between two rotations \[rad\], in [0, π]; q and -q count as equal.
pub fn rotation_angle_between(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> f64 {
    let d = a.quaternion().dot(b.quaternion()).abs().min(1.0);
    // 2·atan2(|a⁻¹b|_v, |w|), accurate for small angles unlike 2·acos(d).
    let rel = a.inverse() * b;
    let s = rel.quaternion().imag().norm();
    2.0 * crate::fast::atan::atan2_nonneg(s, d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn close(a: &Isometry3<f64>, b: &Isometry3<f64>, tol: f64) -> bool {
        (a.translation.vector - b.translation.vector).norm() < tol
            && rotation_angle_between(&a.rotation, &b.rotation) < tol
    }

    #[test]
    fn series_and_closed_forms_agree_at_the_threshold() {
        let t = SERIES_THRESHOLD_RAD;
        let (lo, hi) = (t * (1.0 - 1e-12), t * (1.0 + 1e-12));
        assert!((coef_c(lo) - coef_c(hi)).abs() < 1e-14);
        assert!((coef_vinv(lo) - coef_vinv(hi)).abs() < 1e-13);
    }

    #[test]
    fn edge_case_angles_round_trip() {
        let axis = Vector3::new(0.3, -0.5, 0.8).normalize();
        for &theta in &[
            0.0,
            1e-12,
            1e-8,
            1e-6,
            1e-3,
            0.0999,
            0.1,
            0.1001,
            1.0,
            3.0,
            std::f64::consts::PI - 1e-7,
            std::f64::consts::PI,
        ] {
            let g =
                Isometry3::from_parts(Translation3::new(0.2, -0.1, 0.05), so3_exp(&(axis * theta)));
            let xi = Twist::log(&g);
            assert!(
                (xi.angle() - theta).abs() < 1e-12,
                "theta {theta}: got {}",
                xi.angle()
            );
            assert!(close(&xi.exp(), &g, 1e-12), "theta {theta}");
        }
    }

    #[test]
    fn rotation_about_a_known_line_gives_that_line() {
        // Rotation by 0.7 rad about the line through q with direction u.
        let u = Vector3::new(0.0, 1.0, 0.0);
        let q = Vector3::new(0.05, 0.3, -0.1);
        let r = so3_exp(&(u * 0.7));
        let g = Isometry3::from_parts(Translation3::from(q - r * q), r);
        let xi = Twist::log(&g);
        let expected_v = -(u * 0.7).cross(&q);
        assert!((xi.v - expected_v).norm() < 1e-14);
        assert!((xi.omega - u * 0.7).norm() < 1e-14);
    }

    #[test]
    fn log_is_sign_invariant() {
        let q = so3_exp(&Vector3::new(0.1, 0.2, -0.3));
        let neg = UnitQuaternion::new_unchecked(-q.into_inner());
        assert!((so3_log(&q) - so3_log(&neg)).norm() < 1e-15);
    }

    fn arb_twist() -> impl Strategy<Value = Twist> {
        (
            prop::array::uniform3(-1.0f64..1.0),
            prop::array::uniform3(-1.0f64..1.0),
            0.0f64..std::f64::consts::PI,
        )
            .prop_map(|(v, w, th)| {
                let w = Vector3::from(w);
                let n = w.norm();
                let omega = if n < 1e-9 {
                    Vector3::zeros()
                } else {
                    w / n * th
                };
                Twist::new(Vector3::from(v), omega)
            })
    }

    proptest! {
        #[test]
        fn exp_of_log_is_identity(xi in arb_twist(), scale in prop::sample::select(vec![1.0, 1e-6, 1e-12])) {
            let xi = Twist::new(xi.v, xi.omega * scale);
            let g = xi.exp();
            prop_assert!(close(&Twist::log(&g).exp(), &g, 1e-12));
        }

        #[test]
        fn log_of_exp_is_identity_below_pi(xi in arb_twist()) {
            prop_assume!(xi.angle() < std::f64::consts::PI - 1e-6);
            let back = Twist::log(&xi.exp());
            prop_assert!((back.omega - xi.omega).norm() < 1e-10);
            prop_assert!((back.v - xi.v).norm() < 1e-9);
        }

        #[test]
        fn log_quat_equals_log(xi in arb_twist(), scale in prop::sample::select(vec![1.0, 0.05, 1e-6, 1e-12]), sign in prop::bool::ANY) {
            let xi = Twist::new(xi.v, xi.omega * scale);
            let g = xi.exp();
            let q = if sign { g.rotation } else { UnitQuaternion::new_unchecked(-g.rotation.into_inner()) };
            let fast = Twist::log_quat(&q, &g.translation.vector);
            let reference = Twist::log(&g);
            prop_assert!((fast.omega - reference.omega).norm() < 1e-12);
            prop_assert!((fast.v - reference.v).norm() < 1e-11 * (1.0 + reference.v.norm()));
        }

        #[test]
        fn exp_matches_nalgebra(w in prop::array::uniform3(-2.0f64..2.0)) {
            let w = Vector3::from(w);
            let ours = so3_exp(&w);
            let theirs = UnitQuaternion::from_scaled_axis(w);
            prop_assert!(rotation_angle_between(&ours, &theirs) < 1e-12);
        }

        #[test]
        fn exp_is_a_homomorphism_along_one_twist(xi in arb_twist(), a in 0.0f64..0.5, b in 0.0f64..0.5) {
            let ga = Twist::new(xi.v * a, xi.omega * a).exp();
            let gb = Twist::new(xi.v * b, xi.omega * b).exp();
            let gab = Twist::new(xi.v * (a + b), xi.omega * (a + b)).exp();
            prop_assert!(close(&(ga * gb), &gab, 1e-12));
        }
    }
}
