//! The ROS 2 message types that carry a tracked pose, decoded from CDR ([`super::cdr`]):
//!
//! | type | reference frame | child |
//! | --- | --- | --- |
//! | `geometry_msgs/msg/PoseStamped` | `header.frame_id` | the topic |
//! | `geometry_msgs/msg/PoseWithCovarianceStamped` | `header.frame_id` | the topic |
//! | `nav_msgs/msg/Odometry` | `header.frame_id` | `child_frame_id` |
//! | `geometry_msgs/msg/TransformStamped` | `header.frame_id` | `child_frame_id` |
//! | `tf2_msgs/msg/TFMessage` (`/tf`, `/tf_static`) | each transform's `header.frame_id` | its `child_frame_id` |
//!
//! Every pose is stamped with its `header.stamp` (seconds + nanoseconds), not the time the
//! bag received it. A quaternion must be finite with a norm within
//! [`QUAT_NORM_TOLERANCE`] of 1 (it is then normalised). A pose whose every value is NaN, or
//! zero, is a tracker that lost the object and published on: no pose (counted by the reader).

use super::cdr::{CdrError, CdrReader, CdrResult};
use crate::format::QUAT_NORM_TOLERANCE;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

/// A message type that carries poses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PoseType {
    /// `geometry_msgs/msg/PoseStamped`.
    PoseStamped,
    /// `geometry_msgs/msg/PoseWithCovarianceStamped`.
    PoseWithCovarianceStamped,
    /// `nav_msgs/msg/Odometry`.
    Odometry,
    /// `geometry_msgs/msg/TransformStamped`.
    TransformStamped,
    /// `tf2_msgs/msg/TFMessage`: a sequence of `TransformStamped`.
    TfMessage,
}

impl PoseType {
    /// The type named by a schema (`pkg/msg/Type`, or `pkg/Type`); `None` for other types.
    pub fn of_schema(name: &str) -> Option<Self> {
        let short = name.replacen("/msg/", "/", 1);
        Some(match short.as_str() {
            "geometry_msgs/PoseStamped" => Self::PoseStamped,
            "geometry_msgs/PoseWithCovarianceStamped" => Self::PoseWithCovarianceStamped,
            "nav_msgs/Odometry" => Self::Odometry,
            "geometry_msgs/TransformStamped" => Self::TransformStamped,
            "tf2_msgs/TFMessage" => Self::TfMessage,
            _ => return None,
        })
    }

    /// Whether the child of its poses is named by the message (a frame) rather than by the
    /// topic.
    pub fn names_child(self) -> bool {
        matches!(
            self,
            Self::Odometry | Self::TransformStamped | Self::TfMessage
        )
    }
}

/// One decoded pose: `parent_from_child` at `t`, the frame names borrowed from the message.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RawTransform<'a> {
    /// `header.stamp` \[s\].
    pub t: f64,
    /// `header.frame_id`.
    pub parent: &'a [u8],
    /// `child_frame_id`, or empty for a type without one (the topic names the child).
    pub child: &'a [u8],
    /// `parent_from_child`; `None` where every value is NaN or zero: a tracker that lost the
    /// object and published on (`format::is_lost`).
    pub pose: Option<Isometry3<f64>>,
}

/// Decode one message of type `ty`, handing each pose it carries to `out` (a `TFMessage`
/// carries any number).
pub fn decode<'a>(
    ty: PoseType,
    message: &'a [u8],
    out: &mut impl FnMut(RawTransform<'a>),
) -> CdrResult<()> {
    let mut r = CdrReader::new(message)?;
    match ty {
        PoseType::PoseStamped | PoseType::PoseWithCovarianceStamped => {
            let (t, parent) = header(&mut r)?;
            let pose = pose(&mut r)?;
            out(RawTransform {
                t,
                parent,
                child: b"",
                pose,
            });
        }
        PoseType::Odometry | PoseType::TransformStamped => out(transform_stamped(&mut r, ty)?),
        PoseType::TfMessage => {
            // A TransformStamped takes at least 8 + 4 + 4 + 7 * 8 bytes.
            let n = r.sequence_len(72, "TFMessage.transforms")?;
            for _ in 0..n {
                out(transform_stamped(&mut r, PoseType::TransformStamped)?);
            }
        }
    }
    Ok(())
}

/// `std_msgs/Header`: the stamp \[s\] and the frame.
fn header<'a>(r: &mut CdrReader<'a>) -> CdrResult<(f64, &'a [u8])> {
    let sec = r.i32("header.stamp.sec")?;
    let nanosec = r.u32("header.stamp.nanosec")?;
    let frame = r.str_bytes("header.frame_id")?;
    Ok((sec as f64 + nanosec as f64 * 1e-9, frame))
}

/// A `TransformStamped` (a `Transform`: translation, rotation) or an `Odometry` (a
/// `PoseWithCovariance`; its twist after it is not read).
fn transform_stamped<'a>(r: &mut CdrReader<'a>, ty: PoseType) -> CdrResult<RawTransform<'a>> {
    let (t, parent) = header(r)?;
    let child = r.str_bytes("child_frame_id")?;
    let pose = pose(r)?;
    if ty == PoseType::Odometry {
        r.f64s::<36>("pose.covariance")?;
    }
    Ok(RawTransform {
        t,
        parent,
        child,
        pose,
    })
}

/// A `Pose` or a `Transform`: three float64 of position, four of quaternion (x y z w); `None`
/// where every value is NaN or zero (the tracker lost the object: `format::is_lost`).
fn pose(r: &mut CdrReader) -> CdrResult<Option<Isometry3<f64>>> {
    let [x, y, z] = r.f64s::<3>("position")?;
    let [qx, qy, qz, qw] = r.f64s::<4>("orientation")?;
    if crate::format::is_lost(&[0.0, x, y, z, qx, qy, qz, qw]) {
        return Ok(None);
    }
    if ![x, y, z].iter().all(|v| v.is_finite()) {
        return Err(CdrError(format!("position ({x}, {y}, {z}) is not finite")));
    }
    let q = Quaternion::new(qw, qx, qy, qz);
    let norm = q.norm();
    if !norm.is_finite() || (norm - 1.0).abs() > QUAT_NORM_TOLERANCE {
        return Err(CdrError(format!(
            "quaternion (x y z w) = ({qx}, {qy}, {qz}, {qw}) has norm {norm}, not 1"
        )));
    }
    Ok(Some(Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::new_unchecked(q / norm),
    )))
}
