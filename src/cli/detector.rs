//! The detector commands: `degeneracy`, `tunnel`, `simulate`,
//! `calibrate-threshold`. Arguments here; computations in
//! `extrinsic_audit::pipeline::detector`.

use super::{emit, parse_ell, parse_noise, parse_positive, parse_voxel};
use extrinsic_audit::degeneracy::normals::NormalParams;
use extrinsic_audit::degeneracy::pairs;
use extrinsic_audit::degeneracy::points::{
    accumulate_file_with, read_points_with, read_xyz_classes, read_xyz_with, PointData,
};
use extrinsic_audit::degeneracy::scene::{voxel_downsample_weighted, Cloud};
use extrinsic_audit::degeneracy::scene::{SceneKind, TUNNEL_RADIUS};
use extrinsic_audit::degeneracy::threshold::{Calibration, SEEDS};
use extrinsic_audit::degeneracy::Assembly;
use extrinsic_audit::degeneracy::MetricRule;
use extrinsic_audit::diagnostic::Warning;
use extrinsic_audit::diagnostic::{Error, Result};
use extrinsic_audit::geometry::Transform;
use extrinsic_audit::pipeline::detector::{self as det, RawScan, SimulateParams, TunnelParams};
use extrinsic_audit::pipeline::transform_between;
use extrinsic_audit::progress::{NoProgress, Progress};
use extrinsic_audit::render::OutputFormat;
use extrinsic_audit::report::detector::{MatricesJson, NormalsJson, PairJson};
use extrinsic_audit::tolerances::{
    DEFAULT_ELLS, DEFAULT_TAU, MAX_SIM_NOISE_M, PAIR_GATE_M, PROGRESS_MIN_BYTES,
    PROGRESS_MIN_POINTS, RAW_MIN_NEIGHBOURS, RAW_NORMAL_RADIUS_M, RAW_VOXEL_RANGE_M,
    SIM_VOXEL_RANGE_M,
};
use nalgebra::Vector6;
use std::io::Write;
use std::path::PathBuf;

#[derive(clap::Args, Debug, Clone)]
#[command(
    about = "Degeneracy of your own scan (points with normals, or raw with --estimate-normals), for every detector family",
    long_about = "Reads points with unit normals (CSV x,y,z,nx,ny,nz[,w] with or without a header; \
PLY ascii/binary and PCD ascii/binary/binary_compressed with normal fields) expressed in the body \
frame, or a raw scan (x y z ..., the output of a LiDAR driver; LAS and LAZ files are raw scans) \
with --estimate-normals: optional \
voxel grid (--voxel), PCA normals within --normal-radius (default 0.3 m) from at least \
--min-neighbours points (default 8), at most --knn nearest, an optional planarity gate \
(--min-planarity), oriented toward --viewpoint (default the sensor origin). H and M are \
assembled about the centroid, so map or UTM coordinates lose no digit. Optionally \
re-expresses them in another frame, and prints for every detector family the generalized \
eigenvalues of H v = lambda M v (ascending), the threshold and the number of eigenvalues below \
it; then the degenerate subspace under the point displacement metric as screws (axis, pitch, \
axis point; or a translation direction) and its per-axis footprint, which depends on the frame.\n\n\
--shift x,y,z and --rotate-rpy r,p,y give the new frame's pose T = (R, d) in the input frame \
(R = Rz(y) Ry(p) Rx(r)), so p_new = R^T (p - d) and n_new = R^T n. The point displacement \
eigenvalues do not change under either; the other families' may.\n\n\
--tau is the point-displacement threshold (dimensionless, default 1e-2). The baselines' \
eigenvalues are dimensioned; those of unnormalized, characteristic length l=, block scaling and \
adapted constant add up \
over points, so they are compared per point (eigenvalue / sum of weights) with the threshold \
`audit calibrate-threshold` finds for each on the synthetic corridors (paper's rule: the \
midpoint of its interval in the 0.10 m voxel, 0.01 m noise configuration); Jacobi and point \
displacement are count-free. The JSON gives each family's threshold on its eigenvalues and the \
per-point one. A weight column (w) is kept with --estimate-normals: each voxel's weight is the \
mean of its points' weights.\n\n\
--show-matrices prints H and M. The degenerate subspace's screws are classified relative to the \
cloud's RMS radius L about its centroid: a translation when the rotation fraction is at most 0.3, \
zero pitch when |pitch| <= 0.1 L; an axis is in the footprint when its score is at least 0.1.\n\n\
With --target, POINTS is the source of a scan pair: each source point (voxel grid when asked) is \
moved by --initial-guess (the pose of the source frame in the target frame), paired with its \
nearest target point within --gate (default 1 m, the paper's), and H and M are assembled from \
the pairs as point-to-plane ICP does (source point, target normal rotated into the source frame).\n\n\
Examples:\n  audit degeneracy scan.pcd\n  audit degeneracy raw_scan.pcd --estimate-normals --voxel 0.1\n  \
audit degeneracy b.pcd --target a.pcd --estimate-normals --voxel 0.1 --initial-guess-file b_in_a.txt\n  \
audit degeneracy scan.ply --shift 1,0,0 --format json --show-matrices\n  \
audit degeneracy points.csv --rotate-rpy 0,0,1.5708 --tau 0.005 --ell 0.5,2"
)]
pub struct DegeneracyArgs {
    /// Point file with normals (CSV, PLY or PCD; detected from the content).
    pub points: PathBuf,
    /// Point-displacement threshold: an eigenvalue below it is degenerate (baselines use their calibrated thresholds).
    #[arg(long, default_value_t = DEFAULT_TAU, value_parser = parse_positive, allow_hyphen_values = true)]
    pub tau: f64,
    /// Origin of the new frame in the input frame, `x,y,z` (m).
    #[arg(long, allow_hyphen_values = true)]
    pub shift: Option<String>,
    /// Orientation of the new frame in the input frame, `roll,pitch,yaw` (rad).
    #[arg(long, allow_hyphen_values = true)]
    pub rotate_rpy: Option<String>,
    /// Characteristic lengths (m) for the characteristic length family, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = DEFAULT_ELLS, value_parser = parse_ell, allow_hyphen_values = true, value_name = "M,...")]
    pub ell: Vec<f64>,
    /// A raw scan: estimate the normals (PCA within --normal-radius, oriented toward --viewpoint) instead of reading them.
    #[arg(long)]
    pub estimate_normals: bool,
    /// With --estimate-normals: voxel grid edge (m) applied first (one centroid per voxel).
    #[arg(long, value_parser = parse_raw_voxel, allow_hyphen_values = true, value_name = "M")]
    pub voxel: Option<f64>,
    /// With --estimate-normals: neighbourhood radius (m).
    #[arg(long, default_value_t = RAW_NORMAL_RADIUS_M, value_parser = parse_positive, allow_hyphen_values = true, value_name = "M")]
    pub normal_radius: f64,
    /// With --estimate-normals: use at most the K nearest neighbours within the radius.
    #[arg(long, value_name = "K")]
    pub knn: Option<usize>,
    /// With --estimate-normals: fewest neighbours (the point counted) for a normal.
    #[arg(long, default_value_t = RAW_MIN_NEIGHBOURS, value_name = "N")]
    pub min_neighbours: usize,
    /// With --estimate-normals: drop points whose neighbourhood planarity (l2-l3)/l1 (eigenvalues descending) is below this, 0 to 1 (planarity gate).
    #[arg(long, value_parser = parse_positive, allow_hyphen_values = true, value_name = "P")]
    pub min_planarity: Option<f64>,
    /// With --estimate-normals: normals point toward this point `x,y,z` (m, input frame; default the sensor origin).
    #[arg(long, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub viewpoint: Option<String>,
    /// Print H and M (in the frame and about the centroid).
    #[arg(long)]
    pub show_matrices: bool,
    /// With --estimate-normals: keep only the LAS/LAZ points of these classifications (`2`: ground).
    #[arg(long, value_delimiter = ',', value_name = "N,...")]
    pub class: Vec<u8>,
    /// Scan pair: H and M from correspondences of POINTS (the source, raw) with this target (normals from the file, or estimated with --estimate-normals).
    #[arg(long, value_name = "FILE")]
    pub target: Option<PathBuf>,
    /// With --target: correspondence gate (m), nearest target point within it.
    #[arg(long, default_value_t = PAIR_GATE_M, value_parser = parse_positive, allow_hyphen_values = true, value_name = "M")]
    pub gate: f64,
    /// With --target: pose of the source frame in the target frame, `x,y,z,roll,pitch,yaw` (m, rad).
    #[arg(long, allow_hyphen_values = true, value_name = "X,Y,Z,R,P,Y")]
    pub initial_guess: Option<String>,
    /// With --target: the same as a file holding a 4x4 row-major matrix (16 numbers).
    #[arg(long, value_name = "FILE")]
    pub initial_guess_file: Option<PathBuf>,
    /// Output format
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
}

#[derive(clap::Args, Debug, Clone)]
#[command(
    about = "The paper's frame sweep on your own scan: decision and count change rates per detector family",
    long_about = "Assembles H and M from POINTS exactly as `audit degeneracy` does (every option of it \
applies: --estimate-normals, --voxel, --target, ...) and applies the paper's 861 frame changes \
(identity, 20 pure rotations, and pure translation, general and orthogonal-control arms at 14 lever \
arms from 0 to 20 m, 20 draws each; seeded) to it. For every family it prints how many changes \
flip the degeneracy decision and the degenerate count, as rates with Wilson 95 % intervals, and \
the largest relative eigenvalue change. With --rig FILE... --from --to, the decision of every \
family in your rig's other frame is added.\n\n\
Examples:\n  audit sweep scan.pcd --estimate-normals --voxel 0.1\n  \
audit sweep scan.pcd --estimate-normals --rig robot.urdf --from base_link --to lidar --format json"
)]
pub struct SweepArgs {
    /// Everything `audit degeneracy` takes.
    #[command(flatten)]
    pub scan: DegeneracyArgs,
    /// Seed of the random frame changes.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Calibration files that define your rig (URDF, TF, LIO YAML, ...).
    #[arg(long, num_args = 1.., value_name = "FILE")]
    pub rig: Vec<PathBuf>,
    /// With --rig: the cloud's frame.
    #[arg(long)]
    pub from: Option<String>,
    /// With --rig: the other frame.
    #[arg(long)]
    pub to: Option<String>,
}

/// `audit sweep`.
pub fn sweep(args: &SweepArgs, out: &mut dyn Write) -> Result<i32> {
    if args.rig.is_empty() && (args.from.is_some() || args.to.is_some()) {
        return Err(Error::usage("--from/--to apply only with --rig"));
    }
    let s = &args.scan;
    let (asm, _, _, _) = scan_assembly(s)?;
    let rig = if args.rig.is_empty() {
        None
    } else {
        Some(transform_between(
            &args.rig,
            args.from.as_deref(),
            args.to.as_deref(),
        )?)
    };
    let report = det::sweep(&asm, s.tau, &s.ell, args.seed, rig.as_ref())
        .map_err(|e| e.in_file(&s.points))?;
    emit(&report, s.format, out)?;
    Ok(0)
}

/// `--voxel` of `degeneracy` within [`RAW_VOXEL_RANGE_M`].
fn parse_raw_voxel(s: &str) -> std::result::Result<f64, String> {
    let v = parse_positive(s)?;
    let (lo, hi) = RAW_VOXEL_RANGE_M;
    if !(lo..=hi).contains(&v) {
        return Err(format!("expected {lo} to {hi} m, found `{s}`"));
    }
    Ok(v)
}

#[derive(clap::Args, Debug, Clone)]
#[command(
    about = "Reproduce the paper's circular-tunnel example (footprint changes, eigenvalues do not)",
    long_about = "Builds a noise-free circular tunnel (radius 2.85 m about z, exact radial \
normals), solves H v = lambda M v with the point displacement metric with the body origin \
on the axis and again in a frame shifted off the axis, and prints the eigenvalues, the \
nullity, the per-axis footprint of the degenerate subspace (frame-dependent) and the \
rotational degenerate twist as a coordinate tuple.\n\n\
Expected: on the axis the rotational twist is [0 0 1 0 0 0] and the footprint rot-z + \
trans-z; one metre off the axis the twist is [0 0 1 0 1 0] and the footprint rot-z + \
trans-y + trans-z; nullity 2 in both; identical eigenvalues.\n\n\
Examples:\n  audit tunnel\n  audit tunnel --shift 0,2,0 --format json\n  \
audit tunnel --radius 1.5 --length 30"
)]
pub struct TunnelArgs {
    /// Tunnel radius (m).
    #[arg(long, default_value_t = TUNNEL_RADIUS)]
    pub radius: f64,
    /// Tunnel length along z (m), centred on the origin.
    #[arg(long, default_value_t = 20.0)]
    pub length: f64,
    /// Distance between rings of points along the axis (m).
    #[arg(long, default_value_t = 0.1)]
    pub ring_spacing: f64,
    /// Points per ring (equally spaced in angle).
    #[arg(long, default_value_t = 360)]
    pub points_per_ring: usize,
    /// Origin of the second frame in the first, `x,y,z` (m); no rotation.
    #[arg(long, default_value = "1,0,0", allow_hyphen_values = true)]
    pub shift: String,
    /// Degeneracy threshold on the point displacement eigenvalues.
    #[arg(long, default_value_t = DEFAULT_TAU, value_parser = parse_positive, allow_hyphen_values = true)]
    pub tau: f64,
    /// Output format
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
}

#[derive(clap::Args, Debug, Clone)]
#[command(
    about = "Show what your rig's extrinsic does to each detector on a synthetic scene",
    long_about = "Builds a synthetic scene (circular tunnel, rectangular corridor or right-angle \
corner; see `audit calibrate-threshold --help` for the geometry) about the origin of frame --from, \
expresses it in both frames of your rig (the transform from --from to --to composed from FILE...), \
and prints, for every detector family, the generalized eigenvalues in both frames, whether the \
degeneracy decision changes, the degenerate count, the per-axis footprint in both frames, the \
largest principal angle between the degenerate subspaces after transport v = Ad(T) v', and the \
difference between the corrections a remapping estimator applies in the two frames, \
Delta = (P_A - Ad(T) P_B Ad(T)^-1) xi, for the update --update.\n\n\
The scene goes through the paper's pipeline (range noise, voxel grid with a random origin, PCA \
normals within 0.30 m from at least 8 neighbours) unless --exact-normals is given.\n\n\
Without FILE, --shift and --rotate-rpy give the pose of frame B in frame A directly.\n\n\
Examples:\n  audit simulate robot.urdf --from base_link --to velodyne\n  \
audit simulate fastlio.yaml --from imu --to lidar --scene corridor --noise 0.01 --seed 3\n  \
audit simulate --shift 0.3,0,0.2 --rotate-rpy 0,0,1.57 --scene tunnel --format json"
)]
pub struct SimulateArgs {
    /// Calibration files that define the frames (URDF, TF, LIO YAML, ...).
    pub files: Vec<PathBuf>,
    /// Body frame (the scene is built about its origin).
    #[arg(long)]
    pub from: Option<String>,
    /// Sensor frame.
    #[arg(long)]
    pub to: Option<String>,
    /// Without FILE: origin of frame B in frame A, `x,y,z` (m).
    #[arg(long, allow_hyphen_values = true)]
    pub shift: Option<String>,
    /// Without FILE: orientation of frame B in frame A, `roll,pitch,yaw` (rad).
    #[arg(long, allow_hyphen_values = true)]
    pub rotate_rpy: Option<String>,
    /// Scene: tunnel (2 degenerate directions), corridor (1) or corner (0).
    #[arg(long, default_value = "tunnel")]
    pub scene: String,
    /// Range-noise standard deviation (m).
    #[arg(long, default_value_t = 0.0, value_parser = parse_noise, allow_hyphen_values = true)]
    pub noise: f64,
    /// Seed of the scene (sampling phase, noise, voxel grid origin).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Voxel size (m) of the preprocessing pipeline.
    #[arg(long, default_value_t = 0.1, value_parser = parse_voxel, allow_hyphen_values = true)]
    pub voxel: f64,
    /// Keep the exact surface normals (no voxel grid, no normal estimation).
    #[arg(long)]
    pub exact_normals: bool,
    /// Point-displacement threshold (baselines use their calibrated thresholds, see `audit degeneracy --help`).
    #[arg(long, default_value_t = DEFAULT_TAU, value_parser = parse_positive, allow_hyphen_values = true)]
    pub tau: f64,
    /// Characteristic lengths (m), comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = DEFAULT_ELLS, value_parser = parse_ell, allow_hyphen_values = true, value_name = "M,...")]
    pub ell: Vec<f64>,
    /// Pose update xi = `wx,wy,wz,tx,ty,tz` in frame A (rad, m) for the correction difference.
    #[arg(
        long,
        default_value = "0.01,-0.02,0.015,0.05,0.03,-0.04",
        allow_hyphen_values = true
    )]
    pub update: String,
    /// Output format
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
}

#[derive(clap::Args, Debug, Clone)]
#[command(
    about = "Find each detector's threshold interval that reproduces analytically known degenerate counts",
    long_about = "Sweeps the threshold tau over three synthetic corridors whose number of degenerate \
directions follows from geometry (rectangular corridor: 1, circular tunnel of radius 2.85 m: 2, \
right-angle L corner: 0) under nine preprocessing configurations (range noise 0, 0.01, 0.05 m x \
voxel 0.05, 0.10, 0.20 m; eight seeds each; 216 instances) and reports, per metric family, the \
interval lo < tau <= hi in which the count of eigenvalues below tau equals the analytic count for \
every instance of a configuration, and the intersection across configurations.\n\n\
The paper reports [5.3e-3, 8.3e-2] for the point displacement metric and empty intersections for \
every other family; with the defaults this gives (5.1e-3, 7.0e-2] for point displacement, empty \
intersections for characteristic length l=0.25 and l=10 and Jacobi, and non-empty ones for unnormalized, characteristic length l=2.85 and block scaling. \
The families whose eigenvalues add up over points (unnormalized, characteristic length l=, block scaling) are swept per point \
(eigenvalue / number of points), as `audit degeneracy` compares them; Jacobi and point \
displacement are count-free. \
Differences from the paper's setup: the noise levels (0.05 m chosen as the highest because at \
0.03 m unnormalized and characteristic length l=10 kept a threshold where the paper reports them failing), the two finer voxel \
sizes, the corridor dimensions (3.0 m x 2.5 m, 12 m long) and the sampling (regular grid at half \
the voxel with a random phase) are our choices, as the paper does not give them; the residuals come \
from one cloud with its own estimated normals (no source/target pair, no correspondence gating, \
no dual-normal weighting). The pipeline otherwise follows the paper: range noise, voxel grid with a \
random origin, PCA normals within 0.30 m from at least 8 points, estimated from the noisy points.\n\n\
Examples:\n  audit calibrate-threshold\n  audit calibrate-threshold --seeds 2 --format json\n  \
audit calibrate-threshold --noise 0 --voxel 0.1 --ell 0.5,5"
)]
pub struct CalibrateThresholdArgs {
    /// Seeds per configuration and scene.
    #[arg(long, default_value_t = SEEDS)]
    pub seeds: u64,
    /// Range-noise levels (m), comma-separated.
    #[arg(long, default_value = "0,0.01,0.05")]
    pub noise: String,
    /// Voxel sizes (m), comma-separated (at least 0.02).
    #[arg(long, default_value = "0.05,0.1,0.2")]
    pub voxel: String,
    /// Characteristic lengths (m), comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = DEFAULT_ELLS, value_parser = parse_ell, allow_hyphen_values = true, value_name = "M,...")]
    pub ell: Vec<f64>,
    /// Worker threads (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Output format
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
}

/// Parse `x,y,z` (three finite numbers).
fn parse_triple(s: &str, what: &str) -> Result<[f64; 3]> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(Error::usage(format!(
            "{what}: expected three comma-separated numbers x,y,z, found {s:?}"
        )));
    }
    let mut v = [0.0; 3];
    for (k, p) in parts.iter().enumerate() {
        v[k] = p
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                Error::usage(format!("{what}: expected a finite number, found {p:?}"))
            })?;
    }
    Ok(v)
}

/// A comma-separated list of numbers in `[min, max]` (1 to 16 of them).
fn parse_list(s: &str, what: &str, (min, max): (f64, f64)) -> Result<Vec<f64>> {
    let v: Vec<f64> = s
        .split(',')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .map(|p| {
            p.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && (min..=max).contains(x))
                .ok_or_else(|| {
                    Error::usage(format!(
                        "{what}: expected numbers from {min} to {max}, found {p:?}"
                    ))
                })
        })
        .collect::<Result<_>>()?;
    if v.is_empty() || v.len() > 16 {
        return Err(Error::usage(format!(
            "{what}: expected 1 to 16 values, found {}",
            v.len()
        )));
    }
    Ok(v)
}

/// The frame the user asked for (identity without options).
fn frame_from_args(shift: Option<&str>, rpy: Option<&str>) -> Result<Transform> {
    let d = match shift {
        Some(s) => parse_triple(s, "--shift")?,
        None => [0.0; 3],
    };
    let r = match rpy {
        Some(s) => parse_triple(s, "--rotate-rpy")?,
        None => [0.0; 3],
    };
    Transform::from_rpy(r, d)
}

pub fn degeneracy(args: &DegeneracyArgs, out: &mut dyn Write) -> Result<i32> {
    let (asm, warnings, normals, pair) = scan_assembly(args)?;
    let frame = frame_from_args(args.shift.as_deref(), args.rotate_rpy.as_deref())?;
    let mut report = det::degeneracy_of(&asm, &warnings, &frame, args.tau, &args.ell)
        .map_err(|e| e.in_file(&args.points))?;
    report.normals = normals;
    report.pair = pair;
    if args.show_matrices {
        report.matrices = Some(MatricesJson::new(&asm));
    }
    emit(&report, args.format, out)?;
    Ok(0)
}

/// What a scan gives: its assembly in the requested frame, the file's
/// warnings, the normal estimation and the pair, when asked.
type ScanAssembly = (
    Assembly,
    Vec<Warning>,
    Option<NormalsJson>,
    Option<PairJson>,
);

/// The assembly `audit degeneracy` (and `audit sweep`) analyses.
fn scan_assembly(args: &DegeneracyArgs) -> Result<ScanAssembly> {
    let frame = frame_from_args(args.shift.as_deref(), args.rotate_rpy.as_deref())?;
    let pair_only = args.initial_guess.is_some() || args.initial_guess_file.is_some();
    if pair_only && args.target.is_none() {
        return Err(Error::usage(
            "--initial-guess and --initial-guess-file apply only with --target",
        ));
    }
    let mut pair = None;
    let (asm, warnings, normals) = if let Some(target) = &args.target {
        let (asm, w, n, p) = pair_assembly(args, target, &frame)?;
        pair = Some(p);
        (asm, w, n)
    } else if args.estimate_normals {
        raw_assembly(args, &frame)?
    } else {
        if !args.class.is_empty() {
            return Err(Error::usage(
                "--class applies only with --estimate-normals (LAS and LAZ are raw scans)",
            ));
        }
        if args.voxel.is_some() || args.viewpoint.is_some() || args.knn.is_some() {
            return Err(Error::usage(
                "--voxel, --viewpoint and --knn apply only with --estimate-normals",
            ));
        }
        // Streamed: H and M without holding the points; the frame by congruence.
        let acc = accumulate_file_with(&args.points, Some(&frame), &*read_progress(&args.points))
            .map_err(raw_scan_hint)?;
        (acc.assembly, acc.warnings, None)
    };
    Ok((asm, warnings, normals, pair))
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

/// The initial guess of a pair (identity without one).
fn initial_guess(args: &DegeneracyArgs, warnings: &mut Vec<Warning>) -> Result<Transform> {
    match (&args.initial_guess, &args.initial_guess_file) {
        (Some(_), Some(_)) => Err(Error::usage(
            "give --initial-guess or --initial-guess-file, not both",
        )),
        (Some(s), None) => {
            let v = parse_update(s).map_err(|_| {
                Error::usage(format!(
                    "--initial-guess: expected six numbers x,y,z,roll,pitch,yaw, found {s:?}"
                ))
            })?;
            Transform::from_rpy([v[3], v[4], v[5]], [v[0], v[1], v[2]])
        }
        (None, Some(f)) => {
            let text = std::fs::read_to_string(f).map_err(|e| Error::io(f, &e))?;
            let v: Vec<f64> = text
                .split_whitespace()
                .map(|t| t.trim_matches(',').parse::<f64>())
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| {
                    Error::parse("expected 16 numbers (a 4x4 row-major matrix)").in_file(f)
                })?;
            if v.len() != 16 {
                return Err(Error::parse(format!(
                    "expected 16 numbers (a 4x4 row-major matrix), found {}",
                    v.len()
                ))
                .in_file(f));
            }
            let m: [[f64; 4]; 4] = std::array::from_fn(|i| std::array::from_fn(|j| v[4 * i + j]));
            Transform::from_matrix4(m, warnings).map_err(|e| e.in_file(f))
        }
        (None, None) => Ok(Transform::identity()),
    }
}

/// A scan pair's assembly in `frame`: the source's points (raw, voxel grid
/// when asked), the target with normals (read, or estimated as a raw scan).
fn pair_assembly(
    args: &DegeneracyArgs,
    target: &std::path::Path,
    frame: &Transform,
) -> Result<(Assembly, Vec<Warning>, Option<NormalsJson>, PairJson)> {
    let mut warnings = Vec::new();
    let guess = initial_guess(args, &mut warnings)?;
    let src = read_raw(args, &args.points)?;
    // The source's weights, as in the single-cloud path (the mean per voxel).
    let (source, source_weights) = match args.voxel {
        Some(v) => voxel_downsample_weighted(&src.points, src.weights.as_deref(), v, [0.0; 3]),
        None => (src.points, src.weights),
    };
    warnings.extend(src.warnings);
    let (cloud, normals) = if args.estimate_normals {
        let data = read_raw(args, target)?;
        warnings.extend(data.warnings);
        let (c, nj) = det::raw_scan_cloud_with(
            &data.points,
            &raw_params(args)?,
            &*normals_progress(&data.points),
        )
        .map_err(|e| e.in_file(target))?;
        (c, Some(nj))
    } else {
        let data = read_points_with(target, &*read_progress(target))?;
        warnings.extend(data.warnings);
        (
            Cloud {
                points: data.points,
                normals: data.normals,
            },
            None,
        )
    };
    let (asm, st) = pairs::pair_assembly_weighted(
        &source,
        source_weights.as_deref(),
        &cloud,
        &guess,
        args.gate,
    )
    .map_err(|e| e.in_file(&args.points))?;
    let pj = PairJson {
        target: target.display().to_string(),
        gate_m: args.gate,
        initial_guess: det::frame_json(&guess),
        source_points: st.source,
        target_points: st.target,
        correspondences: st.matched,
        mean_distance_m: st.mean_distance,
    };
    Ok((asm.congruence(&frame.adjoint()), warnings, normals, pj))
}

/// A raw scan's points: every point, or with --class the LAS/LAZ points of
/// those classifications.
fn read_raw(args: &DegeneracyArgs, path: &std::path::Path) -> Result<PointData> {
    let progress = read_progress(path);
    if args.class.is_empty() {
        read_xyz_with(path, &*progress)
    } else {
        read_xyz_classes(path, &args.class, &*progress)
    }
}

/// A bar on a terminal's standard error while reading `path`, when it is
/// large enough to take about a second (issue 13).
fn read_progress(path: &std::path::Path) -> Box<dyn Progress> {
    let big = std::fs::metadata(path).is_ok_and(|m| m.len() >= PROGRESS_MIN_BYTES);
    if big {
        Box::new(super::display::TermProgress::new())
    } else {
        Box::new(NoProgress)
    }
}

/// A bar while estimating the normals of `points`, when they are many.
fn normals_progress(points: &[[f64; 3]]) -> Box<dyn Progress> {
    if points.len() >= PROGRESS_MIN_POINTS {
        Box::new(super::display::TermProgress::new())
    } else {
        Box::new(NoProgress)
    }
}

/// The raw-scan options of the arguments.
fn raw_params(args: &DegeneracyArgs) -> Result<RawScan> {
    let viewpoint = match args.viewpoint.as_deref() {
        Some(s) => parse_triple(s, "--viewpoint")?,
        None => [0.0; 3],
    };
    Ok(RawScan {
        voxel: args.voxel,
        normals: NormalParams {
            radius: args.normal_radius,
            knn: args.knn,
            min_neighbours: args.min_neighbours,
            min_planarity: args.min_planarity,
            viewpoint,
        },
        threads: 0,
    })
}

/// A raw scan's assembly in `frame`: points read (normals not required),
/// voxel grid, PCA normals in the input frame, then the frame by congruence.
fn raw_assembly(
    args: &DegeneracyArgs,
    frame: &Transform,
) -> Result<(Assembly, Vec<Warning>, Option<NormalsJson>)> {
    let data = read_raw(args, &args.points)?;
    let raw = raw_params(args)?;
    let progress = normals_progress(&data.points);
    let (asm, nj) =
        det::raw_scan_assembly_with(&data.points, data.weights.as_deref(), &raw, &*progress)
            .map_err(|e| e.in_file(&args.points))?;
    Ok((asm.congruence(&frame.adjoint()), data.warnings, Some(nj)))
}

pub fn tunnel(args: &TunnelArgs, out: &mut dyn Write) -> Result<i32> {
    let report = det::tunnel(&TunnelParams {
        radius: args.radius,
        length: args.length,
        ring_spacing: args.ring_spacing,
        points_per_ring: args.points_per_ring,
        shift: parse_triple(&args.shift, "--shift")?,
        tau: args.tau,
    })?;
    emit(&report, args.format, out)?;
    Ok(0)
}

fn parse_update(s: &str) -> Result<Vector6<f64>> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect::<Option<Vec<f64>>>()
        .ok_or_else(|| Error::usage(format!("--update: expected six numbers, found {s:?}")))?;
    if v.len() != 6 {
        return Err(Error::usage(format!(
            "--update: expected six numbers wx,wy,wz,tx,ty,tz, found {}",
            v.len()
        )));
    }
    Ok(Vector6::from_column_slice(&v))
}

/// The rig transform: composed from files, or given by --shift/--rotate-rpy.
fn simulate_transform(args: &SimulateArgs) -> Result<Transform> {
    if args.files.is_empty() {
        if args.shift.is_none() && args.rotate_rpy.is_none() {
            return Err(Error::usage(
                "expected calibration FILE... with --from/--to, or --shift/--rotate-rpy",
            ));
        }
        return frame_from_args(args.shift.as_deref(), args.rotate_rpy.as_deref());
    }
    if args.shift.is_some() || args.rotate_rpy.is_some() {
        return Err(Error::usage("--shift/--rotate-rpy apply only without FILE"));
    }
    transform_between(&args.files, args.from.as_deref(), args.to.as_deref())
}

pub fn simulate(args: &SimulateArgs, out: &mut dyn Write) -> Result<i32> {
    let t = simulate_transform(args)?;
    let scene = SceneKind::parse(&args.scene).ok_or_else(|| {
        Error::usage(format!(
            "--scene: expected tunnel, corridor or corner, found {:?}",
            args.scene
        ))
    })?;
    let params = SimulateParams {
        scene,
        noise: args.noise,
        seed: args.seed,
        voxel: args.voxel,
        exact_normals: args.exact_normals,
        tau: args.tau,
        ells: args.ell.clone(),
        update: parse_update(&args.update)?,
    };
    emit(&det::simulate(&params, &t)?, args.format, out)?;
    Ok(0)
}

/// The sweep the arguments ask for.
pub fn calibration_from_args(args: &CalibrateThresholdArgs) -> Result<Calibration> {
    if args.seeds == 0 || args.seeds > 1000 {
        return Err(Error::usage(format!(
            "--seeds: expected 1 to 1000, found {}",
            args.seeds
        )));
    }
    let ells = &args.ell;
    let mut rules = vec![MetricRule::Unnormalized];
    rules.extend(ells.iter().map(|&l| MetricRule::CharacteristicLength(l)));
    rules.extend([
        MetricRule::BlockScaling,
        MetricRule::Jacobi,
        MetricRule::PointDisplacement,
    ]);
    let mut c = Calibration {
        noise_levels: parse_list(&args.noise, "--noise", (0.0, MAX_SIM_NOISE_M))?,
        voxel_sizes: parse_list(&args.voxel, "--voxel", SIM_VOXEL_RANGE_M)?,
        seeds: args.seeds,
        rules,
        ..Calibration::default()
    };
    if args.threads > 0 {
        c.threads = args.threads.min(64);
    }
    Ok(c)
}

pub fn calibrate_threshold(args: &CalibrateThresholdArgs, out: &mut dyn Write) -> Result<i32> {
    let c = calibration_from_args(args)?;
    let progress = super::display::TermProgress::new();
    emit(
        &det::calibrate_threshold_with(&c, &progress)?,
        args.format,
        out,
    )?;
    Ok(0)
}
