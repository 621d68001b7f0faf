//! Files on disk: expanding directories into the files a command reads, and
//! writing a file atomically.

use crate::diagnostic::{Code, Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Deepest directory level walked below a given directory (a calibration tree
/// is shallow; a symlink loop must not hang the walk).
const MAX_WALK_DEPTH: usize = 16;

/// Expand directories (recursively, sorted) into the files `accept` takes;
/// plain files are taken as given.
pub fn expand_paths(paths: &[PathBuf], accept: fn(&Path) -> bool) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        let meta = std::fs::metadata(p).map_err(|e| Error::io(p, &e))?;
        if meta.is_dir() {
            let mut found = Vec::new();
            walk(p, accept, &mut found, 0)?;
            found.sort();
            out.extend(found);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

fn walk(dir: &Path, accept: fn(&Path) -> bool, out: &mut Vec<PathBuf>, depth: usize) -> Result<()> {
    if depth > MAX_WALK_DEPTH {
        return Ok(());
    }
    let rd = std::fs::read_dir(dir).map_err(|e| Error::io(dir, &e))?;
    for entry in rd {
        let entry = entry.map_err(|e| Error::io(dir, &e))?;
        let path = entry.path();
        let ft = entry.file_type().map_err(|e| Error::io(&path, &e))?;
        // A rosbag2 folder (metadata.yaml + its files) is one input.
        if ft.is_dir() && accept(&path) && crate::formats::bag::is_bag(&path) {
            out.push(path);
        } else if ft.is_dir() {
            walk(&path, accept, out, depth + 1)?;
        } else if accept(&path) {
            out.push(path);
        }
    }
    Ok(())
}

/// Write a file atomically: a temporary file `.NAME.tmp.PID` in the same
/// directory, written, flushed and synced, then renamed over the target, and the
/// directory synced so the rename itself is durable. An interrupted run leaves
/// the old file complete; a failed write removes the temporary and leaves the
/// old file. A process killed mid-write may leave its own temporary (nothing
/// runs after SIGKILL); a later run with the same pid overwrites it.
/// A symlink at `path` is replaced by the file, not followed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
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
        f.write_all(bytes)?;
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
