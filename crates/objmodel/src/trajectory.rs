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
