//! ROS 2 bags (MCAP): the poses of an object and of a palm, as demonstrations.
//!
//! A bag (an `.mcap` file, or the folder `ros2 bag record` writes) is read once, linearly,
//! chunks decompressed (zstd, lz4) by the `mcap` crate. Messages are CDR, little- or
//! big-endian ([`cdr`]); the pose types read are `PoseStamped`,
//! `PoseWithCovarianceStamped`, `Odometry`, `TransformStamped` and the `TFMessage`s of `/tf`
//! and `/tf_static` ([`messages`]). Every pose is stamped with its `header.stamp`, not the
//! time the bag received it, and each stream is sorted by stamp (messages need not arrive in
//! order; of equal stamps the last received is kept).
//!
//! The object and the palm are each chosen by a topic or a tf frame name ([`select`]; frame
//! names such as `tag36h11:0` are taken whole) and expressed in one reference frame, composing
//! static and dynamic transforms along the tf tree ([`tf_tree`]). The palm's stamps are
//! shifted by the palm's clock offset ([`crate::classify::Clocks`]) before anything else.
//! With a split duration, the recording is cut at the object's rests into demonstrations
//! named `BAG#1`, `BAG#2`, ... ([`split`]; the rule is there); without, it is one
//! demonstration named after the bag.
//!
//! The files, each importing only files above it: `cdr.rs`, `messages.rs`, `tf_tree.rs`,
//! `read.rs` (the bag's inventory, tf tree and pose topics), `select.rs`, `split.rs`, and this
//! one, [`read_bag_demonstrations`].

pub mod cdr;
pub mod messages;
pub mod read;
pub mod select;
pub mod split;
pub mod tf_tree;

pub use read::{is_bag, read_bag, BagContents, TopicInfo};
pub use select::Selected;
pub use split::DEFAULT_SPLIT_REST_S;

use crate::trajectory::Demonstration;
use crate::Result;
use std::path::Path;

/// What to take from a bag.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BagSelection {
    /// The object: a pose topic or a tf frame (see [`select`]).
    pub object: String,
    /// The palm, for an instrumented demonstration: a pose topic or a tf frame.
    pub palm: Option<String>,
    /// The frame both are expressed in (gravity is given in it); `None`: the root of the
    /// object's tf tree.
    pub reference: Option<String>,
    /// Cut the recording at the object's rests of at least this long \[s\] ([`split`]);
    /// `None`: the whole bag is one demonstration.
    pub split_rest_s: Option<f64>,
}

/// One demonstration read from a bag, and what looked wrong while reading it.
#[derive(Clone, Debug)]
pub struct BagDemonstration {
    /// The poses (`reference_from_object`, `reference_from_palm`), the palm's stamps on the
    /// object's clock.
    pub demo: Demonstration,
    /// Warnings (poses dropped, duplicates), for the demonstration's report.
    pub warnings: Vec<String>,
    /// The reference frame.
    pub reference: String,
}

/// Read the demonstrations of a bag: the object and palm `sel` names, the palm's stamps
/// shifted by `palm_time_offset_s` \[s\].
pub fn read_bag_demonstrations(
    path: &Path,
    sel: &BagSelection,
    palm_time_offset_s: f64,
) -> Result<Vec<BagDemonstration>> {
    let topics: Vec<&str> = std::iter::once(sel.object.as_str())
        .chain(sel.palm.as_deref())
        .collect();
    let bag = read_bag(path, &topics)?;
    let object_sel = select::resolve(&bag, &sel.object, "object")?;
    let palm_sel = sel
        .palm
        .as_deref()
        .map(|p| select::resolve(&bag, p, "palm"))
        .transpose()?;
    let reference = match &sel.reference {
        Some(r) => r.clone(),
        None => select::default_reference(&bag, &object_sel),
    };
    let mut warnings = Vec::new();
    let mut note = |what: &str, s: &select::SelectedPoses| {
        if s.dropped > 0 {
            warnings.push(format!(
                "{} {what} poses dropped: a transform on the way to '{reference}' was unknown \
                 at their stamps",
                s.dropped
            ));
        }
        if s.duplicates > 0 {
            warnings.push(format!(
                "{} {what} messages had the stamp of another and were dropped",
                s.duplicates
            ));
        }
        if s.lost > 0 {
            warnings.push(format!(
                "{} {what} poses had every value NaN or zero (the tracker lost it) and were \
                 left out, as frames not recorded",
                s.lost
            ));
        }
    };
    let object = select::poses_in(&bag, &object_sel, &reference, "object")?;
    note("object", &object);
    let palm = match &palm_sel {
        Some(p) => {
            let mut palm = select::poses_in(&bag, p, &reference, "palm")?;
            note("palm", &palm);
            palm.poses
                .iter_mut()
                .for_each(|x| x.t += palm_time_offset_s);
            Some(palm.poses)
        }
        None => None,
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string());
    let whole = |demo| BagDemonstration {
        demo,
        warnings: warnings.clone(),
        reference: reference.clone(),
    };
    let Some(min_rest) = sel.split_rest_s else {
        return Ok(vec![whole(Demonstration {
            name,
            object: object.poses,
            palm,
        })]);
    };
    let parts = split::split_at_rests(&object.poses, min_rest);
    if parts.is_empty() {
        return Err(select::bag_error(
            &bag,
            format!(
                "the object ({}) never moves between rests of {min_rest} s: nothing to split",
                sel.object
            ),
        ));
    }
    Ok(parts
        .into_iter()
        .enumerate()
        .map(|(k, r)| {
            let o = object.poses[r].to_vec();
            let (t0, t1) = (o[0].t, o[o.len() - 1].t);
            whole(Demonstration {
                name: format!("{name}#{}", k + 1),
                palm: palm.as_deref().map(|p| split::palm_for_part(p, t0, t1)),
                object: o,
            })
        })
        .collect())
}
