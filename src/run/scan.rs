//! One scan, or one pair of scans, of a run made into every family's answer
//! in every frame: the workers' job.
//!
//! A scan's points are decoded ([`load`]), checked as every point file's
//! are (a non-finite coordinate or normal dropped and counted, coordinates
//! within `MAX_COORDINATE`, normals renormalised when off unit length),
//! then used as stored when the scan has normal fields, or else down-sampled
//! (voxel grid anchored at the scan frame's origin) and given PCA normals
//! (the single-scan pipeline of `audit degeneracy --estimate-normals`).
//! `H` and `M` are assembled once, in the scan frame, and described about
//! every body frame by congruence. A pair assembles the source's points
//! against the target's normals at the initial guess
//! ([`crate::degeneracy::pairs`]). Every step runs on the worker's thread
//! alone: the run is parallel across scans.

use super::source::{Payload, ScanItem};
use crate::degeneracy::normals::{estimate_normals_progress, NormalParams};
use crate::degeneracy::pairs::{correspondences, PairStats};
use crate::degeneracy::points::{read_points_with, read_xyz_with};
use crate::degeneracy::scene::{voxel_downsample, Cloud};
use crate::degeneracy::threshold::default_threshold;
use crate::degeneracy::{analyse, footprint, Accumulator, Assembly, MetricRule};
use crate::diagnostic::{Code, Error, Result, Warning};
use crate::formats::bag::pointcloud2::{self, CloudError};
use crate::geometry::Transform;
use crate::progress::NoProgress;
use crate::tolerances::{MAX_COORDINATE, NORMAL_UNIT_TOL, NORMAL_ZERO_TOL};
use std::sync::Arc;

/// How every scan is processed (the same for the whole run).
#[derive(Debug, Clone)]
pub struct Settings {
    /// The families, in report order.
    pub rules: Vec<MetricRule>,
    /// Point-displacement threshold (the others use their calibrated ones).
    pub tau: f64,
    /// Voxel edge (m) for scans whose normals are estimated; `None`: none.
    pub voxel: Option<f64>,
    /// Normal estimation.
    pub normals: NormalParams,
    /// Estimate normals even where the scan has normal fields.
    pub estimate: bool,
    /// Correspondence gate of a pair (m).
    pub gate: f64,
    /// Most cells a scan may have.
    pub max_cells: usize,
}

/// Why a scan was left out (its kebab-case name is the CSV's `reason`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Skip {
    /// `height` or `width` 0, or no point left.
    Empty,
    /// Fields, steps or data that contradict each other; a bad coordinate
    /// or normal; a message that does not decode.
    InvalidCloud,
    /// More cells than `MAX_SCAN_CELLS`.
    TooLarge,
    /// The file could not be read.
    Unreadable,
    /// Normal estimation kept no point.
    NoNormals,
    /// The points do not determine `H` and `M` (fewer than three, collinear).
    Unusable,
    /// A pair's scans have no pose.
    NoPose,
    /// No source point has a target point within the gate.
    NoCorrespondence,
}

impl Skip {
    /// The name (`invalid-cloud`).
    pub fn name(self) -> &'static str {
        match self {
            Skip::Empty => "empty",
            Skip::InvalidCloud => "invalid-cloud",
            Skip::TooLarge => "too-large",
            Skip::Unreadable => "unreadable",
            Skip::NoNormals => "no-normals",
            Skip::Unusable => "unusable",
            Skip::NoPose => "no-pose",
            Skip::NoCorrespondence => "no-correspondence",
        }
    }
}

/// Where a scan's normals came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NormalsFrom {
    /// The scan's own normal fields.
    Fields,
    /// PCA (voxel grid first when asked).
    Estimated,
}

/// One family in one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FamilyResult {
    /// Generalized eigenvalues, ascending (`None` when the metric fails).
    pub eigenvalues: Option<[f64; 6]>,
    /// The threshold on these eigenvalues (per point ones times the weight).
    pub threshold: f64,
    /// Degenerate directions.
    pub count: Option<usize>,
    /// Per-axis footprint of the degenerate subspace (rot x y z, trans x y z).
    pub footprint: Option<[bool; 6]>,
    /// Why the family has no answer.
    pub error: Option<String>,
}

impl FamilyResult {
    /// The smallest eigenvalue over the threshold (below 1: degenerate).
    pub fn margin(&self) -> Option<f64> {
        self.eigenvalues.map(|e| e[0] / self.threshold)
    }
}

/// One scan (or pair) analysed, or left out.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The scan (a pair's source).
    pub scan: ScanMeta,
    /// A pair's target.
    pub target: Option<ScanMeta>,
    /// Why it was left out, and the message.
    pub skipped: Option<(Skip, String)>,
    /// Cells read (a pair's source's).
    pub cells: Option<usize>,
    /// Cells dropped as non-finite.
    pub nonfinite: Option<usize>,
    /// Points in `H` (a pair's correspondences).
    pub points: usize,
    /// Where the normals came from (a pair's target's).
    pub normals: Option<NormalsFrom>,
    /// A pair's matching.
    pub pair: Option<PairOutcome>,
    /// Per frame of the run (the scan frame first): `None` where the frame
    /// is unknown to the scan's transforms.
    pub frames: Vec<Option<Vec<FamilyResult>>>,
    /// Named warnings of this scan.
    pub warnings: Vec<Warning>,
}

/// What identifies a scan in the outputs.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanMeta {
    /// Its place in the run.
    pub index: usize,
    /// Its time in the run (s).
    pub time_s: Option<f64>,
    /// Its stamp (ns).
    pub stamp_ns: Option<i128>,
    /// Its frame.
    pub frame_id: Option<String>,
    /// Its file (for sequences) or where in the bag.
    pub place: String,
}

impl ScanMeta {
    /// The metadata of a source item.
    pub fn of(item: &ScanItem) -> Self {
        ScanMeta {
            index: item.index,
            time_s: item.time_s,
            stamp_ns: item.stamp_ns,
            frame_id: item.frame_id.clone(),
            place: item.place.clone(),
        }
    }
}

/// A pair's matching.
#[derive(Debug, Clone, PartialEq)]
pub struct PairOutcome {
    /// The initial guess (pose of the source frame in the target frame).
    pub guess: Transform,
    /// What the correspondence search found.
    pub stats: PairStats,
}

/// The poses of the run's frames in one scan's frame (the scan frame first,
/// the identity; `None`: unknown to the scan's transforms).
pub type FramePoses = Arc<Vec<Option<Transform>>>;

/// A job for a worker.
#[derive(Debug, Clone)]
pub enum Job {
    /// One scan.
    Scan(Arc<ScanItem>, FramePoses),
    /// A pair: target, source, the guess (or why there is none), the
    /// source's frames.
    Pair(
        Arc<ScanItem>,
        Arc<ScanItem>,
        std::result::Result<Transform, String>,
        FramePoses,
    ),
}

impl Job {
    /// Cells it holds, for the work queue's budget.
    pub fn cells(&self) -> usize {
        match self {
            Job::Scan(s, _) => s.cells,
            Job::Pair(t, s, ..) => t.cells + s.cells,
        }
    }
}

/// A scan's points as read, before normals are estimated.
struct Read {
    points: Vec<[f64; 3]>,
    normals: Option<Vec<[f64; 3]>>,
    cells: Option<usize>,
    nonfinite: Option<usize>,
    warnings: Vec<Warning>,
}

type Skipped = (Skip, String);

/// Read a scan's points; `normals`: read its normal fields when it has them.
fn load(item: &ScanItem, normals: bool, s: &Settings) -> std::result::Result<Read, Skipped> {
    match &item.payload {
        Payload::Cloud2 { data, encoding } => {
            let c = pointcloud2::decode(data, *encoding)
                .map_err(|e| (Skip::InvalidCloud, format!("sensor_msgs/PointCloud2: {e}")))?;
            let p = c.points(normals, s.max_cells).map_err(|e| match e {
                CloudError::Empty => (
                    Skip::Empty,
                    format!("height {} x width {}: no cell", c.height, c.width),
                ),
                CloudError::TooLarge(n) => (
                    Skip::TooLarge,
                    format!(
                        "{n} cells: expected at most {} (MAX_SCAN_CELLS)",
                        s.max_cells
                    ),
                ),
                CloudError::Invalid(m) => (Skip::InvalidCloud, m),
            })?;
            let mut warnings = Vec::new();
            if p.integer_xyz {
                warnings.push(Warning::new(
                    Code::AssumedConvention,
                    "x, y or z is an integer field: taken as metres as it is (PointCloud2 has no scale)",
                ));
            }
            if p.extra_bytes > 0 {
                warnings.push(Warning::new(
                    Code::Ignored,
                    format!(
                        "{} bytes of data past the last point (height x row_step) ignored",
                        p.extra_bytes
                    ),
                ));
            }
            Ok(Read {
                points: p.points,
                normals: p.normals,
                cells: Some(p.cells),
                nonfinite: Some(p.nonfinite),
                warnings,
            })
        }
        Payload::KittiBin(f) => kitti_bin(f, s.max_cells),
        Payload::PointFile(f) => point_file(f, normals),
    }
}

/// A KITTI velodyne `.bin`: float32 little-endian x, y, z, intensity.
fn kitti_bin(f: &std::path::Path, max_cells: usize) -> std::result::Result<Read, Skipped> {
    let cap = (max_cells * 16) as u64;
    let bytes = crate::input::read_bytes(
        f,
        cap,
        "the KITTI scan size cap (MAX_SCAN_CELLS x 16 bytes)",
    )
    .map_err(|e| (Skip::Unreadable, e.message))?;
    if bytes.len() % 16 != 0 {
        return Err((
            Skip::InvalidCloud,
            format!(
                "{} bytes: expected a multiple of 16 (float32 x, y, z, intensity per point)",
                bytes.len()
            ),
        ));
    }
    let mut points = Vec::with_capacity(bytes.len() / 16);
    for r in bytes.chunks_exact(16) {
        let v = |k: usize| f64::from(f32::from_le_bytes([r[k], r[k + 1], r[k + 2], r[k + 3]]));
        let p = [v(0), v(4), v(8)];
        if p.iter().all(|x| x.is_finite()) {
            points.push(p);
        }
    }
    let cells = bytes.len() / 16;
    Ok(Read {
        nonfinite: Some(cells - points.len()),
        cells: Some(cells),
        points,
        normals: None,
        warnings: Vec::new(),
    })
}

/// A point file: with its normals when it has them (and they are asked
/// for), else its points alone.
fn point_file(f: &std::path::Path, normals: bool) -> std::result::Result<Read, Skipped> {
    let unreadable = |e: Error| (Skip::Unreadable, e.message);
    if normals {
        match read_points_with(f, &NoProgress) {
            Ok(d) => {
                return Ok(Read {
                    points: d.points,
                    normals: Some(d.normals),
                    cells: None,
                    nonfinite: None,
                    warnings: d.warnings,
                })
            }
            Err(e) if !misses_normals(&e) => return Err(unreadable(e)),
            Err(_) => {}
        }
    }
    let d = read_xyz_with(f, &NoProgress).map_err(unreadable)?;
    Ok(Read {
        points: d.points,
        normals: None,
        cells: None,
        nonfinite: None,
        warnings: d.warnings,
    })
}

/// The point readers' refusal of a file without normal fields.
fn misses_normals(e: &Error) -> bool {
    let m = &e.message;
    m.contains("missing normal_x") || m.contains("missing nx") || m.contains("6 or 7 columns")
}

/// The checks every point reader applies to a record: coordinates within
/// `MAX_COORDINATE`, normals not zero, renormalised when off unit length.
fn check(r: &mut Read) -> std::result::Result<(), Skipped> {
    if let Some(x) = r.points.iter().flatten().find(|x| x.abs() > MAX_COORDINATE) {
        return Err((
            Skip::InvalidCloud,
            format!("a coordinate of {x:e} m: expected within +-{MAX_COORDINATE:e}"),
        ));
    }
    let Some(ns) = r.normals.as_mut() else {
        return Ok(());
    };
    let (mut fixed, mut worst) = (0usize, 0.0f64);
    for n in ns.iter_mut() {
        let n2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        if (n2 - 1.0).abs() <= NORMAL_UNIT_TOL {
            continue;
        }
        let norm = n2.sqrt();
        if norm.is_nan() || norm < NORMAL_ZERO_TOL {
            return Err((
                Skip::InvalidCloud,
                format!("a zero normal [{}, {}, {}]", n[0], n[1], n[2]),
            ));
        }
        if (norm - 1.0).abs() > NORMAL_UNIT_TOL {
            fixed += 1;
            worst = worst.max((norm - 1.0).abs());
            *n = [n[0] / norm, n[1] / norm, n[2] / norm];
        }
    }
    if fixed > 0 {
        r.warnings.push(Warning::new(
            Code::AssumedConvention,
            format!("{fixed} normals were not unit length (largest | |n| - 1 | = {worst:.3e}); renormalised"),
        ));
    }
    Ok(())
}

/// A scan's cloud with normals: as stored, or estimated (voxel grid first).
fn with_normals(r: Read, s: &Settings) -> std::result::Result<(Cloud, NormalsFrom), Skipped> {
    if let (Some(n), false) = (&r.normals, s.estimate) {
        return Ok((
            Cloud {
                points: r.points,
                normals: n.clone(),
            },
            NormalsFrom::Fields,
        ));
    }
    let pts = match s.voxel {
        Some(v) => voxel_downsample(&r.points, v, [0.0; 3]),
        None => r.points,
    };
    let (cloud, _, _) = estimate_normals_progress(&pts, &s.normals, 1, &NoProgress)
        .map_err(|e| (Skip::Unusable, e.message))?;
    if cloud.is_empty() {
        return Err((
            Skip::NoNormals,
            format!(
                "no point got a normal: {} points, none with {} neighbours within {} m",
                pts.len(),
                s.normals.min_neighbours,
                s.normals.radius
            ),
        ));
    }
    Ok((cloud, NormalsFrom::Estimated))
}

/// A pair's source points: as stored when the scan has normals (and they
/// are not re-estimated), else down-sampled as a raw scan is.
fn source_points(r: Read, s: &Settings) -> Vec<[f64; 3]> {
    match (&r.normals, s.estimate, s.voxel) {
        (Some(_), false, _) | (_, _, None) => r.points,
        (_, _, Some(v)) => voxel_downsample(&r.points, v, [0.0; 3]),
    }
}

/// `H` and `M` of a cloud, on this thread.
fn assemble(c: &Cloud) -> Result<Assembly> {
    let mut acc = Accumulator::new().threads(1);
    acc.add(&c.points, &c.normals, None)?;
    Ok(acc.finish())
}

/// Every family in every frame (`frames[0]` the scan frame); an error when
/// point displacement has none in the scan frame (collinear points: no
/// family is meaningful then).
fn families(
    asm: &Assembly,
    frames: &[Option<Transform>],
    s: &Settings,
) -> Result<Vec<Option<Vec<FamilyResult>>>> {
    let mut out = Vec::with_capacity(frames.len());
    for (k, t) in frames.iter().enumerate() {
        let Some(t) = t else {
            out.push(None);
            continue;
        };
        let a = if k == 0 {
            *asm
        } else {
            asm.congruence(&t.adjoint())
        };
        let fr: Vec<FamilyResult> = s.rules.iter().map(|r| family(&a, r, s.tau)).collect();
        if k == 0 {
            let pd = s
                .rules
                .iter()
                .position(|r| *r == MetricRule::PointDisplacement);
            if let Some(e) = pd.and_then(|i| fr[i].error.clone()) {
                return Err(Error::invalid(e));
            }
        }
        out.push(Some(fr));
    }
    Ok(out)
}

fn family(asm: &Assembly, rule: &MetricRule, tau: f64) -> FamilyResult {
    let threshold = default_threshold(rule, tau);
    match analyse(asm, rule, threshold) {
        Ok(a) => FamilyResult {
            eigenvalues: Some(a.eig.values),
            threshold: a.raw_threshold(),
            count: Some(a.degenerate_count),
            footprint: Some(footprint(&a.degenerate_vectors())),
            error: None,
        },
        Err(e) => FamilyResult {
            eigenvalues: None,
            threshold: threshold * rule.count_scale(asm).unwrap_or(1.0),
            count: None,
            footprint: None,
            error: Some(e.message),
        },
    }
}

/// An outcome that says why the scan was left out.
fn skipped(
    scan: ScanMeta,
    target: Option<ScanMeta>,
    (why, msg): Skipped,
    frames: usize,
) -> Outcome {
    Outcome {
        scan,
        target,
        skipped: Some((why, msg)),
        cells: None,
        nonfinite: None,
        points: 0,
        normals: None,
        pair: None,
        frames: vec![None; frames],
        warnings: Vec::new(),
    }
}

/// A worker's job done (never a panic: every failure is a skipped outcome).
pub fn run(job: &Job, s: &Settings) -> Outcome {
    match job {
        Job::Scan(item, frames) => scan(item, frames, s),
        Job::Pair(target, source, guess, frames) => pair(target, source, guess, frames, s),
    }
}

fn scan(item: &ScanItem, frames: &[Option<Transform>], s: &Settings) -> Outcome {
    let meta = ScanMeta::of(item);
    let mut r = match load(item, true, s).and_then(|mut r| check(&mut r).map(|_| r)) {
        Ok(r) => r,
        Err(e) => return skipped(meta, None, e, frames.len()),
    };
    let (cells, nonfinite) = (r.cells, r.nonfinite);
    if r.points.is_empty() {
        let msg = format!("no finite point of {} cells", cells.unwrap_or(0));
        return skipped(meta, None, (Skip::Empty, msg), frames.len());
    }
    let mut warnings = std::mem::take(&mut r.warnings);
    let (cloud, from) = match with_normals(r, s) {
        Ok(c) => c,
        Err(e) => return skipped(meta, None, e, frames.len()),
    };
    let res = assemble(&cloud).and_then(|a| families(&a, frames, s));
    match res {
        Ok(fr) => Outcome {
            scan: meta,
            target: None,
            skipped: None,
            cells,
            nonfinite,
            points: cloud.len(),
            normals: Some(from),
            pair: None,
            frames: fr,
            warnings: std::mem::take(&mut warnings),
        },
        Err(e) => skipped(meta, None, (Skip::Unusable, e.message), frames.len()),
    }
}

fn pair(
    target: &ScanItem,
    source: &ScanItem,
    guess: &std::result::Result<Transform, String>,
    frames: &[Option<Transform>],
    s: &Settings,
) -> Outcome {
    let (meta, tmeta) = (ScanMeta::of(source), Some(ScanMeta::of(target)));
    let n = frames.len();
    let guess = match guess {
        Ok(g) => *g,
        Err(m) => return skipped(meta, tmeta, (Skip::NoPose, m.clone()), n),
    };
    let read = |item: &ScanItem| load(item, true, s).and_then(|mut r| check(&mut r).map(|_| r));
    let (t, src) = match (read(target), read(source)) {
        (Ok(t), Ok(src)) => (t, src),
        (Err((w, m)), _) => {
            return skipped(
                meta,
                tmeta,
                (w, format!("target scan {}: {m}", target.index)),
                n,
            )
        }
        (_, Err((w, m))) => {
            return skipped(
                meta,
                tmeta,
                (w, format!("source scan {}: {m}", source.index)),
                n,
            )
        }
    };
    let (cells, nonfinite) = (src.cells, src.nonfinite);
    let mut warnings = t.warnings.clone();
    warnings.extend(src.warnings.iter().cloned());
    let (tcloud, from) = match with_normals(t, s) {
        Ok(c) => c,
        Err((w, m)) => {
            return skipped(
                meta,
                tmeta,
                (w, format!("target scan {}: {m}", target.index)),
                n,
            )
        }
    };
    let sp = source_points(src, s);
    let (matched, stats) = match correspondences(&sp, &tcloud, &guess, s.gate) {
        Ok(x) => x,
        Err(e) => return skipped(meta, tmeta, (Skip::Unusable, e.message), n),
    };
    if matched.is_empty() {
        let msg = format!(
            "none of the {} source points has a target point within {} m at the initial guess",
            sp.len(),
            s.gate
        );
        return skipped(meta, tmeta, (Skip::NoCorrespondence, msg), n);
    }
    match assemble(&matched).and_then(|a| families(&a, frames, s)) {
        Ok(fr) => Outcome {
            scan: meta,
            target: tmeta,
            skipped: None,
            cells,
            nonfinite,
            points: matched.len(),
            normals: Some(from),
            pair: Some(PairOutcome { guess, stats }),
            frames: fr,
            warnings,
        },
        Err(e) => skipped(meta, tmeta, (Skip::Unusable, e.message), n),
    }
}
