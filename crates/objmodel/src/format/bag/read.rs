//! Reading an MCAP bag once, linearly (every chunk, compressed with zstd or lz4 or not):
//! the inventory of its topics, the tf tree of its `TFMessage` topics, and the poses of the
//! other pose topics asked for.

use super::messages::{decode, PoseType, RawTransform};
use super::tf_tree::{sort_dedup, TfTree};
use crate::trajectory::StampedPose;
use crate::{Error, Result};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// A topic of the bag.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TopicInfo {
    /// Its name.
    pub topic: String,
    /// Its message type (schema name), e.g. `geometry_msgs/msg/PoseStamped`.
    pub schema: String,
    /// Its message encoding, e.g. `cdr`.
    pub encoding: String,
    /// How many messages it holds.
    pub messages: u64,
}

impl TopicInfo {
    /// The pose type of its messages, if it carries poses in CDR.
    pub fn pose_type(&self) -> Option<PoseType> {
        PoseType::of_schema(&self.schema).filter(|_| self.encoding == "cdr")
    }

    /// Whether it is a tf topic (its transforms go into the tf tree).
    pub fn is_tf(&self) -> bool {
        self.pose_type() == Some(PoseType::TfMessage)
    }

    /// Whether its transforms are static (`/tf_static`).
    pub fn is_static_tf(&self) -> bool {
        self.is_tf() && self.topic.trim_end_matches('/').ends_with("tf_static")
    }
}

/// The poses of one pose topic (not a tf topic).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TopicPoses {
    /// `header.frame_id` of its messages: the frame its poses are expressed in.
    pub frame: String,
    /// `frame_from_child`, sorted by stamp, one per stamp.
    pub poses: Vec<StampedPose>,
    /// Messages dropped because another had the same stamp.
    pub duplicates: usize,
    /// Messages left out because every value of their pose was NaN or zero (the tracker lost
    /// the object).
    pub lost: usize,
}

/// What was read of a bag.
#[derive(Clone, Debug, Default)]
pub struct BagContents {
    /// The bag (a file, or a bag folder).
    pub path: PathBuf,
    /// Every topic, by name.
    pub topics: BTreeMap<String, TopicInfo>,
    /// The tf tree (`/tf`, `/tf_static`).
    pub tf: TfTree,
    /// Poses on tf dropped because another had the same stamp.
    pub tf_duplicates: usize,
    /// Transforms on tf left out because every value was NaN or zero, by child frame.
    pub tf_lost: HashMap<String, usize>,
    /// The poses of the pose topics asked for.
    pub streams: HashMap<String, TopicPoses>,
}

/// Whether `path` is a bag: an `.mcap` file, or a folder holding one (what `ros2 bag record`
/// writes: `NAME/NAME_0.mcap` and `metadata.yaml`).
pub fn is_bag(path: &Path) -> bool {
    has_mcap_name(path) || !mcap_files(path).is_empty()
}

fn has_mcap_name(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("mcap"))
}

/// The `.mcap` files of a bag folder, by name; empty for anything else.
fn mcap_files(path: &Path) -> Vec<PathBuf> {
    let Ok(dir) = std::fs::read_dir(path) else {
        return vec![];
    };
    let mut v: Vec<PathBuf> = dir
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| has_mcap_name(p) && p.is_file())
        .collect();
    v.sort();
    v
}

/// Read a bag: its inventory, its tf tree, and the poses of `topics` (pose topics).
pub fn read_bag(path: &Path, topics: &[&str]) -> Result<BagContents> {
    let files = if path.is_dir() {
        let f = mcap_files(path);
        if f.is_empty() {
            return Err(Error::File {
                file: path.to_path_buf(),
                msg: "a folder without .mcap files is not a bag".into(),
            });
        }
        f
    } else {
        vec![path.to_path_buf()]
    };
    let mut bag = BagContents {
        path: path.to_path_buf(),
        ..BagContents::default()
    };
    for f in &files {
        read_file(f, topics, &mut bag)?;
    }
    bag.tf_duplicates = bag.tf.finish();
    for s in bag.streams.values_mut() {
        s.duplicates = sort_dedup(&mut s.poses);
    }
    Ok(bag)
}

/// What is known of a channel while reading.
struct ChannelUse {
    topic: String,
    pose_type: Option<PoseType>,
    tf: bool,
    static_tf: bool,
    wanted: bool,
}

/// Read one `.mcap` file into `bag`.
fn read_file(path: &Path, topics: &[&str], bag: &mut BagContents) -> Result<()> {
    let err = |msg: String| Error::File {
        file: path.to_path_buf(),
        msg,
    };
    let file = std::fs::File::open(path).map_err(|source| Error::Io {
        file: path.to_path_buf(),
        source,
    })?;
    // SAFETY: read-only and private; a concurrent truncation of the file would stop the
    // process (SIGBUS), as with any memory-mapped reader (see `format::mapped`).
    let map = unsafe { memmap2::Mmap::map(&file) }.map_err(|source| Error::Io {
        file: path.to_path_buf(),
        source,
    })?;
    let mut stream = mcap::read::RawMessageStream::new(&map)
        .map_err(|e| err(format!("not an MCAP file: {e}")))?;
    let mut channels: HashMap<u16, ChannelUse> = HashMap::new();
    let mut index = 0u64;
    while let Some(m) = stream.next() {
        let m = m.map_err(|e| err(format!("after {index} messages: {e}")))?;
        index += 1;
        let id = m.header.channel_id;
        if let std::collections::hash_map::Entry::Vacant(slot) = channels.entry(id) {
            let Some(ch) = stream.get_channel(id) else {
                return Err(err(format!(
                    "message {index} is on channel {id}, which no channel record defines"
                )));
            };
            let info = TopicInfo {
                topic: ch.topic.clone(),
                schema: ch
                    .schema
                    .as_ref()
                    .map(|s| s.name.clone())
                    .unwrap_or_default(),
                encoding: ch.message_encoding.clone(),
                messages: 0,
            };
            slot.insert(ChannelUse {
                topic: ch.topic.clone(),
                pose_type: info.pose_type(),
                tf: info.is_tf(),
                static_tf: info.is_static_tf(),
                wanted: topics.contains(&ch.topic.as_str()) && info.pose_type().is_some(),
            });
            bag.topics.entry(ch.topic.clone()).or_insert(info);
        }
        let ch = &channels[&id];
        if let Some(t) = bag.topics.get_mut(&ch.topic) {
            t.messages += 1;
        }
        let Some(ty) = ch.pose_type.filter(|_| ch.tf || ch.wanted) else {
            continue;
        };
        let at = |msg: String| {
            err(format!(
                "{} message {index} (log time {} ns): {msg}",
                ch.topic, m.header.log_time
            ))
        };
        let mut failed = None;
        let decoded = if ch.tf {
            let (tf, lost) = (&mut bag.tf, &mut bag.tf_lost);
            decode(ty, &m.data, &mut |r: RawTransform| {
                let Some(pose) = r.pose else {
                    *lost
                        .entry(String::from_utf8_lossy(r.child).into_owned())
                        .or_default() += 1;
                    return;
                };
                if failed.is_none() {
                    if let Err(e) = tf.insert(r.parent, r.child, r.t, pose, ch.static_tf, &ch.topic)
                    {
                        failed = Some(e);
                    }
                }
            })
        } else {
            let s = bag.streams.entry(ch.topic.clone()).or_default();
            decode(ty, &m.data, &mut |r: RawTransform| {
                let frame = String::from_utf8_lossy(r.parent);
                if s.poses.is_empty() {
                    s.frame = frame.into_owned();
                } else if s.frame != frame && failed.is_none() {
                    failed = Some(format!(
                        "header.frame_id is '{frame}', but earlier messages were in '{}'",
                        s.frame
                    ));
                }
                match r.pose {
                    Some(pose) => s.poses.push(StampedPose::new(r.t, pose)),
                    None => s.lost += 1,
                }
            })
        };
        decoded.map_err(|e| at(e.0))?;
        if let Some(e) = failed {
            return Err(at(e));
        }
    }
    Ok(())
}
