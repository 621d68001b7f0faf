//! Binary records (PLY and PCD): scalar types and the record decoder, with
//! monomorphic fast paths for the usual all-`double` and all-`float` records.

use super::check::Checker;
use super::record::Sink;
use super::source::Source;
use crate::bytes::{get_at, Endian};
use crate::diagnostic::{Error, Result};
use std::io::Read;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

impl Scalar {
    pub(crate) fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::I64 | Scalar::U64 | Scalar::F64 => 8,
        }
    }
    pub(crate) fn ply(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    pub(crate) fn pcd(ty: &str, size: usize) -> Option<Scalar> {
        Some(match (ty, size) {
            ("I", 1) => Scalar::I8,
            ("U", 1) => Scalar::U8,
            ("I", 2) => Scalar::I16,
            ("U", 2) => Scalar::U16,
            ("I", 4) => Scalar::I32,
            ("U", 4) => Scalar::U32,
            ("I", 8) => Scalar::I64,
            ("U", 8) => Scalar::U64,
            ("F", 4) => Scalar::F32,
            ("F", 8) => Scalar::F64,
            _ => return None,
        })
    }
    /// The value at byte `at` of `b` (`None`: `b` ends before it).
    #[inline(always)]
    pub(crate) fn read(self, b: &[u8], at: usize, endian: Endian) -> Option<f64> {
        Some(match self {
            Scalar::I8 => get_at::<i8>(b, at, endian)? as f64,
            Scalar::U8 => get_at::<u8>(b, at, endian)? as f64,
            Scalar::I16 => get_at::<i16>(b, at, endian)? as f64,
            Scalar::U16 => get_at::<u16>(b, at, endian)? as f64,
            Scalar::I32 => get_at::<i32>(b, at, endian)? as f64,
            Scalar::U32 => get_at::<u32>(b, at, endian)? as f64,
            Scalar::I64 => get_at::<i64>(b, at, endian)? as f64,
            Scalar::U64 => get_at::<u64>(b, at, endian)? as f64,
            Scalar::F32 => get_at::<f32>(b, at, endian)? as f64,
            Scalar::F64 => get_at::<f64>(b, at, endian)?,
        })
    }
}

/// Where each role (x y z nx ny nz w) sits in a record.
#[derive(Debug, Clone)]
pub(crate) struct Layout {
    /// Record size in bytes (at least 1).
    pub rec: usize,
    /// (byte offset, type) of each role; the weight may be absent.
    pub roles: [Option<(usize, Scalar)>; 7],
    pub endian: Endian,
}

/// A run of records: `first` is the index of its first record in the file
/// (a multiple of the block length), `count` how many to decode, `total` how
/// many the header claims.
pub(crate) struct Run {
    pub first: usize,
    pub count: usize,
    pub total: usize,
    /// "PLY", "vertex", "vertices" (for messages).
    pub names: [&'static str; 3],
    /// Header line that claims `total`.
    pub line: usize,
}

impl Run {
    /// The error when the stream ends after `k` records of the file.
    pub(crate) fn truncated(&self, rec: usize, k: usize) -> Error {
        let [fmt, _, items] = self.names;
        Error::parse(format!(
            "{fmt}: header line {} claims {} {items} of {rec} bytes, the file holds {k}",
            self.line, self.total
        ))
        .at_line(self.line, None)
    }

    /// The error when `extra` bytes follow the records (and whatever the
    /// header declares after them) from byte `offset`: the header claims fewer
    /// records than the file holds (issue 12).
    pub(crate) fn excess(&self, rec: usize, extra: u64, offset: u64) -> Error {
        let [fmt, _, items] = self.names;
        Error::parse(format!(
            "{fmt}: header line {} claims {} {items} of {rec} bytes, the file holds {extra} more bytes after them (from byte offset {offset}); expected the count to match the data",
            self.line, self.total
        ))
        .at_line(self.line, None)
    }

    /// "vertex 12 (byte offset 345)".
    fn locate(&self, k: usize, offset: u64) -> String {
        format!("{} {k} (byte offset {offset})", self.names[1])
    }
}

/// Decoding modes: 0 generic, 1/2 f64 little/big endian, 3/4 f32 little/big.
fn mode(layout: &Layout) -> u8 {
    let mut types = layout.roles.iter().flatten().map(|(_, s)| *s);
    let first = types.next();
    let uniform = layout
        .roles
        .iter()
        .flatten()
        .all(|(_, s)| Some(*s) == first);
    match (uniform, first, layout.endian) {
        (true, Some(Scalar::F64), Endian::Little) => 1,
        (true, Some(Scalar::F64), Endian::Big) => 2,
        (true, Some(Scalar::F32), Endian::Little) => 3,
        (true, Some(Scalar::F32), Endian::Big) => 4,
        _ => 0,
    }
}

/// The value of role type `s` at byte `o` of record `b` (0 past its end).
#[inline(always)]
fn get<const MODE: u8>(b: &[u8], o: usize, s: Scalar, endian: Endian) -> f64 {
    match MODE {
        1 => get_at::<f64>(b, o, Endian::Little).unwrap_or(0.0),
        2 => get_at::<f64>(b, o, Endian::Big).unwrap_or(0.0),
        3 => get_at::<f32>(b, o, Endian::Little).map_or(0.0, f64::from),
        4 => get_at::<f32>(b, o, Endian::Big).map_or(0.0, f64::from),
        _ => s.read(b, o, endian).unwrap_or(0.0),
    }
}

/// Decode `run.count` records from `src` into the checker.
pub(crate) fn decode_records<R: Read, S: Sink>(
    src: &mut Source<R>,
    layout: &Layout,
    run: &Run,
    ck: &mut Checker<S>,
) -> Result<()> {
    match mode(layout) {
        1 => decode::<1, R, S>(src, layout, run, ck),
        2 => decode::<2, R, S>(src, layout, run, ck),
        3 => decode::<3, R, S>(src, layout, run, ck),
        4 => decode::<4, R, S>(src, layout, run, ck),
        _ => decode::<0, R, S>(src, layout, run, ck),
    }
}

fn decode<const MODE: u8, R: Read, S: Sink>(
    src: &mut Source<R>,
    layout: &Layout,
    run: &Run,
    ck: &mut Checker<S>,
) -> Result<()> {
    let rec = layout.rec.max(1);
    let mut batch = Batch::new();
    let mut k = 0usize;
    while k < run.count {
        src.fill(rec)?;
        let at = src.offset();
        let data = src.data();
        let n = (data.len() / rec).min(run.count - k);
        if n == 0 {
            return Err(run.truncated(rec, run.first + k));
        }
        // Batches of at most BATCH records that end where blocks end.
        let mut r = 0;
        while r < n {
            let m = (n - r).min(BATCH).min(ck.until_block_end());
            batch.decode::<MODE>(&data[r * rec..(r + m) * rec], layout);
            let (p, nn, w) = batch.slices(m);
            if let Err((i, f)) = ck.batch(p, nn, w) {
                let j = r + i;
                return Err(f.error(run.locate(run.first + k + j, at + (j * rec) as u64), None));
            }
            r += m;
        }
        src.consume(n * rec);
        k += n;
    }
    Ok(())
}

/// Records decoded per batch.
const BATCH: usize = 256;

/// One batch of decoded records.
struct Batch {
    p: Box<[[f64; 3]; BATCH]>,
    n: Box<[[f64; 3]; BATCH]>,
    w: Box<[f64; BATCH]>,
}

impl Batch {
    fn new() -> Self {
        Batch {
            p: Box::new([[0.0; 3]; BATCH]),
            n: Box::new([[0.0; 3]; BATCH]),
            w: Box::new([1.0; BATCH]),
        }
    }

    /// Decode the whole records in `bytes` (at most `BATCH`).
    #[inline(always)]
    fn decode<const MODE: u8>(&mut self, bytes: &[u8], layout: &Layout) {
        let rec = layout.rec.max(1);
        let r = &layout.roles;
        let g = |b: &[u8], role: usize, default: f64| match r[role] {
            Some((o, s)) => get::<MODE>(b, o, s, layout.endian),
            None => default,
        };
        for (i, b) in bytes.chunks_exact(rec).take(BATCH).enumerate() {
            self.p[i] = [g(b, 0, 0.0), g(b, 1, 0.0), g(b, 2, 0.0)];
            // Without normal fields (a raw scan) the normal is a placeholder +z.
            self.n[i] = [g(b, 3, 0.0), g(b, 4, 0.0), g(b, 5, 1.0)];
            self.w[i] = g(b, 6, 1.0);
        }
    }

    fn slices(&self, m: usize) -> (&[[f64; 3]], &[[f64; 3]], &[f64]) {
        let m = m.min(BATCH);
        (&self.p[..m], &self.n[..m], &self.w[..m])
    }
}
