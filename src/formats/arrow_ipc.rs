//! A small, bounded reader of Arrow IPC *files* (Feather v2, `.feather`) for
//! flat tables of Utf8 / LargeUtf8 and Float64 columns: what a calibration
//! table such as Argoverse 2's `egovehicle_SE3_sensor` needs.
//!
//! Layout followed, from the Arrow columnar format specification
//! (<https://arrow.apache.org/docs/format/Columnar.html>):
//! - "IPC File Format": `ARROW1`, padding to 8 bytes, the stream, the `Footer`
//!   flatbuffer (`version`, `schema`, `dictionaries`, `recordBatches`: `Block
//!   { offset: long, metaDataLength: int, bodyLength: long }`), its int32
//!   length, `ARROW1`.
//! - "IPC Streaming Format" / "Encapsulated message format": at each block,
//!   `0xFFFFFFFF` (absent in files before 0.15), an int32 metadata size, the
//!   flatbuffer `Message` (header `RecordBatch { length, nodes: [FieldNode
//!   { length, null_count }], buffers: [Buffer { offset, length }],
//!   compression }`), padding, then the body the buffers point into.
//! - "Compression" (`BodyCompression { codec: LZ4_FRAME | ZSTD, method:
//!   BUFFER }`): each buffer is an int64 little-endian uncompressed length
//!   (-1: the bytes follow uncompressed), then one LZ4 frame or ZSTD frame.
//! - "Physical Memory Layout": validity bitmaps (LSB first, 1 = valid; absent
//!   when the node has no null), variable-size binary (int32 offsets for Utf8,
//!   int64 for LargeUtf8, then the UTF-8 bytes), Float64 values little-endian;
//!   buffer order per field is validity, offsets, data.
//!
//! Flatbuffers (Schema.fbs, Message.fbs, File.fbs of the format) are read by
//! hand: root uoffset, vtable through the table's soffset, one u16 field offset
//! per slot, a union as a type byte slot followed by its table slot.
//!
//! Bounds: every offset, length and count is checked against the bytes there
//! before use; a vector of N entries needs its N entries' bytes; a column of N
//! rows needs N values' bytes in its buffers before anything is allocated for
//! it; decompressed bytes count against one budget per file (`cap`, the
//! `--max-file-size` cap) and are read incrementally, so memory grows with
//! bytes actually decompressed, never with a length the file claims. Nested
//! types (List, Struct, ...), dictionary-encoded columns, big-endian files and
//! Arrow's view types are refused with a message naming the column.

use crate::bytes::{self, Endian, Primitive, Short};
use crate::diagnostic::{Error, Result};
use crate::tolerances::ARROW_ZSTD_MIN_WINDOW_LOG;
use std::io::Read;

/// The magic string at both ends of an Arrow IPC file.
pub const MAGIC: &[u8] = b"ARROW1";

/// Whether `bytes` start like an Arrow IPC file.
pub fn is_arrow_file(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

/// Column values, one per row; `None` is a null.
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    /// Utf8 or LargeUtf8.
    Str(Vec<Option<String>>),
    /// Float64.
    F64(Vec<Option<f64>>),
}

/// The requested columns of every record batch, concatenated.
#[derive(Debug, Clone, PartialEq)]
pub struct Columns {
    /// Rows in all record batches.
    pub rows: usize,
    /// `(name, values)` in the order requested.
    pub columns: Vec<(String, Column)>,
}

fn err(msg: impl std::fmt::Display) -> Error {
    Error::parse(format!("Arrow IPC file: {msg}"))
}

// ---------------------------------------------------------------------------
// Bounds-checked little-endian reads (the crate's byte reader)
// ---------------------------------------------------------------------------

fn short(s: Short) -> Error {
    err(format!(
        "expected {} bytes at byte {}, found {} (truncated or corrupt)",
        s.wanted, s.at, s.left
    ))
}

fn slice(b: &[u8], pos: usize, len: usize) -> Result<&[u8]> {
    bytes::slice_at(b, pos, len).map_err(short)
}

/// The little-endian field of type `T` at byte `pos` of `b`.
fn at<T: Primitive>(b: &[u8], pos: usize) -> Result<T> {
    bytes::read_at(b, pos, Endian::Little).map_err(short)
}

fn u16_at(b: &[u8], pos: usize) -> Result<u16> {
    at(b, pos)
}
fn u32_at(b: &[u8], pos: usize) -> Result<u32> {
    at(b, pos)
}
fn i32_at(b: &[u8], pos: usize) -> Result<i32> {
    at(b, pos)
}
fn i64_at(b: &[u8], pos: usize) -> Result<i64> {
    at(b, pos)
}

/// A non-negative int64 from the file as a size, else an error naming it.
fn size(v: i64, what: &str) -> Result<usize> {
    usize::try_from(v).map_err(|_| err(format!("{what}: expected a non-negative size, found {v}")))
}

// ---------------------------------------------------------------------------
// Flatbuffer tables
// ---------------------------------------------------------------------------

/// One flatbuffer table: its buffer, position and vtable.
#[derive(Clone, Copy)]
struct Fb<'a> {
    buf: &'a [u8],
    pos: usize,
    vtable: usize,
    vt_len: usize,
}

impl<'a> Fb<'a> {
    /// The root table of a flatbuffer.
    fn root(buf: &'a [u8]) -> Result<Self> {
        Fb::at(buf, u32_at(buf, 0)? as usize)
    }

    fn at(buf: &'a [u8], pos: usize) -> Result<Self> {
        let soff = i64::from(i32_at(buf, pos)?);
        let vtable = i64::try_from(pos)
            .ok()
            .and_then(|p| p.checked_sub(soff))
            .and_then(|v| usize::try_from(v).ok())
            .ok_or_else(|| {
                err(format!(
                    "flatbuffer table at byte {pos}: vtable outside the buffer"
                ))
            })?;
        let vt_len = usize::from(u16_at(buf, vtable)?);
        if vt_len < 4 {
            return Err(err(format!(
                "flatbuffer vtable at byte {vtable}: length {vt_len}, expected at least 4"
            )));
        }
        slice(buf, vtable, vt_len)?;
        Ok(Fb {
            buf,
            pos,
            vtable,
            vt_len,
        })
    }

    /// Where field `slot` is stored, `None` when absent.
    fn field(&self, slot: usize) -> Result<Option<usize>> {
        let o = 4 + 2 * slot;
        if o + 2 > self.vt_len {
            return Ok(None);
        }
        let f = usize::from(u16_at(self.buf, self.vtable + o)?);
        Ok((f != 0).then(|| self.pos.saturating_add(f)))
    }

    fn u8_or(&self, slot: usize, default: u8) -> Result<u8> {
        match self.field(slot)? {
            Some(p) => at(self.buf, p),
            None => Ok(default),
        }
    }
    fn i16_or(&self, slot: usize, default: i16) -> Result<i16> {
        match self.field(slot)? {
            Some(p) => at(self.buf, p),
            None => Ok(default),
        }
    }
    fn i64_or(&self, slot: usize, default: i64) -> Result<i64> {
        match self.field(slot)? {
            Some(p) => i64_at(self.buf, p),
            None => Ok(default),
        }
    }

    /// The target of the uoffset in `slot`.
    fn target(&self, slot: usize) -> Result<Option<usize>> {
        let Some(p) = self.field(slot)? else {
            return Ok(None);
        };
        let off = u32_at(self.buf, p)? as usize;
        p.checked_add(off)
            .filter(|&t| t < self.buf.len())
            .map(Some)
            .ok_or_else(|| {
                err(format!(
                    "flatbuffer offset at byte {p} points outside the buffer"
                ))
            })
    }

    fn table(&self, slot: usize) -> Result<Option<Fb<'a>>> {
        self.target(slot)?.map(|t| Fb::at(self.buf, t)).transpose()
    }

    /// A vector in `slot` whose elements are `elem` bytes: (first element, count).
    fn vector(&self, slot: usize, elem: usize) -> Result<Option<(usize, usize)>> {
        let Some(v) = self.target(slot)? else {
            return Ok(None);
        };
        let n = u32_at(self.buf, v)? as usize;
        let bytes = n
            .checked_mul(elem)
            .ok_or_else(|| err(format!("flatbuffer vector at byte {v}: {n} entries")))?;
        slice(self.buf, v + 4, bytes)?;
        Ok(Some((v + 4, n)))
    }

    /// The tables of a vector of tables.
    fn tables(&self, slot: usize) -> Result<Vec<Fb<'a>>> {
        let Some((start, n)) = self.vector(slot, 4)? else {
            return Ok(Vec::new());
        };
        (0..n)
            .map(|i| {
                let p = start + 4 * i;
                Fb::at(self.buf, p.saturating_add(u32_at(self.buf, p)? as usize))
            })
            .collect()
    }

    fn string(&self, slot: usize) -> Result<Option<&'a str>> {
        let Some(s) = self.target(slot)? else {
            return Ok(None);
        };
        let n = u32_at(self.buf, s)? as usize;
        let b = slice(self.buf, s + 4, n)?;
        std::str::from_utf8(b)
            .map(Some)
            .map_err(|_| err(format!("flatbuffer string at byte {s}: expected UTF-8")))
    }
}

// ---------------------------------------------------------------------------
// Schema
// ---------------------------------------------------------------------------

/// How a top-level field is stored.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Utf8,
    LargeUtf8,
    Float64,
    /// Another flat type: skipped, `buffers` buffers.
    Skip {
        buffers: usize,
        name: &'static str,
    },
}

#[derive(Debug, Clone)]
struct Field {
    name: String,
    kind: Kind,
}

/// The flat `Type` union members, Schema.fbs numbering: name and buffer count.
fn flat_type(t: u8) -> Option<(&'static str, usize)> {
    Some(match t {
        1 => ("Null", 0),
        2 => ("Int", 2),
        3 => ("FloatingPoint", 2),
        4 => ("Binary", 3),
        5 => ("Utf8", 3),
        6 => ("Bool", 2),
        7 => ("Decimal", 2),
        8 => ("Date", 2),
        9 => ("Time", 2),
        10 => ("Timestamp", 2),
        11 => ("Interval", 2),
        15 => ("FixedSizeBinary", 2),
        18 => ("Duration", 2),
        19 => ("LargeBinary", 3),
        20 => ("LargeUtf8", 3),
        _ => return None,
    })
}

fn field(f: &Fb) -> Result<Field> {
    // Field slots: name 0, nullable 1, type_type 2, type 3, dictionary 4, children 5.
    let name = f.string(0)?.unwrap_or("").to_string();
    let t = f.u8_or(2, 0)?;
    let Some((tname, buffers)) = flat_type(t) else {
        return Err(err(format!(
            "column \"{}\": type number {t} (nested, view or unknown): expected flat columns (Utf8, Float64, ...)",
            crate::sanitize::quote(&name)
        )));
    };
    if f.field(4)?.is_some() || f.vector(5, 4)?.is_some_and(|(_, n)| n > 0) {
        return Err(err(format!(
            "column \"{}\": dictionary-encoded or with children: expected a plain {tname} column",
            crate::sanitize::quote(&name)
        )));
    }
    let kind = match t {
        5 => Kind::Utf8,
        20 => Kind::LargeUtf8,
        // FloatingPoint { precision: HALF 0 | SINGLE 1 | DOUBLE 2 }.
        3 if f.table(3)?.map(|p| p.i16_or(0, 0)).transpose()? == Some(2) => Kind::Float64,
        3 => Kind::Skip {
            buffers,
            name: "FloatingPoint (half or single)",
        },
        _ => Kind::Skip {
            buffers,
            name: tname,
        },
    };
    Ok(Field { name, kind })
}

fn kind_name(k: Kind) -> &'static str {
    match k {
        Kind::Utf8 => "Utf8",
        Kind::LargeUtf8 => "LargeUtf8",
        Kind::Float64 => "Float64",
        Kind::Skip { name, .. } => name,
    }
}

fn buffers_of(k: Kind) -> usize {
    match k {
        Kind::Utf8 | Kind::LargeUtf8 => 3,
        Kind::Float64 => 2,
        Kind::Skip { buffers, .. } => buffers,
    }
}

/// A record-batch block of the footer: message offset, metadata and body lengths.
#[derive(Debug, Clone, Copy)]
struct Block {
    offset: usize,
    meta_len: usize,
    body_len: usize,
}

/// The schema and the record-batch blocks of the footer.
fn footer(bytes: &[u8]) -> Result<(Vec<Field>, Vec<Block>)> {
    let n = bytes.len();
    if n < 2 * MAGIC.len() + 4 || !bytes.ends_with(MAGIC) {
        return Err(err(format!(
            "expected the magic `ARROW1` at the end too, found {n} bytes without it (truncated?)"
        )));
    }
    let len_pos = n - MAGIC.len() - 4;
    let flen = i32_at(bytes, len_pos)?;
    let flen = usize::try_from(flen)
        .ok()
        .filter(|&l| l <= len_pos.saturating_sub(8))
        .ok_or_else(|| {
            err(format!(
                "footer length {flen} at byte {len_pos}: expected 0..={}",
                len_pos.saturating_sub(8)
            ))
        })?;
    let buf = &bytes[len_pos - flen..len_pos];
    // Footer slots: version 0, schema 1, dictionaries 2, recordBatches 3.
    let root = Fb::root(buf)?;
    let schema = root
        .table(1)?
        .ok_or_else(|| err("footer: expected a schema, found none"))?;
    // Schema slots: endianness 0 (Little 0, Big 1), fields 1.
    if schema.i16_or(0, 0)? != 0 {
        return Err(err("big-endian file: expected little-endian"));
    }
    let fields = schema
        .tables(1)?
        .iter()
        .map(field)
        .collect::<Result<Vec<_>>>()?;
    let Some((start, count)) = root.vector(3, 24)? else {
        return Ok((fields, Vec::new()));
    };
    let blocks = (0..count)
        .map(|i| {
            let p = start + 24 * i;
            Ok(Block {
                offset: size(i64_at(buf, p)?, "record batch offset")?,
                meta_len: size(
                    i64::from(i32_at(buf, p + 8)?),
                    "record batch metadata length",
                )?,
                body_len: size(i64_at(buf, p + 16)?, "record batch body length")?,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    disjoint(&blocks, len_pos - flen)?;
    Ok((fields, blocks))
}

/// Blocks in file order, none overlapping the next or the footer (at
/// `footer`): each byte of the file is read as at most one batch, so the rows
/// returned never outnumber what the file holds (many blocks naming one batch
/// would multiply them).
fn disjoint(blocks: &[Block], footer: usize) -> Result<()> {
    let mut from = MAGIC.len();
    for (k, b) in blocks.iter().enumerate() {
        let end = b
            .offset
            .checked_add(b.meta_len)
            .and_then(|e| e.checked_add(b.body_len))
            .filter(|&e| b.offset >= from && e <= footer)
            .ok_or_else(|| {
                err(format!(
                    "record batch {} at byte {} ({} + {} bytes): expected a block after byte {from} and before the footer at byte {footer}, not overlapping another",
                    k + 1,
                    b.offset,
                    b.meta_len,
                    b.body_len
                ))
            })?;
        from = end;
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Record batches
// ---------------------------------------------------------------------------

#[derive(Debug, Clone, Copy, PartialEq)]
enum Codec {
    Lz4Frame,
    Zstd,
}

/// A record batch: rows, field nodes, buffers (offset, length in the body),
/// its compression and body.
struct Batch<'a> {
    rows: usize,
    nodes: Vec<(i64, i64)>,
    buffers: Vec<(usize, usize)>,
    codec: Option<Codec>,
    body: &'a [u8],
}

/// The flatbuffer `Message` of a block and the body after it.
fn message(bytes: &[u8], b: Block) -> Result<(&[u8], &[u8])> {
    let meta = slice(bytes, b.offset, b.meta_len)?;
    let body_at = b.offset.saturating_add(b.meta_len);
    let body = slice(bytes, body_at, b.body_len)?;
    // Continuation marker 0xFFFFFFFF then the size, or (before 0.15) the size alone.
    let (skip, len) = match i32_at(meta, 0)? {
        -1 => (8, i32_at(meta, 4)?),
        l => (4, l),
    };
    let len = usize::try_from(len)
        .ok()
        .filter(|&l| l <= meta.len().saturating_sub(skip))
        .ok_or_else(|| {
            err(format!(
                "message at byte {}: metadata size {len} does not fit its block of {} bytes",
                b.offset, b.meta_len
            ))
        })?;
    Ok((&meta[skip..skip + len], body))
}

fn batch<'a>(bytes: &'a [u8], b: Block) -> Result<Batch<'a>> {
    let (meta, body) = message(bytes, b)?;
    // Message slots: version 0, header_type 1, header 2, bodyLength 3.
    let msg = Fb::root(meta)?;
    let ht = msg.u8_or(1, 0)?;
    if ht != 3 {
        return Err(err(format!(
            "message at byte {}: header type {ht}, expected a RecordBatch (3)",
            b.offset
        )));
    }
    let rb = msg.table(2)?.ok_or_else(|| {
        err(format!(
            "message at byte {}: expected a RecordBatch, found none",
            b.offset
        ))
    })?;
    // RecordBatch slots: length 0, nodes 1, buffers 2, compression 3.
    let rows = size(rb.i64_or(0, 0)?, "record batch length")?;
    let read_pairs = |slot| -> Result<Vec<(i64, i64)>> {
        let Some((start, n)) = rb.vector(slot, 16)? else {
            return Ok(Vec::new());
        };
        (0..n)
            .map(|i| {
                Ok((
                    i64_at(meta, start + 16 * i)?,
                    i64_at(meta, start + 16 * i + 8)?,
                ))
            })
            .collect()
    };
    let nodes = read_pairs(1)?;
    let buffers = read_pairs(2)?
        .into_iter()
        .map(|(o, l)| {
            let (o, l) = (size(o, "buffer offset")?, size(l, "buffer length")?);
            slice(body, o, l)?;
            Ok((o, l))
        })
        .collect::<Result<Vec<_>>>()?;
    let codec = match rb.table(3)? {
        None => None,
        // BodyCompression slots: codec 0 (LZ4_FRAME 0, ZSTD 1), method 1 (BUFFER 0).
        Some(c) => match (c.u8_or(0, 0)?, c.u8_or(1, 0)?) {
            (0, 0) => Some(Codec::Lz4Frame),
            (1, 0) => Some(Codec::Zstd),
            (codec, method) => {
                return Err(err(format!("body compression codec {codec} method {method}: expected LZ4_FRAME (0) or ZSTD (1) per buffer (0)")))
            }
        },
    };
    Ok(Batch {
        rows,
        nodes,
        buffers,
        codec,
        body,
    })
}

/// The bytes of buffer `i` of a batch, decompressed when the batch is
/// compressed; `budget` is what may still be decompressed in this file.
fn buffer<'a>(b: &Batch<'a>, i: usize, budget: &mut u64) -> Result<std::borrow::Cow<'a, [u8]>> {
    use std::borrow::Cow;
    let (o, l) = b.buffers[i];
    let raw = &b.body[o..o + l];
    let Some(codec) = b.codec else {
        return Ok(Cow::Borrowed(raw));
    };
    if raw.is_empty() {
        return Ok(Cow::Borrowed(raw));
    }
    let claimed = i64_at(raw, 0)?;
    if claimed == -1 {
        return Ok(Cow::Borrowed(&raw[8..]));
    }
    let want = u64::try_from(claimed)
        .ok()
        .filter(|&c| c <= *budget)
        .ok_or_else(|| {
            Error::limit(format!(
                "Arrow IPC file: buffer {i} claims {claimed} bytes uncompressed: expected 0..={} (what is left of the --max-file-size cap)",
                *budget
            ))
        })?;
    let out = decompress(codec, &raw[8..], want, i)?;
    if out.len() as u64 != want {
        return Err(err(format!(
            "buffer {i}: decompresses to {}{} bytes, its header says {want}",
            out.len(),
            if out.len() as u64 > want { "+" } else { "" }
        )));
    }
    *budget -= want;
    Ok(Cow::Owned(out))
}

/// Decompress one frame, reading at most `want + 1` bytes (so the output
/// grows with the data, never with the claim).
fn decompress(codec: Codec, frame: &[u8], want: u64, i: usize) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    let bad = |e: std::io::Error| err(format!("buffer {i}: expected a {codec:?} frame: {e}"));
    match codec {
        Codec::Lz4Frame => {
            let d = lz4::Decoder::new(frame).map_err(bad)?;
            d.take(want + 1).read_to_end(&mut out).map_err(bad)?;
        }
        Codec::Zstd => {
            let mut d = zstd::stream::read::Decoder::with_buffer(frame).map_err(bad)?;
            // The window (the decoder's own allocation) fits the claim, or
            // zstd's default window when the claim is small.
            let log = (64 - want.leading_zeros()).clamp(ARROW_ZSTD_MIN_WINDOW_LOG, 31);
            d.window_log_max(log).map_err(bad)?;
            d.take(want + 1).read_to_end(&mut out).map_err(bad)?;
        }
    }
    Ok(out)
}

// ---------------------------------------------------------------------------
// Columns
// ---------------------------------------------------------------------------

/// Validity of `rows` rows: `None` when every row is valid.
fn validity(bits: &[u8], rows: usize, nulls: i64, col: &str) -> Result<Option<Vec<bool>>> {
    if bits.is_empty() {
        if nulls > 0 {
            return Err(err(format!(
                "column \"{col}\": {nulls} nulls and no validity bitmap"
            )));
        }
        return Ok(None);
    }
    let need = rows.div_ceil(8);
    if bits.len() < need {
        return Err(err(format!(
            "column \"{col}\": validity bitmap of {} bytes for {rows} rows: expected {need}",
            bits.len()
        )));
    }
    Ok(Some(
        (0..rows).map(|r| bits[r / 8] >> (r % 8) & 1 == 1).collect(),
    ))
}

fn floats(
    data: &[u8],
    rows: usize,
    valid: Option<Vec<bool>>,
    col: &str,
) -> Result<Vec<Option<f64>>> {
    let need = rows
        .checked_mul(8)
        .filter(|&n| n <= data.len())
        .ok_or_else(|| {
            err(format!(
                "column \"{col}\": {rows} Float64 rows need {} bytes, the buffer holds {}",
                rows.saturating_mul(8),
                data.len()
            ))
        })?;
    (0..need / 8)
        .map(|r| {
            let v: f64 = at(data, 8 * r)?;
            Ok(valid.as_ref().is_none_or(|m| m[r]).then_some(v))
        })
        .collect()
}

fn strings(
    offsets: &[u8],
    data: &[u8],
    rows: usize,
    wide: bool,
    valid: Option<Vec<bool>>,
    col: &str,
) -> Result<Vec<Option<String>>> {
    let w = if wide { 8 } else { 4 };
    let need = rows
        .checked_add(1)
        .and_then(|n| n.checked_mul(w))
        .filter(|&n| n <= offsets.len());
    if need.is_none() {
        return Err(err(format!(
            "column \"{col}\": {rows} string rows need {} offset bytes, the buffer holds {}",
            (rows + 1).saturating_mul(w),
            offsets.len()
        )));
    }
    let off = |r: usize| -> Result<usize> {
        let v = if wide {
            i64_at(offsets, r * 8)?
        } else {
            i64::from(i32_at(offsets, r * 4)?)
        };
        size(v, "string offset")
    };
    (0..rows)
        .map(|r| {
            let (a, b) = (off(r)?, off(r + 1)?);
            if b < a || b > data.len() {
                return Err(err(format!(
                    "column \"{col}\" row {}: string offsets {a}..{b} outside the {} data bytes",
                    r + 1,
                    data.len()
                )));
            }
            if valid.as_ref().is_some_and(|m| !m[r]) {
                return Ok(None);
            }
            String::from_utf8(data[a..b].to_vec())
                .map(Some)
                .map_err(|_| err(format!("column \"{col}\" row {}: expected UTF-8", r + 1)))
        })
        .collect()
}

/// Column `f` of batch `b`, whose buffers start at `first`.
fn column(
    b: &Batch,
    f: &Field,
    node: (i64, i64),
    first: usize,
    budget: &mut u64,
) -> Result<Column> {
    let col = crate::sanitize::quote(&f.name);
    let (len, nulls) = node;
    if size(len, "field node length")? != b.rows || !(0..=len).contains(&nulls) {
        return Err(err(format!(
            "column \"{col}\": {len} rows ({nulls} nulls) in a batch of {}",
            b.rows
        )));
    }
    let valid = validity(&buffer(b, first, budget)?, b.rows, nulls, &col)?;
    Ok(match f.kind {
        Kind::Float64 => Column::F64(floats(&buffer(b, first + 1, budget)?, b.rows, valid, &col)?),
        Kind::Utf8 | Kind::LargeUtf8 => {
            let offsets = buffer(b, first + 1, budget)?;
            let data = buffer(b, first + 2, budget)?;
            Column::Str(strings(
                &offsets,
                &data,
                b.rows,
                f.kind == Kind::LargeUtf8,
                valid,
                &col,
            )?)
        }
        Kind::Skip { name, .. } => {
            return Err(err(format!("column \"{col}\": {name} is not read")))
        }
    })
}

fn append(to: &mut Column, from: Column) {
    match (to, from) {
        (Column::Str(a), Column::Str(b)) => a.extend(b),
        (Column::F64(a), Column::F64(b)) => a.extend(b),
        _ => {}
    }
}

/// Where each wanted column is among `fields`, with its kind checked.
fn locate(fields: &[Field], wanted: &[(&str, bool)]) -> Result<Vec<usize>> {
    let names = || {
        fields
            .iter()
            .map(|f| crate::sanitize::quote(&f.name))
            .collect::<Vec<_>>()
            .join(", ")
    };
    wanted
        .iter()
        .map(|&(name, text)| {
            let mut at = fields.iter().enumerate().filter(|(_, f)| f.name == name);
            let (i, f) = at.next().ok_or_else(|| {
                err(format!(
                    "expected a column \"{name}\", found columns {}",
                    names()
                ))
            })?;
            if at.next().is_some() {
                return Err(err(format!(
                    "column \"{name}\" appears twice: expected one"
                )));
            }
            let ok = if text {
                matches!(f.kind, Kind::Utf8 | Kind::LargeUtf8)
            } else {
                f.kind == Kind::Float64
            };
            if !ok {
                let want = if text { "Utf8 or LargeUtf8" } else { "Float64" };
                return Err(err(format!(
                    "column \"{name}\": expected {want}, found {}",
                    kind_name(f.kind)
                )));
            }
            Ok(i)
        })
        .collect()
}

/// Read the columns `wanted` (name, `true` for a string column, `false` for
/// Float64) of every record batch of the Arrow IPC file `bytes`; at most
/// `cap` bytes are decompressed in all.
pub fn read_columns(bytes: &[u8], wanted: &[(&str, bool)], cap: u64) -> Result<Columns> {
    if !is_arrow_file(bytes) {
        let v1 = if bytes.starts_with(b"FEA1") {
            " (a Feather version 1 file: rewrite it with pyarrow's feather.write_feather, version 2)"
        } else {
            ""
        };
        return Err(err(format!("expected the magic `ARROW1` at the start{v1}")));
    }
    let (fields, blocks) = footer(bytes)?;
    let at = locate(&fields, wanted)?;
    let first: Vec<usize> = fields
        .iter()
        .scan(0usize, |n, f| {
            let here = *n;
            *n += buffers_of(f.kind);
            Some(here)
        })
        .collect();
    let total: usize = fields.iter().map(|f| buffers_of(f.kind)).sum();
    let mut budget = cap;
    let mut table = Columns {
        rows: 0,
        columns: Vec::new(),
    };
    for (k, &blk) in blocks.iter().enumerate() {
        let b = batch(bytes, blk)?;
        if b.nodes.len() != fields.len() || b.buffers.len() != total {
            return Err(err(format!(
                "record batch {}: {} field nodes and {} buffers: expected {} and {} for the schema's columns",
                k + 1, b.nodes.len(), b.buffers.len(), fields.len(), total
            )));
        }
        for (j, &i) in at.iter().enumerate() {
            let c = column(&b, &fields[i], b.nodes[i], first[i], &mut budget)?;
            match table.columns.get_mut(j) {
                Some((_, to)) => append(to, c),
                None => table.columns.push((fields[i].name.clone(), c)),
            }
        }
        table.rows = table.rows.saturating_add(b.rows);
    }
    if table.columns.is_empty() {
        // No record batch: every wanted column empty.
        table.columns = at
            .iter()
            .map(|&i| {
                let empty = match fields[i].kind {
                    Kind::Float64 => Column::F64(Vec::new()),
                    _ => Column::Str(Vec::new()),
                };
                (fields[i].name.clone(), empty)
            })
            .collect();
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_or_unmagical_input_is_an_error() {
        for b in [
            &b""[..],
            b"ARROW1",
            b"ARROW1\0\0ARROW1",
            b"FEA1xxxx",
            b"ARROW1\0\0\xff\xff\xff\x7fARROW1",
        ] {
            assert!(read_columns(b, &[("x", false)], 1 << 20).is_err(), "{b:?}");
        }
    }

    #[test]
    fn blocks_must_not_overlap() {
        let b = |offset, meta_len, body_len| Block {
            offset,
            meta_len,
            body_len,
        };
        assert!(disjoint(&[b(8, 100, 100), b(208, 50, 50)], 400).is_ok());
        // The same batch named twice would double its rows.
        let e = disjoint(&[b(8, 100, 100), b(8, 100, 100)], 400).expect_err("aliased");
        assert!(e.message.contains("record batch 2 at byte 8"), "{e}");
        assert!(disjoint(&[b(8, 100, 100)], 150).is_err(), "into the footer");
        assert!(disjoint(&[b(0, 100, 100)], 400).is_err(), "over the magic");
        assert!(disjoint(&[b(8, usize::MAX, 1)], 400).is_err(), "overflow");
    }
}
