//! The detector commands' computations: every family on the user's scan
//! (`scan` reads it), the paper's frame sweep on it, the paper's circular
//! tunnel, a synthetic scene seen from both frames of a rig, and the
//! threshold calibration. Each takes a plain options struct and returns its
//! typed report; `values` parses the options' textual forms (`x,y,z`, lists).

mod options;
mod points;
mod scan;
mod values;

pub(crate) use options::check_tau_ells;
pub use options::{DetectorOptions, NormalOptions};
pub use points::{Coords, Points};
pub use scan::{read_scan, InitialGuess, KeptCloud, Scan, ScanOptions, ScanPair};
pub use values::{parse_frame, parse_initial_guess, parse_scene, parse_triple, parse_update};

use crate::analysis::metric::adapted_metric_matrix;
use crate::analysis::Family;
use crate::degeneracy::information_shares;
use crate::degeneracy::points::PointData;
use crate::degeneracy::points::{accumulate_records, collect_records};
use crate::degeneracy::scene::{synthesize, tunnel_exact, Preprocess, SceneKind};
use crate::degeneracy::threshold::default_threshold;
use crate::degeneracy::threshold::Calibration;
use crate::degeneracy::{
    analyse, canonical_basis, check_transport, classify_subspace, correction_difference,
    footprint_flags, footprint_scores, reexpress, rel_diff, Analysis, Assembly, MetricRule,
};
use crate::degeneracy::{frame_sweep, paper_frame_changes, Arm};
use crate::diagnostic::{Error, Result};
use crate::geometry::Transform;
use crate::progress::ProgressFactory;
use crate::report::detector::{
    CorrectionJson, DegeneracyReport, FamilyComparison, FamilyEigen, FromTo, HmJson, MatricesJson,
    PairJson, PoseJson, RigDecisionJson, ScanSceneData, SceneCloud, SimulateReport, SubspaceJson,
    SweepFamilyJson, SweepReport, ThresholdReport, TunnelFrameJson, TunnelReport,
};
use crate::tolerances::MAX_SCENE_CLOUD_POINTS;
use crate::tolerances::{
    DEFAULT_PITCH_TOL, MAX_CALIBRATION_SEEDS, MAX_CALIBRATION_THREADS, MAX_SIM_NOISE_M,
    SIM_VOXEL_RANGE_M,
};
use nalgebra::{DMatrix, Vector6};
use scan::{normals_progress, with_normals, RawScan};
use std::path::PathBuf;

fn check_tau(tau: f64) -> Result<()> {
    if tau.is_finite() && tau > 0.0 {
        Ok(())
    } else {
        Err(Error::usage(format!(
            "--tau: expected a positive number, found {tau}"
        )))
    }
}

/// A pose as the reports print it.
pub fn frame_json(t: &Transform) -> PoseJson {
    let d = t.translation();
    PoseJson {
        translation_m: [d.x, d.y, d.z],
        rpy_rad: t.rpy(),
    }
}

/// A scan pair as the report prints it.
fn pair_json(p: &ScanPair) -> PairJson {
    PairJson {
        target: p.target.display().to_string(),
        gate_m: p.gate,
        initial_guess: frame_json(&p.initial_guess),
        source_points: p.stats.source,
        target_points: p.stats.target,
        correspondences: p.stats.matched,
        mean_distance_m: p.stats.mean_distance,
    }
}

/// Every family on points with normals, re-expressed in `frame` (the points
/// are copied; `audit degeneracy` streams a file instead, see
/// `degeneracy_of`).
pub fn degeneracy(
    data: &PointData,
    frame: &Transform,
    tau: f64,
    ells: &[f64],
) -> Result<DegeneracyReport> {
    check_tau(tau)?;
    let (p, n) = reexpress(&data.points, &data.normals, frame);
    let asm = Assembly::from_points(&p, &n, data.weights.as_deref())?;
    degeneracy_of(&asm, &data.warnings, frame, tau, ells)
}

/// Every family on an assembly already expressed in `frame` (e.g.
/// `degeneracy::points::accumulate_file`, which applies the frame change to
/// the sums by congruence).
pub fn degeneracy_of(
    asm: &Assembly,
    warnings: &[crate::diagnostic::Warning],
    frame: &Transform,
    tau: f64,
    ells: &[f64],
) -> Result<DegeneracyReport> {
    check_tau(tau)?;
    let asm = *asm;
    // Point displacement first: its error (collinear points) is the one to report.
    let pd = analyse(&asm, &MetricRule::PointDisplacement, tau)?;
    let mut families = Vec::new();
    for rule in MetricRule::default_set(ells, None) {
        let threshold = default_threshold(&rule, tau);
        let an: Result<Analysis> = if rule == MetricRule::PointDisplacement {
            Ok(pd.clone())
        } else {
            analyse(&asm, &rule, threshold)
        };
        families.push(match an {
            Ok(a) => FamilyEigen {
                family: rule.family(),
                ell_m: rule.ell(&asm),
                eigenvalues: Some(a.eig.values),
                threshold: a.raw_threshold(),
                threshold_per_point: rule.family().spec().per_point.then_some(a.tau),
                degenerate_count: Some(a.degenerate_count),
                error: None,
                label: rule.label(),
            },
            Err(e) => FamilyEigen {
                family: rule.family(),
                ell_m: rule.ell(&asm).filter(|x| x.is_finite()),
                eigenvalues: None,
                threshold: threshold * rule.count_scale(&asm).unwrap_or(1.0),
                threshold_per_point: rule.family().spec().per_point.then_some(threshold),
                degenerate_count: None,
                error: Some(e.message),
                label: rule.label(),
            },
        });
    }
    let degenerate_subspace = classify_subspace(&asm, &pd)
        .iter()
        .map(SubspaceJson::scored)
        .collect();
    let scores = footprint_scores(&pd.degenerate_vectors());
    Ok(DegeneracyReport {
        schema_version: crate::report::SCHEMA_VERSION,
        points: asm.count,
        frame: frame_json(frame),
        families,
        degenerate_subspace,
        footprint: footprint_flags(&scores),
        footprint_scores: scores,
        matrices: None,
        normals: None,
        pair: None,
        warnings: DegeneracyReport::warning_lines(warnings),
        scene: ScanSceneData {
            centroid_m: asm.center,
            rms_radius_m: asm.rms_radius(),
            frame_xyzw: frame.quaternion_xyzw(),
            guess: None,
            weakest: (
                std::array::from_fn(|i| pd.eig.vectors[(i, 0)]),
                pd.eig.values[0],
            ),
            cloud: None,
        },
    })
}

/// What `audit degeneracy` is asked for.
#[derive(Debug, Clone)]
pub struct DegeneracyOptions {
    /// The scan and the frame.
    pub scan: ScanOptions,
    /// Point-displacement threshold (the other families use their calibrated
    /// thresholds).
    pub tau: f64,
    /// Characteristic lengths (m) of the characteristic length family.
    pub ells: Vec<f64>,
    /// Add `H` and `M` to the report.
    pub show_matrices: bool,
}

/// Every family on the user's scan ([`read_scan`], then [`degeneracy_of`]).
pub fn degeneracy_scan(
    opts: &DegeneracyOptions,
    bars: &dyn ProgressFactory,
) -> Result<DegeneracyReport> {
    let scan = read_scan(&opts.scan, bars)?;
    let mut report = degeneracy_of(
        &scan.assembly,
        &scan.warnings,
        &opts.scan.frame,
        opts.tau,
        &opts.ells,
    )
    .map_err(|e| e.in_file(&opts.scan.points))?;
    report.normals = scan.normals;
    report.pair = scan.pair.as_ref().map(pair_json);
    report.scene.guess = scan.pair.as_ref().map(|p| {
        let d = p.initial_guess.translation();
        ([d.x, d.y, d.z], p.initial_guess.quaternion_xyzw())
    });
    if let Some(kept) = &scan.cloud {
        report.scene.cloud = Some(scene_cloud(kept, &report.scene, &opts.scan.frame));
    }
    if opts.show_matrices {
        report.matrices = Some(MatricesJson::new(&scan.assembly));
    }
    Ok(report)
}

/// Every family on `points`, as `audit degeneracy` on a scan file: `H` and
/// `M` about the centroid, re-expressed in `opts.frame`; normals estimated
/// (long estimations reported to a progress from `bars`) when there are none.
pub fn degeneracy_points(
    points: &Points,
    opts: &DetectorOptions,
    bars: &dyn ProgressFactory,
) -> Result<DegeneracyReport> {
    points.check_lengths()?;
    let n = points.xyz.len();
    let weight = |i: usize| points.weights.map_or(1.0, |w| w[i]);
    let weighted = points.weights.is_some();
    let (asm, warnings, normals) = match points.normals {
        Some(nrm) => {
            if opts.normals.estimation_asked() {
                return Err(Error::usage(
                    "points: voxel, viewpoint and knn apply only to points without normals",
                ));
            }
            let record = |i| {
                let (p, q) = (points.xyz.row(i), nrm.row(i));
                [p[0], p[1], p[2], q[0], q[1], q[2], weight(i)]
            };
            let acc = accumulate_records(n, record, weighted, Some(&opts.frame))?;
            (acc.assembly, acc.warnings, None)
        }
        None => {
            let record = |i| {
                let p = points.xyz.row(i);
                [p[0], p[1], p[2], 0.0, 0.0, 1.0, weight(i)]
            };
            let data = collect_records(n, record, weighted)?;
            let progress = normals_progress(bars, data.points.len());
            let raw = RawScan::new(&opts.normals);
            let (cloud, w, nj) =
                with_normals(&data.points, data.weights.as_deref(), &raw, &*progress)?;
            let asm = Assembly::from_points(&cloud.points, &cloud.normals, w.as_deref())?;
            (
                asm.congruence(&opts.frame.adjoint()),
                data.warnings,
                Some(nj),
            )
        }
    };
    let mut report = degeneracy_of(&asm, &warnings, &opts.frame, opts.tau, &opts.ells)?;
    report.normals = normals;
    if opts.show_matrices {
        report.matrices = Some(MatricesJson::new(&asm));
    }
    Ok(report)
}

/// The points of a scan's scene: every k-th (k the smallest that keeps at
/// most [`MAX_SCENE_CLOUD_POINTS`]) with its share of the weakest direction
/// (moved from the report's frame into the points' by `Ad(frame)`).
fn scene_cloud(kept: &KeptCloud, scene: &ScanSceneData, frame: &Transform) -> SceneCloud {
    let c = &kept.cloud;
    let v = frame.adjoint() * Vector6::from(scene.weakest.0);
    let center = frame.apply(&scene.centroid_m.into());
    let shares = information_shares(
        &c.points,
        &c.normals,
        kept.weights.as_deref(),
        &v,
        center.into(),
    );
    let stride = c.points.len().div_ceil(MAX_SCENE_CLOUD_POINTS).max(1);
    let every = |v: &[[f64; 3]]| v.iter().step_by(stride).copied().collect::<Vec<_>>();
    SceneCloud {
        points_m: every(&c.points),
        shares: shares.map(|s| s.into_iter().step_by(stride).collect()),
        total: c.points.len(),
        stride,
        target_m: kept.target.as_deref().map(every),
    }
}

/// The tunnel's parameters.
#[derive(Debug, Clone)]
pub struct TunnelParams {
    /// Radius (m).
    pub radius: f64,
    /// Length along z (m), centred on the origin.
    pub length: f64,
    /// Distance between rings (m).
    pub ring_spacing: f64,
    /// Points per ring.
    pub points_per_ring: usize,
    /// Origin of the second frame in the first (m).
    pub shift: [f64; 3],
    /// Threshold on the point-displacement eigenvalues.
    pub tau: f64,
}

/// Whether some non-zero twist in the span has zero translational part: the
/// translational block of an orthonormal basis is rank-deficient.
pub fn contains_pure_rotation(vs: &[Vector6<f64>]) -> bool {
    if vs.is_empty() {
        return false;
    }
    let m = DMatrix::from_fn(6, vs.len(), |i, j| vs[j][i]);
    let q = m.qr().q();
    let t = q.rows(3, 3).into_owned();
    let sv = t.svd(false, false).singular_values;
    // A 3 x k block with k > 3 always has a null vector.
    vs.len() > 3 || sv.iter().any(|&s| s <= 1e-6)
}

fn tunnel_frame(an: &Analysis, shift: [f64; 3]) -> (TunnelFrameJson, Vec<Vector6<f64>>) {
    let basis = canonical_basis(&an.degenerate_vectors());
    let rot: Vec<Vector6<f64>> = basis
        .iter()
        .filter(|v| v.fixed_rows::<3>(0).norm() > 0.0)
        .copied()
        .collect();
    // Rounding noise (|x| < 1e-12) printed as 0.
    let clean =
        |v: &Vector6<f64>| std::array::from_fn(|i| if v[i].abs() < 1e-12 { 0.0 } else { v[i] });
    let f = TunnelFrameJson {
        origin_m: shift,
        eigenvalues: an.eig.values,
        nullity: an.degenerate_count,
        footprint: an.footprint(),
        footprint_frame_dependent: true,
        rotational_twists: rot.iter().map(clean).collect(),
        contains_pure_rotation: contains_pure_rotation(&an.degenerate_vectors()),
    };
    (f, rot)
}

fn check_tunnel(p: &TunnelParams) -> Result<()> {
    for (name, v) in [
        ("radius", p.radius),
        ("length", p.length),
        ("ring spacing", p.ring_spacing),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::usage(format!(
                "--{name}: expected a positive number of metres, found {v}"
            )));
        }
    }
    if p.points_per_ring < 3 || p.points_per_ring > 100_000 {
        return Err(Error::usage(format!(
            "--points-per-ring: expected 3 to 100000, found {}",
            p.points_per_ring
        )));
    }
    if p.length / p.ring_spacing * p.points_per_ring as f64 > 2e7 {
        return Err(Error::limit(
            "tunnel would have more than 2e7 points: increase --ring-spacing",
        ));
    }
    Ok(())
}

/// The paper's circular tunnel, on the axis and shifted.
pub fn tunnel(p: &TunnelParams) -> Result<TunnelReport> {
    check_tunnel(p)?;
    let cloud = tunnel_exact(p.radius, p.length, p.ring_spacing, p.points_per_ring);
    let asm = Assembly::from_points(&cloud.points, &cloud.normals, None)?;
    let t = Transform::from_translation(p.shift)?;
    let (p2, n2) = reexpress(&cloud.points, &cloud.normals, &t);
    let asm2 = Assembly::from_points(&p2, &n2, None)?;
    let a = t.adjoint();
    let cong = asm.congruence(&a);
    let an1 = analyse(&asm, &MetricRule::PointDisplacement, p.tau)?;
    let an2 = analyse(&asm2, &MetricRule::PointDisplacement, p.tau)?;
    let (f1, r1) = tunnel_frame(&an1, [0.0; 3]);
    let (f2, r2) = tunnel_frame(&an2, p.shift);
    let eigenvalue_max_abs_diff = (0..6)
        .map(|k| (f1.eigenvalues[k] - f2.eigenvalues[k]).abs())
        .fold(0.0, f64::max);
    let tuple_angle = match (r1.first(), r2.first()) {
        (Some(x), Some(y)) => {
            let c = (x.dot(y) / (x.norm() * y.norm())).clamp(-1.0, 1.0);
            Some(c.acos().to_degrees())
        }
        _ => None,
    };
    let tc = check_transport(&an1, &an2, &a);
    Ok(TunnelReport {
        radius_m: p.radius,
        points: cloud.len(),
        tau: p.tau,
        metric: Family::PointDisplacement,
        on_axis: f1,
        shifted: f2,
        eigenvalue_max_abs_diff,
        rotational_tuple_angle_deg: tuple_angle,
        transported_subspace_angle_deg: tc.subspace_angle.map(f64::to_degrees),
        congruence_rel_diff: HmJson {
            h: rel_diff(&cong.h, &asm2.h),
            m: rel_diff(&cong.m, &asm2.m),
        },
    })
}

/// A synthetic scene for `simulate`.
#[derive(Debug, Clone)]
pub struct SimulateParams {
    /// The scene.
    pub scene: SceneKind,
    /// Range noise (m).
    pub noise: f64,
    /// Seed.
    pub seed: u64,
    /// Voxel size (m) of the preprocessing.
    pub voxel: f64,
    /// Exact normals, no preprocessing.
    pub exact_normals: bool,
    /// Point-displacement threshold.
    pub tau: f64,
    /// Characteristic lengths (m).
    pub ells: Vec<f64>,
    /// Update `xi` in frame A for the correction difference.
    pub update: Vector6<f64>,
}

/// A scene built about frame A, seen from frame B (`t`: pose of B in A).
pub fn simulate(p: &SimulateParams, t: &Transform) -> Result<SimulateReport> {
    check_tau(p.tau)?;
    let pre = if p.exact_normals {
        Preprocess::exact(0.05, p.noise, p.seed)
    } else {
        if !(p.voxel.is_finite() && p.voxel >= 0.02) {
            return Err(Error::usage(format!(
                "--voxel: expected at least 0.02 m, found {}",
                p.voxel
            )));
        }
        Preprocess::pipeline(p.voxel, p.noise, p.seed)
    };
    let cloud = synthesize(p.scene, &pre)?;
    let asm_a = Assembly::from_points(&cloud.points, &cloud.normals, None)?;
    let (pb, nb) = reexpress(&cloud.points, &cloud.normals, t);
    let asm_b = Assembly::from_points(&pb, &nb, None)?;
    let (a, a_inv) = (t.adjoint(), t.adjoint_inverse());
    let rules = MetricRule::default_set(&p.ells, adapted_metric_matrix(t, DEFAULT_PITCH_TOL));
    let mut families = Vec::new();
    for rule in rules {
        let tau = default_threshold(&rule, p.tau);
        let an_a = analyse(&asm_a, &rule, tau)?;
        let an_b = analyse(&asm_b, &rule, tau)?;
        let tc = check_transport(&an_a, &an_b, &a);
        let delta = correction_difference(&an_a, &an_b, &a, &a_inv, &p.update);
        let max_rel = (0..6)
            .map(|k| {
                (an_a.eig.values[k] - an_b.eig.values[k]).abs()
                    / an_a.eig.values[k].abs().max(1e-12)
            })
            .fold(0.0, f64::max);
        let footprint = FromTo {
            from: an_a.footprint(),
            to: an_b.footprint(),
        };
        families.push(FamilyComparison {
            family: rule.family(),
            ell_m: [rule.ell(&asm_a), rule.ell(&asm_b)],
            threshold: an_a.raw_threshold(),
            eigenvalues: FromTo {
                from: an_a.eig.values,
                to: an_b.eig.values,
            },
            degenerate_count: FromTo {
                from: an_a.degenerate_count,
                to: an_b.degenerate_count,
            },
            decision_changes: an_a.degenerate() != an_b.degenerate(),
            footprint_changes: footprint.from != footprint.to,
            footprint,
            subspace_angle_deg: tc.subspace_angle.map(f64::to_degrees),
            correction_difference: CorrectionJson {
                rotation_rad: delta.fixed_rows::<3>(0).norm(),
                translation_m: delta.fixed_rows::<3>(3).norm(),
            },
            max_eigenvalue_rel_change: max_rel,
            label: rule.label(),
        });
    }
    Ok(SimulateReport {
        scene: p.scene.name(),
        points: cloud.len(),
        noise_m: p.noise,
        seed: p.seed,
        tau: p.tau,
        transform: frame_json(t),
        families,
        lever_arm_m: t.lever_arm(),
    })
}

/// Where `audit simulate` takes the rig's transform from.
#[derive(Debug, Clone, Default)]
pub struct SimulateRig {
    /// Calibration files; the transform is the chain `from` -> `to`.
    pub files: Vec<PathBuf>,
    /// The body frame (frame A).
    pub from: Option<String>,
    /// The sensor frame (frame B).
    pub to: Option<String>,
    /// Without files: the pose of frame B in frame A (`--shift`, `--rotate-rpy`).
    pub pose: Option<Transform>,
    /// How the files are read (`--arg`, `--package-path`, `--confine`, ...).
    pub load: crate::formats::LoadOptions,
}

/// The pose of frame B in frame A: composed from the files, or given.
pub fn simulate_transform(rig: &SimulateRig) -> Result<Transform> {
    match (&rig.pose, rig.files.is_empty()) {
        (None, true) => Err(Error::usage(
            "expected calibration FILE... with --from/--to, or --shift/--rotate-rpy",
        )),
        (Some(t), true) => Ok(*t),
        (Some(_), false) => Err(Error::usage("--shift/--rotate-rpy apply only without FILE")),
        (None, false) => super::load::transform_between(
            &rig.files,
            rig.from.as_deref(),
            rig.to.as_deref(),
            &rig.load,
        ),
    }
}

/// `calibrate_threshold`, reporting the sweep's progress.
pub fn calibrate_threshold_with(
    c: &Calibration,
    progress: &dyn crate::progress::Progress,
) -> Result<ThresholdReport> {
    let res = crate::degeneracy::threshold::calibrate_with(c, progress)?;
    Ok(ThresholdReport::new(
        &res,
        &c.noise_levels,
        &c.voxel_sizes,
        c.seeds,
    ))
}

/// What `audit calibrate-threshold` is asked for: the sweep over the
/// synthetic corridors, every default family ([`MetricRule::default_set`]).
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrateOptions {
    /// Seeds per configuration and scene, 1 to `MAX_CALIBRATION_SEEDS`.
    pub seeds: u64,
    /// Range-noise levels (m), 0 to [`MAX_SIM_NOISE_M`].
    pub noise_levels: Vec<f64>,
    /// Voxel sizes (m), in [`SIM_VOXEL_RANGE_M`].
    pub voxel_sizes: Vec<f64>,
    /// Characteristic lengths (m) of the characteristic length family.
    pub ells: Vec<f64>,
    /// Worker threads (0: the default, one per core up to 8; at most
    /// `MAX_CALIBRATION_THREADS`).
    pub threads: usize,
}

impl CalibrateOptions {
    /// `--noise` as text: a list of range-noise levels.
    pub fn parse_noise_levels(s: &str) -> Result<Vec<f64>> {
        values::parse_list(s, "--noise", (0.0, MAX_SIM_NOISE_M))
    }

    /// `--voxel` as text: a list of voxel sizes.
    pub fn parse_voxel_sizes(s: &str) -> Result<Vec<f64>> {
        values::parse_list(s, "--voxel", SIM_VOXEL_RANGE_M)
    }

    /// The calibration these options describe, checked.
    pub fn calibration(&self) -> Result<Calibration> {
        if self.seeds == 0 || self.seeds > MAX_CALIBRATION_SEEDS {
            return Err(Error::usage(format!(
                "--seeds: expected 1 to {MAX_CALIBRATION_SEEDS}, found {}",
                self.seeds
            )));
        }
        check_levels(&self.noise_levels, "--noise", (0.0, MAX_SIM_NOISE_M))?;
        check_levels(&self.voxel_sizes, "--voxel", SIM_VOXEL_RANGE_M)?;
        let mut c = Calibration {
            noise_levels: self.noise_levels.clone(),
            voxel_sizes: self.voxel_sizes.clone(),
            seeds: self.seeds,
            rules: MetricRule::default_set(&self.ells, None),
            ..Calibration::default()
        };
        if self.threads > 0 {
            c.threads = self.threads.min(MAX_CALIBRATION_THREADS);
        }
        Ok(c)
    }
}

/// A list of levels: 1 to [`MAX_LIST_VALUES`](crate::tolerances::MAX_LIST_VALUES) finite numbers in `[min, max]`.
fn check_levels(v: &[f64], what: &str, (min, max): (f64, f64)) -> Result<()> {
    if let Some(x) = v
        .iter()
        .find(|x| !(x.is_finite() && (min..=max).contains(*x)))
    {
        return Err(Error::usage(format!(
            "{what}: expected numbers from {min} to {max}, found {x}"
        )));
    }
    values::check_count(v.len(), what)
}

/// The threshold calibration `opts` describe ([`CalibrateOptions::calibration`]),
/// its sweep reported to a progress from `bars` once the options are checked.
pub fn calibrate(opts: &CalibrateOptions, bars: &dyn ProgressFactory) -> Result<ThresholdReport> {
    let c = opts.calibration()?;
    calibrate_threshold_with(&c, &*bars.progress())
}

/// Wilson score interval (95 %, `z = 1.96`) of `k` successes in `n` trials;
/// `[0, 1]` for `n = 0`.
pub fn wilson95(k: usize, n: usize) -> [f64; 2] {
    if n == 0 {
        return [0.0, 1.0];
    }
    let (k, n, z) = (k as f64, n as f64, 1.96f64);
    let z2 = z * z;
    let centre = (k + z2 / 2.0) / (n + z2);
    let half = z / (n + z2) * (k * (n - k) / n + z2 / 4.0).sqrt();
    [(centre - half).max(0.0), (centre + half).min(1.0)]
}

/// The paper's 861-change frame sweep on the user's assembly, every default
/// family with its threshold (`tau` for point displacement), and, with `rig`,
/// the decision of every family in the rig's other frame.
pub fn sweep(
    asm: &Assembly,
    tau: f64,
    ells: &[f64],
    seed: u64,
    rig: Option<&Transform>,
) -> Result<SweepReport> {
    check_tau(tau)?;
    let rules = MetricRule::default_set(ells, None);
    let taus: Vec<f64> = rules.iter().map(|r| default_threshold(r, tau)).collect();
    let changes = paper_frame_changes(seed);
    let rows = frame_sweep(asm, &changes, &rules, &taus)?;
    let mut families = Vec::new();
    for (row, rule) in rows.iter().zip(&rules) {
        let reference = analyse(asm, rule, row.tau)?;
        let n = row.evaluations;
        let rig_json = match rig {
            Some(t) => {
                let other = analyse(&asm.congruence(&t.adjoint()), rule, row.tau)?;
                Some(RigDecisionJson {
                    degenerate_count: other.degenerate_count,
                    decision_changes: other.degenerate() != reference.degenerate(),
                })
            }
            None => None,
        };
        families.push(SweepFamilyJson {
            family: rule.family(),
            label: rule.label(),
            ell_m: rule.ell(asm),
            threshold: reference.raw_threshold(),
            degenerate_count: reference.degenerate_count,
            decision_changes: row.decision_changes,
            decision_change_rate: row.decision_changes as f64 / n.max(1) as f64,
            decision_change_wilson95: wilson95(row.decision_changes, n),
            count_changes: row.count_changes,
            count_change_rate: row.count_changes as f64 / n.max(1) as f64,
            count_change_wilson95: wilson95(row.count_changes, n),
            decision_changes_by_arm: row.decision_changes_by_arm,
            max_eigenvalue_rel_change: row.max_eigenvalue_change,
            rig: rig_json,
        });
    }
    Ok(SweepReport {
        schema_version: crate::report::SCHEMA_VERSION,
        points: asm.count,
        seed,
        frame_changes: changes.len(),
        arms: Arm::ALL.map(|a| a.name()),
        rig: rig.map(frame_json),
        families,
    })
}
