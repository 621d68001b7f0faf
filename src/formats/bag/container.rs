//! Which container a bag is, and the wanted messages read from it: an MCAP
//! file, a rosbag2 sqlite3 `.db3`, a ROS 1 `.bag` (each read through its own
//! index: [`super::mcap_file`], [`super::db3`], [`super::ros1`]), or a rosbag2
//! folder, whose `metadata.yaml` lists its files (MCAP or `.db3`, each
//! possibly zstd-compressed whole or per message).
//!
//! A container is recognised by its magic bytes, else by its extension; a
//! folder by its `metadata.yaml`.

use super::contents::Contents;
use super::{db3, mcap_file, ros1};
use crate::diagnostic::{Error, Result};
use crate::formats::spec::{Input, HEAD_BYTES};
use crate::input::ReadError;
use crate::tolerances::{MAX_BAG_DECOMPRESSED_BYTES, MAX_BAG_METADATA_BYTES, MAX_BAG_RECORD_BYTES};
use std::io::{Read, Write};
use std::path::Path;

/// The first bytes of a ROS 1 bag, whatever its version (`#ROSBAG V2.0`).
pub(super) const ROS1_MAGIC: &[u8] = b"#ROSBAG";

/// The magic bytes of the containers.
pub(super) const MAGIC: &[&[u8]] = &[mcap_file::MAGIC, db3::MAGIC, ROS1_MAGIC];

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Container {
    Mcap,
    Db3,
    Ros1,
    Folder,
}

fn magic_of(head: &[u8]) -> Option<Container> {
    if head.starts_with(mcap_file::MAGIC) {
        Some(Container::Mcap)
    } else if head.starts_with(db3::MAGIC) {
        Some(Container::Db3)
    } else if head.starts_with(ROS1_MAGIC) {
        Some(Container::Ros1)
    } else {
        None
    }
}

fn by_extension(ext: &str) -> Option<Container> {
    match ext {
        "mcap" => Some(Container::Mcap),
        "db3" => Some(Container::Db3),
        "bag" => Some(Container::Ros1),
        _ => None,
    }
}

/// The container `input` is: a folder with `metadata.yaml`, a file by its
/// magic bytes, else by its extension.
pub(super) fn container(input: &Input) -> Option<Container> {
    if input.is_folder() {
        return input
            .folder_holds("metadata.yaml")
            .then_some(Container::Folder);
    }
    magic_of(input.head()).or_else(|| by_extension(input.ext()))
}

/// [`container`] of the file or folder at `path` (one that cannot be opened
/// by its extension alone).
pub(super) fn container_at(path: &Path) -> Option<Container> {
    match Input::peek(path) {
        Some(input) => container(&input),
        None => by_extension(
            &path
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase())
                .unwrap_or_default(),
        ),
    }
}

fn head_of(path: &Path) -> Vec<u8> {
    crate::input::read_head(path, HEAD_BYTES).unwrap_or_default()
}

/// The messages of the topics `wanted` accepts, from the container `input` is.
pub(super) fn read(input: &Input, wanted: &dyn Fn(&str) -> bool) -> Result<Contents> {
    match container(input) {
        Some(Container::Mcap) => read_mcap(input, wanted),
        Some(Container::Db3) => read_db3(input, wanted),
        Some(Container::Ros1) => {
            let (stream, len) = input.stream()?;
            ros1::read(stream, len, input.path(), wanted)
        }
        Some(Container::Folder) => read_folder(input.path(), wanted),
        None => Err(Error::parse(
            "expected a bag (.mcap, .db3, .bag, or a rosbag2 folder with metadata.yaml), found none of them",
        )
        .in_file(input.path())),
    }
}

fn read_mcap(input: &Input, wanted: &dyn Fn(&str) -> bool) -> Result<Contents> {
    let (stream, len) = input.stream()?;
    mcap_file::read(stream, len, input.path(), wanted)
}

/// SQLite reads a database from a file: bytes held in memory are written to
/// a temporary one first (created exclusively, deleted after).
fn read_db3(input: &Input, wanted: &dyn Fn(&str) -> bool) -> Result<Contents> {
    if let Some(path) = input.file_on_disk() {
        return db3::read(path, wanted);
    }
    let mut tmp = tempfile::Builder::new()
        .prefix("audit-bag-")
        .suffix(".db3")
        .tempfile()
        .map_err(|e| Error::io(Path::new("temporary file"), &e))?;
    tmp.write_all(input.bytes()?)
        .map_err(|e| Error::io(Path::new("temporary file"), &e))?;
    // Errors and messages name the input, not the temporary file.
    let mut c = db3::read(tmp.path(), wanted).map_err(|mut e| {
        e.location.file = Some(input.path().to_path_buf());
        e
    })?;
    for m in &mut c.messages {
        m.file = input.path().to_path_buf();
    }
    Ok(c)
}

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

/// A `compression_mode: FILE` split decompressed into a temporary file with
/// the inner extension (`x.db3.zstd` -> `x.db3`), bounded by
/// [`MAX_BAG_DECOMPRESSED_BYTES`]. The file is deleted when the guard drops.
fn decompress_split(f: &Path) -> Result<tempfile::TempPath> {
    let input = crate::input::open_regular(f)?;
    let inner = f.file_stem().map(Path::new).and_then(|s| s.extension());
    let suffix = format!(
        ".{}",
        inner.map(|e| e.to_string_lossy()).unwrap_or_default()
    );
    let mut tmp = tempfile::Builder::new()
        .prefix("audit-bag-")
        .suffix(&suffix)
        .tempfile()
        .map_err(|e| Error::io(Path::new("temporary file"), &e))?;
    let mut dec = zstd::stream::read::Decoder::new(input)
        .map_err(|e| Error::parse(format!("zstd: {e}")).in_file(f))?;
    let n = std::io::copy(
        &mut (&mut dec).take(MAX_BAG_DECOMPRESSED_BYTES + 1),
        tmp.as_file_mut(),
    )
    .map_err(|e| {
        Error::parse(format!(
            "expected a zstd-compressed rosbag2 file (compression_mode file): {e}"
        ))
        .in_file(f)
    })?;
    if n > MAX_BAG_DECOMPRESSED_BYTES {
        return Err(Error::limit(format!(
            "decompresses to more than {MAX_BAG_DECOMPRESSED_BYTES} bytes: expected a rosbag2 split of a few GiB"
        ))
        .in_file(f));
    }
    Ok(tmp.into_temp_path())
}

/// `compression_mode: MESSAGE`: each message's bytes are one zstd frame.
fn decompress_messages(c: &mut Contents) -> Result<()> {
    for m in &mut c.messages {
        let mut out = Vec::new();
        zstd::stream::read::Decoder::new(m.data.as_slice())
            .and_then(|d| {
                d.take(MAX_BAG_RECORD_BYTES as u64 + 1)
                    .read_to_end(&mut out)
            })
            .map_err(|e| {
                Error::parse(format!(
                    "{} message ({}): expected zstd-compressed bytes (compression_mode message): {e}",
                    m.topic, m.place
                ))
                .in_file(&m.file)
            })?;
        if out.len() > MAX_BAG_RECORD_BYTES {
            return Err(Error::limit(format!(
                "{} message ({}) decompresses to more than {MAX_BAG_RECORD_BYTES} bytes",
                m.topic, m.place
            ))
            .in_file(&m.file));
        }
        m.data = out;
    }
    Ok(())
}

/// A rosbag2 folder: the files its `metadata.yaml` lists, read in order.
fn read_folder(dir: &Path, wanted: &dyn Fn(&str) -> bool) -> Result<Contents> {
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
    let mut out = Contents::default();
    for rel in &info.relative_file_paths {
        let f = dir.join(rel);
        // FILE mode: a split that is not itself a container is decompressed.
        let tmp = match compression {
            Compression::File if f.is_file() && magic_of(&head_of(&f)).is_none() => {
                Some(decompress_split(&f)?)
            }
            _ => None,
        };
        let read_from = tmp.as_deref().unwrap_or(&f);
        let mut c = match container_at(read_from) {
            Some(Container::Mcap) => read_mcap(&Input::open(read_from, 0)?, wanted)?,
            Some(Container::Db3) => db3::read(read_from, wanted)?,
            _ => {
                return Err(Error::parse(format!(
                    "rosbag2 file {rel}: expected an .mcap or .db3 file{}, found {}",
                    if compression == Compression::File {
                        " (zstd-compressed)"
                    } else {
                        ""
                    },
                    if f.exists() {
                        "neither"
                    } else {
                        "no such file"
                    }
                ))
                .in_file(&meta_path))
            }
        };
        if tmp.is_some() {
            for m in &mut c.messages {
                m.file = f.clone();
                m.place = format!("{} of the decompressed file", m.place);
            }
        }
        if compression == Compression::Message {
            decompress_messages(&mut c)?;
        }
        for t in c.topics {
            if !out.topics.contains(&t) {
                out.topics.push(t);
            }
        }
        out.messages.extend(c.messages);
    }
    Ok(out)
}
