//! `audit spread PATHS...`: many calibrations of one frame pair, each file
//! loaded into its own frame graph and composed for its pair, then their
//! mean, spread and outliers ([`crate::analysis::spread`]) and each one's rig
//! report for its pitch verdict and bands. A directory is walked (a fleet:
//! `vehicles/*/sensors_calibration.yaml`); a calibration is named by its file
//! name, or by its folder when the file names repeat.
//!
//! # Frame pairs
//!
//! A file's pair is, first found: its own `PATH:FROM:TO` (for every file
//! read from PATH, a file or a folder walked); `--from`/`--to`; the pair a
//! rig file declares; the file's only edge. The files whose pair is not their
//! own `PATH:FROM:TO` must agree on one pair (else the error names the first
//! file that differs); a file given as `PATH:FROM:TO` may name the pair
//! otherwise (the user says the frames are the same under other names). The
//! report's `from` and `to` are the first calibration's pair; each
//! calibration lists its own (`calibrations[].from`, `.to`).
//!
//! `PATH:FROM:TO` is split from the right (a frame name holds no `:`, a
//! file name may): an argument that exists as a path is a path whatever
//! colons it holds; otherwise its last two `:`-separated fields are FROM and
//! TO and the rest is the path.

use super::files::expand_paths;
use super::rig::{report, RigOptions};
use super::survey::is_any_input;
use crate::analysis::spread::{self, AxisSpread, Spread};
use crate::diagnostic::{Error, Result, Warning};
use crate::formats::{self, LoadOptions};
use crate::frames::FrameGraph;
use crate::geometry::uncertainty::{outputs, pitch_decision};
use crate::geometry::{PitchVerdict, Transform};
use crate::report::diff::DiffToleranceJson;
use crate::report::spread::{
    AxisJson, BandRangeJson, CalibrationJson, MeanJson, OutlierTestJson, OutliersJson,
    SetPitchJson, SpreadJson, SpreadReport, SubsetJson, METHOD,
};
use crate::report::{RigReport, SCHEMA_VERSION};
use crate::tolerances::OUTLIER_FEW;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// What `audit spread` reads and how: set the fields on
/// `SpreadOptions::default()`.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct SpreadOptions {
    /// Calibration files, or directories walked for them.
    pub paths: Vec<PathBuf>,
    /// `--from` (else the pair a rig file declares, or the file's one edge).
    pub from: Option<String>,
    /// `--to`.
    pub to: Option<String>,
    /// How the files are read.
    pub load: LoadOptions,
    /// Lengths of the bands, pitch tolerance.
    pub rig: RigOptions,
    /// `--tolerance LENGTH,ANGLE`: a calibration further than this from the mean
    /// is beyond it (the fleet gate).
    pub tolerance: Option<DiffToleranceJson>,
    /// Per-path frame pairs (`PATH:FROM:TO`, [`SpreadOptions::add_input`]):
    /// every file read from the path (a file, or a folder walked) is composed
    /// `FROM` -> `TO`, and may name the pair otherwise than the other files.
    pub pairs: Vec<(PathBuf, String, String)>,
}

impl SpreadOptions {
    /// Add one command-line input: `PATH`, or `PATH:FROM:TO` (split from the
    /// right; an argument that exists as a path is that path whatever colons
    /// it holds). An empty FROM or TO is an error.
    ///
    /// ```
    /// use extrinsic_audit::SpreadOptions;
    ///
    /// # fn main() -> extrinsic_audit::Result<()> {
    /// let mut opts = SpreadOptions::default();
    /// opts.add_input("runs/a:b.yaml:imu_link:velodyne")?;
    /// assert_eq!(opts.paths, [std::path::PathBuf::from("runs/a:b.yaml")]);
    /// assert_eq!(opts.pairs[0].1, "imu_link");
    /// assert_eq!(opts.pairs[0].2, "velodyne");
    /// assert!(opts.add_input("run.yaml::lidar").is_err());
    /// # Ok(())
    /// # }
    /// ```
    pub fn add_input(&mut self, arg: &str) -> Result<()> {
        let whole = PathBuf::from(arg);
        let parts: Vec<&str> = arg.rsplitn(3, ':').collect();
        match parts.as_slice() {
            [to, from, path] if !whole.exists() && !path.is_empty() => {
                if from.is_empty() || to.is_empty() {
                    return Err(Error::usage(format!(
                        "expected PATH:FROM:TO with both frame names, found `{arg}`"
                    )));
                }
                self.paths.push(PathBuf::from(path));
                self.pairs
                    .push((PathBuf::from(path), from.to_string(), to.to_string()));
            }
            _ => self.paths.push(whole),
        }
        Ok(())
    }

    /// The pair given for `path` (`PATH:FROM:TO`), if any.
    fn pair_of(&self, path: &Path) -> Option<(String, String)> {
        self.pairs
            .iter()
            .find(|(p, _, _)| p == path)
            .map(|(_, f, t)| (f.clone(), t.clone()))
    }
}

/// One calibration read: its file, transform, pair, and whether the pair was
/// its own `PATH:FROM:TO`; of its rig report only what the spread report
/// shows (the whole report is kilobytes a vehicle: issue 29's 100,000).
struct Read {
    path: PathBuf,
    transform: Transform,
    from: String,
    to: String,
    own_pair: bool,
    lever_arm_m: f64,
    /// The screw's `h`, its uncertainty and the pitch verdict.
    h_m: Option<f64>,
    h_uncertainty_m: Option<f64>,
    pitch_verdict: Option<PitchVerdict>,
    /// The certificate's `(ell_m, band)` per length.
    bands: Vec<(f64, [f64; 2])>,
}

impl Read {
    /// The parts of `report` the spread report shows.
    fn new(path: &Path, transform: Transform, report: RigReport, own_pair: bool) -> Read {
        let screw = &report.screw;
        Read {
            path: path.to_path_buf(),
            transform,
            own_pair,
            lever_arm_m: report.lever_arm_m,
            h_m: screw.translation_along_axis_m,
            h_uncertainty_m: screw.translation_along_axis_uncertainty_m,
            pitch_verdict: screw.pitch_verdict,
            bands: report
                .certificate
                .iter()
                .map(|c| (c.ell_m, c.band))
                .collect(),
            from: report.from,
            to: report.to,
        }
    }
}

/// The files to read, each with the pair its `PATH:FROM:TO` gives.
type Input = (PathBuf, Option<(String, String)>);

fn files(opts: &SpreadOptions) -> Result<Vec<Input>> {
    let mut out = Vec::new();
    for p in &opts.paths {
        let pair = opts.pair_of(p);
        if p.is_dir() {
            let found = expand_paths(std::slice::from_ref(p), is_any_input)?;
            out.extend(found.into_iter().map(|f| (f, pair.clone())));
        } else {
            out.push((p.clone(), pair));
        }
    }
    if out.is_empty() {
        return Err(Error::usage(
            "expected calibration files (or folders of them), found none",
        ));
    }
    Ok(out)
}

fn read_one(
    path: &Path,
    own: Option<&(String, String)>,
    opts: &SpreadOptions,
    warnings: &mut Vec<Warning>,
) -> Result<Read> {
    let loaded = formats::load_file(path, &opts.load)?;
    let declared = loaded
        .rig
        .as_ref()
        .filter(|m| !m.from.is_empty() && !m.to.is_empty())
        .map(|m| (m.from.clone(), m.to.clone()));
    let mut graph = FrameGraph::new();
    graph.add(loaded)?;
    warnings.extend(graph.warnings().iter().cloned());
    let half = opts.from.is_some() != opts.to.is_some();
    let given = own
        .cloned()
        .or_else(|| opts.from.clone().zip(opts.to.clone()));
    let (from, to) = match (given, declared) {
        (Some(p), _) => p,
        (None, Some(p)) if !half => p,
        (None, None) if !half && graph.edges().len() == 1 => {
            let e = &graph.edges()[0];
            (e.parent.clone(), e.child.clone())
        }
        _ => {
            return Err(Error::usage(
                "expected the frame pair: --from FRAME --to FRAME or PATH:FROM:TO (this file declares none and has several edges)",
            )
            .in_file(path))
        }
    };
    let chain = graph.transform(&from, &to).map_err(|e| e.in_file(path))?;
    let mut report = report(&chain, &opts.rig).map_err(|e| e.in_file(path))?;
    report.from = from;
    report.to = to;
    Ok(Read::new(path, chain.transform, report, own.is_some()))
}

/// Names: file names without their extension when they differ, else the
/// parent folders (a fleet's vehicles), else the paths as given.
fn names(paths: &[PathBuf]) -> Vec<String> {
    let by = |f: &dyn Fn(&Path) -> Option<String>| -> Option<Vec<String>> {
        let v: Vec<String> = paths.iter().map(|p| f(p)).collect::<Option<_>>()?;
        let unique: HashSet<&String> = v.iter().collect();
        (unique.len() == v.len()).then_some(v)
    };
    let file = |p: &Path| p.file_stem().map(|n| n.to_string_lossy().into_owned());
    let folder = |p: &Path| {
        p.parent()
            .and_then(Path::file_name)
            .map(|n| n.to_string_lossy().into_owned())
    };
    by(&file)
        .or_else(|| by(&folder))
        .unwrap_or_else(|| paths.iter().map(|p| p.display().to_string()).collect())
}

fn axis_json(a: &AxisSpread, names: &[String]) -> AxisJson {
    AxisJson {
        std: a.std,
        max_abs: a.max_abs,
        max_abs_calibration: a.max_abs_index.map(|i| names[i].clone()),
        norm_max: a.norm_max,
    }
}

fn spread_json(s: &Spread, names: &[String]) -> SpreadJson {
    let p = &s.spreads;
    SpreadJson {
        rotation_from_deg: axis_json(&p.rotation_from, names),
        rotation_to_deg: axis_json(&p.rotation_to, names),
        translation_from_mm: axis_json(&p.translation_from, names),
        translation_to_mm: axis_json(&p.translation_to, names),
    }
}

fn mean_json(s: &Spread) -> MeanJson {
    let m = &s.mean;
    let r = m.rotation();
    let d = m.translation();
    MeanJson {
        translation_m: [d.x, d.y, d.z],
        quaternion_xyzw: m.quaternion_xyzw(),
        rotation_matrix: [0, 1, 2].map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]),
        angle_deg: m.rotation_angle_axis().0.to_degrees(),
        lever_arm_m: m.lever_arm(),
        eigen_gap: s.eigen_gap,
    }
}

/// The set's pitch: `h` of the mean, the spread of the calibrations' `h`
/// (each along the axis aligned with the mean's) as its uncertainty.
fn set_pitch(s: &Spread, reads: &[Read], opts: &SpreadOptions) -> SetPitchJson {
    let mut per = [0usize; 3];
    for r in reads {
        match r.pitch_verdict {
            Some(PitchVerdict::Zero) => per[0] += 1,
            Some(PitchVerdict::Nonzero) => per[1] += 1,
            Some(PitchVerdict::Undecidable) => per[2] += 1,
            None => {}
        }
    }
    let (_, axis) = s.mean.rotation_angle_axis();
    let Some(e0) = axis else {
        return SetPitchJson {
            h_m: None,
            h_spread_m: None,
            verdict: None,
            per_calibration: per,
        };
    };
    let h = outputs(&s.mean, Some(&e0)).h;
    let hs: Vec<f64> = reads
        .iter()
        .map(|r| outputs(&r.transform, Some(&e0)).h)
        .collect();
    let n = hs.len() as f64;
    let mean_h = hs.iter().sum::<f64>() / n;
    let spread = (hs.len() > 1)
        .then(|| (hs.iter().map(|x| (x - mean_h).powi(2)).sum::<f64>() / (n - 1.0)).sqrt());
    // One calibration: its own uncertainty (the rounding of its numbers).
    let sigma = spread.or(reads[0].h_uncertainty_m).unwrap_or(0.0);
    SetPitchJson {
        h_m: Some(h),
        h_spread_m: spread,
        verdict: Some(pitch_decision(h, sigma, opts.rig.pitch_tol).verdict),
        per_calibration: per,
    }
}

fn outliers_json(s: &Spread, names: &[String]) -> OutliersJson {
    let test = |t: &Option<spread::OutlierTest>| {
        t.as_ref().map(|t| OutlierTestJson {
            centre: t.centre,
            robust_sigma: t.robust_sigma,
            median_distance: t.median_distance,
            limit: t.limit,
        })
    };
    let o = &s.outliers;
    OutliersJson {
        tested: o.rotation.is_some(),
        few: names.len() < OUTLIER_FEW,
        rotation: test(&o.rotation),
        translation: test(&o.translation),
        names: o.flagged.iter().map(|&i| names[i].clone()).collect(),
    }
}

/// `-1` when the calibration's screw axis points against the mean's (`e .
/// e_mean < 0`), else `1`: its `h` is then said along the axis oriented
/// with the mean's, so that the signs of a set compare. On a small rotation
/// the axis is set by calibration noise and flips from one calibration to
/// the next; `h = e . t` flips with it while the screw is the same.
fn axis_sign(t: &Transform, s: &Spread) -> f64 {
    match (t.rotation_angle_axis().1, s.mean.rotation_angle_axis().1) {
        (Some(e), Some(e0)) if e.dot(&e0) < 0.0 => -1.0,
        _ => 1.0,
    }
}

fn calibration_json(
    i: usize,
    r: &Read,
    s: &Spread,
    names: &[String],
    tol: Option<&DiffToleranceJson>,
) -> CalibrationJson {
    let d = &s.deviations[i];
    let t = r.transform.translation();
    let dist = |t: &Option<spread::OutlierTest>| t.as_ref().map(|t| t.distance[i]);
    CalibrationJson {
        name: names[i].clone(),
        file: r.path.display().to_string(),
        from: r.from.clone(),
        to: r.to.clone(),
        translation_m: [t.x, t.y, t.z],
        quaternion_xyzw: r.transform.quaternion_xyzw(),
        deviation: *d,
        rotation_distance: dist(&s.outliers.rotation),
        translation_distance: dist(&s.outliers.translation),
        outlier: s.outliers.flagged.contains(&i),
        exceeds: tol
            .is_some_and(|t| d.distance_mm > t.translation_mm || d.angle_deg > t.rotation_deg),
        lever_arm_m: r.lever_arm_m,
        h_m: r.h_m.map(|h| h * axis_sign(&r.transform, s)),
        h_uncertainty_m: r.h_uncertainty_m,
        pitch_verdict: r.pitch_verdict,
        bands: r.bands.iter().map(|&(_, b)| b).collect(),
    }
}

fn band_ranges(reads: &[Read]) -> Vec<BandRangeJson> {
    let first = &reads[0].bands;
    (0..first.len())
        .map(|k| BandRangeJson {
            ell_m: first[k].0,
            low: reads
                .iter()
                .map(|r| r.bands[k].1[0])
                .fold(f64::INFINITY, f64::min),
            high: reads.iter().map(|r| r.bands[k].1[1]).fold(0.0, f64::max),
        })
        .collect()
}

/// The set's pair (the first calibration's), after checking that the files
/// whose pair is not their own `PATH:FROM:TO` agree on one: else an error
/// naming the first file that differs.
fn one_pair(reads: &[Read]) -> Result<(String, String)> {
    let mut implicit = reads.iter().filter(|r| !r.own_pair);
    if let Some(first) = implicit.next() {
        let (f, t) = (&first.from, &first.to);
        if let Some(r) = implicit.find(|r| (&r.from, &r.to) != (f, t)) {
            return Err(Error::usage(format!(
                "expected one frame pair in every file ({f} -> {t}, from {}), found {} -> {}: give --from FRAME --to FRAME, or name this file's pair as PATH:FROM:TO",
                first.path.display(),
                r.from,
                r.to
            ))
            .in_file(&r.path));
        }
    }
    Ok((reads[0].from.clone(), reads[0].to.clone()))
}

/// Read every calibration and report their spread; the warnings the files
/// raised are returned beside it.
///
/// ```
/// use extrinsic_audit::{spread, SpreadOptions};
///
/// # fn main() -> extrinsic_audit::Result<()> {
/// // Five noisy copies of the KITTI IMU -> Velodyne extrinsic and one planted
/// // outlier (1.5 deg about x, +25 mm in x), one rig TOML each.
/// let mut opts = SpreadOptions::default();
/// opts.paths = vec![concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/spread/kitti-repeat").into()];
/// let (report, warnings) = spread(&opts)?;
/// assert!(warnings.is_empty());
/// assert_eq!((report.from.as_str(), report.to.as_str(), report.count), ("imu", "lidar", 6));
/// // scipy's Rotation.mean and numpy's mean (tests/fixtures/spread/spread_reference.json).
/// let q = report.mean.quaternion_xyzw;
/// let scipy = [-0.00521525574549396, 0.001049568981181026, 0.0003820267702573023, 0.9999857766828539];
/// assert!((0..4).all(|k| (q[k] - scipy[k]).abs() < 1e-12));
/// assert!((report.mean.translation_m[0] - 0.8147164666666667).abs() < 1e-12);
/// assert_eq!(report.outliers.names, ["kitti-repeat-outlier"]);
/// # Ok(())
/// # }
/// ```
pub fn spread(opts: &SpreadOptions) -> Result<(SpreadReport, Vec<Warning>)> {
    let inputs = files(opts)?;
    let mut warnings = Vec::new();
    let mut reads = Vec::with_capacity(inputs.len());
    let mut failed = None;
    super::parallel::ordered(
        &inputs,
        |_, (p, pair)| {
            let mut w = Vec::new();
            (read_one(p, pair.as_ref(), opts, &mut w), w)
        },
        |_, (r, w)| {
            warnings.extend(w);
            match r {
                Ok(r) => reads.push(r),
                Err(e) => failed = Some(e),
            }
            failed.is_none()
        },
    );
    if let Some(e) = failed {
        return Err(e);
    }
    let (from, to) = one_pair(&reads)?;
    let paths: Vec<PathBuf> = inputs.into_iter().map(|(p, _)| p).collect();
    let names = names(&paths);
    let transforms: Vec<Transform> = reads.iter().map(|r| r.transform).collect();
    let s = spread::spread(&transforms)?;
    let tol = opts.tolerance.as_ref();
    let calibrations: Vec<CalibrationJson> = (0..reads.len())
        .map(|i| calibration_json(i, &reads[i], &s, &names, tol))
        .collect();
    let without_outliers = if s.outliers.flagged.is_empty() {
        None
    } else {
        let keep: Vec<usize> = (0..reads.len())
            .filter(|i| !s.outliers.flagged.contains(i))
            .collect();
        let kept_names: Vec<String> = keep.iter().map(|&i| names[i].clone()).collect();
        let sub = spread::spread(&keep.iter().map(|&i| transforms[i]).collect::<Vec<_>>())?;
        Some(SubsetJson {
            mean: mean_json(&sub),
            spread: spread_json(&sub, &kept_names),
            calibrations: kept_names,
        })
    };
    let report = SpreadReport {
        schema_version: SCHEMA_VERSION,
        from,
        to,
        method: METHOD,
        count: reads.len(),
        mean: mean_json(&s),
        pitch: set_pitch(&s, &reads, opts),
        spread: spread_json(&s, &names),
        outliers: outliers_json(&s, &names),
        without_outliers,
        bands: band_ranges(&reads),
        tolerance: opts.tolerance,
        exceeded: calibrations
            .iter()
            .filter(|c| c.exceeds)
            .map(|c| c.name.clone())
            .collect(),
        calibrations,
    };
    Ok((report, warnings))
}

/// Whether the spread plot may be written to `target` (an `.svg` name, none
/// of the inputs), checked before anything is read.
pub fn check_spread_plot_target(target: &Path, inputs: &[PathBuf]) -> Result<()> {
    super::output::plot_target("spread", target, inputs)
}

/// Draw the spread plot (a strip plot per axis, outliers named) to `target`.
pub fn write_spread_plot(target: &Path, inputs: &[PathBuf], report: &SpreadReport) -> Result<()> {
    super::output::write_plot("spread", target, inputs, &report.plot())
}
