//! Files on disk: expanding directories into the files a command reads, and
//! writing a file atomically.

use crate::diagnostic::{Code, Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Expand directories (recursively, sorted; symlinked directories followed
/// once) into the files `accept` takes; plain files are taken as given. A
/// directory beyond `MAX_WALK_DEPTH` is an error, never skipped silently.
pub fn expand_paths(paths: &[PathBuf], accept: fn(&Path) -> bool) -> Result<Vec<PathBuf>> {
    let walked = super::walk::walk_with(paths, &[], accept)?;
    if let Some(limit) = walked.findings.into_iter().find(|d| d.code == Code::Limit) {
        return Err(limit);
    }
    Ok(walked.files.into_iter().map(|f| f.path).collect())
}

/// Write a file atomically: a temporary file `.NAME.tmp.PID` in the same
/// directory, written, flushed and synced, then renamed over the target, and the
/// directory synced so the rename itself is durable. An interrupted run leaves
/// the old file complete; a failed write removes the temporary and leaves the
/// old file. A process killed mid-write may leave its own temporary (nothing
/// runs after SIGKILL); a later run with the same pid overwrites it.
/// A symlink at `path` is replaced by the file, not followed. An existing
/// regular file's permissions are carried over to the new one.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_with(path, &mut |w| w.write_all(bytes))
}

/// [`write_atomic`] of what `write` writes: a large file (a fleet's
/// baseline) streamed, never held whole. An error from `write` is an error
/// of the write: the temporary is removed, the old file left.
pub fn write_atomic_with(
    path: &Path,
    write: &mut dyn FnMut(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let tmp = dir.join(format!(".{name}.tmp.{}", std::process::id()));
    let res = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        {
            let mut w = std::io::BufWriter::new(&mut f);
            write(&mut w)?;
            w.flush()?;
        }
        // An existing file keeps its mode (a 0600 baseline stays 0600).
        if let Some(m) = std::fs::metadata(path).ok().filter(|m| m.is_file()) {
            f.set_permissions(m.permissions())?;
        }
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)?;
        Ok(())
    })();
    if let Err(e) = res {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::new(Code::Io, format!("cannot write: {e}")).in_file(path));
    }
    // Best effort: some file systems cannot sync a directory.
    if let Ok(d) = std::fs::File::open(&dir) {
        let _ = d.sync_all();
    }
    Ok(())
}
