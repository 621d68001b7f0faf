//! Point files with normals: CSV, PLY (ascii, binary little and big endian) and
//! PCD (ascii, binary).
//!
//! - CSV: `x,y,z,nx,ny,nz[,w]`, with or without a header line. A header names
//!   the columns (`x y z nx ny nz w`; `normal_x`.. and `weight` also accepted) in
//!   any order; without one the columns are positional. Commas, semicolons, tabs
//!   or spaces separate fields; `#` starts a comment line.
//! - PLY: `element vertex` with scalar properties `x y z nx ny nz` (optional `w`
//!   or `weight`), any numeric type. Elements before `vertex` must have scalar
//!   properties only (they are skipped); elements after it (faces with list
//!   properties included: each list by its own count) are read by their
//!   declared types and must end the file, or it is an error.
//! - PCD (0.7): `FIELDS x y z normal_x normal_y normal_z` (or `nx ny nz`), with
//!   `SIZE`/`TYPE`/`COUNT`, `DATA ascii`, `binary` or `binary_compressed`
//!   (LZF, decompressed in memory).
//! - LAS 1.0-1.4 and LAZ (detected by the `LASF` magic): raw scans only (no
//!   normals), see `las`. From a stream (standard input, [`parse_points`])
//!   the file is held in memory (the `las` crate seeks), within the size cap.
//!
//! Checks: a file claiming more points than it holds is an error (pre-allocation
//! is capped, never taken from the header); a zero normal is an error naming the
//! line (or vertex); normals off unit length by more than [`NORMAL_UNIT_TOL`] are
//! renormalised with one `assumed-convention` warning for the file; points with
//! a non-finite coordinate or normal (PCL marks invalid points with NaN) are
//! skipped with a warning; a coordinate beyond [`MAX_COORDINATE`] and a negative
//! or non-finite weight are errors.
//!
//! # Streaming
//!
//! Every reader decodes from a fixed-size buffer ([`POINT_READ_BUFFER`]) into a
//! sink, one record at a time: [`read_points`] and [`parse_points`] collect the
//! points (for commands that need them: normal estimation, pairs, sweeps),
//! [`accumulate_file`] and [`accumulate_reader`] feed them straight into an
//! [`Accumulator`] and hold no point at all. Binary PLY and PCD files large
//! enough are split into block-aligned record ranges decoded on scoped threads;
//! the block sums are combined in file order, so the result is the same bits
//! whatever the thread count and however the reads fall.
//!
//! [`NORMAL_UNIT_TOL`]: crate::tolerances::NORMAL_UNIT_TOL
//! [`MAX_COORDINATE`]: crate::tolerances::MAX_COORDINATE
//! [`POINT_READ_BUFFER`]: crate::tolerances::POINT_READ_BUFFER

mod binary;
mod check;
mod csv;
mod decode;
mod las;
mod lzf;
mod parallel;
mod pcd;
mod ply;
mod record;
mod source;
mod write;

pub use record::PointFormat;
pub use write::{write_csv, write_pcd, write_ply, Encoding};

use crate::bytes::LAS_MAGIC;
use crate::degeneracy::{Accumulator, Assembly};
use crate::diagnostic::{Error, Result, Warning};
use crate::geometry::se3::Transform;
use crate::progress::{Counted, NoProgress, Progress};
use crate::tolerances::MAX_POINT_FILE_SIZE;
use check::Stats;
use decode::{decode, detect, las_without_normals, Kind};
use record::Sink;
use source::Source;
use std::fs::File;
use std::io::Read;
use std::path::Path;

/// Cap on the capacity reserved from a header's point count.
const MAX_PREALLOC: usize = 1 << 20;

/// Points with unit normals and optional weights.
#[derive(Debug, Clone, PartialEq)]
pub struct PointData {
    /// Points, in the file's frame and unit.
    pub points: Vec<[f64; 3]>,
    /// Unit normals, one per point (renormalised where the file's were not).
    pub normals: Vec<[f64; 3]>,
    /// Weights, one per point, when the file has a weight column.
    pub weights: Option<Vec<f64>>,
    /// The reader used.
    pub format: PointFormat,
    /// Named warnings (renormalised normals, skipped records, ...).
    pub warnings: Vec<Warning>,
}

/// `H` and `M` of a point file, assembled without holding its points.
#[derive(Debug, Clone, PartialEq)]
pub struct Accumulated {
    /// In the requested frame (`assembly.count`: the points used).
    pub assembly: Assembly,
    /// The reader used.
    pub format: PointFormat,
    /// Named warnings (renormalised normals, skipped records, ...).
    pub warnings: Vec<Warning>,
}

/// Collects the points.
#[derive(Default)]
struct Collect {
    points: Vec<[f64; 3]>,
    normals: Vec<[f64; 3]>,
    weights: Option<Vec<f64>>,
}

impl Collect {
    /// The points held, with the file's format and the reader's warnings.
    fn into_data(self, format: PointFormat, stats: &Stats) -> PointData {
        PointData {
            points: self.points,
            normals: self.normals,
            weights: self.weights,
            format,
            warnings: stats.warnings(),
        }
    }
}

impl Sink for Collect {
    fn begin(&mut self, weighted: bool, hint: usize) {
        let cap = hint.min(MAX_PREALLOC);
        self.points.reserve(cap);
        self.normals.reserve(cap);
        if weighted {
            self.weights = Some(Vec::with_capacity(cap));
        }
    }
    fn point(&mut self, p: &[f64; 3], n: &[f64; 3], w: f64) {
        self.points.push(*p);
        self.normals.push(*n);
        if let Some(ws) = self.weights.as_mut() {
            ws.push(w);
        }
    }
    fn points(&mut self, p: &[[f64; 3]], n: &[[f64; 3]], w: &[f64]) {
        self.points.extend_from_slice(p);
        self.normals.extend_from_slice(n);
        if let Some(ws) = self.weights.as_mut() {
            ws.extend_from_slice(w);
        }
    }
    fn end_block(&mut self) {}
}

impl Sink for Accumulator {
    fn begin(&mut self, _weighted: bool, _hint: usize) {}
    #[inline(always)]
    fn point(&mut self, p: &[f64; 3], n: &[f64; 3], w: f64) {
        self.push_point(p, n, w);
    }
    fn points(&mut self, p: &[[f64; 3]], n: &[[f64; 3]], w: &[f64]) {
        self.push_slices(p, n, Some(w));
    }
    fn end_block(&mut self) {
        Accumulator::end_block(self);
    }
}

/// Open a point file (a regular file: a FIFO or a device is refused, see
/// `crate::input`), refused over [`MAX_POINT_FILE_SIZE`]; with its length.
fn open_points(path: &Path) -> Result<(File, u64)> {
    let (f, len) = crate::input::open_stream(path)?;
    if len > MAX_POINT_FILE_SIZE {
        return Err(Error::limit(format!(
            "point file is {len} bytes, more than the limit of {MAX_POINT_FILE_SIZE}"
        ))
        .in_file(path));
    }
    Ok((f, len))
}

/// Read a point file, detecting the format from its content (`ply` magic, a PCD
/// header) and otherwise reading CSV.
pub fn read_points(path: &Path) -> Result<PointData> {
    read_path(path, false, &NoProgress)
}

/// [`read_points`], reporting the bytes read to `progress`.
pub fn read_points_with(path: &Path, progress: &dyn Progress) -> Result<PointData> {
    read_path(path, false, progress)
}

/// Read the points of a raw scan (x y z; normal fields, when present, are
/// read but not required: absent ones are the placeholder `+z`). Positional
/// CSV takes the first three columns as x, y, z.
pub fn read_xyz(path: &Path) -> Result<PointData> {
    read_path(path, true, &NoProgress)
}

/// [`read_xyz`], reporting the bytes read (the points read, for LAS and LAZ)
/// to `progress`.
pub fn read_xyz_with(path: &Path, progress: &dyn Progress) -> Result<PointData> {
    read_path(path, true, progress)
}

/// [`read_xyz_with`] keeping only the points whose LAS classification is in
/// `classes` (e.g. `[2]`, ground); an error for a file that is not LAS or LAZ.
pub fn read_xyz_classes(path: &Path, classes: &[u8], progress: &dyn Progress) -> Result<PointData> {
    let (mut f, len) = open_points(path)?;
    if !is_las_file(&mut f).map_err(|e| e.in_file(path))? {
        return Err(Error::usage(
            "--class: expected a LAS or LAZ file (other formats have no classification)",
        )
        .in_file(path));
    }
    let mut sink = Collect::default();
    let r = las::decode(f, len, &mut sink, (Some(classes), progress));
    progress.finish();
    let (format, stats) = r.map_err(|e| e.in_file(path))?;
    Ok(sink.into_data(format, &stats))
}

fn read_path(path: &Path, xyz_only: bool, progress: &dyn Progress) -> Result<PointData> {
    if crate::input::is_stdin(path) {
        let r = crate::input::Capped::new(std::io::stdin().lock(), MAX_POINT_FILE_SIZE);
        return read_mode(r, xyz_only).map_err(|e| e.in_file("<stdin>"));
    }
    let (mut f, len) = open_points(path)?;
    if is_las_file(&mut f).map_err(|e| e.in_file(path))? {
        let r = read_las(f, len, xyz_only, progress);
        progress.finish();
        return r.map_err(|e| e.in_file(path));
    }
    progress.start(len, "bytes read");
    let r = read_mode(Counted::new(f, 0, progress), xyz_only);
    progress.finish();
    r.map_err(|e| e.in_file(path))
}

/// Whether a file starts with the LAS magic (the file is left at its start).
fn is_las_file(f: &mut File) -> Result<bool> {
    use std::io::{Seek, SeekFrom};
    let mut m = [0u8; 4];
    let n = f.read(&mut m).map_err(|e| source::io_error(&e))?;
    f.seek(SeekFrom::Start(0))
        .map_err(|e| source::io_error(&e))?;
    Ok(n == 4 && &m == LAS_MAGIC)
}

/// A LAS or LAZ file, seekable, `len` bytes: raw scans only.
fn read_las<R>(r: R, len: u64, xyz_only: bool, progress: &dyn Progress) -> Result<PointData>
where
    R: Read + std::io::Seek + Send + Sync + 'static,
{
    if !xyz_only {
        return Err(las_without_normals());
    }
    let mut sink = Collect::default();
    let (format, stats) = las::decode(r, len, &mut sink, (None, progress))?;
    Ok(sink.into_data(format, &stats))
}

/// Parse a point file held in memory.
pub fn parse_points(bytes: &[u8]) -> Result<PointData> {
    read_from(bytes)
}

/// Parse a raw scan held in memory (as [`read_xyz`]; LAS and LAZ included).
pub fn parse_xyz(bytes: &[u8]) -> Result<PointData> {
    read_mode(bytes, true)
}

/// Read a point file from any reader, holding the points.
pub fn read_from<R: Read>(r: R) -> Result<PointData> {
    read_mode(r, false)
}

fn read_mode<R: Read>(r: R, xyz_only: bool) -> Result<PointData> {
    let mut sink = Collect::default();
    let mut src = Source::new(r);
    if detect(&mut src)? == Kind::Las {
        // The `las` crate seeks: the stream is held in memory, within the cap.
        let bytes = src.read_rest(MAX_POINT_FILE_SIZE)?;
        let len = bytes.len() as u64;
        return read_las(std::io::Cursor::new(bytes), len, xyz_only, &NoProgress);
    }
    let (format, stats) = decode(&mut src, &mut sink, xyz_only)?;
    Ok(sink.into_data(format, &stats))
}

/// `H` and `M` of a point file, streamed from disk in bounded reads (binary
/// PLY and PCD over several threads when large), optionally re-expressed in
/// the frame whose pose in the file's frame is `frame` (exactly, by congruence
/// of the sums with `Ad(frame)`).
pub fn accumulate_file(path: &Path, frame: Option<&Transform>) -> Result<Accumulated> {
    accumulate_file_with(path, frame, &NoProgress)
}

/// [`accumulate_file`], reporting the bytes read to `progress`.
pub fn accumulate_file_with(
    path: &Path,
    frame: Option<&Transform>,
    progress: &dyn Progress,
) -> Result<Accumulated> {
    if crate::input::is_stdin(path) {
        // `-`: standard input, read serially, bounded (issue 12).
        let r = crate::input::Capped::new(std::io::stdin().lock(), MAX_POINT_FILE_SIZE);
        return accumulate_reader(r, frame).map_err(|e| e.in_file("<stdin>"));
    }
    let (f, len) = open_points(path)?;
    let mut acc = Accumulator::new();
    progress.start(len, "bytes read");
    let mut src = Source::new(Counted::new(f, 0, progress));
    // A regular file (the only kind opened): split by its length, reopened per range.
    let res = parallel::decode_file(path, len, &mut src, &mut acc, progress);
    progress.finish();
    let (format, stats) = res.map_err(|e| e.in_file(path))?;
    Ok(finish(&acc, format, stats, frame))
}

/// `H` and `M` of a point file read from `r` (one thread), as
/// [`accumulate_file`].
pub fn accumulate_reader<R: Read>(r: R, frame: Option<&Transform>) -> Result<Accumulated> {
    let mut acc = Accumulator::new();
    let mut src = Source::new(r);
    let (format, stats) = decode(&mut src, &mut acc, false)?;
    Ok(finish(&acc, format, stats, frame))
}

/// Points held by the caller: `n` records `[x, y, z, nx, ny, nz, w]` from
/// `record(i)`, checked as a file's records are (a non-finite point skipped
/// with a warning, a normal off unit length renormalised, a coordinate out of
/// bounds, a zero normal or a bad weight an error naming `point i`, counted
/// from 0), summed into `H` and `M` re-expressed in `frame` as
/// [`accumulate_file`] does. `weighted`: `w` is a weight (else 1).
pub fn accumulate_records(
    n: usize,
    record: impl Fn(usize) -> [f64; 7],
    weighted: bool,
    frame: Option<&Transform>,
) -> Result<Accumulated> {
    let mut acc = Accumulator::new();
    let stats = check_records(&mut acc, n, record, weighted)?;
    Ok(finish(&acc, PointFormat::Memory, stats, frame))
}

/// The records of [`accumulate_records`], checked the same way and held (a
/// raw scan's records carry the placeholder normal `+z`, as [`read_xyz`]
/// reads them).
pub fn collect_records(
    n: usize,
    record: impl Fn(usize) -> [f64; 7],
    weighted: bool,
) -> Result<PointData> {
    let mut sink = Collect::default();
    let stats = check_records(&mut sink, n, record, weighted)?;
    Ok(sink.into_data(PointFormat::Memory, &stats))
}

fn check_records<S: Sink>(
    sink: &mut S,
    n: usize,
    record: impl Fn(usize) -> [f64; 7],
    weighted: bool,
) -> Result<Stats> {
    let mut ck = check::Checker::new(sink, weighted, n);
    for i in 0..n {
        ck.record(&record(i))
            .map_err(|f| f.error(format!("point {i}"), None))?;
    }
    Ok(ck.stats)
}

fn finish(
    acc: &Accumulator,
    format: PointFormat,
    stats: Stats,
    frame: Option<&Transform>,
) -> Accumulated {
    let asm = acc.finish();
    Accumulated {
        assembly: match frame {
            Some(t) => asm.congruence(&t.adjoint()),
            None => asm,
        },
        format,
        warnings: stats.warnings(),
    }
}
