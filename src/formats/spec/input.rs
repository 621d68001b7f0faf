//! The input a format reads: its bytes (or, for a file not read whole, an open
//! handle with its first bytes and size; or a folder), its path and
//! extension, the text decoded on demand, and the cheap facts sniffers share
//! (the first characters, the text after a BOM and whitespace, the YAML keys
//! at line starts), each computed once for all sniffers.
//!
//! Files are opened and read through `crate::input` only: a regular file (a
//! FIFO or device is refused before anything blocks on it), read whole at
//! most once and within `--max-file-size`, and only when a format asks for
//! the bytes or the text; a container format (a bag) streams the file
//! through [`Input::stream`] instead. Text is decoded as `crate::input`
//! decodes it: UTF-8, a byte-order mark stripped, lone CRs read as LF.

use super::parsed::Parsed;
use crate::diagnostic::{Error, Result};
use std::borrow::Cow;
use std::cell::OnceCell;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// How many bytes of a file [`Input::head`] holds before the file is read:
/// more than the longest magic a format declares (16, SQLite's).
pub(crate) const HEAD_BYTES: usize = 64;

/// Files up to this size (as their descriptor reports it) are read whole
/// when opened, within the cap, whether or not a format asks for their bytes.
const SMALL_FILE: u64 = 64 * 1024;

/// How many characters [`Input::text_head`] holds.
const TEXT_HEAD_CHARS: usize = 4096;

/// What the `--max-file-size` cap is called in its `limit` error.
const CAP: &str = "the --max-file-size cap";

/// How a format loads a file its input names (a rig TOML's `[[include]]`):
/// as `formats::load_file` loads any file, detection included, with its own
/// `--key` and `--invert`. The loader lends it to the input: a format never
/// reaches the registry itself.
pub(crate) trait Includes {
    /// Load `path` with `key` and `invert` (the other options as given).
    fn include(&self, path: &Path, key: Option<String>, invert: bool) -> Result<Parsed>;
}

/// One input: a file, a folder, or bytes or text held in memory, as read
/// from `path`.
pub struct Input<'a> {
    path: PathBuf,
    ext: String,
    body: Body<'a>,
    /// How files it names are loaded (`None`: they cannot be).
    includes: Option<&'a dyn Includes>,
    /// The text of a body that is not text yet (decoded on demand).
    decoded: OnceCell<Result<String>>,
    /// Facts about the text, for the sniffers.
    facts: OnceCell<Facts>,
}

enum Body<'a> {
    Bytes(Cow<'a, [u8]>),
    Text(Cow<'a, str>),
    File(Opened),
    Folder,
}

/// A regular file, open, not read yet.
struct Opened {
    file: File,
    len: u64,
    head: Vec<u8>,
    cap: u64,
    whole: OnceCell<Result<Vec<u8>>>,
}

impl Opened {
    fn read_whole(&self, path: &Path) -> Result<Vec<u8>> {
        let mut f = &self.file;
        f.seek(SeekFrom::Start(0))
            .map_err(|e| Error::io(path, &e))?;
        crate::input::read_open(f, self.len, self.cap).map_err(|e| e.into_error(path, CAP))
    }
}

/// What the sniffers share about the text.
#[derive(Default)]
struct Facts {
    /// Byte length of the first [`TEXT_HEAD_CHARS`] characters.
    head_end: usize,
    /// Byte offset of the text after a BOM and leading whitespace.
    trimmed_start: usize,
    /// The keys at line starts (byte ranges), sorted by their text: built
    /// when a sniffer first asks.
    keys: OnceCell<Vec<(usize, usize)>>,
}

/// A file read as a stream (a bag through its index), or bytes in memory.
pub(crate) enum Stream<'a> {
    /// The file, at its start.
    File(File),
    /// Bytes held in memory.
    Memory(std::io::Cursor<&'a [u8]>),
}

impl Read for Stream<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        match self {
            Stream::File(f) => f.read(buf),
            Stream::Memory(c) => c.read(buf),
        }
    }
}

/// Reads `n` bytes at the current position into `buf` (replacing what it
/// held), into the vector's spare capacity where the reader allows: a
/// [`File`] reads straight into it (std's `read_buf`), where a plain `Read`
/// first zeroes the buffer, which wrote a bag's 4 MiB chunk twice (57 % of
/// `--frames`' instructions on a 1 GB MCAP, by callgrind). Fewer than `n`
/// bytes left: `UnexpectedEof`.
pub(crate) trait ReadBlock: Read + Seek {
    /// Read exactly `n` bytes into `buf`.
    fn read_block(&mut self, n: usize, buf: &mut Vec<u8>) -> std::io::Result<()>;
}

impl ReadBlock for File {
    fn read_block(&mut self, n: usize, buf: &mut Vec<u8>) -> std::io::Result<()> {
        buf.clear();
        buf.reserve_exact(n);
        self.by_ref().take(n as u64).read_to_end(buf)?;
        if buf.len() != n {
            return Err(std::io::ErrorKind::UnexpectedEof.into());
        }
        Ok(())
    }
}

impl ReadBlock for Stream<'_> {
    fn read_block(&mut self, n: usize, buf: &mut Vec<u8>) -> std::io::Result<()> {
        match self {
            Stream::File(f) => f.read_block(n, buf),
            Stream::Memory(c) => {
                let data = *c.get_ref();
                let at = usize::try_from(c.position()).unwrap_or(usize::MAX);
                let end = at.checked_add(n).filter(|&e| e <= data.len());
                let Some(end) = end else {
                    return Err(std::io::ErrorKind::UnexpectedEof.into());
                };
                buf.clear();
                buf.extend_from_slice(&data[at..end]);
                c.set_position(end as u64);
                Ok(())
            }
        }
    }
}

impl Seek for Stream<'_> {
    fn seek(&mut self, to: SeekFrom) -> std::io::Result<u64> {
        match self {
            Stream::File(f) => f.seek(to),
            Stream::Memory(c) => c.seek(to),
        }
    }
}

impl Input<'static> {
    /// The input at `path`: standard input for `-` (read whole, at most
    /// `cap` bytes), a folder, or a regular file opened with its first bytes
    /// (read whole, at most `cap` bytes, when a format asks).
    pub fn open(path: &Path, cap: u64) -> Result<Input<'static>> {
        if crate::input::is_stdin(path) {
            let bytes = crate::input::read_bytes(path, cap, CAP)?;
            return Ok(Input::new(path, Body::Bytes(Cow::Owned(bytes))));
        }
        // Opened first, its type from the descriptor (a directory is a
        // folder): no `stat` of the path before it.
        let (file, len) = match crate::input::open_file(path) {
            Ok(f) => f,
            Err(crate::input::ReadError::Directory) => return Ok(Input::new(path, Body::Folder)),
            Err(_) if path.is_dir() => return Ok(Input::new(path, Body::Folder)),
            Err(e) => return Err(e.into_error(path, "a file")),
        };
        if len <= SMALL_FILE.min(cap) {
            // A small file is read whole now, its head taken from the bytes:
            // one read (and the one that finds the end) instead of the head's
            // read, a seek and the whole's (system calls per file were a third
            // of `check` over 10,000 files, issue 29). A failed read is left
            // to be read (and reported) as any file is, on first use.
            if let Ok(bytes) = crate::input::read_open(&file, len, cap) {
                return Ok(Input::read_whole(path, file, len, bytes, cap));
            }
            (&file)
                .seek(SeekFrom::Start(0))
                .map_err(|e| Error::io(path, &e))?;
        }
        let head = crate::input::head_of(&file, HEAD_BYTES).map_err(|e| Error::io(path, &e))?;
        let opened = Opened {
            file,
            len,
            head,
            cap,
            whole: OnceCell::new(),
        };
        Ok(Input::new(path, Body::File(opened)))
    }

    /// A regular file at `path` opened by [`crate::input::open_file`] (its
    /// descriptor's size `len`) and read whole (`bytes`), as [`Input::open`]
    /// with the cap `cap` makes it; `None` when `open` would not have read it
    /// whole at once (larger than a small file or than the cap).
    pub(crate) fn from_opened(
        path: &Path,
        file: File,
        len: u64,
        bytes: Vec<u8>,
        cap: u64,
    ) -> Option<Input<'static>> {
        if len > SMALL_FILE.min(cap) || bytes.len() as u64 > cap {
            return None;
        }
        Some(Input::read_whole(path, file, len, bytes, cap))
    }

    /// A small file read whole at once: its head taken from the bytes.
    fn read_whole(path: &Path, file: File, len: u64, bytes: Vec<u8>, cap: u64) -> Input<'static> {
        let opened = Opened {
            file,
            len,
            head: bytes[..bytes.len().min(HEAD_BYTES)].to_vec(),
            cap,
            whole: OnceCell::from(Ok(bytes)),
        };
        Input::new(path, Body::File(opened))
    }

    /// The folder or regular file at `path` with its first bytes only (`-`
    /// is a file name here, and nothing more is read: a cap of 0 bytes);
    /// `None` when it is neither or cannot be opened.
    pub(crate) fn peek(path: &Path) -> Option<Input<'static>> {
        if path.is_dir() {
            return Some(Input::new(path, Body::Folder));
        }
        let (file, len) = crate::input::open_stream(path).ok()?;
        let head = crate::input::head_of(&file, HEAD_BYTES).ok()?;
        let opened = Opened {
            file,
            len,
            head,
            cap: 0,
            whole: OnceCell::new(),
        };
        Some(Input::new(path, Body::File(opened)))
    }
}

impl<'a> Input<'a> {
    fn new(path: &Path, body: Body<'a>) -> Self {
        Input {
            path: path.to_path_buf(),
            ext: extension(path),
            body,
            includes: None,
            decoded: OnceCell::new(),
            facts: OnceCell::new(),
        }
    }

    /// Bytes held in memory, as if read from `path`.
    pub fn from_bytes(path: &Path, bytes: impl Into<Cow<'a, [u8]>>) -> Self {
        Input::new(path, Body::Bytes(bytes.into()))
    }

    /// Text held in memory, as if read from `path` (a BOM stripped, lone CRs
    /// read as LF).
    pub fn from_text(path: &Path, text: &'a str) -> Self {
        Input::new(path, Body::Text(crate::input::normalize(text)))
    }

    /// The input with `includes` to load the files it names.
    pub(crate) fn with_includes(self, includes: &'a dyn Includes) -> Self {
        Input {
            includes: Some(includes),
            ..self
        }
    }

    /// How to load a file the input names (`None`: it was not made by the
    /// loader, which alone can).
    pub(crate) fn includes(&self) -> Option<&'a dyn Includes> {
        self.includes
    }

    /// The path it was read from (names it in provenance and messages).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The lower-case extension, with the known double ones (`launch.py`,
    /// `urdf.xacro`, ...); empty when there is none.
    pub fn ext(&self) -> &str {
        &self.ext
    }

    /// Whether the input is a folder.
    pub fn is_folder(&self) -> bool {
        matches!(self.body, Body::Folder)
    }

    /// Whether the input is a folder holding a file `name`.
    pub(crate) fn folder_holds(&self, name: &str) -> bool {
        self.is_folder() && self.path.join(name).is_file()
    }

    /// The file on disk it is read from (`None`: held in memory, or a folder).
    pub(crate) fn file_on_disk(&self) -> Option<&Path> {
        matches!(self.body, Body::File(_)).then_some(self.path.as_path())
    }

    /// The first bytes (up to `HEAD_BYTES`, 64; all of them for bytes held in
    /// memory), without reading a file further: for magic bytes.
    pub fn head(&self) -> &[u8] {
        match &self.body {
            Body::Bytes(b) => b,
            Body::Text(t) => t.as_bytes(),
            Body::File(o) => &o.head,
            Body::Folder => &[],
        }
    }

    /// Every byte (a file is read whole on first use, within the cap). After
    /// `Input::decode`, the decoded text's bytes.
    pub fn bytes(&self) -> Result<&[u8]> {
        match &self.body {
            Body::Bytes(b) => Ok(b),
            Body::Text(t) => Ok(t.as_bytes()),
            Body::File(o) => o
                .whole
                .get_or_init(|| o.read_whole(&self.path))
                .as_deref()
                .map_err(Clone::clone),
            Body::Folder => Err(folder(&self.path)),
        }
    }

    /// Read the input as text from here on: a file is read whole (the
    /// `--max-file-size` cap, I/O errors), then decoded (a byte that is not
    /// UTF-8 is an error at its line and column).
    pub(crate) fn decode(&mut self) -> Result<()> {
        let bytes = match std::mem::replace(&mut self.body, Body::Folder) {
            Body::Text(t) => {
                self.body = Body::Text(t);
                return Ok(());
            }
            Body::Folder => return Err(folder(&self.path)),
            Body::Bytes(b) => b.into_owned(),
            Body::File(mut o) => match o.whole.take() {
                Some(r) => r?,
                None => o.read_whole(&self.path)?,
            },
        };
        let text = crate::input::decode(bytes).map_err(|e| e.in_file(&self.path))?;
        self.body = Body::Text(Cow::Owned(text));
        self.decoded = OnceCell::new();
        self.facts = OnceCell::new();
        Ok(())
    }

    /// The text (decoded on first use when `Input::decode` has not run).
    pub fn text(&self) -> Result<&str> {
        if let Body::Text(t) = &self.body {
            return Ok(t);
        }
        self.decoded
            .get_or_init(|| {
                let bytes = self.bytes()?.to_vec();
                crate::input::decode(bytes).map_err(|e| e.in_file(&self.path))
            })
            .as_deref()
            .map_err(Clone::clone)
    }

    /// The input as a seekable stream at its start, and its length: a file
    /// is read where its reader seeks, never whole.
    pub(crate) fn stream(&self) -> Result<(Stream<'_>, u64)> {
        match &self.body {
            Body::File(o) => {
                let mut f = o.file.try_clone().map_err(|e| Error::io(&self.path, &e))?;
                f.seek(SeekFrom::Start(0))
                    .map_err(|e| Error::io(&self.path, &e))?;
                Ok((Stream::File(f), o.len))
            }
            Body::Folder => Err(folder(&self.path)),
            _ => {
                let b = self.bytes()?;
                Ok((Stream::Memory(std::io::Cursor::new(b)), b.len() as u64))
            }
        }
    }

    fn facts(&self) -> &Facts {
        self.facts.get_or_init(|| {
            let Ok(t) = self.text() else {
                return Facts::default();
            };
            let head_end = t
                .char_indices()
                .nth(TEXT_HEAD_CHARS)
                .map_or(t.len(), |(i, _)| i);
            let trimmed = t.trim_start_matches('\u{feff}').trim_start();
            Facts {
                head_end,
                trimmed_start: t.len() - trimmed.len(),
                keys: OnceCell::new(),
            }
        })
    }

    /// The text, or nothing when the input is not text.
    fn text_or_empty(&self) -> &str {
        self.text().unwrap_or("")
    }

    /// The first 4096 characters of the text.
    pub fn text_head(&self) -> &str {
        &self.text_or_empty()[..self.facts().head_end]
    }

    /// The text after a BOM and leading whitespace.
    pub fn trimmed(&self) -> &str {
        &self.text_or_empty()[self.facts().trimmed_start..]
    }

    /// Whether the text holds `needle`.
    pub fn contains(&self, needle: &str) -> bool {
        self.text_or_empty().contains(needle)
    }

    /// Whether the text starts like XML.
    pub fn looks_xml(&self) -> bool {
        self.trimmed().starts_with('<')
    }

    /// Whether a line that is not a comment starts (after indentation) with
    /// `key:` (spaces allowed before the colon; `key` holds no colon): the
    /// keys of all lines are collected once, for every sniffer.
    pub fn has_key(&self, key: &str) -> bool {
        let text = self.text_or_empty();
        let keys = self.facts().keys.get_or_init(|| line_keys(text));
        keys.binary_search_by(|&(a, b)| text[a..b].cmp(key)).is_ok()
    }
}

/// The key of every line that is not a comment and holds a colon: what comes
/// before its first colon, indentation and trailing blanks removed; sorted by
/// that text.
fn line_keys(text: &str) -> Vec<(usize, usize)> {
    let mut keys = Vec::new();
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        let t = line.trim_start();
        if !t.starts_with('#') {
            if let Some(colon) = t.find(':') {
                let start = at + (line.len() - t.len());
                keys.push((start, start + t[..colon].trim_end().len()));
            }
        }
        at += line.len();
    }
    keys.sort_by(|&(a, b), &(c, d)| text[a..b].cmp(&text[c..d]));
    keys.dedup_by(|x, y| text[x.0..x.1] == text[y.0..y.1]);
    keys
}

fn folder(path: &Path) -> Error {
    crate::input::ReadError::Directory.into_error(path, CAP)
}

/// The lower-case extension of `path`, with the known double ones.
fn extension(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    for multi in [
        ".launch.xml",
        ".launch.yaml",
        ".launch.yml",
        ".launch.py",
        ".urdf.xacro",
    ] {
        if name.ends_with(multi) {
            return multi[1..].to_string();
        }
    }
    path.extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The check the YAML dialects made before the keys were collected once.
    fn key_line(text: &str, key: &str) -> bool {
        text.lines().any(|l| {
            let t = l.trim_start();
            !t.starts_with('#')
                && t.strip_prefix(key)
                    .is_some_and(|r| r.trim_start().starts_with(':'))
        })
    }

    #[test]
    fn keys_at_line_starts_are_found_as_a_line_scan_finds_them() {
        let text = "a: 1\n  b : 2\n# c: 3\n- node: x\nkey x: y\nd\t:\r\ne\nf:g: h\n\u{a0}i:\nextrinsics/t/t: 0\n";
        let input = Input::from_text(Path::new("x.yaml"), text);
        for key in [
            "a",
            "b",
            "c",
            "- node",
            "node",
            "key",
            "key x",
            "d",
            "e",
            "f",
            "f:g",
            "i",
            "extrinsics/t/t",
            "extrinsics",
            "",
            "x",
        ] {
            if key.contains(':') {
                continue;
            }
            assert_eq!(input.has_key(key), key_line(text, key), "{key:?}");
        }
    }

    #[test]
    fn facts_of_text_and_of_bytes() {
        let input = Input::from_text(Path::new("R.URDF"), "\u{feff}  <robot/>\r");
        assert_eq!(input.ext(), "urdf");
        assert!(input.looks_xml());
        assert_eq!(input.text().unwrap(), "  <robot/>\n");
        let long = "é".repeat(5000);
        let input = Input::from_text(Path::new("a.launch.py"), &long);
        assert_eq!(
            (input.ext(), input.text_head().chars().count()),
            ("launch.py", 4096)
        );
        let bin = Input::from_bytes(Path::new("x"), &b"LASF\xff\xfe"[..]);
        assert!(bin.text().is_err());
        assert_eq!((bin.trimmed(), bin.has_key("a")), ("", false));
        assert!(bin.head().starts_with(crate::bytes::LAS_MAGIC));
    }

    /// A block read from a file and from memory: the bytes at the position,
    /// the position moved past them, what the buffer held replaced; a block
    /// past the end refused as `UnexpectedEof`, the case the bag readers
    /// report as a truncated chunk.
    #[test]
    fn a_block_is_read_exactly_or_refused_at_the_end() {
        use std::io::{Seek, SeekFrom, Write};
        let data: Vec<u8> = (0..=255u8).cycle().take(70_000).collect();
        let mut tmp = tempfile::tempfile().unwrap();
        tmp.write_all(&data).unwrap();
        let mut streams = [
            Stream::File(tmp),
            Stream::Memory(std::io::Cursor::new(&data[..])),
        ];
        for s in &mut streams {
            let mut buf = vec![9u8; 3];
            s.seek(SeekFrom::Start(1_000)).unwrap();
            s.read_block(65_536, &mut buf).unwrap();
            assert_eq!(buf, &data[1_000..66_536]);
            s.read_block(3_464, &mut buf).unwrap();
            assert_eq!(buf, &data[66_536..]);
            s.seek(SeekFrom::Start(69_999)).unwrap();
            let e = s.read_block(2, &mut buf).unwrap_err();
            assert_eq!(e.kind(), std::io::ErrorKind::UnexpectedEof);
        }
    }
}
