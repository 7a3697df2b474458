//! Writing files: atomically ([`write_atomic`]), and trajectories as TUM files
//! ([`write_tum`]).

use crate::trajectory::StampedPose;
use crate::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

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
