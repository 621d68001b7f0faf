//! A user's scan made into `H` and `M` for the detector (`audit degeneracy`,
//! `audit sweep`), in one of three ways:
//!
//! - points with normals: streamed from the file into the sums, the frame
//!   applied to them by congruence (no point held);
//! - a raw scan (`estimate_normals`): points read whole (LAS/LAZ filtered by
//!   classification when asked), voxel grid, PCA normals toward the viewpoint
//!   in the input frame, then the frame by congruence;
//! - a scan pair (`target`): the source's points (voxel grid when asked) moved
//!   by the initial guess and paired with their nearest target point within
//!   the gate, as point-to-plane ICP does; the target's normals read, or
//!   estimated as a raw scan's.
//!
//! Long reads and normal estimations report to a [`ProgressFactory`] when they
//! are long enough to show ([`PROGRESS_MIN_BYTES`], [`PROGRESS_MIN_POINTS`]).

use super::options::NormalOptions;
use crate::degeneracy::normals::{estimate_normals_progress, merge_duplicates, NormalParams};
use crate::degeneracy::pairs::{self, PairStats};
use crate::degeneracy::points::{
    accumulate_file_with, read_points_with, read_xyz_classes, read_xyz_with, PointData,
};
use crate::degeneracy::scene::{voxel_downsample_weighted, Cloud};
use crate::degeneracy::Assembly;
use crate::diagnostic::{Error, Result, Warning};
use crate::geometry::Transform;
use crate::progress::{NoProgress, Progress, ProgressFactory};
use crate::report::detector::NormalsJson;
use crate::tolerances::{
    MAX_MATRIX_FILE_SIZE, PAIR_GATE_M, PROGRESS_MIN_BYTES, PROGRESS_MIN_POINTS,
};
use std::path::{Path, PathBuf};

/// How a scan is read (the options of `audit degeneracy`).
#[derive(Debug, Clone)]
pub struct ScanOptions {
    /// The point file (a pair's source).
    pub points: PathBuf,
    /// The frame `H` and `M` are expressed in: its pose in the input frame.
    pub frame: Transform,
    /// A raw scan: estimate the normals instead of reading them.
    pub estimate_normals: bool,
    /// How a raw scan's normals are estimated; its voxel grid also applies to
    /// a pair's source.
    pub normals: NormalOptions,
    /// Only the LAS/LAZ points of these classifications (raw scans).
    pub classes: Vec<u8>,
    /// A scan pair: the target's point file.
    pub target: Option<PathBuf>,
    /// A pair's correspondence gate (m).
    pub gate: f64,
    /// A pair's initial guess: the pose of the source frame in the target frame.
    pub initial_guess: InitialGuess,
    /// Keep the points `H` and `M` were assembled from (`Scan::cloud`, for
    /// the 3D scene); a file with normals is then read a second time, whole
    /// (the streamed sums stay the report's).
    pub keep_points: bool,
}

impl ScanOptions {
    /// Points with normals read from `points`, in their own frame, with the
    /// defaults of `audit degeneracy` for everything else.
    pub fn new(points: impl Into<PathBuf>) -> Self {
        ScanOptions {
            points: points.into(),
            frame: Transform::identity(),
            estimate_normals: false,
            normals: NormalOptions::default(),
            classes: Vec::new(),
            target: None,
            gate: PAIR_GATE_M,
            initial_guess: InitialGuess::Identity,
            keep_points: false,
        }
    }
}

/// The initial guess of a scan pair.
#[derive(Debug, Clone, PartialEq)]
pub enum InitialGuess {
    /// The frames coincide.
    Identity,
    /// This pose (`--initial-guess`).
    Pose(Transform),
    /// A file holding a 4x4 row-major matrix, 16 numbers
    /// (`--initial-guess-file`; read with the rotation checks of a matrix).
    File(PathBuf),
}

/// A scan made into `H` and `M`, in the requested frame.
#[derive(Debug, Clone)]
pub struct Scan {
    /// `H` and `M` about the centroid.
    pub assembly: Assembly,
    /// The files' warnings.
    pub warnings: Vec<Warning>,
    /// What the normal estimation kept, when normals were estimated.
    pub normals: Option<NormalsJson>,
    /// The pair's correspondences, for a scan pair.
    pub pair: Option<ScanPair>,
    /// The points assembled, with `keep_points`.
    pub cloud: Option<KeptCloud>,
}

/// The points a scan's `H` and `M` were assembled from, in the input frame
/// (a pair's: the matched source points with the target normals rotated into
/// the source frame), and a pair's target points in the target frame.
#[derive(Debug, Clone, Default)]
pub struct KeptCloud {
    /// Points and normals.
    pub cloud: Cloud,
    /// Their weights (none: 1 each).
    pub weights: Option<Vec<f64>>,
    /// A pair's target points.
    pub target: Option<Vec<[f64; 3]>>,
}

/// How a scan pair was matched.
#[derive(Debug, Clone)]
pub struct ScanPair {
    /// The target's point file.
    pub target: PathBuf,
    /// The correspondence gate (m).
    pub gate: f64,
    /// The pose of the source frame in the target frame the pairs used.
    pub initial_guess: Transform,
    /// What the matching found.
    pub stats: PairStats,
}

/// Read the scan `opts` describes (see the module docs).
pub fn read_scan(opts: &ScanOptions, bars: &dyn ProgressFactory) -> Result<Scan> {
    if opts.target.is_none() && opts.initial_guess != InitialGuess::Identity {
        return Err(Error::usage(
            "--initial-guess and --initial-guess-file apply only with --target",
        ));
    }
    if let Some(target) = &opts.target {
        return pair_scan(opts, target, bars);
    }
    if opts.estimate_normals {
        return raw_scan(opts, bars);
    }
    if !opts.classes.is_empty() {
        return Err(Error::usage(
            "--class applies only with --estimate-normals (LAS and LAZ are raw scans)",
        ));
    }
    if opts.normals.estimation_asked() {
        return Err(Error::usage(
            "--voxel, --viewpoint and --knn apply only with --estimate-normals",
        ));
    }
    // Streamed: H and M without holding the points; the frame by congruence.
    let progress = file_progress(bars, &opts.points);
    let acc =
        accumulate_file_with(&opts.points, Some(&opts.frame), &*progress).map_err(raw_scan_hint)?;
    let cloud = match opts.keep_points {
        true => {
            let d = read_points_with(&opts.points, &NoProgress)?;
            Some(KeptCloud {
                cloud: Cloud {
                    points: d.points,
                    normals: d.normals,
                },
                weights: d.weights,
                target: None,
            })
        }
        false => None,
    };
    Ok(Scan {
        assembly: acc.assembly,
        warnings: acc.warnings,
        normals: None,
        pair: None,
        cloud,
    })
}

/// A file without normal fields is likely a raw scan: say how to read it.
fn raw_scan_hint(mut e: Error) -> Error {
    let m = &e.message;
    if m.contains("missing normal_x") || m.contains("missing nx") || m.contains("6 or 7 columns") {
        e.message
            .push_str("; a raw scan (no normals)? add --estimate-normals");
    }
    e
}

/// A bar for reading `path` when it is large enough to take about a second
/// ([`PROGRESS_MIN_BYTES`]), none otherwise.
fn file_progress(bars: &dyn ProgressFactory, path: &Path) -> Box<dyn Progress> {
    if crate::input::reported_size(path).is_some_and(|n| n >= PROGRESS_MIN_BYTES) {
        bars.progress()
    } else {
        Box::new(NoProgress)
    }
}

/// A bar for estimating the normals of `n` points when they are many
/// ([`PROGRESS_MIN_POINTS`]), none otherwise.
pub(super) fn normals_progress(bars: &dyn ProgressFactory, n: usize) -> Box<dyn Progress> {
    if n >= PROGRESS_MIN_POINTS {
        bars.progress()
    } else {
        Box::new(NoProgress)
    }
}

/// A raw scan's points: every point, or the LAS/LAZ points of the classes asked.
fn read_raw(opts: &ScanOptions, path: &Path, bars: &dyn ProgressFactory) -> Result<PointData> {
    let progress = file_progress(bars, path);
    if opts.classes.is_empty() {
        read_xyz_with(path, &*progress)
    } else {
        read_xyz_classes(path, &opts.classes, &*progress)
    }
}

/// How a raw scan (points without normals) becomes points with normals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct RawScan {
    /// Voxel edge (m) of the down-sampling (one centroid per voxel, grid
    /// anchored at the frame's origin); `None`: every point.
    pub voxel: Option<f64>,
    /// Normal estimation.
    pub normals: NormalParams,
    /// Threads for the normal estimation (0: one per core).
    pub threads: usize,
}

impl RawScan {
    fn of(opts: &ScanOptions) -> Self {
        Self::new(&opts.normals)
    }

    /// The estimation `n` asks for, one thread per core.
    pub(super) fn new(n: &NormalOptions) -> Self {
        RawScan {
            voxel: n.voxel,
            normals: n.params(),
            threads: 0,
        }
    }
}

/// A raw scan's assembly: points read (normals not required), voxel grid, PCA
/// normals in the input frame (the file's weights, the mean per voxel), then
/// the frame by congruence.
fn raw_scan(opts: &ScanOptions, bars: &dyn ProgressFactory) -> Result<Scan> {
    let data = read_raw(opts, &opts.points, bars)?;
    let progress = normals_progress(bars, data.points.len());
    let in_file = |e: Error| e.in_file(&opts.points);
    let (cloud, weights, normals) = with_normals(
        &data.points,
        data.weights.as_deref(),
        &RawScan::of(opts),
        &*progress,
    )
    .map_err(in_file)?;
    let asm = Assembly::from_points(&cloud.points, &cloud.normals, weights.as_deref())
        .map_err(in_file)?;
    Ok(Scan {
        assembly: asm.congruence(&opts.frame.adjoint()),
        warnings: data.warnings,
        normals: Some(normals),
        pair: None,
        cloud: opts.keep_points.then_some(KeptCloud {
            cloud,
            weights,
            target: None,
        }),
    })
}

/// A scan pair's assembly: the source's points (raw, voxel grid when asked,
/// their weights the mean per voxel), the target with normals (read, or
/// estimated as a raw scan), then the frame by congruence.
fn pair_scan(opts: &ScanOptions, target: &Path, bars: &dyn ProgressFactory) -> Result<Scan> {
    let mut warnings = Vec::new();
    let guess = match &opts.initial_guess {
        InitialGuess::Identity => Transform::identity(),
        InitialGuess::Pose(t) => *t,
        InitialGuess::File(f) => read_matrix(f, &mut warnings)?,
    };
    let src = read_raw(opts, &opts.points, bars)?;
    let (source, source_weights) = match opts.normals.voxel {
        Some(v) => voxel_downsample_weighted(&src.points, src.weights.as_deref(), v, [0.0; 3]),
        None => (src.points, src.weights),
    };
    warnings.extend(src.warnings);
    let (cloud, normals) = if opts.estimate_normals {
        let data = read_raw(opts, target, bars)?;
        warnings.extend(data.warnings);
        let progress = normals_progress(bars, data.points.len());
        let (c, _, nj) = with_normals(&data.points, None, &RawScan::of(opts), &*progress)
            .map_err(|e| e.in_file(target))?;
        (c, Some(nj))
    } else {
        let data = read_points_with(target, &*file_progress(bars, target))?;
        warnings.extend(data.warnings);
        let cloud = Cloud {
            points: data.points,
            normals: data.normals,
        };
        (cloud, None)
    };
    let (asm, st) = pairs::pair_assembly_weighted(
        &source,
        source_weights.as_deref(),
        &cloud,
        &guess,
        opts.gate,
    )
    .map_err(|e| e.in_file(&opts.points))?;
    let kept = match opts.keep_points {
        true => Some(pairs::matched_weighted(
            &source,
            source_weights.as_deref(),
            &cloud,
            &guess,
            opts.gate,
        )?),
        false => None,
    };
    let pair = ScanPair {
        target: target.to_path_buf(),
        gate: opts.gate,
        initial_guess: guess,
        stats: st,
    };
    Ok(Scan {
        assembly: asm.congruence(&opts.frame.adjoint()),
        warnings,
        normals,
        pair: Some(pair),
        cloud: kept.map(|(matched, weights)| KeptCloud {
            cloud: matched,
            weights,
            target: Some(cloud.points),
        }),
    })
}

/// A 4x4 row-major matrix file (16 numbers, whitespace or commas between
/// them), through the checks of a rotation matrix.
fn read_matrix(path: &Path, warnings: &mut Vec<Warning>) -> Result<Transform> {
    let text = crate::input::read_text(path, MAX_MATRIX_FILE_SIZE, "the matrix file size cap")?;
    let v: Vec<f64> = text
        .split_whitespace()
        .map(|t| t.trim_matches(',').parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| Error::parse("expected 16 numbers (a 4x4 row-major matrix)").in_file(path))?;
    if v.len() != 16 {
        return Err(Error::parse(format!(
            "expected 16 numbers (a 4x4 row-major matrix), found {}",
            v.len()
        ))
        .in_file(path));
    }
    let m: [[f64; 4]; 4] = std::array::from_fn(|i| std::array::from_fn(|j| v[4 * i + j]));
    Transform::from_matrix4(m, warnings).map_err(|e| e.in_file(path))
}

/// A raw scan's points with estimated normals: duplicates merged, voxel
/// grid, PCA normals toward the viewpoint; the weights of the points kept
/// (when given); what the estimation kept.
pub(super) fn with_normals(
    points: &[[f64; 3]],
    weights: Option<&[f64]>,
    raw: &RawScan,
    progress: &dyn Progress,
) -> Result<(Cloud, Option<Vec<f64>>, NormalsJson)> {
    let read = points.len();
    let merged = merge_duplicates(points, weights);
    let (points, weights) = match &merged {
        Some((p, w)) => (&p[..], w.as_deref()),
        None => (points, weights),
    };
    let duplicates = read - points.len();
    let grid;
    let (pts, wts) = match raw.voxel {
        Some(v) => {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::usage(format!(
                    "--voxel: expected a positive number of metres, found {v}"
                )));
            }
            let (g, w) = voxel_downsample_weighted(points, weights, v, [0.0; 3]);
            grid = g;
            (&grid[..], w)
        }
        None => (points, weights.map(<[f64]>::to_vec)),
    };
    let (cloud, st, kept) = estimate_normals_progress(pts, &raw.normals, raw.threads, progress)?;
    let wts = wts.map(|w| {
        kept.iter()
            .map(|&i| w.get(i).copied().unwrap_or(1.0))
            .collect()
    });
    if cloud.is_empty() {
        let merged = if duplicates > 0 {
            format!(" ({duplicates} duplicates merged)")
        } else {
            String::new()
        };
        return Err(Error::invalid(format!(
            "no point got a normal: {} points{merged}, none with {} neighbours within {} m (raise --normal-radius or lower --min-neighbours)",
            pts.len(),
            raw.normals.min_neighbours,
            raw.normals.radius
        )));
    }
    let n = &raw.normals;
    let normals = NormalsJson {
        points_read: read,
        duplicates_merged: duplicates,
        voxel_m: raw.voxel,
        points_after_voxel: pts.len(),
        radius_m: n.radius,
        knn: n.knn,
        min_neighbours: n.min_neighbours,
        min_planarity: n.min_planarity,
        viewpoint_m: n.viewpoint,
        kept: st.kept,
        dropped_sparse: st.sparse,
        dropped_not_planar: st.not_planar,
    };
    Ok((cloud, wts, normals))
}
