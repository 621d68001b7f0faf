//! `audit FILE... --from A --to B`: the rig report.

use super::args::{
    parse_kappa, parse_lambda, BagArgs, EllArgs, FileSizeArgs, JointArgs, OutputArgs, PitchTolArgs,
    ReadArgs, RenameArgs, SigmaArgs, XacroArgs,
};
use super::{deny_warnings, emit_warned, print_notes, print_warnings};
use clap::Args;
use extrinsic_audit::{
    DetectorConfig, Error, Format, LoadOptions, OdometryDetector, OutputFormat, Result, RigOptions,
    Robot, UrdfVersion,
};
use std::io::Write;
use std::path::PathBuf;

#[derive(Debug, Args, Clone)]
pub struct AuditArgs {
    /// Files to load into one frame graph (URDF, launch, tf_static dump, YAML, JSON, TOML rig)
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Parent frame: the transform printed is the pose of --to in --from
    #[arg(long, value_name = "FRAME")]
    pub from: Option<String>,
    /// Child frame (e.g. the LiDAR)
    #[arg(long, value_name = "FRAME")]
    pub to: Option<String>,
    /// List the frames and edges the files yield (with file:line), then exit;
    /// --format text, json, dot, mermaid, markdown or svg draws the tree, and
    /// --from/--to highlight their chain
    #[arg(long)]
    pub frames: bool,
    #[command(flatten)]
    pub ell: EllArgs,
    /// Detector threshold kappa: with --lambda, does the band certify that lambda cannot cross kappa?
    #[arg(long, requires = "lambda", value_parser = parse_kappa, allow_hyphen_values = true)]
    pub kappa: Option<f64>,
    /// Detector eigenvalue lambda (see --kappa)
    #[arg(long, requires = "kappa", value_parser = parse_lambda, allow_hyphen_values = true)]
    pub lambda: Option<f64>,
    #[command(flatten)]
    pub pitch: PitchTolArgs,
    #[command(flatten)]
    pub sigma: SigmaArgs,
    #[command(flatten)]
    pub joints: JointArgs,
    #[command(flatten)]
    pub renames: RenameArgs,
    #[command(flatten)]
    pub read: ReadArgs,
    /// Skip format detection (see the README's formats table)
    #[arg(long, value_name = "NAME")]
    pub input_format: Option<String>,
    /// Read every URDF as this version (1.0, 1.1 or 1.2) whatever its `<robot version>`
    /// says: 1.1 applies quat_xyzw, which ROS ignores in a 1.0 file
    #[arg(long, value_name = "X.Y")]
    pub urdf_version: Option<UrdfVersion>,
    #[command(flatten)]
    pub size: FileSizeArgs,
    #[command(flatten)]
    pub output: OutputArgs,
    #[command(flatten)]
    pub xacro: XacroArgs,
    /// Every warning is an error (exit 2 after printing them): for CI runs
    /// that must not pass with a joint outside its limits or a value that
    /// looks like degrees
    #[arg(long, alias = "deny-warnings")]
    pub strict: bool,
    #[command(flatten)]
    pub bag: BagArgs,
    /// Your odometry's detector: what it does on this rig (lio-sam,
    /// lego-loam, loam, dcreg, x-icp, fast-lio, point-lio, dlio); a LIO-SAM,
    /// FAST-LIO or DLIO config among the files says it without the flag, and
    /// a DCReg or X-ICP configuration file among them says it with its
    /// thresholds
    #[arg(long, value_name = "NAME", value_parser = parse_detector)]
    pub detector: Option<&'static OdometryDetector>,
}

fn parse_detector(s: &str) -> std::result::Result<&'static OdometryDetector, String> {
    OdometryDetector::find(s).ok_or_else(|| {
        let names: Vec<&str> = OdometryDetector::all().iter().map(|d| d.name).collect();
        format!("expected one of {}, found `{s}`", names.join(", "))
    })
}

impl AuditArgs {
    /// How the files are read.
    pub fn load_options(&self) -> Result<LoadOptions> {
        let format = match &self.input_format {
            None => None,
            Some(name) => Some(Format::from_name(name)?),
        };
        let mut load = LoadOptions::default();
        load.joints = self.joints.positions();
        load.format = format;
        load.max_file_size = self.size.max_file_size;
        load.urdf_version = self.urdf_version;
        load.bag = self.bag.bag_options();
        load.renames = self.renames.renames.clone();
        self.read.apply(&mut load);
        self.xacro.apply(&mut load);
        Ok(load)
    }
}

/// The files split into calibrations and the one detector configuration
/// among them (DCReg's `icp.yaml`, an X-ICP ICP file), which reveals the
/// detector and its thresholds and adds no edge.
fn split_config(files: &[PathBuf]) -> Result<(Vec<PathBuf>, Option<DetectorConfig>)> {
    let mut calibrations = Vec::new();
    let mut config: Option<DetectorConfig> = None;
    for f in files {
        match (OdometryDetector::read_config(f)?, &config) {
            (Some(_), Some(first)) => {
                return Err(Error::usage(format!(
                    "expected one detector configuration, found a second beside {}",
                    first.file
                ))
                .in_file(f))
            }
            (Some(c), None) => config = Some(c),
            (None, _) => calibrations.push(f.clone()),
        }
    }
    if calibrations.is_empty() {
        if let Some(c) = &config {
            return Err(Error::usage(
                "expected calibration files beside the detector configuration, found none",
            )
            .in_file(&c.file));
        }
    }
    Ok((calibrations, config))
}

pub fn run(args: &AuditArgs, out: &mut dyn Write) -> Result<i32> {
    super::check_output(&args.output, &args.files)?;
    let (files, config) = split_config(&args.files)?;
    if let (Some(d), Some(c)) = (args.detector, &config) {
        if d.name != c.detector {
            return Err(Error::usage(format!(
                "--detector {} names another detector than the {} configuration given",
                d.name, c.detector
            ))
            .in_file(&c.file));
        }
    }
    let robot = Robot::load(&files, &args.load_options()?)?;
    // The files named and those they included.
    let inputs = robot.files();
    print_warnings(robot.warnings());
    print_notes(robot.notes());
    deny_warnings(args.strict, robot.warnings())?;
    if args.frames {
        return super::frames::run(
            &robot,
            args.from.as_deref(),
            args.to.as_deref(),
            &args.output,
            &inputs,
            out,
        );
    }
    let (from, to) = robot.frame_pair(args.from.as_deref(), args.to.as_deref())?;
    let chain = robot.chain(&from, &to)?;
    print_warnings(&chain.warnings);
    print_notes(&chain.notes);
    deny_warnings(args.strict, &chain.warnings)?;
    let mut opts = RigOptions::default();
    opts.ells = args.ell.ell.clone();
    opts.pitch_tol = args.pitch.pitch_tol;
    opts.sigma = args.sigma.user_sigma();
    opts.kappa_lambda = args.kappa.zip(args.lambda);
    let (report, chain_warnings) = robot.report(&from, &to, &opts)?;
    let warnings: Vec<_> = robot
        .warnings()
        .iter()
        .chain(&chain_warnings)
        .cloned()
        .collect();
    let mut report = report;
    let revealed = || {
        report
            .sources
            .iter()
            .find_map(|s| OdometryDetector::revealed_by(&s.format))
    };
    if let Some(c) = &config {
        report.detector = Some(c.advise(&chain.transform, &from, &to));
    } else if let Some(d) = args.detector.or_else(revealed) {
        report.detector = Some(d.advise(&chain.transform, &from, &to));
    }
    // The 3D scene draws the whole tree, the chain marked (built only for
    // it: a large tree's document costs seconds).
    if args.output.format == OutputFormat::Mcap {
        report.tree = Some(robot.frame_tree(Some(&chain)));
    }
    emit_warned(&report, &warnings, &args.output, &inputs, out)?;
    // The process exits right after the report (`main_with` returns the
    // code to `main`; the Python console script calls `sys.exit` with it):
    // dropping a large robot frees every edge one by one for nothing (a
    // 100,000-link URDF: about 35 M instructions, issue 29), so its memory
    // is left to the exit. Only here, at the end of the command, never in
    // the library.
    std::mem::forget(robot);
    Ok(0)
}
