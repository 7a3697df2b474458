//! The one boundary between rapier's maths types (glam's `DVec3`, `DQuat`, `DPose3`, re-exported
//! as `rapier3d_f64::math::{Vector, Rotation, Pose}`) and nalgebra's, which the rest of the
//! project speaks. Nothing else in this crate converts.
//!
//! Both libraries store a unit quaternion `q = w + xi + yj + zk` and a translation `t`, and apply
//! a pose as `p ↦ q p q* + t`, so the conversions copy components and lose nothing.

use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rapier3d_f64::math::{Pose, Rotation, Vector};

/// nalgebra vector from a rapier (glam) vector.
pub fn vec_to_na(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

/// nalgebra point from a rapier (glam) vector.
pub fn point_to_na(v: Vector) -> Point3<f64> {
    Point3::new(v.x, v.y, v.z)
}

/// rapier (glam) vector from a nalgebra vector.
pub fn vec_from_na(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// nalgebra unit quaternion from a rapier (glam) rotation.
pub fn rot_to_na(q: Rotation) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(q.w, q.x, q.y, q.z))
}

/// rapier (glam) rotation from a nalgebra unit quaternion.
pub fn rot_from_na(q: &UnitQuaternion<f64>) -> Rotation {
    let q = q.quaternion();
    Rotation::from_xyzw(q.i, q.j, q.k, q.w).normalize()
}

/// nalgebra isometry from a rapier pose.
pub fn pose_to_na(p: &Pose) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(vec_to_na(p.translation)),
        rot_to_na(p.rotation),
    )
}

/// rapier pose from a nalgebra isometry.
pub fn pose_from_na(p: &Isometry3<f64>) -> Pose {
    Pose::from_parts(vec_from_na(&p.translation.vector), rot_from_na(&p.rotation))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_is_exact_and_acts_alike() {
        let iso = Isometry3::new(Vector3::new(0.1, -0.2, 0.3), Vector3::new(0.4, -0.5, 0.6));
        let pose = pose_from_na(&iso);
        let back = pose_to_na(&pose);
        assert!((back.to_homogeneous() - iso.to_homogeneous()).norm() < 1e-14);
        let p = Vector3::new(0.7, 0.8, -0.9);
        let a = iso * Point3::from(p);
        let b = pose.transform_point(vec_from_na(&p));
        assert!((a.coords - vec_to_na(b)).norm() < 1e-14);
    }
}
