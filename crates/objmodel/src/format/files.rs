//! Pose files as a whole: opening one for streaming ([`open`]), reading one into memory
//! ([`read_trajectory`]), and a demonstration with its palm file ([`read_demonstration`]).

use super::detect::has_csv_name;
use super::layout::Format;
use super::length_unit::DeclaredUnits;
use super::mapped;
use super::reader::PoseReader;
use crate::trajectory::{Demonstration, StampedPose};
use crate::{Error, Result};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

/// Capacity of the read buffer used by [`open`].
const BUF_CAPACITY: usize = 1 << 20;

/// Open a pose file for streaming (`-` is standard input). The format is [`Format::Csv`] for a
/// `.csv` name, else decided by [`super::detect_format`] at the first non-comment line.
/// Regular files of at least 16 MB are read through memory-mapped windows (no copy out of the
/// page cache; truncating such a file while it is read stops the process with SIGBUS, as with
/// any memory-mapped reader), others through a buffer.
pub fn open(path: &Path) -> Result<PoseReader<Box<dyn BufRead + Send>>> {
    open_as(path, false)
}

/// [`open`], but a regular file of any size is read through memory-mapped windows: the way
/// [`open`] reads files of 16 MB and more, for small files. An entry point for tests and
/// fuzzing (`fuzz/`), which compare the mapped reading with the others; not part of the
/// supported interface.
#[doc(hidden)]
pub fn open_mapped(path: &Path) -> Result<PoseReader<Box<dyn BufRead + Send>>> {
    open_as(path, true)
}

/// [`open`]; `always_map`: map every regular file, whatever its size.
fn open_as(path: &Path, always_map: bool) -> Result<PoseReader<Box<dyn BufRead + Send>>> {
    if path.as_os_str() == "-" {
        let stdin = BufReader::with_capacity(BUF_CAPACITY, std::io::stdin());
        return Ok(reader_for(Box::new(stdin), path, "<stdin>".into()));
    }
    let f = open_file(path)?;
    let mapped = f
        .get_ref()
        .metadata()
        .is_ok_and(|m| m.is_file() && (always_map || m.len() >= mapped::MIN_MAPPED_BYTES));
    let source: Box<dyn BufRead + Send> = if mapped {
        Box::new(mapped::MappedFile::new(f.into_inner()))
    } else {
        Box::new(f)
    };
    Ok(reader_for(source, path, path.to_path_buf()))
}

/// A buffered regular file.
fn open_file(path: &Path) -> Result<BufReader<std::fs::File>> {
    let io = |source| Error::Io {
        file: path.to_path_buf(),
        source,
    };
    let f = std::fs::File::open(path).map_err(io)?;
    if f.metadata().map_err(io)?.is_dir() {
        return Err(Error::File {
            file: path.to_path_buf(),
            msg: "is a directory".into(),
        });
    }
    Ok(BufReader::with_capacity(BUF_CAPACITY, f))
}

/// A reader of `path`'s format: CSV for a `.csv` name, else detected from the content.
fn reader_for<R: BufRead>(reader: R, path: &Path, name: PathBuf) -> PoseReader<R> {
    if has_csv_name(path) {
        PoseReader::new(reader, name, Format::Csv)
    } else {
        PoseReader::detecting(reader, name)
    }
}

/// The first `n` poses of a pose file (fewer if it has fewer), read through a small buffer
/// (to look at a file before streaming it); `-` (standard input) gives none.
pub fn read_first(path: &Path, n: usize) -> Result<Vec<StampedPose>> {
    Ok(read_first_declared(path, n)?.0)
}

/// [`read_first`], and the units the file declares (a CSV header's: [`DeclaredUnits`]; none
/// for standard input, which cannot be read twice).
pub fn read_first_declared(path: &Path, n: usize) -> Result<(Vec<StampedPose>, DeclaredUnits)> {
    read_first_declared_of(path, None, n)
}

/// [`read_first_declared`] of the rigid body `body` of a Motive take, where named.
fn read_first_declared_of(
    path: &Path,
    body: Option<&str>,
    n: usize,
) -> Result<(Vec<StampedPose>, DeclaredUnits)> {
    if path.as_os_str() == "-" {
        return Ok((vec![], DeclaredUnits::default()));
    }
    let f = std::fs::File::open(path).map_err(|source| Error::Io {
        file: path.to_path_buf(),
        source,
    })?;
    let mut reader = reader_for(
        BufReader::with_capacity(1 << 14, f),
        path,
        path.to_path_buf(),
    )
    .with_rigid_body(body);
    let poses = reader.by_ref().take(n).collect::<Result<Vec<_>>>()?;
    Ok((poses, reader.declared_units()))
}

/// The units a pose file declares ([`read_first_declared`]); none for a file whose first pose
/// cannot be read (the reading proper reports the problem, with its place).
pub fn declared_units(path: &Path) -> DeclaredUnits {
    read_first_declared(path, 1).map_or_else(|_| DeclaredUnits::default(), |(_, u)| u)
}

/// One body's poses in a pose file: the file's, or one rigid body's of an OptiTrack Motive take
/// that holds several (the object and the palm that pushes it, each read on its own).
#[derive(Clone, Copy, Debug)]
pub struct PoseFile<'a> {
    /// The file (`-`: standard input).
    pub path: &'a Path,
    /// The rigid body to read from a Motive take, where named; a file that is no Motive
    /// export with one named is an error.
    pub rigid_body: Option<&'a str>,
}

impl<'a> PoseFile<'a> {
    /// The poses of a whole file.
    pub fn whole(path: &'a Path) -> Self {
        PoseFile {
            path,
            rigid_body: None,
        }
    }

    /// Open it for streaming ([`open`]).
    pub fn open(&self) -> Result<PoseReader<Box<dyn BufRead + Send>>> {
        Ok(open(self.path)?.with_rigid_body(self.rigid_body))
    }

    /// Its first `n` poses and the units the file declares ([`read_first_declared`]).
    pub fn read_first_declared(&self, n: usize) -> Result<(Vec<StampedPose>, DeclaredUnits)> {
        read_first_declared_of(self.path, self.rigid_body, n)
    }
}

/// Read a whole trajectory (see [`open`]). A file without a single pose is an error.
pub fn read_trajectory(path: &Path) -> Result<Vec<StampedPose>> {
    if path.as_os_str() == "-" {
        return collect(open(path)?, 0);
    }
    let f = open_file(path)?;
    let size = f.get_ref().metadata().map(|m| m.len()).unwrap_or(0);
    collect(reader_for(f, path, path.to_path_buf()), size)
}

/// All poses of `reader`; `size` (bytes, may be 0) sizes the vector.
fn collect<R: BufRead>(mut reader: PoseReader<R>, size: u64) -> Result<Vec<StampedPose>> {
    // about 100 bytes per TUM line; capped so that a file of long lines costs little
    let mut poses = Vec::with_capacity((size / 96).min(1 << 24) as usize);
    reader.read_into(&mut poses)?;
    if poses.is_empty() {
        let lines = reader.lines_read();
        let msg = if let Some(why) = reader.skipped_lines().why_no_poses() {
            why
        } else if lines == 0 {
            "no poses: the file is empty".to_string()
        } else if reader.has_csv_header() {
            format!("no poses: the file has a CSV header but no data ({lines} lines)")
        } else {
            format!("no poses: only comments and blank lines ({lines} lines)")
        };
        return Err(Error::File {
            file: reader.file().to_path_buf(),
            msg,
        });
    }
    poses.shrink_to_fit();
    Ok(poses)
}

/// True if `path` names a palm trajectory: `NAME.palm.EXT` (case-insensitive), e.g.
/// `box.palm.tum`.
pub fn is_palm_file(path: &Path) -> bool {
    path.file_stem()
        .map(|s| s.to_string_lossy().to_ascii_lowercase())
        .is_some_and(|s| s.ends_with(".palm"))
}

/// The palm trajectory that goes with an object trajectory, if such a file exists:
/// `NAME.tum` -> `NAME.palm.tum`, else `NAME.palm.csv` (for `NAME.csv` the `.csv` one first).
/// `None` if there is none, or if `object_path` is itself a palm file (or `-`).
pub fn palm_path_for(object_path: &Path) -> Option<PathBuf> {
    if is_palm_file(object_path) || object_path.as_os_str() == "-" {
        return None;
    }
    let stem = object_path.file_stem()?.to_string_lossy().into_owned();
    let exts = if has_csv_name(object_path) {
        ["csv", "tum"]
    } else {
        ["tum", "csv"]
    };
    exts.iter()
        .map(|ext| object_path.with_file_name(format!("{stem}.palm.{ext}")))
        .find(|p| p.is_file())
}

/// Read a demonstration: the object trajectory in `path` and a palm trajectory from `palm`
/// if given, else from [`palm_path_for`] if that finds a file. The name is the file stem.
pub fn read_demonstration(path: &Path, palm: Option<&Path>) -> Result<Demonstration> {
    let object = read_trajectory(path)?;
    let palm_path = palm.map(Path::to_path_buf).or_else(|| palm_path_for(path));
    let palm = palm_path.as_deref().map(read_trajectory).transpose()?;
    let name = if path.as_os_str() == "-" {
        "stdin".to_string()
    } else {
        path.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    Ok(Demonstration { name, object, palm })
}
