//! A bounded reader: a fixed buffer over any `Read`, refilled in place, with
//! line and record access. The buffer grows only for a single line or record
//! longer than it, up to the caps in `tolerances`.

use crate::diagnostic::{Code, Error, Result};
use crate::tolerances::{MAX_POINT_LINE_BYTES, POINT_READ_BUFFER};
use std::io::Read;

pub(crate) struct Source<R> {
    r: R,
    buf: Vec<u8>,
    start: usize,
    end: usize,
    eof: bool,
    /// Stream offset of `buf[0]`.
    base: u64,
    /// Lines returned by `read_line` so far.
    lines: usize,
}

pub(crate) fn io_error(e: &std::io::Error) -> Error {
    Error::new(Code::Io, format!("cannot read: {e}"))
}

impl<R: Read> Source<R> {
    pub(crate) fn new(r: R) -> Self {
        Self::at(r, 0)
    }

    /// A reader positioned at `base` in the underlying stream (for offsets in
    /// messages).
    pub(crate) fn at(r: R, base: u64) -> Self {
        Source {
            r,
            buf: vec![0; POINT_READ_BUFFER],
            start: 0,
            end: 0,
            eof: false,
            base,
            lines: 0,
        }
    }

    /// Stream offset of the next unread byte.
    pub(crate) fn offset(&self) -> u64 {
        self.base + self.start as u64
    }

    /// Lines returned by [`Source::read_line`] so far.
    pub(crate) fn lines(&self) -> usize {
        self.lines
    }

    /// The unread bytes held now.
    pub(crate) fn data(&self) -> &[u8] {
        &self.buf[self.start..self.end]
    }

    pub(crate) fn consume(&mut self, n: usize) {
        self.start = (self.start + n).min(self.end);
    }

    /// Read until at least `want` bytes are held or the stream ends.
    pub(crate) fn fill(&mut self, want: usize) -> Result<()> {
        while self.end - self.start < want && !self.eof {
            if self.start > 0 {
                self.buf.copy_within(self.start..self.end, 0);
                self.base += self.start as u64;
                self.end -= self.start;
                self.start = 0;
            }
            if self.buf.len() < want {
                self.buf.resize(want, 0);
            }
            match self.r.read(&mut self.buf[self.end..]) {
                Ok(0) => self.eof = true,
                Ok(n) => self.end += n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(io_error(&e)),
            }
        }
        Ok(())
    }

    /// The next line into `out` (without `\n` or a trailing `\r`): `None` at the
    /// end of the stream, otherwise whether the line ended with `\n`.
    pub(crate) fn read_line(&mut self, out: &mut Vec<u8>) -> Result<Option<bool>> {
        out.clear();
        loop {
            if self.start == self.end {
                self.fill(1)?;
                if self.start == self.end {
                    if out.is_empty() {
                        return Ok(None);
                    }
                    self.lines += 1;
                    trim_cr(out);
                    return Ok(Some(false));
                }
            }
            let data = &self.buf[self.start..self.end];
            if let Some(k) = data.iter().position(|&c| c == b'\n') {
                out.extend_from_slice(&data[..k]);
                self.start += k + 1;
                self.lines += 1;
                trim_cr(out);
                return Ok(Some(true));
            }
            out.extend_from_slice(data);
            self.start = self.end;
            if out.len() > MAX_POINT_LINE_BYTES {
                return Err(Error::limit(format!(
                    "expected lines of at most {MAX_POINT_LINE_BYTES} bytes, found a longer one at line {}",
                    self.lines + 1
                ))
                .at_line(self.lines + 1, None));
            }
        }
    }

    /// Everything left in the stream (from the next unread byte), refused
    /// past `cap` bytes.
    pub(crate) fn read_rest(&mut self, cap: u64) -> Result<Vec<u8>> {
        let mut out = self.data().to_vec();
        self.start = self.end;
        (&mut self.r)
            .take(cap.saturating_sub(out.len() as u64).saturating_add(1))
            .read_to_end(&mut out)
            .map_err(|e| io_error(&e))?;
        if out.len() as u64 > cap {
            return Err(Error::limit(format!(
                "point stream is more than the limit of {cap} bytes"
            )));
        }
        Ok(out)
    }

    /// Skip `n` bytes; returns how many there were.
    pub(crate) fn skip(&mut self, n: u64) -> Result<u64> {
        let mut left = n;
        while left > 0 {
            if self.start == self.end {
                self.fill(1)?;
                if self.start == self.end {
                    break;
                }
            }
            let k = ((self.end - self.start) as u64).min(left) as usize;
            self.start += k;
            left -= k as u64;
        }
        Ok(n - left)
    }
}

impl<R: Read> Source<R> {
    /// Whether any byte is left (a binary file after its last record).
    pub(crate) fn has_more(&mut self) -> Result<bool> {
        self.fill(1)?;
        Ok(!self.data().is_empty())
    }

    /// The line number of the next non-blank line, if any (an ascii file after
    /// its last record).
    pub(crate) fn next_nonblank(&mut self) -> Result<Option<usize>> {
        let mut buf = Vec::new();
        while self.read_line(&mut buf)?.is_some() {
            if !buf.iter().all(u8::is_ascii_whitespace) {
                return Ok(Some(self.lines));
            }
        }
        Ok(None)
    }
}

fn trim_cr(v: &mut Vec<u8>) {
    if v.last() == Some(&b'\r') {
        v.pop();
    }
}

/// Header lines up to and including the one `is_end` accepts (each must end
/// with a line break). After it the source stands at the first data byte.
pub(crate) fn header_lines<R: Read>(
    src: &mut Source<R>,
    is_end: &dyn Fn(&str) -> bool,
    what: &str,
) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    let mut buf = Vec::new();
    while lines.len() <= 100_000 {
        match src.read_line(&mut buf)? {
            Some(true) => {}
            _ => break,
        }
        let line = String::from_utf8_lossy(&buf).into_owned();
        let done = is_end(&line);
        lines.push(line);
        if done {
            return Ok(lines);
        }
    }
    Err(Error::parse(format!(
        "{what}: expected the end of the header, found end of file"
    )))
}
