//! Pose file formats: TUM (`timestamp tx ty tz qx qy qz qw`) and CSV with a header.

use crate::trajectory::StampedPose;
use crate::{Error, Result};
use std::io::Write;
use std::path::Path;

/// Write `bytes` to `path` atomically: to a temporary file in the same directory, flushed and
/// synced, then renamed over `path`. A crash leaves either the old file or the new one.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |source| Error::Io { file: path.to_path_buf(), source };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(io)
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
