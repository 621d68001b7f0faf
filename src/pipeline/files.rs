//! Files on disk: expanding directories into the files a command reads, and
//! the one write primitive every output file goes through ([`write_atomic`]:
//! the baseline, `survey --plot`).
//!
//! What a write guarantees, against files a pull request may have planted:
//!
//! - the temporary file is created exclusively (`O_CREAT | O_EXCL`, which
//!   never follows a symlink) under an unpredictable name
//!   `.NAME.<12 random characters>.tmp` ([`WRITE_TEMP_RANDOM_CHARS`]) in the
//!   target's directory, by the `tempfile` crate; a planted file or link at
//!   any name is never opened;
//! - the temporary is removed on every path: an error or a panic (its `Drop`),
//!   SIGINT, SIGTERM and SIGHUP ([`super::cleanup`]); only SIGKILL can leave
//!   it (the target is never half-written);
//! - the target is replaced by `rename(2)` in the same directory: atomic, and
//!   it replaces a directory entry, never writes through one;
//! - a target that is a symlink is refused by name (never followed, never
//!   replaced): a committed link would otherwise redirect the write, or be
//!   silently swapped for a file; so is a target reached through a symlinked
//!   directory inside the current directory (the checkout, in CI), which a
//!   pull request can plant, and a file of several hard links (one of them
//!   may be an input) ([`unsafe_target`]);
//! - the callers refuse a target that is one of their inputs by file identity
//!   ([`same_file`]: device and inode), which sees through symlinks, hard
//!   links, `..` and the spelling of a name on a case-insensitive file system.

use super::cleanup;
use crate::diagnostic::{Code, Error, Result};
use crate::tolerances::WRITE_TEMP_RANDOM_CHARS;
use std::io::Write;
use std::path::{Component, Path, PathBuf};

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

/// Whether `a` and `b` name the same existing file: on Unix the same device
/// and inode (a symlink is followed, a hard link is the file, `..` and a
/// name's case on a case-insensitive file system do not matter); elsewhere
/// the same canonical path. A path that does not exist is no file.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// Why `path` may not be written (`None`: it may): it is a symlink, a file
/// of several hard links, or it is reached through a symlinked directory
/// inside the current directory.
/// Links outside the current directory (`/tmp` on macOS, a linked home) are
/// the operator's layout and are followed.
pub fn unsafe_target(path: &Path) -> Option<String> {
    if let Ok(m) = std::fs::symlink_metadata(path) {
        if m.file_type().is_symlink() {
            let to =
                std::fs::read_link(path).map_or_else(|_| "?".into(), |t| t.display().to_string());
            return Some(format!(
                "it is a symlink (to {to}): a link is never written through or replaced; expected a regular file or no file"
            ));
        }
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            if m.is_file() && m.nlink() > 1 {
                return Some(format!(
                    "it is a file with {} hard links (names): replacing one name would part it from the others, one of which may be an input; expected a file of one name",
                    m.nlink()
                ));
            }
        }
    }
    let link = linked_directory(path)?;
    Some(format!(
        "its directory {} is a symlink inside the current directory: expected a real directory (give the path the link leads to)",
        link.display()
    ))
}

/// The first directory on the way to `path` that is a symlink inside the
/// current directory, walking the components as the kernel does (`..` after
/// a link leaves where the link leads, not where it stands).
fn linked_directory(path: &Path) -> Option<PathBuf> {
    let cwd = std::env::current_dir().ok()?.canonicalize().ok()?;
    let parent = path.parent()?;
    let mut cur = if path.is_absolute() {
        PathBuf::from("/")
    } else {
        cwd.clone()
    };
    for c in parent.components() {
        match c {
            Component::Prefix(_) | Component::RootDir => cur = PathBuf::from(c.as_os_str()),
            Component::CurDir => {}
            Component::ParentDir => {
                cur.pop();
            }
            Component::Normal(n) => {
                let next = cur.join(n);
                let is_link =
                    std::fs::symlink_metadata(&next).is_ok_and(|m| m.file_type().is_symlink());
                if is_link && next.starts_with(&cwd) {
                    return Some(next);
                }
                // Followed (outside the current directory) or a real
                // directory; a missing one ends the walk (the write fails).
                cur = next.canonicalize().ok()?;
            }
        }
    }
    None
}

/// The directory `path` is written in (`.` for a bare file name).
pub(crate) fn dir_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `.NAME.` (the name cut to 100 bytes, so that the temporary's name stays
/// within the 255 bytes a file system allows).
fn temp_prefix(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let mut cut = name.len().min(100);
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    format!(".{}.", &name[..cut])
}

/// Create `p` exclusively (`O_CREAT | O_EXCL`: an existing file or link at
/// `p` is an error, never opened), mode `0666` less the umask.
fn create_new(p: &Path) -> std::io::Result<std::fs::File> {
    let mut o = std::fs::OpenOptions::new();
    o.write(true).create_new(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::mode(&mut o, 0o666);
    o.open(p)
}

/// Write `bytes` to `path` atomically (see the module documentation): a
/// temporary file created exclusively in the same directory, written and
/// synced, renamed over the target, then the directory synced so that the
/// rename is durable. An existing file's permissions are carried over; a new
/// file gets `0666` less the umask, as `File::create` would. On any error the
/// old file is untouched, the temporary removed, and the error names `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_with(path, &mut |w| w.write_all(bytes))
}

/// [`write_atomic`] of what `write` writes: a large file (a fleet's
/// baseline) streamed through a buffer, never held whole. An error from
/// `write` is an error of the write: the temporary is removed, the old file
/// left.
pub fn write_atomic_with(
    path: &Path,
    write: &mut dyn FnMut(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let mut f = AtomicFile::create(path)?;
    write(&mut f).map_err(|e| f.error(e))?;
    f.commit()
}

/// A file written atomically over time (`audit run`'s rows as the scans
/// finish): [`write_atomic`]'s temporary, buffered, put in place by
/// [`commit`](AtomicFile::commit); dropped without it, the temporary is
/// removed and the old file left.
pub struct AtomicFile {
    path: PathBuf,
    dir: PathBuf,
    old_mode: Option<std::fs::Permissions>,
    out: std::io::BufWriter<tempfile::NamedTempFile>,
    _interrupted: Option<cleanup::Registered>,
}

impl AtomicFile {
    /// Create the temporary beside `path` (refused as [`write_atomic`]
    /// refuses a target).
    pub fn create(path: &Path) -> Result<Self> {
        if let Some(why) = unsafe_target(path) {
            return Err(Error::usage(format!("refusing to write: {why}")).in_file(path));
        }
        let dir = dir_of(path);
        let old_mode = std::fs::metadata(path)
            .ok()
            .filter(|m| m.is_file())
            .map(|m| m.permissions());
        let prefix = temp_prefix(path);
        // Registered before it is created (a signal between the two would
        // leave it); a name that turns out to be taken is forgotten with the
        // retry.
        let mut interrupted = None;
        let tmp = tempfile::Builder::new()
            .prefix(&prefix)
            .suffix(".tmp")
            .rand_bytes(WRITE_TEMP_RANDOM_CHARS)
            .make_in(&dir, |p| {
                interrupted = Some(cleanup::register(p));
                create_new(p)
            })
            .map_err(|e| cannot_write(path, e))?;
        Ok(AtomicFile {
            path: path.to_path_buf(),
            dir,
            old_mode,
            out: std::io::BufWriter::new(tmp),
            _interrupted: interrupted,
        })
    }

    /// A write error of this file, naming its target.
    pub fn error(&self, e: std::io::Error) -> Error {
        cannot_write(&self.path, e)
    }

    /// Flush, sync, and rename the temporary over the target, then sync the
    /// directory so that the rename is durable.
    pub fn commit(self) -> Result<()> {
        let path = self.path;
        let cannot = |e| cannot_write(&path, e);
        let tmp = self.out.into_inner().map_err(|e| cannot(e.into_error()))?;
        if let Some(p) = self.old_mode {
            // An existing file keeps its mode exactly (a 0600 baseline stays
            // 0600).
            tmp.as_file().set_permissions(p).map_err(cannot)?;
        }
        tmp.as_file().sync_all().map_err(cannot)?;
        // On failure the temporary comes back inside the error and is
        // removed when that is dropped.
        tmp.persist(&path).map_err(|e| cannot(e.error))?;
        // Best effort: some file systems cannot sync a directory.
        if let Ok(d) = std::fs::File::open(&self.dir) {
            let _ = d.sync_all();
        }
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.out.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

/// For writers that go back over what they wrote (an MCAP file's chunk
/// headers): the buffer is flushed first.
impl std::io::Seek for AtomicFile {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        self.out.seek(pos)
    }
}

fn cannot_write(path: &Path, e: std::io::Error) -> Error {
    Error::new(Code::Io, format!("cannot write: {e}")).in_file(path)
}
