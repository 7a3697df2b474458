//! Where an object rested: the place of the object frame's origin over a rest, along and
//! across gravity ([`RestPlace`]), and with the σ of its height ([`RestHeight`]). A rest on the
//! support is the face rested on at the support's height ([`crate::support`]): its height
//! above the support is that face's offset.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Where a rest was: the mean position of the object frame's origin over it, in the frame the
/// poses are given in, split along and across gravity.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RestPlace {
    /// Height \[m\] along −gravity (above the origin of the poses' frame).
    pub height: f64,
    /// The position less its component along gravity \[m\].
    pub across: Vector3<f64>,
}

impl RestPlace {
    /// The place of `position` with gravity pointing along the unit `down`.
    pub fn new(position: &Vector3<f64>, down: &Vector3<f64>) -> Self {
        let along = down.dot(position);
        Self {
            height: -along,
            across: position - down * along,
        }
    }

    /// The position this place was made from ([`RestPlace::new`]'s inverse), with the same
    /// unit `down`.
    pub fn position(&self, down: &Vector3<f64>) -> Vector3<f64> {
        self.across - down * self.height
    }
}

/// Where a rest on the support held the object: its place, and the σ \[m\] of its height from
/// the tracking noise.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RestHeight {
    /// The place ([`RestPlace`]).
    pub place: RestPlace,
    /// The σ \[m\] of its height.
    pub sigma_m: f64,
}
