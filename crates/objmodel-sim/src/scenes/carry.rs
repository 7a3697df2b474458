//! A carry: the box grasped, lifted, turned in the air and put down, as in the general-motion
//! scene (paper Fig. 3c) and the carries of a session.
//!
//! The grasp is kinematic: while held the box follows five key poses (where it rests, lifted,
//! over the middle of the way turned, 4 cm above its end, and at its end 1.5 mm above the
//! table) with minimum-jerk timing `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵` on each leg (translation
//! interpolated linearly in `s`, rotation by slerp); then it is released and falls into place.

use super::Run;
use crate::spec::{BoxFace, BoxSpec};
use crate::Result;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector2, Vector3};

/// Minimum-jerk timing `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵` of `τ` clamped to \[0, 1\].
pub fn min_jerk(tau: f64) -> f64 {
    let t = tau.clamp(0.0, 1.0);
    t * t * t * (10.0 - 15.0 * t + 6.0 * t * t)
}

/// Where a carry goes: the box's rotation and place over the middle of the way, and the face
/// it ends on with its yaw and place.
#[derive(Debug, Clone, Copy)]
pub struct CarryPath {
    /// How high the box is lifted first \[m\].
    pub lift: f64,
    /// Over where it is turned, world x-y \[m\] (5 cm higher than the lift).
    pub mid_xy: Vector2<f64>,
    /// Its rotation there, `world_from_box`.
    pub mid_rotation: UnitQuaternion<f64>,
    /// The face it is put down on.
    pub end_face: BoxFace,
    /// Its yaw there \[rad\].
    pub end_yaw: f64,
    /// Where it is put down, world x-y \[m\].
    pub end_xy: Vector2<f64>,
}

impl CarryPath {
    /// The five key poses `world_from_box` from `start`, for `spec`.
    pub fn key_poses(&self, spec: &BoxSpec, start: &Isometry3<f64>) -> [Isometry3<f64>; 5] {
        let (k, _) = self.end_face.axis_sign();
        let end_rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), self.end_yaw)
            * face_down(self.end_face);
        let rest_h = spec.half_extents()[k] + 0.0015;
        let at = |xy: Vector2<f64>, z: f64, r: UnitQuaternion<f64>| {
            Isometry3::from_parts(Translation3::new(xy.x, xy.y, z), r)
        };
        [
            *start,
            Isometry3::from_parts(
                Translation3::from(start.translation.vector + Vector3::z() * self.lift),
                start.rotation,
            ),
            at(self.mid_xy, rest_h + self.lift + 0.05, self.mid_rotation),
            at(self.end_xy, rest_h + 0.04, end_rotation),
            at(self.end_xy, rest_h, end_rotation),
        ]
    }
}

/// The rotation that turns `face` of the box down (its outward normal onto `-z`).
pub fn face_down(face: BoxFace) -> UnitQuaternion<f64> {
    UnitQuaternion::rotation_between(&face.normal(), &-Vector3::z()).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    })
}

/// Grasp the box, move it through `keys` (leg `i` in `durations[i]` seconds) and release it.
/// Returns the times of the grasp and the release \[s\].
pub fn carry(
    run: &mut Run,
    keys: &[Isometry3<f64>; 5],
    durations: &[f64; 4],
) -> Result<(f64, f64)> {
    let boxb = run.boxb;
    run.world.set_grasped(boxb, true);
    let grasp = run.world.t;
    for (leg, dur) in keys.windows(2).zip(durations) {
        let (a, b) = (leg[0], leg[1]);
        let t0 = run.world.t;
        while run.world.t < t0 + dur - 0.5 * run.world.dt {
            let s = min_jerk((run.world.t + run.world.dt - t0) / dur);
            let tr = a.translation.vector.lerp(&b.translation.vector, s);
            let rot = a.rotation.slerp(&b.rotation, s);
            run.world
                .set_kinematic(boxb, &Isometry3::from_parts(Translation3::from(tr), rot));
            run.step()?;
        }
    }
    run.world.set_grasped(boxb, false);
    Ok((grasp, run.world.t))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_jerk_starts_and_ends_at_rest_and_is_symmetric() {
        assert_eq!(min_jerk(-1.0), 0.0);
        assert_eq!(min_jerk(2.0), 1.0);
        assert!((min_jerk(0.5) - 0.5).abs() < 1e-15);
        for i in 1..100 {
            let t = i as f64 / 100.0;
            assert!((min_jerk(t) + min_jerk(1.0 - t) - 1.0).abs() < 1e-12);
            // s'(τ) = 30 τ² (1 − τ)² ≥ 0, zero at both ends.
            let h = 1e-6;
            let slope = (min_jerk(t + h) - min_jerk(t - h)) / (2.0 * h);
            assert!((slope - 30.0 * t * t * (1.0 - t) * (1.0 - t)).abs() < 1e-6);
        }
    }

    #[test]
    fn the_last_key_rests_the_end_face_down_just_above_the_table() {
        let spec = BoxSpec::new("brick", [0.2, 0.1, 0.06], 0.6);
        for face in BoxFace::ALL {
            let path = CarryPath {
                lift: 0.1,
                mid_xy: Vector2::new(0.05, 0.0),
                mid_rotation: UnitQuaternion::identity(),
                end_face: face,
                end_yaw: 0.7,
                end_xy: Vector2::new(0.1, -0.2),
            };
            let keys = path.key_poses(&spec, &Isometry3::identity());
            let end = keys[4];
            let down = end.rotation * face.normal();
            assert!((down + Vector3::z()).norm() < 1e-12, "{face:?}: {down}");
            let (k, _) = face.axis_sign();
            assert!((end.translation.z - spec.half_extents()[k] - 0.0015).abs() < 1e-15);
            assert!((keys[3].translation.z - end.translation.z - 0.04).abs() < 1e-12);
        }
    }
}
