//! Pose file formats: TUM (`timestamp tx ty tz qx qy qz qw`) and CSV with a header.
//!
//! * **TUM**: one pose per line, fields separated by any number of spaces or tabs, `#` starts
//!   a comment (whole line or trailing), blank lines are skipped, `\r\n` is accepted.
//! * **CSV**: a header line names the columns (case-insensitive, any order): `timestamp`
//!   (or `t`, `time`), `tx ty tz` (or `x y z`), `qx qy qz qw`; other columns are ignored.
//!   Fields are comma separated with optional spaces and optional double quotes. A commented
//!   header (`#timestamp,x,...`) is accepted too.
//!
//! In both the quaternion is in TUM order (x y z w) and a line gives `world_from_object`.
//! Values must be finite, the quaternion's norm within [`QUAT_NORM_TOLERANCE`] of 1 (it is then
//! normalised; its sign is kept) and timestamps strictly increasing; gaps are fine.
//!
//! Reading streams ([`PoseReader`], [`open`]); every error names the file, the line and the
//! problem, e.g. `demo.tum:17: expected 8 columns (timestamp tx ty tz qx qy qz qw), found 7`.

mod check;
mod csv;
mod mapped;
mod number;
mod reader;
#[cfg(target_arch = "x86_64")]
mod simd;
#[cfg(test)]
mod tests;
mod tum;

pub use number::parse_f64;
pub use reader::PoseReader;

use crate::trajectory::{Demonstration, StampedPose};
use crate::{Error, Result};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A quaternion whose norm differs from 1 by more than this (relative) is rejected as corrupt;
/// smaller deviations (rounding in the file) are normalised silently.
pub const QUAT_NORM_TOLERANCE: f64 = 1e-2;

/// Capacity of the read buffer used by [`open`].
const BUF_CAPACITY: usize = 1 << 20;

/// Which text format a file is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// `timestamp tx ty tz qx qy qz qw`, whitespace separated (TUM RGB-D benchmark).
    Tum,
    /// Comma separated with a header line naming the columns.
    Csv,
}

/// Decide the format of `path` from its name and its first non-comment line: a `.csv`
/// extension (any case), or a first line with a comma and a field that has letters and is not a
/// number (a header such as `t,x,y,z,qx,qy,qz,qw`), means CSV; anything else is TUM.
pub fn detect_format(path: &Path, first_line: &str) -> Format {
    let is_csv_ext = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    if is_csv_ext || csv::looks_like_header(first_line.trim().as_bytes()) {
        Format::Csv
    } else {
        Format::Tum
    }
}

/// Open a pose file for streaming (`-` is standard input). The format is [`Format::Csv`] for a
/// `.csv` name, else decided by [`detect_format`] at the first non-comment line. Regular files
/// of at least 16 MB are read through memory-mapped windows (no copy out of the page cache;
/// truncating such a file while it is read stops the process with SIGBUS, as with any
/// memory-mapped reader), others through a buffer.
pub fn open(path: &Path) -> Result<PoseReader<Box<dyn BufRead + Send>>> {
    if path.as_os_str() == "-" {
        let stdin = BufReader::with_capacity(BUF_CAPACITY, std::io::stdin());
        return Ok(reader_for(Box::new(stdin), path, "<stdin>".into()));
    }
    let f = open_file(path)?;
    let mapped = f
        .get_ref()
        .metadata()
        .is_ok_and(|m| m.is_file() && m.len() >= mapped::MIN_MAPPED_BYTES);
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
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
    {
        PoseReader::new(reader, name, Format::Csv)
    } else {
        PoseReader::detecting(reader, name)
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
        let msg = if lines == 0 {
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
    let csv_first = object_path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let exts = if csv_first {
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

/// Write `bytes` to `path` atomically: to a temporary file in the same directory, flushed and
/// synced, then renamed over `path`. A crash leaves either the old file or the new one, and a
/// failure leaves the old file untouched and no temporary file behind.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let io = |source| Error::Io {
        file: path.to_path_buf(),
        source,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let unique = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp = dir.join(format!(".{name}.tmp{}-{unique}", std::process::id()));
    let mut created = false;
    let result = (|| {
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        created = true;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() && created {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(io)?;
    // Make the rename itself durable (best effort: not every platform can sync a directory).
    if let Ok(d) = std::fs::File::open(&dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// Write a trajectory as a TUM file (atomically), with `comment` as `#` header lines.
pub fn write_tum(path: &Path, poses: &[StampedPose], comment: &str) -> Result<()> {
    let mut s = String::with_capacity(poses.len() * 100 + comment.len() + 64);
    for line in comment.lines() {
        s.push_str("# ");
        s.push_str(line);
        s.push('\n');
    }
    s.push_str("# timestamp tx ty tz qx qy qz qw\n");
    for p in poses {
        let t = p.pose.translation.vector;
        let q = p.pose.rotation.quaternion();
        use std::fmt::Write as _;
        let _ = writeln!(
            s,
            "{:.6} {:.9} {:.9} {:.9} {:.9} {:.9} {:.9} {:.9}",
            p.t, t.x, t.y, t.z, q.i, q.j, q.k, q.w
        );
    }
    write_atomic(path, s.as_bytes())
}
