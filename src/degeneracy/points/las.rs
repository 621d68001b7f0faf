//! LAS (1.0 to 1.4) and LAZ (LASzip) point files: LAS decoded by the `las`
//! crate, LAZ by the `laz` crate's LASzip decoder (the one `las` uses), both
//! after a header check of our own.
//!
//! LAS records carry no normals: a LAS file is a raw scan, read by
//! [`read_xyz`](super::read_xyz) (`--estimate-normals`); the normal-reading
//! path refuses it as it refuses a PCD without normal fields. Coordinates are
//! `X * scale + offset` in f64, as the LAS specification and laspy compute
//! them. Returns are not read; the classification only to keep the points
//! of given classes (`--class`, e.g. 2 for ground).
//!
//! The `las` crate trusts its header (a point count times the record length
//! that overflows, an extended VLR of 2^64 bytes, a LASzip chunk table of
//! 2^32 entries are allocated or multiplied as found), so the header is
//! checked first against the file's length:
//! - LAS: the records must end exactly where the file (or its extended VLRs)
//!   ends: fewer bytes is a truncated file, more is a header claiming fewer
//!   points than the file holds, both errors naming the counts;
//! - LAZ: the chunk table must lie inside the file, its chunks' bytes must
//!   add up to the point data and its chunks' points to the header's count
//!   (for fixed-size chunks: `ceil(count / chunk_size)` chunks); the decoder
//!   then sees the file end where the compressed points end and must decode
//!   exactly the header's count (one point fewer or one more: an error).
//!   Point-wise LAZ (LASzip 1.x, no chunk table) is decoded unchecked.

use super::check::{Checker, Stats};
use super::record::{PointFormat, Sink};
use crate::bytes::{read_at, Endian, Primitive};
use crate::diagnostic::{Error, Result};
use crate::progress::Progress;
use crate::tolerances::LAS_READ_BATCH;
use std::io::{Read, Seek, SeekFrom};
use std::sync::atomic::{AtomicU64, Ordering};

/// What our check reads of the public header block.
#[derive(Debug, Clone, Copy)]
struct Raw {
    data_start: u64,
    compressed: bool,
    rec: u64,
    count: u64,
    /// Start of the first extended VLR (LAS 1.4).
    evlr: Option<u64>,
    evlr_count: u32,
}

/// The little-endian field at byte `o` of `b` (0 past its end: every caller
/// reads inside the bytes it has checked, the header's or a record's).
#[inline(always)]
fn le<T: Primitive + Default>(b: &[u8], o: usize) -> T {
    read_at(b, o, Endian::Little).unwrap_or_default()
}

fn le_u16(b: &[u8], o: usize) -> u64 {
    le::<u16>(b, o).into()
}

fn le_u32(b: &[u8], o: usize) -> u64 {
    le::<u32>(b, o).into()
}

fn le_u64(b: &[u8], o: usize) -> u64 {
    le(b, o)
}

fn le_f64(b: &[u8], o: usize) -> f64 {
    le(b, o)
}

fn parse_error(msg: String) -> Error {
    Error::parse(format!("LAS: {msg}"))
}

/// The public header block (`b`: the file's first bytes, up to 375).
fn raw_header(b: &[u8], len: u64) -> Result<Raw> {
    if b.len() < 227 {
        return Err(parse_error(format!(
            "expected a header of at least 227 bytes, the file holds {len}"
        )));
    }
    let (major, minor) = (b[24], b[25]);
    let need: u64 = match (major, minor) {
        (1, 0..=2) => 227,
        (1, 3) => 235,
        (1, 4) => 375,
        _ => {
            return Err(parse_error(format!(
                "expected version 1.0 to 1.4, found {major}.{minor}"
            )))
        }
    };
    let header_size = le_u16(b, 94);
    if header_size < need || (b.len() as u64) < need {
        return Err(parse_error(format!(
            "version {major}.{minor} needs a header of {need} bytes, found {} (file of {len} bytes)",
            header_size.min(len)
        )));
    }
    let data_start = le_u32(b, 96);
    let format = b[104];
    let rec = le_u16(b, 105);
    let mut count = le_u32(b, 107);
    let (mut evlr, mut evlr_count) = (None, 0);
    if minor >= 4 {
        let c14 = le_u64(b, 247);
        if count == 0 || c14 == count {
            count = c14;
        } else {
            return Err(parse_error(format!(
                "the legacy point count {count} and the LAS 1.4 point count {c14} differ"
            )));
        }
        evlr_count = le_u32(b, 243) as u32;
        if evlr_count > 0 {
            evlr = Some(le_u64(b, 235));
        }
    }
    for (k, o) in [131usize, 139, 147].into_iter().enumerate() {
        let (s, off) = (le_f64(b, o), le_f64(b, o + 24));
        if !(s.is_finite() && s != 0.0 && off.is_finite()) {
            return Err(parse_error(format!(
                "expected a finite non-zero {} scale and a finite offset, found {s:e} and {off:e}",
                ["x", "y", "z"][k]
            )));
        }
    }
    if data_start < header_size || data_start > len {
        return Err(parse_error(format!(
            "expected the point data to start between the header's end ({header_size}) and the file's end ({len}), found byte {data_start}"
        )));
    }
    // Every point format starts with X, Y, Z and is at least 20 bytes long.
    if rec < 20 {
        return Err(parse_error(format!(
            "expected a point record length of at least 20 bytes, found {rec}"
        )));
    }
    Ok(Raw {
        data_start,
        compressed: format & 0xC0 != 0,
        rec,
        count,
        evlr,
        evlr_count,
    })
}

/// The extended VLRs the `las` crate reads (the first one) must lie in the
/// file, its length included.
fn check_evlr<R: Read + Seek>(r: &mut R, raw: &Raw, len: u64) -> Result<()> {
    let Some(start) = raw.evlr else {
        return Ok(());
    };
    let fits = start.checked_add(60).is_some_and(|e| e <= len);
    if !fits || start < raw.data_start {
        return Err(parse_error(format!(
            "header claims {} extended VLRs from byte {start}, outside the point data's end and the file's ({len} bytes)",
            raw.evlr_count
        )));
    }
    let mut h = [0u8; 60];
    seek_read(r, start, &mut h)?;
    let n = le_u64(&h, 20);
    if n > len - start - 60 {
        return Err(parse_error(format!(
            "the extended VLR at byte {start} claims {n} bytes, the file holds {} after it",
            len - start - 60
        )));
    }
    Ok(())
}

fn seek_read<R: Read + Seek>(r: &mut R, at: u64, out: &mut [u8]) -> Result<()> {
    r.seek(SeekFrom::Start(at))
        .and_then(|_| r.read_exact(out))
        .map_err(|e| parse_error(format!("cannot read {} bytes at byte {at}: {e}", out.len())))
}

/// Uncompressed records: the file ends with them (or with extended VLRs).
fn check_las_records(raw: &Raw, len: u64) -> Result<()> {
    let avail = len - raw.data_start;
    let holds = avail / raw.rec;
    let claims = |extra: &str| {
        parse_error(format!(
            "header claims {} points of {} bytes from byte {}, the file holds {holds}{extra}",
            raw.count, raw.rec, raw.data_start
        ))
    };
    let need = raw.count.checked_mul(raw.rec).filter(|&n| n <= avail);
    let Some(need) = need else {
        return Err(claims(""));
    };
    let end = raw.data_start + need;
    let tail_ok = match raw.evlr {
        Some(start) => start >= end,
        None => end == len,
    };
    if !tail_ok {
        return Err(claims(&format!(
            " ({} more bytes after them); expected the count to match the data",
            len - end
        )));
    }
    Ok(())
}

/// The LASzip record of the VLRs and its compressor (1: point-wise, one
/// chunk; 2 and 3: chunked).
fn laz_vlr(header: &las::Header) -> Result<(laz::LazVlr, u16)> {
    let v = header
        .vlrs()
        .iter()
        .find(|v| v.user_id == "laszip encoded" && v.record_id == 22204)
        .ok_or_else(|| parse_error("compressed (LAZ) without a LASzip VLR".into()))?;
    let vlr = laz::LazVlr::from_buffer(&v.data)
        .map_err(|e| parse_error(format!("bad LASzip VLR: {e}")))?;
    let compressor = v.data.first().copied().unwrap_or(0) as u16;
    Ok((vlr, compressor))
}

/// LAZ: the chunk table is in the file, its entries are bounded by the data
/// before it, and its chunks hold the header's point count.
fn check_laz_chunks<R: Read + Seek>(
    r: &mut R,
    raw: &Raw,
    (vlr, compressor): &(laz::LazVlr, u16),
    len: u64,
) -> Result<Option<u64>> {
    if vlr.chunk_size() == 0 || *compressor < 2 {
        return Ok(None);
    }
    let start = raw.data_start;
    let mut off = [0u8; 8];
    seek_read(r, start, &mut off)?;
    let mut table: i64 = le(&off, 0);
    if table <= start as i64 && len >= 8 {
        // A streaming writer puts the offset in the file's last 8 bytes.
        seek_read(r, len - 8, &mut off)?;
        table = le(&off, 0);
    }
    let table = u64::try_from(table).unwrap_or(0);
    if table <= start + 8 || table.checked_add(8).is_none_or(|e| e > len) {
        return Err(parse_error(format!(
            "the LASzip chunk table at byte {table} is outside the file ({len} bytes): the file is truncated or damaged"
        )));
    }
    let mut th = [0u8; 8];
    seek_read(r, table, &mut th)?;
    let chunks = le_u32(&th, 4);
    // Each chunk starts with one record stored raw.
    let data = table - start - 8;
    if chunks > data / raw.rec.max(1) {
        return Err(parse_error(format!(
            "the LASzip chunk table claims {chunks} chunks, {data} bytes of point data hold at most {}",
            data / raw.rec.max(1)
        )));
    }
    r.seek(SeekFrom::Start(start))
        .map_err(|e| parse_error(e.to_string()))?;
    let ct = laz::laszip::ChunkTable::read_from(&mut *r, vlr)
        .map_err(|e| parse_error(format!("cannot read the LASzip chunk table: {e}")))?;
    let bytes: u64 = ct.as_ref().iter().map(|c| c.byte_count).sum();
    if bytes != data {
        return Err(parse_error(format!(
            "the LASzip chunks hold {bytes} bytes, the point data before the chunk table {data}: the file is damaged"
        )));
    }
    let (lo, hi) = if vlr.uses_variable_size_chunks() {
        let n: u64 = ct.as_ref().iter().map(|c| c.point_count).sum();
        (n, n)
    } else {
        let c = u64::from(vlr.chunk_size());
        (chunks.saturating_sub(1) * c + 1, chunks * c)
    };
    if raw.count < lo.min(hi) || raw.count > hi || (chunks == 0) != (raw.count == 0) {
        return Err(parse_error(format!(
            "header claims {} points, the LASzip chunk table {chunks} chunks of {} points (from {lo} to {hi} points); expected the count to match the data",
            raw.count,
            vlr.chunk_size()
        )));
    }
    Ok(Some(table))
}

/// Check a LAS or LAZ file (`len` bytes) and decode its points into `sink`.
pub(crate) fn decode<R, S>(
    mut r: R,
    len: u64,
    sink: &mut S,
    (classes, progress): (Option<&[u8]>, &dyn Progress),
) -> Result<(PointFormat, Stats)>
where
    R: Read + Seek + Send + Sync + 'static,
    S: Sink,
{
    let mut head = vec![0u8; 375.min(len) as usize];
    seek_read(&mut r, 0, &mut head)?;
    let raw = raw_header(&head, len)?;
    check_evlr(&mut r, &raw, len)?;
    let mut ck = Checker::new(sink, false, raw.count.min(1 << 20) as usize);
    progress.start(raw.count, "points read");
    if raw.compressed {
        laz_points(r, &raw, (&head, len), &mut ck, (classes, progress))?;
        return Ok((PointFormat::Laz, ck.stats));
    }
    check_las_records(&raw, len)?;
    rewind(&mut r)?;
    let mut reader = las::Reader::new(std::io::BufReader::new(r)).map_err(las_error)?;
    las_points(&mut reader, raw.count, &mut ck, (classes, progress))?;
    Ok((PointFormat::Las, ck.stats))
}

fn rewind<R: Seek>(r: &mut R) -> Result<()> {
    r.seek(SeekFrom::Start(0))
        .map(|_| ())
        .map_err(|e| parse_error(e.to_string()))
}

/// LAZ, decoded by `laz` from the checked chunk table: the decoder sees the
/// file end where the compressed points end, and must run out of data right
/// after the header's count (a count below the points held decodes one more;
/// a count above them runs out early: both errors).
fn laz_points<R, S>(
    mut r: R,
    raw: &Raw,
    (head, len): (&[u8], u64),
    ck: &mut Checker<S>,
    (classes, progress): (Option<&[u8]>, &dyn Progress),
) -> Result<()>
where
    R: Read + Seek + Send + Sync + 'static,
    S: Sink,
{
    rewind(&mut r)?;
    let header = las::Header::new(&mut r).map_err(las_error)?;
    let vlr = laz_vlr(&header)?;
    let data_end = check_laz_chunks(&mut r, raw, &vlr, len)?;
    let (vlr, _) = vlr;
    let first = vlr.items().first().map(|i| i.item_type());
    if !matches!(
        first,
        Some(laz::LazItemType::Point10 | laz::LazItemType::Point14)
    ) {
        return Err(parse_error(format!(
            "expected the LASzip items to start with the point (x y z), found {first:?}"
        )));
    }
    if vlr.items_size() != raw.rec {
        return Err(parse_error(format!(
            "the LASzip items make records of {} bytes, the header says {}",
            vlr.items_size(),
            raw.rec
        )));
    }
    r.seek(SeekFrom::Start(raw.data_start))
        .map_err(|e| parse_error(e.to_string()))?;
    let limit = std::sync::Arc::new(AtomicU64::new(u64::MAX));
    let fenced = Fence {
        r,
        pos: raw.data_start,
        limit: limit.clone(),
    };
    let mut d = guarded(|| {
        laz::LasZipDecompressor::new(std::io::BufReader::new(fenced), vlr)
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e.to_string()))
    })
    .map_err(|e| parse_error(format!("cannot start the LASzip decoder: {e}")))?;
    if let Some(end) = data_end {
        limit.store(end, Ordering::Relaxed);
    }
    let tr = transforms(head);
    let rec = raw.rec as usize;
    let point14 = first == Some(laz::LazItemType::Point14);
    let mut buf = Vec::new();
    let mut k = 0u64;
    while k < raw.count {
        let n = (raw.count - k).min(LAS_READ_BATCH);
        buf.resize(n as usize * rec, 0);
        guarded(|| d.decompress_many(&mut buf)).map_err(|e| {
            parse_error(format!(
                "cannot decode points {k} to {} ({e}): the compressed data is damaged or ends early; header claims {} points, expected the count to match the data",
                k + n - 1,
                raw.count
            ))
        })?;
        for (i, b) in buf.chunks_exact(rec).enumerate() {
            if !wanted(classes, class_of(b, point14)) {
                continue;
            }
            let p: [f64; 3] =
                std::array::from_fn(|c| tr[c].0 * f64::from(le_i32(b, 4 * c)) + tr[c].1);
            ck.record(&[p[0], p[1], p[2], 0.0, 0.0, 1.0, 1.0])
                .map_err(|f| f.error(format!("LAS: point {}", k + i as u64), None))?;
        }
        k += n;
        progress.advance(n);
    }
    let mut one = vec![0u8; rec];
    if data_end.is_some() && raw.count > 0 && guarded(|| d.decompress_one(&mut one)).is_ok() {
        return Err(parse_error(format!(
            "header claims {} points, the compressed data holds more; expected the count to match the data",
            raw.count
        )));
    }
    Ok(())
}

/// A LASzip call. On damaged compressed data laz-rs can trip its own debug
/// assertions and overflow checks (debug builds; a release build wraps and
/// decodes garbage, which the header checks cannot see: LAZ has no
/// checksum): the panic is caught and reported as damaged data.
fn guarded<T>(f: impl FnOnce() -> std::io::Result<T>) -> std::io::Result<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|_| {
        Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "the LASzip decoder failed",
        ))
    })
}

/// The classification of a LASzip-decoded record: the low five bits of byte
/// 15 (point formats 0-5), byte 16 (formats 6-10).
fn class_of(b: &[u8], point14: bool) -> u8 {
    if point14 {
        b[16]
    } else {
        b[15] & 0x1f
    }
}

/// Whether a point of class `c` is kept (`None`: every point).
fn wanted(classes: Option<&[u8]>, c: u8) -> bool {
    classes.is_none_or(|cs| cs.contains(&c))
}

fn le_i32(b: &[u8], o: usize) -> i32 {
    le(b, o)
}

/// (scale, offset) of x, y, z from the public header block.
fn transforms(head: &[u8]) -> [(f64, f64); 3] {
    std::array::from_fn(|c| (le_f64(head, 131 + 8 * c), le_f64(head, 155 + 8 * c)))
}

/// A reader that ends at `limit` (bytes from the start).
struct Fence<R> {
    r: R,
    pos: u64,
    limit: std::sync::Arc<AtomicU64>,
}

impl<R: Read> Read for Fence<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let left = self.limit.load(Ordering::Relaxed).saturating_sub(self.pos);
        let n = (buf.len() as u64).min(left) as usize;
        let got = self.r.read(&mut buf[..n])?;
        self.pos += got as u64;
        Ok(got)
    }
}

impl<R: Seek> Seek for Fence<R> {
    fn seek(&mut self, to: SeekFrom) -> std::io::Result<u64> {
        self.pos = self.r.seek(to)?;
        Ok(self.pos)
    }
}

fn las_error(e: las::Error) -> Error {
    parse_error(e.to_string())
}

/// Decode the `count` points in batches; the normal is the placeholder `+z`.
fn las_points<S: Sink>(
    reader: &mut las::Reader,
    count: u64,
    ck: &mut Checker<S>,
    (classes, progress): (Option<&[u8]>, &dyn Progress),
) -> Result<()> {
    let mut pd = las::PointDataBuilder::new()
        .for_header(reader.header())
        .build();
    let mut k = 0u64;
    while k < count {
        let got = reader
            .fill_points(LAS_READ_BATCH, &mut pd)
            .map_err(|e| parse_error(format!("point {k}: {e} (header claims {count} points)")))?;
        if got == 0 {
            return Err(parse_error(format!(
                "header claims {count} points, the file holds {k}"
            )));
        }
        let xyz = pd.x().zip(pd.y()).zip(pd.z()).zip(pd.classification());
        for (i, (((x, y), z), c)) in xyz.enumerate() {
            if !wanted(classes, c) {
                continue;
            }
            ck.record(&[x, y, z, 0.0, 0.0, 1.0, 1.0])
                .map_err(|f| f.error(format!("LAS: point {}", k + i as u64), None))?;
        }
        k += got;
        progress.advance(got);
    }
    Ok(())
}
