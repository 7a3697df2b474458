//! The options that choose what to read from a ROS 2 bag (or from an OptiTrack Motive take
//! holding several rigid bodies), shared by `classify`, `learn` and `plot`, and the sources
//! (files, takes or bags) of the demonstrations given on the command line.

use anyhow::{bail, Result};
use objmodel::format::bag::{is_bag, BagSelection};
use objmodel::learn::Source;
use std::path::{Path, PathBuf};

/// What to take from a ROS 2 bag (`.mcap`, or a bag folder).
#[derive(clap::Args, Clone, Debug, Default)]
pub struct BagArgs {
    /// For a bag: the object, a pose topic (e.g. /object_pose) or a tf frame (e.g.
    /// tag36h11:0; taken whole, ':' included). For an OptiTrack Motive take (CSV export)
    /// holding several rigid bodies: the object's rigid body. With it, --palm names the palm
    /// the same way (a topic, frame or rigid body, not a file).
    #[arg(long)]
    pub object: Option<String>,
    /// For a bag: the frame the object and palm are expressed in (give --gravity in it);
    /// default: the root of the object's tf tree.
    #[arg(long)]
    pub reference: Option<String>,
    /// For a bag: cut it into demonstrations NAME#1, NAME#2, ... at the middle of each rest of
    /// the object lasting at least S seconds (`--split`: 2 s, `--split=S`; a rest: the object
    /// stays within 1 cm and 3° of where it stopped); parts that are only rest are dropped.
    #[arg(
        long,
        value_name = "S",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "2"
    )]
    pub split: Option<f64>,
}

impl BagArgs {
    /// The selection for a bag, `palm` being the `--palm` given (a topic or frame name).
    pub fn selection(&self, bag: &Path, palm: Option<&Path>) -> Result<BagSelection> {
        let Some(object) = self.object.clone() else {
            bail!(
                "{}: a bag needs --object TOPIC|FRAME (and --palm TOPIC|FRAME for an \
                 instrumented demonstration); `objmodel classify {} --object ?` lists what it holds",
                bag.display(),
                bag.display()
            );
        };
        if let Some(s) = self.split {
            if !(s > 0.0 && s.is_finite()) {
                bail!("--split must be a positive duration, got {s}");
            }
        }
        Ok(BagSelection {
            object,
            palm: palm.map(|p| p.to_string_lossy().into_owned()),
            reference: self.reference.clone(),
            split_rest_s: self.split,
        })
    }

    /// Refuse the options that are for bags alone, for pose files.
    pub fn check_files(&self) -> Result<()> {
        if self.reference.is_some() || self.split.is_some() {
            bail!("--reference and --split are for bags (.mcap); the demonstrations given are pose files");
        }
        Ok(())
    }

    /// The source of pose file `demo`: a Motive take's rigid bodies where --object names the
    /// object's (`palm`, the `--palm` given, then names the palm's), else the file and its
    /// palm file, `palm_file`.
    pub fn file_source(
        &self,
        demo: &Path,
        palm: Option<&Path>,
        palm_file: impl FnOnce() -> Option<PathBuf>,
    ) -> DemoSource {
        match &self.object {
            Some(object) => DemoSource::Take {
                path: demo.to_path_buf(),
                object: object.clone(),
                palm: palm.map(|p| p.to_string_lossy().into_owned()),
            },
            None => DemoSource::Files {
                object: demo.to_path_buf(),
                palm: palm_file(),
            },
        }
    }
}

/// Where one demonstration (or, for a split bag, several) comes from.
#[derive(Clone, Debug)]
pub enum DemoSource {
    /// Pose files: the object's and the palm's.
    Files {
        /// The object's file.
        object: PathBuf,
        /// The palm's file.
        palm: Option<PathBuf>,
    },
    /// Rigid bodies of an OptiTrack Motive take.
    Take {
        /// The take's CSV export.
        path: PathBuf,
        /// The object's rigid body.
        object: String,
        /// The palm's rigid body.
        palm: Option<String>,
    },
    /// A bag.
    Bag {
        /// The bag.
        path: PathBuf,
        /// What to take from it.
        selection: BagSelection,
    },
}

impl DemoSource {
    /// The library's source.
    pub fn source(&self) -> Source<'_> {
        match self {
            DemoSource::Files { object, palm } => Source::Files {
                object,
                palm: palm.as_deref(),
            },
            DemoSource::Take { path, object, palm } => Source::Take {
                path,
                object,
                palm: palm.as_deref(),
            },
            DemoSource::Bag { path, selection } => Source::Bag { path, selection },
        }
    }

    /// The file named in messages.
    pub fn path(&self) -> &Path {
        match self {
            DemoSource::Files { object, .. } => object,
            DemoSource::Take { path, .. } | DemoSource::Bag { path, .. } => path,
        }
    }
}

/// The source of one demonstration given on the command line (`classify`, `plot`): a bag with
/// the selection of `bag` and `--palm` (a topic or frame), a Motive take's rigid bodies
/// (--object and `--palm`), or a pose file with its palm file (`--palm`, else NAME.palm.*
/// beside it unless `no_palm`).
pub fn single_source(
    demo: &Path,
    palm: Option<&Path>,
    no_palm: bool,
    bag: &BagArgs,
) -> Result<DemoSource> {
    if is_bag(demo) {
        return Ok(DemoSource::Bag {
            path: demo.to_path_buf(),
            selection: bag.selection(demo, palm)?,
        });
    }
    bag.check_files()?;
    Ok(bag.file_source(demo, palm, || crate::opts::palm_for(demo, palm, no_palm)))
}

/// Whether `path` is a bag.
pub fn is_bag_path(path: &Path) -> bool {
    is_bag(path)
}
