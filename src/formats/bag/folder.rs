//! A rosbag2 folder: its `metadata.yaml` lists its files (MCAP or `.db3`,
//! each possibly zstd-compressed whole or per message), read in order.
//!
//! A listed file must be a regular file inside the folder: an absolute path,
//! one through `..`, a FIFO (which would block the read), a device or a
//! directory is refused by name.
//!
//! A split compressed whole (`compression_mode: file`) is decompressed
//! within its budget ([`super::inflate`]) into a temporary file that nothing
//! else can reach, removed on every path: an MCAP into an anonymous file
//! (`tempfile::tempfile`: never named on Linux, unlinked at once elsewhere on
//! Unix), so even a killed run leaves nothing; a `.db3` (SQLite opens a
//! database by name) into a private directory `audit-bag-<pid>-XXXXXX` of the
//! temporary directory, whose name is removed as soon as SQLite has the file
//! open (unlink after open: SQLite reads an immutable database through its
//! open descriptor). A run killed while decompressing a `.db3` leaves that
//! directory; every later decompression first removes the
//! `audit-bag-<pid>-*` directories of processes that no longer run.

use super::contents::{add_topic, Ask, Flow, Listing, RawMessage};
use super::inflate::Budget;
use super::kind::{container_at, magic_of, Container};
use super::{db3, mcap_file};
use crate::diagnostic::{Error, Result};
use crate::formats::spec::HEAD_BYTES;
use crate::input::ReadError;
use crate::tolerances::MAX_BAG_METADATA_BYTES;
use std::fs::File;
use std::io::{Seek, SeekFrom};
use std::path::{Component, Path, PathBuf};

/// A folder's `metadata.yaml`, at most [`MAX_BAG_METADATA_BYTES`].
fn metadata_text(meta_path: &Path) -> Result<String> {
    let bytes =
        crate::input::read_file(meta_path, MAX_BAG_METADATA_BYTES).map_err(|e| match e {
            ReadError::TooLarge { len, .. } => Error::limit(format!(
                "metadata.yaml is {} bytes: expected at most {MAX_BAG_METADATA_BYTES}",
                len.map_or_else(
                    || format!("more than {MAX_BAG_METADATA_BYTES}"),
                    |l| l.to_string()
                )
            ))
            .in_file(meta_path),
            e => e.into_error(meta_path, "rosbag2 metadata"),
        })?;
    String::from_utf8(bytes).map_err(|_| {
        let e = std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "stream did not contain valid UTF-8",
        );
        Error::io(meta_path, &e)
    })
}

#[derive(serde::Deserialize)]
struct Metadata {
    rosbag2_bagfile_information: BagInfo,
}

#[derive(serde::Deserialize)]
struct BagInfo {
    #[serde(default)]
    relative_file_paths: Vec<String>,
    #[serde(default)]
    compression_mode: String,
    #[serde(default)]
    compression_format: String,
}

/// rosbag2's `compression_mode` (rosbag2 writes `FILE`/`MESSAGE`, rosbags
/// `file`/`message`).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Compression {
    None,
    File,
    Message,
}

impl BagInfo {
    fn compression(&self, meta_path: &Path) -> Result<Compression> {
        let mode = match self.compression_mode.to_ascii_lowercase().as_str() {
            "" | "none" => return Ok(Compression::None),
            "file" => Compression::File,
            "message" => Compression::Message,
            other => {
                return Err(Error::parse(format!(
                    "rosbag2 metadata: compression_mode `{other}`: expected none, file or message"
                ))
                .in_file(meta_path))
            }
        };
        if !self.compression_format.eq_ignore_ascii_case("zstd") {
            return Err(Error::parse(format!(
                "rosbag2 metadata: compression_format `{}`: expected zstd (the only format rosbag2 ships)",
                self.compression_format
            ))
            .in_file(meta_path));
        }
        Ok(mode)
    }
}

/// A `compression_mode: file` split's inner container, from its name
/// (`x.db3.zstd`, `x.mcap.zstd`).
fn inner_container(f: &Path) -> Option<Container> {
    let inner = f.file_stem().map(Path::new).and_then(|s| s.extension())?;
    match inner.to_string_lossy().to_ascii_lowercase().as_str() {
        "mcap" => Some(Container::Mcap),
        "db3" => Some(Container::Db3),
        _ => None,
    }
}

/// The file `rel` of the folder `dir`, refused unless it is a regular file
/// inside the folder.
fn split_path(dir: &Path, rel: &str, meta_path: &Path) -> Result<PathBuf> {
    let p = Path::new(rel);
    let outside = p.is_absolute()
        || p.components()
            .any(|c| !matches!(c, Component::Normal(_) | Component::CurDir));
    if outside {
        return Err(Error::parse(format!(
            "rosbag2 metadata: relative_file_paths entry `{}`: expected a file inside the bag folder",
            crate::sanitize::quote(rel)
        ))
        .in_file(meta_path));
    }
    let f = dir.join(p);
    let kind = match std::fs::metadata(&f) {
        Err(_) => "no such file",
        Ok(m) if m.is_file() => return Ok(f),
        Ok(m) if m.is_dir() => "a directory",
        Ok(m) => special_kind(&m),
    };
    Err(Error::parse(format!(
        "rosbag2 file {}: expected a regular file (an .mcap or .db3 split), found {kind}",
        crate::sanitize::quote(rel)
    ))
    .in_file(meta_path))
}

#[cfg(unix)]
fn special_kind(m: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = m.file_type();
    if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &std::fs::Metadata) -> &'static str {
    "a special file"
}

/// A rosbag2 folder: the files its `metadata.yaml` lists, streamed in order.
pub(super) fn stream(
    dir: &Path,
    ask: Ask,
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Listing> {
    let meta_path = dir.join("metadata.yaml");
    let text = metadata_text(&meta_path)?;
    let meta: Metadata = serde_saphyr::from_str(&text).map_err(|e| {
        Error::parse(format!(
            "rosbag2 metadata: expected `rosbag2_bagfile_information` with `relative_file_paths`: {e}"
        ))
        .in_file(&meta_path)
    })?;
    let info = meta.rosbag2_bagfile_information;
    if info.relative_file_paths.is_empty() {
        return Err(Error::parse(
            "rosbag2 metadata: `relative_file_paths` is empty: expected the bag's files",
        )
        .in_file(&meta_path));
    }
    let compression = info.compression(&meta_path)?;
    let mut out = Listing::default();
    let mut stopped = false;
    for rel in &info.relative_file_paths {
        let f = split_path(dir, rel, &meta_path)?;
        let mut go = |m: RawMessage| {
            let flow = each(m)?;
            stopped |= flow == Flow::Stop;
            Ok(flow)
        };
        let listing = split(&f, rel, (compression, &meta_path), ask, &mut go)?;
        for t in listing.topics {
            add_topic(&mut out.topics, t);
        }
        out.warnings.extend(listing.warnings);
        if stopped {
            break;
        }
    }
    out.topics.sort();
    Ok(out)
}

/// One split of a folder.
fn split(
    f: &Path,
    rel: &str,
    (compression, meta_path): (Compression, &Path),
    ask: Ask,
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Listing> {
    let len = crate::input::reported_size(f).unwrap_or(0);
    let mut budget = Budget::new(f, len, ask.limits);
    let head = crate::input::read_head(f, HEAD_BYTES).unwrap_or_default();
    let whole = compression == Compression::File && magic_of(&head).is_none();
    let kind = if whole {
        inner_container(f)
    } else {
        container_at(f)
    };
    let per_message = compression == Compression::Message;
    let topics = match (kind, whole) {
        (Some(Container::Mcap), false) => {
            let (file, n) = crate::input::open_stream(f)?;
            mcap_messages(file, (f, n), per_message, ask, each)?
        }
        (Some(Container::Db3), false) => {
            let db = db3::open(f)?;
            db3::stream(&db, f, (ask.wanted, &mut budget, per_message), each)?
        }
        (Some(Container::Mcap), true) => {
            let mut tmp =
                tempfile::tempfile().map_err(|e| Error::io(Path::new("temporary file"), &e))?;
            let n = unzstd(f, &mut budget, &mut tmp)?;
            tmp.seek(SeekFrom::Start(0)).map_err(|e| Error::io(f, &e))?;
            let mut each = |mut m: RawMessage| {
                m.place = format!("{} of the decompressed file", m.place);
                each(m)
            };
            mcap_messages(tmp, (f, n), false, ask, &mut each)?
        }
        (Some(Container::Db3), true) => {
            let db = TempDb::write(f, |w| unzstd(f, &mut budget, w).map(|_| ()))?.open(f)?;
            let mut each = |mut m: RawMessage| {
                m.file = f.to_path_buf();
                m.place = format!("{} of the decompressed file", m.place);
                each(m)
            };
            db3::stream(&db, f, (ask.wanted, &mut budget, false), &mut each)?
        }
        _ => {
            return Err(Error::parse(format!(
                "rosbag2 file {}: expected an .mcap or .db3 file{}, found neither",
                crate::sanitize::quote(rel),
                if compression == Compression::File {
                    " (zstd-compressed, named .mcap.zstd or .db3.zstd)"
                } else {
                    ""
                },
            ))
            .in_file(meta_path))
        }
    };
    Ok(Listing {
        topics,
        warnings: Vec::new(),
    })
}

/// An MCAP split (`n` bytes) read from `file`, its messages named after `f`;
/// `per_message`: each message's data is one zstd frame.
fn mcap_messages(
    file: File,
    (f, n): (&Path, u64),
    per_message: bool,
    ask: Ask,
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Vec<super::contents::TopicInfo>> {
    let mut chunks = Budget::new(f, n, ask.limits);
    if !per_message {
        return mcap_file::stream(file, n, f, ask.wanted, &mut chunks, each);
    }
    let mut messages = Budget::new(f, n, ask.limits);
    let mut each = |mut m: RawMessage| {
        let what = format!(
            "{} message ({}): expected zstd-compressed bytes (compression_mode message)",
            m.topic, m.place
        );
        let d = zstd::stream::read::Decoder::new(m.data.as_slice())
            .map_err(|e| Error::parse(format!("{what}: {e}")).in_file(f))?;
        m.data = messages.inflate(d, &what)?;
        each(m)
    };
    mcap_file::stream(file, n, f, ask.wanted, &mut chunks, &mut each)
}

/// The zstd file `f` decompressed into `out` within `budget`; the bytes written.
fn unzstd(f: &Path, budget: &mut Budget, out: &mut File) -> Result<u64> {
    let input = crate::input::open_regular(f)?;
    let dec = zstd::stream::read::Decoder::new(input).map_err(|e| {
        Error::parse(format!(
            "expected a zstd-compressed rosbag2 file (compression_mode file): {e}"
        ))
        .in_file(f)
    })?;
    let cap = budget.cap();
    budget.inflate_into(
        dec,
        out,
        cap,
        "zstd-compressed rosbag2 split (compression_mode file)",
    )
}

/// A database written to a private temporary directory, for SQLite to open
/// by name; the name is removed once it is open (see the module docs).
pub(super) struct TempDb {
    dir: tempfile::TempDir,
    path: PathBuf,
}

impl TempDb {
    /// A private directory holding `x.db3`, filled by `fill`; errors name `for_file`.
    pub(super) fn write(
        for_file: &Path,
        fill: impl FnOnce(&mut File) -> Result<()>,
    ) -> Result<TempDb> {
        remove_stale();
        let tmp_err =
            |e: std::io::Error| Error::io(Path::new("temporary directory"), &e).in_file(for_file);
        let dir = tempfile::Builder::new()
            .prefix(&format!("{STALE_PREFIX}{}-", std::process::id()))
            .tempdir()
            .map_err(tmp_err)?;
        let path = dir.path().join("split.db3");
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&path)
            .map_err(tmp_err)?;
        fill(&mut file)?;
        file.sync_data().map_err(tmp_err)?;
        Ok(TempDb { dir, path })
    }

    /// Open the database, then remove its name and the directory; errors name `for_file`.
    pub(super) fn open(self, for_file: &Path) -> Result<rusqlite::Connection> {
        let db = db3::open(&self.path).map_err(|mut e| {
            e.location.file = Some(for_file.into());
            e
        });
        let _ = std::fs::remove_file(&self.path);
        drop(self.dir);
        db
    }
}

/// The name of the temporary directories of `.db3` splits: `audit-bag-<pid>-`.
const STALE_PREFIX: &str = "audit-bag-";

/// Remove the temporary directories that killed runs left (see the module
/// docs): only directories of this user, named for a process that no longer
/// runs.
#[cfg(unix)]
fn remove_stale() {
    use std::os::unix::fs::MetadataExt;
    let Ok(entries) = std::fs::read_dir(std::env::temp_dir()) else {
        return;
    };
    // SAFETY: getuid has no preconditions.
    let me = unsafe { libc::getuid() };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(pid) = name
            .strip_prefix(STALE_PREFIX)
            .and_then(|r| r.split('-').next())
            .and_then(|p| p.parse::<i32>().ok())
        else {
            continue;
        };
        let Ok(m) = std::fs::symlink_metadata(e.path()) else {
            continue;
        };
        // SAFETY: kill with signal 0 only checks whether the process exists.
        let gone = pid > 0
            && unsafe { libc::kill(pid, 0) } == -1
            && std::io::Error::last_os_error().raw_os_error() == Some(libc::ESRCH);
        if m.is_dir() && m.uid() == me && gone {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

#[cfg(not(unix))]
fn remove_stale() {}
