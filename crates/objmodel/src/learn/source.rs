//! Where a demonstration comes from: pose files, a Motive take, poses in memory, a ROS 2 bag.

use crate::format::bag::BagSelection;
use crate::format::PoseFile;
use crate::trajectory::Demonstration;
use std::path::Path;

/// Where a demonstration comes from.
#[derive(Clone, Copy, Debug)]
pub enum Source<'a> {
    /// Pose files (TUM or CSV) of the object and, for an instrumented demonstration, of the
    /// palm; read once, streaming. The demonstration is named after the object file.
    Files {
        /// The object's poses, `world_from_object`.
        object: &'a Path,
        /// The palm's poses, `world_from_palm`.
        palm: Option<&'a Path>,
    },
    /// An OptiTrack Motive take (its CSV export) holding several rigid bodies: the object's
    /// and, for an instrumented demonstration, the palm's, each named; read once each,
    /// streaming. The demonstration is named after the file.
    Take {
        /// The export.
        path: &'a Path,
        /// The object's rigid body.
        object: &'a str,
        /// The palm's rigid body.
        palm: Option<&'a str>,
    },
    /// Poses held in memory.
    Memory(&'a Demonstration),
    /// A ROS 2 bag (an `.mcap` file or a bag folder) and what to take from it: one
    /// demonstration, or several when the selection splits it at rests.
    Bag {
        /// The bag.
        path: &'a Path,
        /// The object's and palm's topics or tf frames, the reference frame, the split.
        selection: &'a BagSelection,
    },
}

impl<'a> Source<'a> {
    /// A direct demonstration's file.
    pub fn file(object: &'a (impl AsRef<Path> + ?Sized)) -> Self {
        Source::Files {
            object: object.as_ref(),
            palm: None,
        }
    }

    /// An instrumented demonstration's files.
    pub fn instrumented(
        object: &'a (impl AsRef<Path> + ?Sized),
        palm: &'a (impl AsRef<Path> + ?Sized),
    ) -> Self {
        Source::Files {
            object: object.as_ref(),
            palm: Some(palm.as_ref()),
        }
    }

    /// The object's and the palm's pose files, for files and takes.
    pub(super) fn pose_files(&self) -> Option<(PoseFile<'a>, Option<PoseFile<'a>>)> {
        match *self {
            Source::Files { object, palm } => {
                Some((PoseFile::whole(object), palm.map(PoseFile::whole)))
            }
            Source::Take { path, object, palm } => {
                let body = |b| PoseFile {
                    path,
                    rigid_body: Some(b),
                };
                Some((body(object), palm.map(body)))
            }
            Source::Memory(_) | Source::Bag { .. } => None,
        }
    }
}
