//! `audit diff OLD NEW [--from A --to B]`: what changed between two
//! calibrations. Exit 1 when a change exceeds `--tolerance` (without a chain,
//! also when an edge is in one file only), 0 otherwise.

use super::args::{
    length_angle, parse_tolerance, EllArgs, JointArgs, OutputArgs, PitchTolArgs, ReadArgs,
    RenameArgs, Tolerance, XacroArgs,
};
use super::{emit, print_warnings};
use clap::Args;
use extrinsic_audit::internals::tolerances::{
    DEFAULT_DIFF_ROTATION_TOL_DEG, DEFAULT_DIFF_TRANSLATION_TOL_MM,
};
use extrinsic_audit::{diff, DiffOptions, Result};
use std::io::Write;
use std::path::PathBuf;

#[derive(Debug, Args, Clone)]
#[command(
    about = "What changed between two calibrations (per edge and for the chain)",
    long_about = "Compares two calibration files, of the same format or not (a URDF \
against a Kalibr YAML or a rig TOML, frames matched with --rename): for every edge in \
both, the change of translation (mm, |d_new - d_old|) and of rotation (deg, the angle of \
R_old^T R_new), the edges only in one file, and for the --from -> --to chain (or the \
pair a rig file declares) the change of lever arm, screw translation, certificate bands \
and every detector family's verdict. Without --from/--to on files that declare no pair \
(two URDFs, two YAMLs), the whole files are compared, edge by edge.\n\nExit status, \
whole files: 0 when every edge in both is within --tolerance and no edge is in one file \
only, 1 otherwise. With a chain: 1 when the chain or a common edge moved beyond \
--tolerance, or a verdict changed (screw kind, adapted metric, a family), 0 otherwise; \
edges in only one file are listed but do not by themselves fail (two formats rarely \
share edges). 2 on bad input.\n\nEach file is \
read as the rig report reads it; per side, --key-old/--key-new pick one key of a YAML/JSON \
file with several transforms (--key: the same key in both), and --invert-old/--invert-new \
(--invert: both) read a file whose numbers are the pose of the parent in the child.",
    after_long_help = "Examples:\n  audit diff old/robot.urdf new/robot.urdf\n  audit diff old/robot.urdf new/robot.urdf --from base_link --to lidar\n  audit diff robot.urdf kalibr.yaml --from imu_link --to lidar --rename kalibr.yaml:imu0=imu_link --rename kalibr.yaml:lidar0=lidar\n  audit diff calibrations/anymal-d.urdf calibrations/anymal-d-lidar-imu.toml --format markdown\n  audit diff a.urdf b.urdf --from base --to lidar --tolerance 0.5mm,0.01deg\n  audit diff calibrations/geode-gamma-avia.toml gamma_config.yaml --key-new T_IMU_LiDAR\n  audit diff run1/camchain-imucam.yaml run2/camchain-imucam.yaml --key cam0 --from imu --to cam0"
)]
pub struct DiffArgs {
    /// The old calibration file
    #[arg(value_name = "OLD")]
    pub old: PathBuf,
    /// The new calibration file
    #[arg(value_name = "NEW")]
    pub new: PathBuf,
    /// Parent frame of the chain compared (else the pair a rig file
    /// declares; with neither, the whole files are compared)
    #[arg(long, value_name = "FRAME")]
    pub from: Option<String>,
    /// Child frame of the chain compared
    #[arg(long, value_name = "FRAME")]
    pub to: Option<String>,
    #[command(flatten)]
    pub renames: RenameArgs,
    /// Largest change that passes: a translation and a rotation, with their
    /// units (`1mm,0.05deg`, `0.002m,1mrad`); a bare translation is
    /// millimetres, a bare rotation degrees
    #[arg(long, value_delimiter = ',', num_args = 1, value_parser = parse_tolerance, value_name = "LENGTH,ANGLE", default_values_t = [Tolerance::Length(DEFAULT_DIFF_TRANSLATION_TOL_MM * 1e-3), Tolerance::Angle(DEFAULT_DIFF_ROTATION_TOL_DEG)])]
    pub tolerance: Vec<Tolerance>,
    #[command(flatten)]
    pub ell: EllArgs,
    #[command(flatten)]
    pub pitch: PitchTolArgs,
    #[command(flatten)]
    pub joints: JointArgs,
    // --key and --invert: both files (--key-old, --invert-new, ...: one).
    #[command(flatten)]
    pub read: ReadArgs,
    /// Read only this key of the old file
    #[arg(long, value_name = "NAME", conflicts_with = "key")]
    pub key_old: Option<String>,
    /// Read only this key of the new file
    #[arg(long, value_name = "NAME", conflicts_with = "key")]
    pub key_new: Option<String>,
    /// The old file stores the other direction (the pose of the parent in the
    /// child): invert its transforms as they are read
    #[arg(long)]
    pub invert_old: bool,
    /// The same for the new file
    #[arg(long)]
    pub invert_new: bool,
    #[command(flatten)]
    pub xacro: XacroArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

pub fn run(args: &DiffArgs, out: &mut dyn Write) -> Result<i32> {
    let tolerance = length_angle("--tolerance", &args.tolerance)?;
    let inputs = [args.old.clone(), args.new.clone()];
    super::check_output(&args.output, &inputs)?;
    let mut opts = DiffOptions::new(&args.old, &args.new);
    opts.from = args.from.clone();
    opts.to = args.to.clone();
    opts.load.renames = args.renames.renames.clone();
    opts.load.joints = args.joints.positions();
    args.xacro.apply(&mut opts.load);
    opts.old_read.key = args.read.key.clone().or_else(|| args.key_old.clone());
    opts.old_read.invert = args.read.invert || args.invert_old;
    opts.new_read.key = args.read.key.clone().or_else(|| args.key_new.clone());
    opts.new_read.invert = args.read.invert || args.invert_new;
    opts.rig.ells = args.ell.ell.clone();
    opts.rig.pitch_tol = args.pitch.pitch_tol;
    opts.tolerance = tolerance;
    let (report, warnings) = diff(&opts)?;
    print_warnings(&warnings);
    emit(&report, &args.output, &inputs, out)?;
    Ok(if report.exceeded.is_empty() { 0 } else { 1 })
}
