//! The advisory lock of `--write-baseline`: two `audit check` runs writing
//! one baseline take turns at read-merge-write, so that neither loses the
//! other's entries.
//!
//! The lock is on the baseline's directory, not on the file: the file is
//! replaced by a rename at each write, so a lock on it would be a lock on an
//! inode the next reader no longer opens. On Unix the directory itself is
//! locked (`flock`, through `std::fs::File::lock`): nothing is created, and
//! the lock goes with the process however it ends. Elsewhere a directory
//! cannot be opened as a file, so a lock file `.NAME.lock` beside the
//! baseline is locked instead (created once, left in place: removing it
//! would let a waiting writer and a new one lock two different files).
//! Other programs that do not take the lock are not stopped (advisory).

use crate::diagnostic::{Code, Error, Result};
use std::fs::File;
use std::path::Path;

/// Held while the baseline is read, merged and written; released on drop.
#[derive(Debug)]
pub struct WriteLock {
    _file: File,
}

#[cfg(unix)]
fn lock_file(dir: &Path, _target: &Path) -> std::io::Result<File> {
    File::open(dir)
}

#[cfg(not(unix))]
fn lock_file(dir: &Path, target: &Path) -> std::io::Result<File> {
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "baseline".into());
    std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(dir.join(format!(".{name}.lock")))
}

/// Take the write lock of the baseline `target` kept in `dir`, waiting for
/// another writer to finish.
pub fn lock_for_write(dir: &Path, target: &Path) -> Result<WriteLock> {
    let fail = |e: std::io::Error| {
        Error::new(
            Code::Io,
            format!(
                "--write-baseline: cannot lock {} against other writers: {e}",
                dir.display()
            ),
        )
        .in_file(target)
    };
    let f = lock_file(dir, target).map_err(fail)?;
    f.lock().map_err(fail)?;
    Ok(WriteLock { _file: f })
}
