//! Time-stamped poses and demonstrations.

use nalgebra::Isometry3;

/// One tracked pose: `pose` is `world_from_object` (or `world_from_palm`) at time `t` \[s\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StampedPose {
    /// Timestamp \[s\]. Strictly increasing within a trajectory.
    pub t: f64,
    /// The tracked frame's pose in the tracker's frame (`world_from_object`).
    pub pose: Isometry3<f64>,
}

impl StampedPose {
    /// A stamped pose.
    pub fn new(t: f64, pose: Isometry3<f64>) -> Self {
        Self { t, pose }
    }
}

/// A demonstration: the object's trajectory and, for an *instrumented* demonstration, the
/// trajectory of the palm (tool plate) it rides on.
#[derive(Clone, Debug, Default)]
pub struct Demonstration {
    /// A name for reports, usually the file name.
    pub name: String,
    /// `world_from_object` over time.
    pub object: Vec<StampedPose>,
    /// `world_from_palm` over time, for an instrumented demonstration.
    pub palm: Option<Vec<StampedPose>>,
}

impl Demonstration {
    /// The same demonstration tracked in another frame: every pose of the object and of the
    /// palm as `new_from_world · world_from_object` (a tracker whose axes differ from this
    /// one's, e.g. one with y up for one with z up).
    pub fn in_frame(&self, new_from_world: &Isometry3<f64>) -> Demonstration {
        let moved = |poses: &[StampedPose]| -> Vec<StampedPose> {
            poses
                .iter()
                .map(|p| StampedPose::new(p.t, new_from_world * p.pose))
                .collect()
        };
        Demonstration {
            name: self.name.clone(),
            object: moved(&self.object),
            palm: self.palm.as_deref().map(moved),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion, Vector3};

    #[test]
    fn a_demonstration_in_another_frame_and_back_is_itself() {
        let pose = |k: f64| {
            Isometry3::from_parts(
                Translation3::new(0.1 * k, -0.2, 0.05 * k),
                UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.1 * k, 0.7)),
            )
        };
        let d = Demonstration {
            name: "d".into(),
            object: (0..5)
                .map(|k| StampedPose::new(k as f64, pose(k as f64)))
                .collect(),
            palm: Some(
                (0..5)
                    .map(|k| StampedPose::new(k as f64, pose(-(k as f64))))
                    .collect(),
            ),
        };
        let a = pose(2.5);
        let there = d.in_frame(&a);
        // new_from_world · world_from_object, for the object and the palm.
        assert!(
            ((there.object[3].pose.translation.vector) - (a * d.object[3].pose).translation.vector)
                .norm()
                < 1e-15
        );
        assert_eq!(there.palm.as_ref().map(Vec::len), Some(5));
        let back = there.in_frame(&a.inverse());
        for (x, y) in back
            .object
            .iter()
            .chain(back.palm.iter().flatten())
            .zip(d.object.iter().chain(d.palm.iter().flatten()))
        {
            assert_eq!(x.t, y.t);
            assert!((x.pose.translation.vector - y.pose.translation.vector).norm() < 1e-12);
            assert!(x.pose.rotation.angle_to(&y.pose.rotation) < 1e-12);
        }
    }
}
