//! Choosing the object's and the palm's poses in a bag, and expressing them in one frame.
//!
//! A selection names either a **topic** (a pose topic: `PoseStamped`,
//! `PoseWithCovarianceStamped`, `Odometry`, `TransformStamped`) or a **tf frame** (the child
//! frame of a transform on `/tf`, e.g. `tag36h11:0`, the frame `apriltag_ros` publishes). It
//! is taken whole, never split (frame names contain `:`): a topic if the bag has a topic of
//! that name, else a tf frame of that name (a leading `/` is ignored for frames, as tf2 does).
//!
//! Both are expressed in the *reference frame*: `--reference` if given, else the root of the
//! tf tree holding the object (its frame, or its topic's `header.frame_id`; that frame itself
//! when tf does not know it). The transform from the reference to a frame is composed along
//! the tf tree (static and dynamic transforms, the dynamic ones interpolated) at each stamp.
//! A frame's stamps are those of the first dynamic transform on its path (its own detection,
//! for a tracked tag); a topic's are its messages' `header.stamp`s. A stamp at which a dynamic
//! transform on the path is unknown (outside its first and last stamps) is dropped, and
//! counted in a warning.

use super::read::BagContents;
use super::tf_tree::Chain;
use crate::trajectory::StampedPose;
use crate::{Error, Result};

/// What a selection names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Selected {
    /// A pose topic.
    Topic(String),
    /// A tf frame.
    Frame(String),
}

/// The poses of a selection, in the reference frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SelectedPoses {
    /// `reference_from_selected`, by stamp.
    pub poses: Vec<StampedPose>,
    /// Stamps dropped: a transform on the path to the reference was unknown then.
    pub dropped: usize,
    /// Poses dropped because another had the same stamp.
    pub duplicates: usize,
    /// Poses left out because every value was NaN or zero (the tracker lost the object); for
    /// a tf frame, every such transform on tf.
    pub lost: usize,
}

/// Find what `spec` names in `bag` (`role`: "object" or "palm", for the error).
pub fn resolve(bag: &BagContents, spec: &str, role: &str) -> Result<Selected> {
    if let Some(t) = bag.topics.get(spec) {
        if t.is_tf() {
            return Err(bag_error(
                bag,
                format!("{role} '{spec}' is a tf topic, which carries many frames: name a frame"),
            ));
        }
        if t.pose_type().is_none() {
            return Err(bag_error(
                bag,
                format!(
                    "{role} topic '{spec}' holds {} ({}), not poses",
                    t.schema, t.encoding
                ),
            ));
        }
        return Ok(Selected::Topic(spec.to_string()));
    }
    let frame = spec.trim_start_matches('/');
    if bag.tf.edge_of(frame).is_some() {
        return Ok(Selected::Frame(frame.to_string()));
    }
    let why = if bag.tf.contains(frame) {
        format!("{role} '{spec}' is a root of the tf tree (no transform has it as child)")
    } else {
        format!("no topic or tf frame '{spec}' for the {role}")
    };
    Err(bag_error(bag, why))
}

/// The frame a selection's poses come in: its topic's `header.frame_id`, or the frame itself.
pub fn home_frame(bag: &BagContents, sel: &Selected) -> String {
    match sel {
        Selected::Topic(t) => bag
            .streams
            .get(t)
            .map(|s| s.frame.clone())
            .unwrap_or_default(),
        Selected::Frame(f) => f.clone(),
    }
}

/// The default reference frame for a selection: the root of its home frame's tf tree.
pub fn default_reference(bag: &BagContents, sel: &Selected) -> String {
    let home = home_frame(bag, sel);
    bag.tf.root(&home)
}

/// The poses of `sel` expressed in `reference`.
pub fn poses_in(
    bag: &BagContents,
    sel: &Selected,
    reference: &str,
    role: &str,
) -> Result<SelectedPoses> {
    let home = home_frame(bag, sel);
    let Some(chain) = bag.tf.chain(reference, &home) else {
        return Err(bag_error(
            bag,
            format!(
                "the {role} ({}) is not connected to the reference frame '{reference}' by tf \
                 (its tree's root is '{}')",
                describe(sel),
                bag.tf.root(&home)
            ),
        ));
    };
    let mut out = SelectedPoses::default();
    match sel {
        Selected::Topic(topic) => {
            let Some(s) = bag.streams.get(topic) else {
                return Err(bag_error(
                    bag,
                    format!("the {role} topic '{topic}' has no poses"),
                ));
            };
            out.duplicates = s.duplicates;
            out.lost = s.lost;
            for p in &s.poses {
                match bag.tf.at(&chain, p.t) {
                    Some(g) => out.poses.push(StampedPose::new(p.t, g * p.pose)),
                    None => out.dropped += 1,
                }
            }
        }
        Selected::Frame(frame) => {
            let Some(driver) = driver(bag, &chain) else {
                return Err(bag_error(
                    bag,
                    format!(
                        "the {role} frame '{frame}' never moves relative to '{reference}': \
                         every transform between them is static"
                    ),
                ));
            };
            // (Counted on the chain's edges: a lost or doubled transform of another frame
            // takes nothing from these poses.)
            let edges = || chain.steps.iter().map(|&(i, _)| &bag.tf.edges()[i]);
            out.duplicates = edges().map(|e| e.duplicates).sum();
            out.lost = edges()
                .map(|e| bag.tf_lost.get(&e.child).copied().unwrap_or(0))
                .sum();
            for p in &bag.tf.edges()[driver].poses {
                match bag.tf.at(&chain, p.t) {
                    Some(g) => out.poses.push(StampedPose::new(p.t, g)),
                    None => out.dropped += 1,
                }
            }
        }
    }
    if out.poses.is_empty() {
        return Err(bag_error(
            bag,
            format!(
                "the {role} ({}) has no pose in '{reference}': the transforms on its path are \
                 never known at the same time",
                describe(sel)
            ),
        ));
    }
    Ok(out)
}

/// The edge whose stamps drive a frame's poses: the first dynamic one from the frame up
/// (the source side of the chain), else the first on the reference's side.
fn driver(bag: &BagContents, chain: &Chain) -> Option<usize> {
    let dynamic = |&&(i, _): &&(usize, bool)| bag.tf.edges()[i].is_dynamic();
    let source_side = chain.steps.iter().rev().filter(|s| !s.1).find(dynamic);
    source_side
        .or_else(|| chain.steps.iter().find(dynamic))
        .map(|s| s.0)
}

fn describe(sel: &Selected) -> String {
    match sel {
        Selected::Topic(t) => format!("topic {t}"),
        Selected::Frame(f) => format!("tf frame {f}"),
    }
}

/// An error about `bag` that lists what it holds.
pub fn bag_error(bag: &BagContents, what: String) -> Error {
    Error::File {
        file: bag.path.clone(),
        msg: format!("{what}.\n{}", inventory(bag)),
    }
}

/// What a bag holds: its pose topics, its tf frames, its other topics.
pub fn inventory(bag: &BagContents) -> String {
    let line = |t: &super::read::TopicInfo| {
        format!("  {} ({}, {} messages)", t.topic, t.schema, t.messages)
    };
    let (poses, others): (Vec<_>, Vec<_>) = bag
        .topics
        .values()
        .partition(|t| t.pose_type().is_some() && !t.is_tf());
    let mut s = String::from("The bag holds:\npose topics:\n");
    if poses.is_empty() {
        s += "  (none)\n";
    }
    poses.iter().for_each(|t| s += &(line(t) + "\n"));
    s += "tf frames (child <- parent):\n";
    let frames = bag.tf.describe();
    if frames.is_empty() {
        s += "  (none)\n";
    }
    frames.iter().for_each(|f| s += &format!("  {f}\n"));
    s += "other topics:\n";
    if others.is_empty() {
        s += "  (none)\n";
    }
    others.iter().for_each(|t| s += &(line(t) + "\n"));
    s.trim_end().to_string()
}
