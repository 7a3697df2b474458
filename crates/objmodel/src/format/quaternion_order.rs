//! The order of a quaternion's components in pose files whose columns are not named. A TUM
//! file's is `qx qy qz qw` by the format, but tools that write `qw qx qy qz` (MuJoCo,
//! transforms3d, pyquaternion, Drake) fill TUM-shaped files that way too, and read as x y z w
//! such a file is a different rotation, with nothing in the file to tell: its rests then teach
//! faces that are not on the object, with confidence. The user says so
//! ([`crate::classify::Config::quaternion_order`], `--quat-order wxyz`). A CSV header names its
//! columns (`qw`, `qx`, ...), and the names decide.

use nalgebra::{Quaternion, UnitQuaternion};
use serde::{Deserialize, Serialize};

/// The order of a quaternion's four components on a line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum QuaternionOrder {
    /// `qx qy qz qw`: TUM's, ROS's, scipy's `as_quat()`, Eigen's `coeffs()`.
    #[default]
    #[serde(rename = "xyzw")]
    Xyzw,
    /// `qw qx qy qz`: MuJoCo's, transforms3d's, pyquaternion's, Drake's.
    #[serde(rename = "wxyz")]
    Wxyz,
}

impl QuaternionOrder {
    /// The rotation whose components, written in this order, were read as `q` in x y z w
    /// order: exact (the same four numbers, moved).
    pub fn reorder(self, q: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
        match self {
            QuaternionOrder::Xyzw => *q,
            QuaternionOrder::Wxyz => {
                let c = q.coords; // [i, j, k, w] as read: the file's first four
                UnitQuaternion::new_unchecked(Quaternion::new(c[0], c[1], c[2], c[3]))
            }
        }
    }

    /// The order in words for people: `x y z w` or `w x y z`.
    pub fn spelled(self) -> &'static str {
        match self {
            QuaternionOrder::Xyzw => "x y z w",
            QuaternionOrder::Wxyz => "w x y z",
        }
    }

    /// The order other than this one.
    pub fn other(self) -> Self {
        match self {
            QuaternionOrder::Xyzw => QuaternionOrder::Wxyz,
            QuaternionOrder::Wxyz => QuaternionOrder::Xyzw,
        }
    }

    /// The rotation `q`, read in this order, as it reads in the other: the same four numbers
    /// of the file, moved (exact; its own inverse).
    pub fn read_in_other(self, q: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
        match self {
            QuaternionOrder::Xyzw => QuaternionOrder::Wxyz.reorder(q),
            QuaternionOrder::Wxyz => {
                // Read w x y z: w, i, j, k are the file's first four; read x y z w, i, j, k
                // and w are.
                UnitQuaternion::new_unchecked(Quaternion::new(q.k, q.w, q.i, q.j))
            }
        }
    }
}

impl std::str::FromStr for QuaternionOrder {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "xyzw" => Ok(QuaternionOrder::Xyzw),
            "wxyz" => Ok(QuaternionOrder::Wxyz),
            _ => Err(format!(
                "unknown quaternion order {s:?}; expected xyzw (TUM, ROS, scipy) or wxyz \
                 (MuJoCo, transforms3d, pyquaternion)"
            )),
        }
    }
}

impl std::fmt::Display for QuaternionOrder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            QuaternionOrder::Xyzw => "xyzw",
            QuaternionOrder::Wxyz => "wxyz",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn w_first_components_read_as_x_first_are_moved_back() {
        let truth = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -1.1, 0.7));
        let c = truth.coords; // i j k w
                              // Written w x y z, read as x y z w: the reader's quaternion has i = w, j = x, ...
        let read = UnitQuaternion::new_unchecked(Quaternion::new(c[2], c[3], c[0], c[1]));
        assert!(read.angle_to(&truth) > 0.1);
        let back = QuaternionOrder::Wxyz.reorder(&read);
        assert_eq!(back.coords, truth.coords);
        assert_eq!(QuaternionOrder::Xyzw.reorder(&read), read);
        for o in [QuaternionOrder::Xyzw, QuaternionOrder::Wxyz] {
            assert_eq!(o.to_string().parse::<QuaternionOrder>(), Ok(o));
        }
        assert!("zyxw".parse::<QuaternionOrder>().is_err());
        for o in [QuaternionOrder::Xyzw, QuaternionOrder::Wxyz] {
            assert_ne!(o.other(), o);
            assert_eq!(o.other().other(), o);
            assert_eq!(o.spelled().replace(' ', ""), o.to_string());
            // Read in one order and then in the other, the file's numbers are read back.
            assert_eq!(o.other().read_in_other(&o.read_in_other(&read)), read);
        }
        assert_eq!(
            QuaternionOrder::Xyzw.read_in_other(&read).coords,
            truth.coords
        );
        assert_eq!(
            QuaternionOrder::Wxyz.read_in_other(&truth).coords,
            read.coords
        );
    }
}
