//! The directory walk of `audit check`: which files are calibration files,
//! directories followed through symlinks once (a loop is reported, not
//! followed), `--exclude GLOB`, and no silent limit (a directory deeper than
//! `MAX_WALK_DEPTH` is a `limit` finding).
//!
//! A calibration file: a name ending in one of the format registry's `walk`
//! extensions (`formats::registry`, [`is_calibration_file`]: `.urdf`,
//! `.xacro`, `.xml`, `.launch`, `.launch.py`, `.yaml`, `.yml`, `.toml`,
//! `.json`, `.txt`), not hidden (no leading `.`), not named in
//! `DEFAULT_WALK_EXCLUDES` (`package.xml`, `CMakeLists.txt`), not an `audit
//! check` baseline or manifest. A FIFO, device or dangling symlink is reported
//! (`ignored`) and never opened. Globs: `*` any characters but `/`, `**` any characters, `?`
//! one character but `/`; a glob without `/` is matched against each file and
//! directory name, one with `/` against the path relative to the checked
//! directory (`/`-separated). An excluded directory is not entered.

use crate::diagnostic::{Code, Diagnostic, Error, Location, Result};
use crate::formats::is_calibration_file;
use crate::tolerances::{DEFAULT_WALK_EXCLUDES, MAX_WALK_DEPTH};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// One file found: its path (as found, under `root`) and the checked path it
/// was found under (the file itself when it was given).
#[derive(Debug, Clone, PartialEq)]
pub struct Found {
    /// The file.
    pub path: PathBuf,
    /// The path given on the command line it was found under.
    pub root: PathBuf,
}

/// What names one file whatever the path to it: device and inode on Unix
/// (one `stat`, where a real path costs a `readlink` per component), the
/// real path elsewhere.
#[cfg(unix)]
pub type FileId = (u64, u64);
/// What names one file whatever the path to it (the real path here).
#[cfg(not(unix))]
pub type FileId = PathBuf;

#[cfg(unix)]
fn id_of(m: &std::fs::Metadata, _path: &Path) -> Option<FileId> {
    use std::os::unix::fs::MetadataExt;
    Some((m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn id_of(_m: &std::fs::Metadata, path: &Path) -> Option<FileId> {
    path.canonicalize().ok()
}

/// The [`FileId`] of the file `path` leads to (symlinks followed); `None`
/// when there is none.
pub fn file_id(path: &Path) -> Option<FileId> {
    std::fs::metadata(path).ok().and_then(|m| id_of(&m, path))
}

/// The device of `dir` when its file system gives each directory entry's
/// type and inode number exactly as `stat` would (ext4, XFS, Btrfs, tmpfs:
/// one `statfs` per directory, the device from the `stat` that found it);
/// `None` elsewhere (overlayfs,
/// whose entries may carry another layer's inode, network and FUSE file
/// systems), where every entry is `stat`ed. A `stat` per file was a third of
/// the walk over 10,000 files (issue 29).
#[cfg(target_os = "linux")]
fn exact_entries_device(dir: &Path, id: &FileId) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt;
    const EXACT: [u64; 4] = [0xEF53, 0x5846_5342, 0x9123_683E, 0x0102_1994];
    let c = std::ffi::CString::new(dir.as_os_str().as_bytes()).ok()?;
    let mut st = std::mem::MaybeUninit::<libc::statfs>::uninit();
    // SAFETY: `c` is a NUL-terminated path and `st` room for one `statfs`,
    // read only when the call filled it (returned 0).
    let st = unsafe {
        if libc::statfs(c.as_ptr(), st.as_mut_ptr()) != 0 {
            return None;
        }
        st.assume_init()
    };
    // `f_type` is signed on glibc, unsigned on musl: its low 32 bits are the
    // magic number.
    #[allow(clippy::unnecessary_cast)]
    let magic = (st.f_type as u64) & 0xFFFF_FFFF;
    // The device is the one the `stat` that found `dir` gave.
    EXACT.contains(&magic).then_some(id.0)
}

#[cfg(not(target_os = "linux"))]
fn exact_entries_device(_dir: &Path, _id: &FileId) -> Option<u64> {
    None
}

/// For an entry that is neither a directory (which may be a mount point)
/// nor a symlink (which is followed): whether it is a regular file, and its
/// [`FileId`] (the directory's device, the entry's inode), from the entry
/// alone (`readdir`'s type and inode, no `stat`). `None`: `stat` it.
#[cfg(target_os = "linux")]
fn quick_entry(entry: &std::fs::DirEntry, dev: u64) -> Option<(bool, FileId)> {
    use std::os::unix::fs::DirEntryExt;
    let t = entry.file_type().ok()?;
    (!t.is_dir() && !t.is_symlink()).then(|| (t.is_file(), (dev, entry.ino())))
}

#[cfg(not(target_os = "linux"))]
fn quick_entry(_entry: &std::fs::DirEntry, _dev: u64) -> Option<(bool, FileId)> {
    None
}

/// What the walk found, and what it has to say (loops, limits).
#[derive(Debug, Clone, Default)]
pub struct Walked {
    /// Every calibration file, each once, sorted per given path.
    pub files: Vec<Found>,
    /// `ignored` warnings (a symlink loop or a directory reached twice) and
    /// `limit` errors (a directory beyond the depth limit).
    pub findings: Vec<Diagnostic>,
}

/// Whether `text` matches `glob` (see the module doc).
pub fn glob_match(glob: &str, text: &str) -> bool {
    fn m(g: &[u8], t: &[u8]) -> bool {
        match g.first() {
            None => t.is_empty(),
            Some(b'*') if g.get(1) == Some(&b'*') => {
                let rest = g[2..].strip_prefix(b"/").unwrap_or(&g[2..]);
                (0..=t.len()).any(|i| m(rest, &t[i..]) || m(&g[2..], &t[i..]))
            }
            Some(b'*') => (0..=t.len())
                .take_while(|&i| i == 0 || t[i - 1] != b'/')
                .any(|i| m(&g[1..], &t[i..])),
            Some(b'?') => t.first().is_some_and(|&c| c != b'/') && m(&g[1..], &t[1..]),
            Some(&c) => t.first() == Some(&c) && m(&g[1..], &t[1..]),
        }
    }
    m(glob.as_bytes(), text.as_bytes())
}

fn excluded(excludes: &[String], rel: &Path) -> bool {
    if excludes.is_empty() {
        return false;
    }
    let rel_s = rel.to_string_lossy().replace('\\', "/");
    let name = rel
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    excludes.iter().any(|g| {
        if g.contains('/') {
            glob_match(g.trim_start_matches("./"), &rel_s)
        } else {
            glob_match(g, &name)
        }
    })
}

struct Walker<'a> {
    excludes: &'a [String],
    accept: fn(&Path) -> bool,
    root: PathBuf,
    /// The directories walked, by identity.
    visited: HashSet<FileId>,
    /// The files taken so far (over every given path): each file once.
    seen: &'a mut HashSet<FileId>,
    out: Walked,
}

impl Walker<'_> {
    /// Walk `dir`, whose [`FileId`] is `id` when a `stat` gave it.
    fn dir(&mut self, dir: &Path, depth: usize, id: Option<FileId>) -> Result<()> {
        if depth > MAX_WALK_DEPTH {
            self.out.findings.push(
                Diagnostic::new(
                    Code::Limit,
                    format!(
                        "directory is {depth} levels below the checked path: expected at most {MAX_WALK_DEPTH} (MAX_WALK_DEPTH); its files were not checked"
                    ),
                )
                .at(&Location::file(dir)),
            );
            return Ok(());
        }
        // A directory is known by its identity (device and inode, from the
        // `stat` that found it), not its canonical path: `realpath` was a
        // `readlink` per component of every directory (issue 29). The path
        // only names a directory reached again.
        let id = match id {
            Some(id) => id,
            // No `stat` gave it: the canonical path's error, as before.
            None => {
                let canon = dir.canonicalize().map_err(|e| Error::io(dir, &e))?;
                file_id(&canon)
                    .ok_or_else(|| Error::io(dir, &std::io::Error::other("no file identity")))?
            }
        };
        if !self.visited.insert(id) {
            let canon = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
            self.out.findings.push(
                Diagnostic::new(
                    Code::Ignored,
                    format!(
                        "directory leads to {}, already walked (a symlink loop or a second link): not walked again",
                        canon.display()
                    ),
                )
                .at(&Location::file(dir)),
            );
            return Ok(());
        }
        let exact = exact_entries_device(dir, &id);
        let mut entries = Vec::new();
        for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, &e))? {
            let entry = entry.map_err(|e| Error::io(dir, &e))?;
            let quick = exact.and_then(|dev| quick_entry(&entry, dev));
            entries.push((entry.path(), quick));
        }
        // One directory's entries are its path, a separator and their names:
        // the bytes of the whole paths order them as their components do,
        // without parsing the shared components again for every pair.
        entries.sort_by(|a, b| a.0.as_os_str().cmp(b.0.as_os_str()));
        for (path, quick) in entries {
            let rel = path.strip_prefix(&self.root).unwrap_or(&path);
            if excluded(self.excludes, rel) {
                continue;
            }
            let (is_dir, is_file, id) = match quick {
                // Neither a directory nor a symlink: what a stat would say.
                Some((is_file, id)) => (false, is_file, Some(id)),
                None => {
                    // Follows symlinks: a link to a directory is walked (once).
                    let meta = std::fs::metadata(&path);
                    let is_dir = meta.as_ref().is_ok_and(|m| m.is_dir());
                    let is_file = meta.as_ref().is_ok_and(|m| m.is_file());
                    (is_dir, is_file, meta.ok().and_then(|m| id_of(&m, &path)))
                }
            };
            if is_dir && (self.accept)(&path) && crate::formats::bag::is_bag(&path) {
                // A rosbag2 folder (metadata.yaml + its files) is one input.
                if id.is_none_or(|id| self.seen.insert(id)) {
                    self.out.files.push(Found {
                        path,
                        root: self.root.clone(),
                    });
                }
            } else if is_dir {
                self.dir(&path, depth + 1, id)?;
            } else if !(self.accept)(&path) || is_default_excluded(&path) {
                continue;
            } else if !is_file {
                // A FIFO or device would block or never end, a dangling link
                // has nothing to read: refused as if named, never opened (a
                // gate must not pass over a calibration it cannot read).
                return Err(Diagnostic::new(
                    Code::Io,
                    "not a regular file (a FIFO, device, socket or dangling symlink): refused, not opened",
                )
                .at(&Location::file(&path)));
            } else if id.is_none_or(|id| self.seen.insert(id)) {
                self.out.files.push(Found {
                    path,
                    root: self.root.clone(),
                });
            }
        }
        Ok(())
    }
}

/// A name in `DEFAULT_WALK_EXCLUDES` (files of a ROS package that are never
/// calibrations).
fn is_default_excluded(path: &Path) -> bool {
    path.file_name()
        .is_some_and(|n| DEFAULT_WALK_EXCLUDES.iter().any(|x| n == *x))
}

/// Expand the given paths: a directory into its calibration files (walked as
/// the module doc says), a file as given.
pub fn walk(paths: &[PathBuf], excludes: &[String]) -> Result<Walked> {
    walk_with(paths, excludes, is_calibration_file)
}

/// [`walk`] taking the files `accept` takes instead of calibration files.
pub fn walk_with(
    paths: &[PathBuf],
    excludes: &[String],
    accept: fn(&Path) -> bool,
) -> Result<Walked> {
    let mut out = Walked::default();
    let mut seen = HashSet::new();
    for p in paths {
        let meta = std::fs::metadata(p).map_err(|e| Error::io(p, &e))?;
        if !meta.is_dir() {
            if id_of(&meta, p).is_none_or(|id| seen.insert(id)) {
                out.files.push(Found {
                    path: p.clone(),
                    root: p.clone(),
                });
            }
            continue;
        }
        let mut w = Walker {
            excludes,
            accept,
            root: p.clone(),
            visited: HashSet::new(),
            seen: &mut seen,
            out: Walked::default(),
        };
        w.dir(p, 0, id_of(&meta, p))?;
        out.files.extend(w.out.files);
        out.findings.extend(w.out.findings);
    }
    Ok(out)
}
