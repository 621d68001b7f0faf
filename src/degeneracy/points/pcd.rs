//! PCD 0.7: `DATA ascii`, `binary` and `binary_compressed` (LZF, fields stored
//! one after the other; decompressed in memory, then read as `binary`).

use super::binary::{decode_records, Layout, Run, Scalar};
use super::check::{Checker, Stats};
use super::record::{column_role, missing_roles, PointFormat, Sink};
use super::source::{header_lines, Source};
use crate::bytes::{read_at, Endian};
use crate::diagnostic::{Error, Result};
use crate::tolerances::{
    MAX_PCD_COUNT, MAX_POINT_FILE_SIZE, MAX_POINT_RECORD_BYTES, POINT_READ_BUFFER,
};
use std::io::Read;

/// What the header says.
pub(super) struct Header {
    pub format: PointFormat,
    /// Points claimed.
    pub n: usize,
    /// Header line of the claim (POINTS, else WIDTH).
    line: usize,
    /// Values per ascii line.
    elems: usize,
    /// (element index, byte offset, type) of each role.
    roles: [Option<(usize, usize, Scalar)>; 7],
    /// Bytes per binary record.
    rec: usize,
    /// (byte offset in a record, bytes) of every field, in order.
    fields: Vec<(usize, usize)>,
}

/// The header's fields, as written.
#[derive(Default)]
struct Fields {
    fields: Vec<String>,
    sizes: Vec<usize>,
    types: Vec<String>,
    counts: Vec<usize>,
    points: Option<usize>,
    width: Option<usize>,
    height: Option<usize>,
    data: String,
    /// Header lines of POINTS and WIDTH.
    points_line: usize,
    width_line: usize,
}

fn header_line(t: &[&str], lineno: usize, h: &mut Fields) -> Result<()> {
    let nums = |what: &str| -> Result<Vec<usize>> {
        t[1..]
            .iter()
            .map(|x| {
                x.parse::<usize>().map_err(|_| {
                    Error::parse(format!(
                        "PCD {what}: expected non-negative integers, found {x:?}"
                    ))
                    .at_line(lineno, None)
                })
            })
            .collect()
    };
    match t.first().copied() {
        None => {}
        Some(s) if s.starts_with('#') => {}
        Some("VERSION") | Some("VIEWPOINT") => {}
        Some("FIELDS") => {
            h.fields = t[1..].iter().map(|s| s.to_string()).collect();
            // A second field of the same name would silently win (issue 12);
            // `_` is PCL's padding (pcd_io.cpp writes one per gap), never read.
            for (k, f) in h.fields.iter().enumerate() {
                if f != "_" && h.fields[..k].contains(f) {
                    return Err(Error::parse(format!(
                        "PCD: FIELDS declares {f:?} twice; expected distinct field names"
                    ))
                    .at_line(lineno, None));
                }
            }
        }
        Some("SIZE") => h.sizes = nums("SIZE")?,
        Some("TYPE") => h.types = t[1..].iter().map(|s| s.to_string()).collect(),
        Some("COUNT") => h.counts = nums("COUNT")?,
        Some("WIDTH") => {
            h.width = nums("WIDTH")?.first().copied();
            h.width_line = lineno;
        }
        Some("HEIGHT") => h.height = nums("HEIGHT")?.first().copied(),
        Some("POINTS") => {
            h.points = nums("POINTS")?.first().copied();
            h.points_line = lineno;
        }
        Some("DATA") => h.data = t.get(1).copied().unwrap_or("").to_string(),
        Some(other) => {
            return Err(Error::parse(format!(
                "PCD: unexpected header line starting with {other:?}"
            ))
            .at_line(lineno, None))
        }
    }
    Ok(())
}

/// FIELDS, SIZE, TYPE and COUNT agree, and every COUNT is in range.
fn check_fields(h: &mut Fields) -> Result<()> {
    if h.counts.is_empty() {
        h.counts = vec![1; h.fields.len()];
    }
    let nf = h.fields.len();
    if nf == 0 || h.sizes.len() != nf || h.types.len() != nf || h.counts.len() != nf {
        return Err(Error::parse(format!(
            "PCD: expected FIELDS, SIZE, TYPE (and COUNT) of equal length, found {}, {}, {}, {}",
            nf,
            h.sizes.len(),
            h.types.len(),
            h.counts.len()
        )));
    }
    // PCD's COUNT is the number of elements of a field: at least 1. A cap keeps
    // the record arithmetic far from overflow (real descriptors use <= 352).
    if let Some((k, c)) = h
        .counts
        .iter()
        .enumerate()
        .find(|(_, c)| **c == 0 || **c > MAX_PCD_COUNT)
    {
        return Err(Error::parse(format!(
            "PCD: field {:?}: expected COUNT between 1 and {MAX_PCD_COUNT}, found {c}",
            h.fields[k]
        )));
    }
    Ok(())
}

pub(super) fn read_header<R: Read>(src: &mut Source<R>, xyz_only: bool) -> Result<Header> {
    let lines = header_lines(src, &|l| l.trim_start().starts_with("DATA"), "PCD")?;
    let mut h = Fields::default();
    for (i, l) in lines.iter().enumerate() {
        let t: Vec<&str> = l.split_whitespace().collect();
        header_line(&t, i + 1, &mut h)?;
    }
    check_fields(&mut h)?;
    let (n, line) = match (h.points, h.width, h.height) {
        (Some(p), _, _) => (p, h.points_line),
        (None, Some(w), Some(hh)) => (w.saturating_mul(hh), h.width_line),
        _ => {
            return Err(Error::parse(
                "PCD: expected POINTS (or WIDTH and HEIGHT) in the header, found neither",
            ))
        }
    };
    let mut roles = [None; 7];
    let mut fields = Vec::with_capacity(h.fields.len());
    let (mut elem, mut byte) = (0usize, 0usize);
    for k in 0..h.fields.len() {
        let Some(s) = Scalar::pcd(&h.types[k], h.sizes[k]) else {
            return Err(Error::parse(format!(
                "PCD: field {:?} has TYPE {} SIZE {}, not a supported combination",
                h.fields[k], h.types[k], h.sizes[k]
            )));
        };
        if let Some(r) = column_role(&h.fields[k]) {
            roles[r] = Some((elem, byte, s));
        }
        fields.push((byte, h.counts[k] * h.sizes[k]));
        elem += h.counts[k];
        byte += h.counts[k] * h.sizes[k];
    }
    let names = ["x", "y", "z", "normal_x", "normal_y", "normal_z"];
    let missing = missing_roles(&roles, names, xyz_only);
    if !missing.is_empty() {
        return Err(Error::parse(format!(
            "PCD: expected FIELDS x y z normal_x normal_y normal_z, missing {} (found {})",
            missing.join(" "),
            h.fields.join(" ")
        )));
    }
    let format = match h.data.as_str() {
        "ascii" => PointFormat::PcdAscii,
        "binary" => PointFormat::PcdBinary,
        "binary_compressed" => PointFormat::PcdBinaryCompressed,
        other => {
            return Err(Error::parse(format!(
                "PCD: expected DATA ascii, binary or binary_compressed, found {other:?}"
            )))
        }
    };
    if format != PointFormat::PcdAscii && byte > MAX_POINT_RECORD_BYTES {
        return Err(Error::limit(format!(
            "PCD: expected records of at most {MAX_POINT_RECORD_BYTES} bytes, found {byte}"
        )));
    }
    Ok(Header {
        format,
        n,
        line,
        elems: elem,
        roles,
        rec: byte,
        fields,
    })
}

/// The binary record layout (PCL writes little endian).
pub(super) fn layout(h: &Header) -> Layout {
    let mut roles = [None; 7];
    for (r, c) in h.roles.iter().enumerate() {
        roles[r] = c.map(|(_, o, s)| (o, s));
    }
    Layout {
        rec: h.rec.max(1),
        roles,
        endian: Endian::Little,
    }
}

/// The records `first .. first + count`.
pub(super) fn run(h: &Header, first: usize, count: usize) -> Run {
    Run {
        first,
        count,
        total: h.n,
        names: ["PCD", "point", "points"],
        line: h.line,
    }
}

/// Decode the data after the header into `sink`.
pub(super) fn body<R: Read, S: Sink>(
    src: &mut Source<R>,
    h: &Header,
    sink: &mut S,
) -> Result<(PointFormat, Stats)> {
    let mut ck = Checker::new(sink, h.roles[6].is_some(), h.n);
    match h.format {
        PointFormat::PcdAscii => ascii(src, h, &mut ck)?,
        PointFormat::PcdBinaryCompressed => {
            let records = compressed_records(src, h)?;
            let mut mem = Source::new(&records[..]);
            decode_records(&mut mem, &layout(h), &run(h, 0, h.n), &mut ck)?
        }
        _ => {
            decode_records(src, &layout(h), &run(h, 0, h.n), &mut ck)?;
            // A header that claims fewer points than the file holds (issue 12).
            let at = src.offset();
            if src.has_more()? {
                let extra = src.skip(u64::MAX)?;
                return Err(run(h, 0, h.n).excess(h.rec, extra, at));
            }
        }
    }
    Ok((h.format, ck.stats))
}

/// `binary_compressed`: two little-endian `u32` (compressed and decompressed
/// sizes), the LZF data, which decompress to every field's values for all
/// points, field after field; returned as records (`binary` layout).
fn compressed_records<R: Read>(src: &mut Source<R>, h: &Header) -> Result<Vec<u8>> {
    src.fill(8)?;
    let d = src.data();
    if d.len() < 8 {
        return Err(Error::parse(
            "PCD binary_compressed: expected the two sizes after DATA, found the end of the file",
        ));
    }
    let size = |k: usize| read_at::<u32>(d, k, Endian::Little).map_or(0, |v| v as usize);
    let (packed, unpacked) = (size(0), size(4));
    src.consume(8);
    let want =
        h.n.checked_mul(h.rec)
            .filter(|&b| b as u64 <= MAX_POINT_FILE_SIZE);
    // LZF expands at most 264 bytes per 3 input bytes: a larger claim is a lie,
    // refused before any allocation (memory stays proportional to the data).
    if want != Some(unpacked) || unpacked / 88 > packed.saturating_add(1) {
        return Err(Error::parse(format!(
            "PCD binary_compressed: header claims {} points of {} bytes, the data announce {unpacked} bytes",
            h.n, h.rec
        )));
    }
    // Read in bounded pieces: memory grows with the data, not with the claim.
    let mut lzf = Vec::new();
    while lzf.len() < packed {
        src.fill(POINT_READ_BUFFER)?;
        let d = src.data();
        if d.is_empty() {
            return Err(Error::parse(format!(
                "PCD binary_compressed: expected {packed} bytes of compressed data, found {}",
                lzf.len()
            )));
        }
        let k = d.len().min(packed - lzf.len());
        lzf.extend_from_slice(&d[..k]);
        src.consume(k);
    }
    let soa = super::lzf::decompress(&lzf, unpacked)?;
    let mut aos = vec![0u8; unpacked];
    let mut at = 0;
    for &(off, len) in &h.fields {
        for (i, rec) in aos.chunks_exact_mut(h.rec.max(1)).enumerate() {
            let from = at + i * len;
            rec[off..off + len].copy_from_slice(&soa[from..from + len]);
        }
        at += h.n * len;
    }
    Ok(aos)
}

fn ascii<R: Read, S: Sink>(src: &mut Source<R>, h: &Header, ck: &mut Checker<S>) -> Result<()> {
    let mut buf = Vec::new();
    let mut k = 0usize;
    while k < h.n {
        if src.read_line(&mut buf)?.is_none() {
            return Err(Error::parse(format!(
                "PCD: header line {} claims {} points, the file holds {k}",
                h.line, h.n
            ))
            .at_line(h.line, None));
        }
        let line = String::from_utf8_lossy(&buf);
        if line.trim().is_empty() {
            continue;
        }
        let lineno = src.lines();
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() < h.elems {
            return Err(Error::parse(format!(
                "PCD: expected {} values, found {}",
                h.elems,
                f.len()
            ))
            .at_line(lineno, None));
        }
        // Without normal fields (a raw scan) the normal is a placeholder +z.
        let mut v = [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0];
        for (r, c) in h.roles.iter().enumerate() {
            if let Some((e, _, _)) = c {
                let tok = f[*e];
                v[r] = if tok.eq_ignore_ascii_case("nan") {
                    f64::NAN
                } else {
                    tok.parse::<f64>().map_err(|_| {
                        Error::parse(format!("PCD: expected a number, found {tok:?}"))
                            .at_line(lineno, Some(e + 1))
                    })?
                };
            }
        }
        ck.record(&v)
            .map_err(|f| f.error(format!("point {k}"), Some(lineno)))?;
        k += 1;
    }
    if let Some(extra) = src.next_nonblank()? {
        return Err(Error::parse(format!(
            "PCD: header line {} claims {} points, the file holds more: line {extra} is past them; expected the count to match the data",
            h.line, h.n
        ))
        .at_line(extra, None));
    }
    Ok(())
}
