//! Tree files: reading one (its schema and version checked), writing one atomically, and
//! updating one in place under a lock, so that two programs that learn into the same file at
//! once both keep their demonstrations.

use super::{Tree, SCHEMA, VERSION};
use crate::{Error, Result};
use std::path::{Path, PathBuf};

impl Tree {
    /// Read a tree file, checking its schema and version.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            file: path.to_path_buf(),
            source,
        })?;
        let file_error = |msg: String| Error::File {
            file: path.to_path_buf(),
            msg,
        };
        let value: serde_json::Value = serde_json::from_str(&text).map_err(|e| Error::Parse {
            file: path.to_path_buf(),
            line: e.line(),
            msg: format!("not valid JSON: {e}"),
        })?;
        match value.get("schema") {
            Some(serde_json::Value::String(s)) if s == SCHEMA => {}
            Some(other) => {
                return Err(file_error(format!(
                    "not an objmodel tree: its \"schema\" is {other}, expected \"{SCHEMA}\""
                )))
            }
            None => {
                return Err(file_error(format!(
                    "not an objmodel tree: it has no \"schema\" field (expected \"{SCHEMA}\")"
                )))
            }
        }
        match value.get("version").and_then(|v| v.as_u64()) {
            Some(v) if v == u64::from(VERSION) => {}
            Some(v) if v > u64::from(VERSION) => {
                return Err(file_error(format!(
                    "written by a newer objmodel (tree schema version {v}; this objmodel reads \
                     version {VERSION}): update objmodel to read it"
                )))
            }
            Some(v) => {
                return Err(file_error(format!(
                    "tree schema version {v} is not supported (this objmodel reads version \
                     {VERSION})"
                )))
            }
            None => {
                return Err(file_error(
                    "the tree has no numeric \"version\" field".to_string(),
                ))
            }
        }
        serde_json::from_value(value).map_err(|e| file_error(format!("invalid tree: {e}")))
    }

    /// Write the tree to `path` atomically (temporary file, sync, rename): a reader sees the
    /// old file or the new one, never a part.
    pub fn save(&self, path: &Path) -> Result<()> {
        crate::format::write_atomic(path, self.to_json().as_bytes())
    }

    /// Read-modify-write the tree file `path` (an empty tree if it does not exist) under an
    /// exclusive lock on `PATH.lock` beside it: `change` gets the tree and says whether it
    /// changed it; only then is the file written (atomically), so a change that adds nothing
    /// leaves the file byte for byte as it was. Another process doing the same waits for the
    /// lock, then reads what this one wrote: neither loses the other's demonstrations.
    pub fn update<T>(
        path: &Path,
        change: impl FnOnce(&mut Tree) -> Result<(T, bool)>,
    ) -> Result<T> {
        let lock_path = lock_path(path);
        let lock = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(|source| Error::Io {
                file: lock_path.clone(),
                source,
            })?;
        lock.lock().map_err(|source| Error::Io {
            file: lock_path.clone(),
            source,
        })?;
        let mut tree = if path.exists() {
            Tree::load(path)?
        } else {
            Tree::default()
        };
        let (out, changed) = change(&mut tree)?;
        if changed {
            tree.save(path)?;
        }
        // The lock is released when `lock` is closed; the lock file stays (removing it would
        // race with a process that has just opened it).
        drop(lock);
        Ok(out)
    }
}

/// The lock file of a tree file: `NAME.lock` beside it.
fn lock_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".lock");
    path.with_file_name(name)
}
