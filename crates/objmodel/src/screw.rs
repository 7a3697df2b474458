//! Screw parameters of a twist (paper eq. 1-4) and the motion-plane normal (eq. 5).
//!
//! For a twist ξ = (v, ω) with ω ≠ 0 (θ = |ω|):
//!
//! ```text
//! axis  l = { r + λ ω/θ : λ ∈ R },   r = ω × v / θ²      (eq. 1, 4)
//! pitch p = ωᵀ v / θ²  \[m/rad\]                              (eq. 2)
//! magnitude m = θ  \[rad\]                                    (eq. 3)
//! ```
//!
//! `r` is the point of the axis closest to the origin of the frame ξ is expressed in. For
//! ω = 0 (a pure translation) the axis is `{λ v/|v|}`, the pitch is infinite and the magnitude
//! is |v| \[m\]. Eq. 5's plane normal is ω/θ for ω ≠ 0 and `v(t) × v(t-1)` normalised otherwise.

use crate::fast::{cross, dot, Real};
use crate::se3::Twist;
use nalgebra::{Unit, Vector3};

/// |ω| \[rad\] at or below which a twist counts as a pure translation (ω = 0 in eq. 1-3).
pub const ZERO_ROTATION_RAD: f64 = 1e-12;

/// A screw: a line (the axis), a pitch and a magnitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Screw {
    /// Unit direction of the axis (ω/θ, or v/|v| for a pure translation).
    pub direction: Unit<Vector3<f64>>,
    /// Point of the axis closest to the origin \[m\]; the origin for a pure translation.
    pub point: Vector3<f64>,
    /// Pitch \[m/rad\]: translation along the axis per radian; `f64::INFINITY` for a translation.
    pub pitch: f64,
    /// Magnitude: rotation angle θ \[rad\], or the translation |v| \[m\] for a pure translation.
    pub magnitude: f64,
}

impl Screw {
    /// The screw of a twist (eq. 1-3). `None` for the zero twist, which has no axis.
    #[inline]
    pub fn from_twist(xi: &Twist) -> Option<Self> {
        let m = moments(&xi.omega.into(), &xi.v.into());
        let theta = m.theta2.sqrt();
        if theta > ZERO_ROTATION_RAD {
            // One division; the rest are products with 1/θ and 1/θ².
            let inv = 1.0 / theta;
            let inv2 = inv * inv;
            Some(Self {
                direction: Unit::new_unchecked(xi.omega * inv),
                point: Vector3::from(m.moment) * inv2,
                pitch: m.omega_v * inv2,
                magnitude: theta,
            })
        } else {
            let n = xi.v.norm();
            (n > 0.0).then(|| Self {
                direction: Unit::new_unchecked(xi.v / n),
                point: Vector3::zeros(),
                pitch: f64::INFINITY,
                magnitude: n,
            })
        }
    }

    /// True for a pure rotation or screw (ω ≠ 0), false for a pure translation.
    pub fn is_rotation(&self) -> bool {
        self.pitch.is_finite()
    }
}

/// A twist's screw before its division by θ²: `θ² = |ω|²`, the moment `ω × v = θ² r` (r the
/// axis point, eq. 1, 4) and `ωᵀv = θ² p` (p the pitch, eq. 2), for `ω` and `v` by coordinate.
/// Generic over the number type, so that [`Screw::from_twist`] and the kernels that take four
/// frames at a time (in `crate::fast`) compute them alike, rounded as nalgebra's `dot` and
/// `cross`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Moments<T> {
    /// θ² = |ω|² \[rad²\].
    pub theta2: T,
    /// ω × v \[m rad²\].
    pub moment: [T; 3],
    /// ωᵀ v \[m rad²\].
    pub omega_v: T,
}

/// The [`Moments`] of the twist `(v, ω)`.
#[inline(always)]
pub(crate) fn moments<T: Real>(omega: &[T; 3], v: &[T; 3]) -> Moments<T> {
    Moments {
        theta2: dot(omega, omega),
        moment: cross(omega, v),
        omega_v: dot(omega, v),
    }
}

/// Eq. 5: the normal of the plane of motion. `omega/|omega|` for a rotation; for a pure
/// translation, the normal of the plane spanned by this frame's and the previous frame's linear
/// velocities, `None` if they are parallel (or there is no previous frame).
pub fn plane_normal(xi: &Twist, previous: Option<&Twist>) -> Option<Unit<Vector3<f64>>> {
    let theta = xi.omega.norm();
    if theta > ZERO_ROTATION_RAD {
        return Some(Unit::new_unchecked(xi.omega / theta));
    }
    let c = xi.v.cross(&previous?.v);
    Unit::try_new(c, 1e-300)
}

/// The unsigned angle \[rad\] between two lines' directions, in [0, π/2].
pub fn line_angle(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let c = a.cross(b).norm();
    let d = a.dot(b).abs();
    c.atan2(d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::se3::so3_exp;
    use nalgebra::{Isometry3, Translation3};
    use proptest::prelude::*;

    proptest! {
        /// Rotating about any line must give that line back: direction (up to the sign of the
        /// angle), the closest point, zero pitch and the angle.
        #[test]
        fn rotation_about_a_line_gives_the_line(
            d in prop::array::uniform3(-1.0f64..1.0),
            q in prop::array::uniform3(-0.5f64..0.5),
            theta in 1e-3f64..3.1,
        ) {
            let u = Vector3::from(d);
            prop_assume!(u.norm() > 0.1);
            let u = u.normalize();
            let q = Vector3::from(q);
            let r = so3_exp(&(u * theta));
            let g = Isometry3::from_parts(Translation3::from(q - r * q), r);
            let s = Screw::from_twist(&Twist::log(&g)).unwrap();
            let closest = q - u * u.dot(&q);
            prop_assert!((s.direction.into_inner() - u).norm() < 1e-9);
            prop_assert!((s.point - closest).norm() < 1e-9);
            prop_assert!(s.pitch.abs() < 1e-9);
            prop_assert!((s.magnitude - theta).abs() < 1e-9);
        }

        /// A helix (rotation plus translation along the axis) has pitch = advance / angle.
        #[test]
        fn helix_pitch(theta in 0.01f64..3.0, advance in -0.2f64..0.2) {
            let u = Vector3::z();
            let q = Vector3::new(0.1, -0.2, 0.0);
            let r = so3_exp(&(u * theta));
            let g = Isometry3::from_parts(Translation3::from(q - r * q + u * advance), r);
            let s = Screw::from_twist(&Twist::log(&g)).unwrap();
            prop_assert!((s.pitch - advance / theta).abs() < 1e-9);
        }
    }

    #[test]
    fn translation_has_infinite_pitch_and_plane_from_two_frames() {
        let a = Twist::new(Vector3::new(0.1, 0.0, 0.0), Vector3::zeros());
        let b = Twist::new(Vector3::new(0.1, 0.05, 0.0), Vector3::zeros());
        let s = Screw::from_twist(&b).unwrap();
        assert!(s.pitch.is_infinite() && !s.is_rotation());
        let n = plane_normal(&b, Some(&a)).unwrap();
        assert!((n.z.abs() - 1.0).abs() < 1e-12);
        assert!(plane_normal(&a, None).is_none());
        assert!(Screw::from_twist(&Twist::new(Vector3::zeros(), Vector3::zeros())).is_none());
    }
}
