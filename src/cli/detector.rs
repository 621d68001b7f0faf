//! The detector commands: `degeneracy` and `sweep` (the library's
//! `Detector` on a scan file), and the paper's experiments `tunnel`,
//! `simulate`, `calibrate-threshold` (from `internals`). Arguments here, made
//! into the library's options; the library reads the scans and computes.

use super::args::{
    parse_noise, parse_positive, parse_voxel, EllArgs, OutputArgs, TauArgs, XacroArgs,
};
use super::display::TermBars;
use super::emit;
use extrinsic_audit::internals::degeneracy::scene::TUNNEL_RADIUS;
use extrinsic_audit::internals::degeneracy::threshold::SEEDS;
use extrinsic_audit::internals::degeneracy::MetricRule;
use extrinsic_audit::internals::pipeline::detector::{
    self as det, CalibrateOptions, SimulateParams, SimulateRig, TunnelParams,
};
use extrinsic_audit::internals::tolerances::{
    DEFAULT_ELLS, PAIR_GATE_M, RAW_MIN_NEIGHBOURS, RAW_NORMAL_RADIUS_M, RAW_VOXEL_RANGE_M,
};
use extrinsic_audit::{
    Detector, DetectorOptions, Error, Family, InitialGuess, LoadOptions, OutputFormat, PairOptions,
    Result, Robot, ScanFile,
};
use std::io::Write;
use std::path::PathBuf;

/// Help text with the family lists of the family table filled in:
/// `{per_point}` (the families whose eigenvalues add up over points),
/// `{per_point_swept}` (those of them `calibrate-threshold` sweeps, comma
/// separated) and `{count_free}` (the others).
fn with_families(text: &str) -> String {
    let label = |f: Family| match f {
        Family::CharacteristicLength => format!("{} l=", f.label()),
        _ => f.label().to_string(),
    };
    let list = |keep: &dyn Fn(Family) -> bool| -> Vec<String> {
        Family::ALL
            .into_iter()
            .filter(|&f| keep(f))
            .map(label)
            .collect()
    };
    let per_point = |f: Family| f.spec().per_point;
    let swept: Vec<Family> = MetricRule::default_set(&DEFAULT_ELLS, None)
        .iter()
        .map(MetricRule::family)
        .collect();
    text.replace("{per_point}", &prose(&list(&per_point)))
        .replace(
            "{per_point_swept}",
            &list(&|f| per_point(f) && swept.contains(&f)).join(", "),
        )
        .replace("{count_free}", &prose(&list(&|f| !per_point(f))))
}

/// `a`, `a and b`, `a, b and c`.
fn prose(names: &[String]) -> String {
    match names.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
        None => String::new(),
    }
}

#[derive(clap::Args, Debug, Clone)]
#[command(
    about = "Degeneracy of your own scan (points with normals, or raw with --estimate-normals), for every detector family",
    long_about = with_families("Reads points with unit normals (CSV x,y,z,nx,ny,nz[,w] with or without a header; \
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
eigenvalues are dimensioned; those of {per_point} add up \
over points, so they are compared per point (eigenvalue / sum of weights) with the threshold \
`audit calibrate-threshold` finds for each on the synthetic corridors (paper's rule: the \
midpoint of its interval in the 0.10 m voxel, 0.01 m noise configuration); {count_free} \
are count-free. The JSON gives each family's threshold on its eigenvalues and the \
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
audit degeneracy points.csv --rotate-rpy 0,0,1.5708 --tau 0.005 --ell 0.5,2")
)]
pub struct DegeneracyArgs {
    /// Point file with normals (CSV, PLY or PCD; detected from the content).
    pub points: PathBuf,
    #[command(flatten)]
    pub tau: TauArgs,
    /// Origin of the new frame in the input frame, `x,y,z` (m).
    #[arg(long, allow_hyphen_values = true)]
    pub shift: Option<String>,
    /// Orientation of the new frame in the input frame, `roll,pitch,yaw` (rad).
    #[arg(long, allow_hyphen_values = true)]
    pub rotate_rpy: Option<String>,
    #[command(flatten)]
    pub ell: EllArgs,
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
    #[command(flatten)]
    pub output: OutputArgs,
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
    /// How the --rig files are read.
    #[command(flatten)]
    pub xacro: XacroArgs,
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
    #[command(flatten)]
    pub tau: TauArgs,
    #[command(flatten)]
    pub output: OutputArgs,
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
    #[command(flatten)]
    pub tau: TauArgs,
    #[command(flatten)]
    pub ell: EllArgs,
    /// Pose update xi = `wx,wy,wz,tx,ty,tz` in frame A (rad, m) for the correction difference.
    #[arg(
        long,
        default_value = "0.01,-0.02,0.015,0.05,0.03,-0.04",
        allow_hyphen_values = true
    )]
    pub update: String,
    #[command(flatten)]
    pub xacro: XacroArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

#[derive(clap::Args, Debug, Clone)]
#[command(
    about = "Find each detector's threshold interval that reproduces analytically known degenerate counts",
    long_about = with_families("Sweeps the threshold tau over three synthetic corridors whose number of degenerate \
directions follows from geometry (rectangular corridor: 1, circular tunnel of radius 2.85 m: 2, \
right-angle L corner: 0) under nine preprocessing configurations (range noise 0, 0.01, 0.05 m x \
voxel 0.05, 0.10, 0.20 m; eight seeds each; 216 instances) and reports, per metric family, the \
interval lo < tau <= hi in which the count of eigenvalues below tau equals the analytic count for \
every instance of a configuration, and the intersection across configurations.\n\n\
The paper reports [5.3e-3, 8.3e-2] for the point displacement metric and empty intersections for \
every other family; with the defaults this gives (5.1e-3, 7.0e-2] for point displacement, empty \
intersections for characteristic length l=0.25 and l=10 and Jacobi, and non-empty ones for unnormalized, characteristic length l=2.85 and block scaling. \
The families whose eigenvalues add up over points ({per_point_swept}) are swept per point \
(eigenvalue / number of points), as `audit degeneracy` compares them; {count_free} \
are count-free. \
Differences from the paper's setup: the noise levels (0.05 m chosen as the highest because at \
0.03 m unnormalized and characteristic length l=10 kept a threshold where the paper reports them failing), the two finer voxel \
sizes, the corridor dimensions (3.0 m x 2.5 m, 12 m long) and the sampling (regular grid at half \
the voxel with a random phase) are our choices, as the paper does not give them; the residuals come \
from one cloud with its own estimated normals (no source/target pair, no correspondence gating, \
no dual-normal weighting). The pipeline otherwise follows the paper: range noise, voxel grid with a \
random origin, PCA normals within 0.30 m from at least 8 points, estimated from the noisy points.\n\n\
Examples:\n  audit calibrate-threshold\n  audit calibrate-threshold --seeds 2 --format json\n  \
audit calibrate-threshold --noise 0 --voxel 0.1 --ell 0.5,5")
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
    #[command(flatten)]
    pub ell: EllArgs,
    /// Worker threads (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    #[command(flatten)]
    pub output: OutputArgs,
}

impl DegeneracyArgs {
    /// The files read: the points, the target, the initial-guess file.
    fn inputs(&self) -> Vec<PathBuf> {
        std::iter::once(&self.points)
            .chain(&self.target)
            .chain(&self.initial_guess_file)
            .cloned()
            .collect()
    }

    /// The detector these options ask for.
    pub fn detector(&self) -> Result<Detector> {
        let mut o = DetectorOptions::default();
        o.tau = self.tau.tau;
        o.ells = self.ell.ell.clone();
        o.frame = det::parse_frame(self.shift.as_deref(), self.rotate_rpy.as_deref())?;
        o.show_matrices = self.show_matrices;
        o.normals.voxel = self.voxel;
        o.normals.radius = self.normal_radius;
        o.normals.knn = self.knn;
        o.normals.min_neighbours = self.min_neighbours;
        o.normals.min_planarity = self.min_planarity;
        o.normals.viewpoint = match &self.viewpoint {
            Some(s) => Some(det::parse_triple(s, "--viewpoint")?),
            None => None,
        };
        Detector::new(o)
    }

    /// The scan file (a pair's source with `--target`).
    pub fn scan_file(&self) -> Result<ScanFile> {
        let initial_guess = match (&self.initial_guess, &self.initial_guess_file) {
            (Some(_), Some(_)) => {
                return Err(Error::usage(
                    "give --initial-guess or --initial-guess-file, not both",
                ))
            }
            (Some(s), None) => InitialGuess::Pose(det::parse_initial_guess(s)?),
            (None, Some(f)) => InitialGuess::File(f.clone()),
            (None, None) => InitialGuess::Identity,
        };
        let mut scan = ScanFile::new(&self.points);
        scan.estimate_normals = self.estimate_normals;
        scan.classes = self.class.clone();
        match &self.target {
            Some(t) => {
                let mut pair = PairOptions::new(t);
                pair.gate = self.gate;
                pair.initial_guess = initial_guess;
                scan.pair = Some(pair);
            }
            None if initial_guess != InitialGuess::Identity => {
                return Err(Error::usage(
                    "--initial-guess and --initial-guess-file apply only with --target",
                ))
            }
            None => {}
        }
        Ok(scan)
    }
}

/// `audit degeneracy`.
pub fn degeneracy(args: &DegeneracyArgs, out: &mut dyn Write) -> Result<i32> {
    let inputs = args.inputs();
    super::check_output(&args.output, &inputs)?;
    let mut scan = args.scan_file()?;
    // The 3D scene draws the points: keep them.
    scan.keep_points = args.output.format == OutputFormat::Mcap;
    let report = args.detector()?.scan_with(&scan, &TermBars)?;
    emit(&report, &args.output, &inputs, out)?;
    Ok(0)
}

/// `audit sweep`.
pub fn sweep(args: &SweepArgs, out: &mut dyn Write) -> Result<i32> {
    let s = &args.scan;
    if args.rig.is_empty() && (args.from.is_some() || args.to.is_some()) {
        return Err(Error::usage("--from/--to apply only with --rig"));
    }
    let mut inputs = s.inputs();
    inputs.extend(args.rig.iter().cloned());
    super::check_output(&s.output, &inputs)?;
    let (detector, scan) = (s.detector()?, s.scan_file()?);
    let rig = if args.rig.is_empty() {
        None
    } else {
        let mut load = LoadOptions::default();
        args.xacro.apply(&mut load);
        let robot = Robot::load(&args.rig, &load)?;
        let (from, to) = robot.frame_pair(args.from.as_deref(), args.to.as_deref())?;
        Some(robot.transform(&from, &to)?)
    };
    let report = detector.sweep(&scan, args.seed, rig.as_ref(), &TermBars)?;
    emit(&report, &s.output, &inputs, out)?;
    Ok(0)
}

/// `audit tunnel`.
pub fn tunnel(args: &TunnelArgs, out: &mut dyn Write) -> Result<i32> {
    super::check_output(&args.output, &[])?;
    let report = det::tunnel(&TunnelParams {
        radius: args.radius,
        length: args.length,
        ring_spacing: args.ring_spacing,
        points_per_ring: args.points_per_ring,
        shift: det::parse_triple(&args.shift, "--shift")?,
        tau: args.tau.tau,
    })?;
    emit(&report, &args.output, &[], out)?;
    Ok(0)
}

/// `audit simulate`.
pub fn simulate(args: &SimulateArgs, out: &mut dyn Write) -> Result<i32> {
    let pose = if args.shift.is_some() || args.rotate_rpy.is_some() {
        Some(det::parse_frame(
            args.shift.as_deref(),
            args.rotate_rpy.as_deref(),
        )?)
    } else {
        None
    };
    let params = SimulateParams {
        scene: det::parse_scene(&args.scene)?,
        noise: args.noise,
        seed: args.seed,
        voxel: args.voxel,
        exact_normals: args.exact_normals,
        tau: args.tau.tau,
        ells: args.ell.ell.clone(),
        update: det::parse_update(&args.update)?,
    };
    let mut load = LoadOptions::default();
    args.xacro.apply(&mut load);
    let rig = SimulateRig {
        files: args.files.clone(),
        from: args.from.clone(),
        to: args.to.clone(),
        pose,
        load,
    };
    super::check_output(&args.output, &args.files)?;
    let t = det::simulate_transform(&rig)?;
    emit(&det::simulate(&params, &t)?, &args.output, &args.files, out)?;
    Ok(0)
}

/// `audit calibrate-threshold`.
pub fn calibrate_threshold(args: &CalibrateThresholdArgs, out: &mut dyn Write) -> Result<i32> {
    let opts = CalibrateOptions {
        seeds: args.seeds,
        noise_levels: CalibrateOptions::parse_noise_levels(&args.noise)?,
        voxel_sizes: CalibrateOptions::parse_voxel_sizes(&args.voxel)?,
        ells: args.ell.ell.clone(),
        threads: args.threads,
    };
    super::check_output(&args.output, &[])?;
    emit(&det::calibrate(&opts, &TermBars)?, &args.output, &[], out)?;
    Ok(0)
}
