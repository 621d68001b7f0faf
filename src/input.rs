//! Reading input safely: the one place the library opens a file it reads.
//!
//! Only regular files are read (and `-`, standard input, where a command takes
//! one file). The type is checked on the opened descriptor, and the file is
//! opened with `O_NONBLOCK` so that opening a FIFO cannot block before the
//! check refuses it. Every read is bounded by the bytes actually read (a
//! `take(cap + 1)`), never by the size the file system reports: `/dev/zero`
//! reports size 0.
//!
//! Text is decoded once here too: UTF-8 only, a byte-order mark stripped, and
//! lone CR line endings (classic Mac) read as LF.

use crate::diagnostic::{Code, Error, Result};
use std::borrow::Cow;
use std::fs::File;
use std::io::Read;
use std::path::Path;

/// The path that names standard input.
pub const STDIN: &str = "-";

/// Whether `path` names standard input (`-`).
pub fn is_stdin(path: &Path) -> bool {
    path.as_os_str() == STDIN
}

/// Why a file could not be opened or read, typed so that a reader with its own
/// wording (an xacro include, a bag's `metadata.yaml`) can say it its way;
/// [`ReadError::into_error`] gives the wording of this module.
#[derive(Debug)]
pub enum ReadError {
    /// Opening, inspecting or reading it failed.
    Io(std::io::Error),
    /// It is a directory.
    Directory,
    /// It is a FIFO, socket or device (which one).
    NotRegular(&'static str),
    /// It holds more than `cap` bytes (`len`: the size its descriptor
    /// reports, when that already says so).
    TooLarge {
        /// The size reported before reading.
        len: Option<u64>,
        /// The cap.
        cap: u64,
    },
}

impl ReadError {
    /// The error naming `path` (`what` names the cap in a `limit` error).
    pub fn into_error(self, path: &Path, what: &str) -> Error {
        match self {
            ReadError::Io(e) => Error::io(path, &e),
            ReadError::Directory => {
                Error::new(Code::Io, "is a directory: expected a file").in_file(path)
            }
            ReadError::NotRegular(kind) => not_regular(path, kind),
            ReadError::TooLarge {
                len: Some(len),
                cap,
            } => Error::limit(format!(
                "file is {len} bytes: expected at most {cap} bytes ({what})"
            ))
            .in_file(path),
            ReadError::TooLarge { len: None, cap } => Error::limit(format!(
                "file is more than {cap} bytes: expected at most {cap} bytes ({what})"
            ))
            .in_file(path),
        }
    }
}

/// A regular file as [`open_file`] opened it (its descriptor's size) and its
/// bytes, read whole: handed from one reader to the next so that a file is
/// read once.
pub(crate) type ReadWhole = (File, u64, Vec<u8>);

/// Open `path` for reading without blocking (a FIFO cannot hold the open) and
/// refuse anything but a regular file; with the size its descriptor reports.
pub fn open_file(path: &Path) -> std::result::Result<(File, u64), ReadError> {
    let f = match open_nonblocking(path) {
        Ok(f) => f,
        // A socket cannot be opened at all: say what it is (stat does not block).
        Err(e) => match std::fs::metadata(path) {
            Ok(m) if !m.is_file() && !m.is_dir() => {
                return Err(ReadError::NotRegular(kind_of(&m.file_type())))
            }
            _ => return Err(ReadError::Io(e)),
        },
    };
    let meta = f.metadata().map_err(ReadError::Io)?;
    let ft = meta.file_type();
    if ft.is_file() {
        return Ok((f, meta.len()));
    }
    if ft.is_dir() {
        return Err(ReadError::Directory);
    }
    Err(ReadError::NotRegular(kind_of(&ft)))
}

/// Open `path` for reading without blocking and refuse anything but a regular
/// file ("not a regular file", naming its kind).
pub fn open_regular(path: &Path) -> Result<File> {
    open_stream(path).map(|(f, _)| f)
}

/// [`open_regular`] with the file's size: the one way to open a file read in
/// a stream (a bag through its index, a point file in bounded pieces) rather
/// than whole.
pub fn open_stream(path: &Path) -> Result<(File, u64)> {
    open_file(path).map_err(|e| e.into_error(path, "a file"))
}

fn not_regular(path: &Path, kind: &str) -> Error {
    Error::new(
        Code::Io,
        format!(
            "not a regular file ({kind}): expected a regular file (to read a pipe, pass `-` and redirect it to standard input)"
        ),
    )
    .in_file(path)
}

#[cfg(unix)]
fn open_nonblocking(path: &Path) -> std::io::Result<File> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
}

#[cfg(not(unix))]
fn open_nonblocking(path: &Path) -> std::io::Result<File> {
    File::open(path)
}

#[cfg(unix)]
fn kind_of(ft: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if ft.is_fifo() {
        "a FIFO"
    } else if ft.is_socket() {
        "a socket"
    } else if ft.is_char_device() {
        "a character device"
    } else if ft.is_block_device() {
        "a block device"
    } else {
        "not a file"
    }
}

#[cfg(not(unix))]
fn kind_of(_: &std::fs::FileType) -> &'static str {
    "not a file"
}

/// Read at most `cap` bytes from `r`; more is a `limit` error (`what` names
/// the cap in the message).
pub fn read_capped(r: impl Read, cap: u64, path: &Path, what: &str) -> Result<Vec<u8>> {
    let mut buf = Vec::new();
    r.take(cap.saturating_add(1))
        .read_to_end(&mut buf)
        .map_err(|e| Error::io(path, &e))?;
    if buf.len() as u64 > cap {
        return Err(Error::limit(format!(
            "file is more than {cap} bytes: expected at most {cap} bytes ({what})"
        ))
        .in_file(path));
    }
    Ok(buf)
}

/// A reader that fails (rather than stopping short) once more than `cap`
/// bytes come through: for streams read without holding them.
pub struct Capped<R> {
    inner: R,
    left: u64,
    cap: u64,
}

impl<R: Read> Capped<R> {
    /// At most `cap` bytes of `inner`.
    pub fn new(inner: R, cap: u64) -> Self {
        Capped {
            inner,
            left: cap,
            cap,
        }
    }
}

impl<R: Read> Read for Capped<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        let want = buf
            .len()
            .min(usize::try_from(self.left).unwrap_or(usize::MAX).max(1));
        let n = self.inner.read(&mut buf[..want])?;
        if n as u64 > self.left {
            return Err(std::io::Error::other(format!(
                "input is more than {} bytes: expected at most that",
                self.cap
            )));
        }
        self.left -= n as u64;
        Ok(n)
    }
}

/// The bytes of a regular file (or of standard input for `-`), at most `cap`.
pub fn read_bytes(path: &Path, cap: u64, what: &str) -> Result<Vec<u8>> {
    if is_stdin(path) {
        return read_capped(std::io::stdin().lock(), cap, Path::new("<stdin>"), what);
    }
    read_file(path, cap).map_err(|e| e.into_error(path, what))
}

/// The bytes of the regular file `path`, at most `cap` (typed errors).
pub fn read_file(path: &Path, cap: u64) -> std::result::Result<Vec<u8>, ReadError> {
    let (f, len) = open_file(path)?;
    read_open(f, len, cap)
}

/// The rest of a file opened by [`open_file`] (`len` bytes by its
/// descriptor), at most `cap`: the reported size refuses a large file before
/// reading it, the bytes read refuse one that grows.
pub fn read_open(f: impl Read, len: u64, cap: u64) -> std::result::Result<Vec<u8>, ReadError> {
    if len > cap {
        return Err(ReadError::TooLarge {
            len: Some(len),
            cap,
        });
    }
    // Room for the size the descriptor reports (and the byte that finds the
    // end): one read for a small file, not one per doubling of the buffer.
    let mut buf = Vec::with_capacity(usize::try_from(len).map_or(0, |n| n.saturating_add(1)));
    f.take(cap.saturating_add(1))
        .read_to_end(&mut buf)
        .map_err(ReadError::Io)?;
    if buf.len() as u64 > cap {
        return Err(ReadError::TooLarge { len: None, cap });
    }
    Ok(buf)
}

/// At most the first `n` bytes of the regular file `path` (`None`: it is not
/// one, or cannot be read): for magic bytes.
pub fn read_head(path: &Path, n: usize) -> Option<Vec<u8>> {
    let (f, _) = open_file(path).ok()?;
    head_of(f, n).ok()
}

/// At most the first `n` bytes of `r` (fewer only at its end).
pub fn head_of(r: impl Read, n: usize) -> std::io::Result<Vec<u8>> {
    let mut head = Vec::with_capacity(n);
    r.take(n as u64).read_to_end(&mut head)?;
    Ok(head)
}

/// The text of a file: [`read_bytes`], then [`decode`].
pub fn read_text(path: &Path, cap: u64, what: &str) -> Result<String> {
    let bytes = read_bytes(path, cap, what)?;
    decode(bytes).map_err(|e| e.in_file(path))
}

/// UTF-8 text with the byte-order mark stripped and lone CRs read as LF; a
/// byte that is not UTF-8 is an error at its line and column.
pub fn decode(bytes: Vec<u8>) -> Result<String> {
    match String::from_utf8(bytes) {
        // The text itself when there is nothing to change (no copy).
        Ok(t) => Ok(match normalize(&t) {
            Cow::Borrowed(b) if b.len() == t.len() => t,
            n => n.into_owned(),
        }),
        Err(e) => {
            let off = e.utf8_error().valid_up_to();
            let valid = std::str::from_utf8(&e.as_bytes()[..off]).unwrap_or("");
            let line = valid.bytes().filter(|&b| b == b'\n').count() + 1;
            let col = valid.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            Err(Error::parse(format!(
                "expected UTF-8 text, found byte 0x{:02x} (binary file?)",
                e.as_bytes().get(off).copied().unwrap_or(0)
            ))
            .at_line(line, Some(col)))
        }
    }
}

/// `text` without a leading byte-order mark, its lone CRs (not followed by LF)
/// replaced by LF; borrowed when there is nothing to change. Offsets after the
/// mark keep their lines: a CR and an LF are both one byte.
pub fn normalize(text: &str) -> Cow<'_, str> {
    let t = strip_bom(text);
    let b = t.as_bytes();
    let lone_cr = b.contains(&b'\r')
        && b.iter()
            .enumerate()
            .any(|(i, &c)| c == b'\r' && b.get(i + 1) != Some(&b'\n'));
    if !lone_cr {
        return Cow::Borrowed(t);
    }
    let mut out = String::with_capacity(t.len());
    let mut chars = t.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '\r' && chars.peek() != Some(&'\n') {
            out.push('\n');
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// `text` without a leading UTF-8 byte-order mark.
pub fn strip_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// The size the file system reports for `path` (symlinks followed), `None`
/// when it cannot say. For decisions that may be wrong without harm (whether
/// a read is long enough to show progress), never to bound a read: a device
/// reports 0.
pub fn reported_size(path: &Path) -> Option<u64> {
    std::fs::metadata(path).ok().map(|m| m.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalize_strips_the_mark_and_reads_lone_crs_as_lf() {
        assert_eq!(normalize("\u{feff}a\r\nb"), "a\r\nb");
        assert_eq!(normalize("a\rb\r\nc\r"), "a\nb\r\nc\n");
        assert!(matches!(normalize("a\nb"), Cow::Borrowed(_)));
    }

    #[test]
    fn capped_reads_stop_at_the_cap() {
        let r = std::io::repeat(0).take(10_000);
        let e = read_capped(r, 100, Path::new("x"), "cap").unwrap_err();
        assert!(e.message.contains("more than 100 bytes"), "{e}");
        let ok = read_capped(&b"abc"[..], 3, Path::new("x"), "cap").unwrap();
        assert_eq!(ok, b"abc");
    }
}
