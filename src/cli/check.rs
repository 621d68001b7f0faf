//! `audit check PATHS...`: CI checks on calibration files.

use super::args::{
    parse_angle_deg, parse_length_m, parse_positive_length_m, parse_tolerance, FileSizeArgs,
    JointArgs, OutputArgs, PitchTolArgs, Tolerance, XacroArgs,
};
use super::emit;
use clap::Args;
use extrinsic_audit::internals::pipeline::manifest;
use extrinsic_audit::internals::tolerances::{
    DEFAULT_MAX_ROTATION_DRIFT_DEG, DEFAULT_MAX_TRANSLATION_DRIFT,
};
use extrinsic_audit::{check_with, CheckOptions, Code, DriftTolerances, LoadOptions, Result};
use std::io::Write;
use std::path::PathBuf;

#[derive(Debug, Args, Clone)]
#[command(
    about = "CI check of calibration files: validation, drift against a baseline",
    long_about = "Checks calibration files in CI: every file parses; rotations are orthonormal and \
quaternions unit (rounding of published digits is a warning, beyond it an error); units are \
plausible (no millimetres in a metre field); the frames each rig declares, and every --pair, \
exist and connect. Files of one robot are loaded together where an audit.toml in the checked \
directory groups them. With --baseline: no transform drifted by more than the tolerances, no \
file or edge appeared or disappeared, no checked pair changed, and no verdict (screw kind, zero \
pitch, adapted metric) changed. The severity table, the baseline and the walk: docs/check.md.\n\n\
Exit codes: 0 clean (warnings allowed), 1 problems found, 2 usage error, unreadable input, \
malformed baseline or refused --write-baseline.",
    after_long_help = "Examples:\n  audit check calibrations/\n  audit check calibrations/ --write-baseline calibrations/baseline.json\n  audit check calibrations/ --write-baseline calibrations/baseline.json --prune\n  audit check calibrations/ --baseline calibrations/baseline.json --format sarif > check.sarif\n  audit check calibrations/ --baseline calibrations/baseline.json --format github\n  audit check robot.urdf --pair base_link:lidar --max-lever-arm 0.5 --require-zero-pitch\n  audit check calibrations/ --deny-warnings --exclude 'old/**'"
)]
pub struct CheckArgs {
    /// Calibration files or directories of them
    #[arg(required = true, value_name = "PATH")]
    pub paths: Vec<PathBuf>,
    /// Compare against this baseline (written earlier with --write-baseline)
    #[arg(long, value_name = "FILE")]
    pub baseline: Option<PathBuf>,
    /// Write the current state as a baseline (atomically: temporary file, then rename)
    #[arg(long, value_name = "FILE")]
    pub write_baseline: Option<PathBuf>,
    /// With --write-baseline: drop the entries of files not checked this run
    /// (accepts removed files); without it only the checked files' entries change
    #[arg(long, requires = "write_baseline")]
    pub prune: bool,
    /// Skip files and directories matching this glob (`*`, `**`, `?`; without
    /// `/` matched against names, with `/` against the path below the checked
    /// directory); repeatable
    #[arg(long = "exclude", value_name = "GLOB")]
    pub exclude: Vec<String>,
    /// Also check this frame pair wherever both frames exist (FROM:TO); repeatable
    #[arg(long = "pair", value_parser = parse_pair, value_name = "FROM:TO")]
    pub pairs: Vec<(String, String)>,
    /// A problem when a checked pair's lever arm exceeds this (a length:
    /// `0.5m`, `500mm`; a bare number is metres)
    #[arg(long, value_parser = parse_positive_length_m, value_name = "LENGTH")]
    pub max_lever_arm: Option<f64>,
    /// A problem when a checked pair does not have zero screw pitch
    #[arg(long)]
    pub require_zero_pitch: bool,
    /// Drift tolerance on translations against the baseline (a length: `1mm`,
    /// `0.1cm`, `0.001m`; a bare number is metres)
    #[arg(long, default_value_t = Tolerance::Length(DEFAULT_MAX_TRANSLATION_DRIFT), value_parser = parse_length_m, value_name = "LENGTH")]
    pub max_translation_drift: Tolerance,
    /// Drift tolerance on rotations against the baseline (an angle: `0.05deg`,
    /// `1mrad`; a bare number is degrees)
    #[arg(long, default_value_t = Tolerance::Angle(DEFAULT_MAX_ROTATION_DRIFT_DEG), value_parser = parse_angle_deg, value_name = "ANGLE")]
    pub max_rotation_drift: Tolerance,
    #[command(flatten)]
    pub pitch: PitchTolArgs,
    #[command(flatten)]
    pub joints: JointArgs,
    /// Accept findings of this code: reported as warnings, never a problem;
    /// repeatable (the policy table: docs/check.md)
    #[arg(long = "allow", value_name = "CODE", value_parser = parse_code)]
    pub allow: Vec<Code>,
    /// Refuse findings of this code: reported as errors (a problem); repeatable
    #[arg(long = "deny", value_name = "CODE", value_parser = parse_code)]
    pub deny: Vec<Code>,
    /// Every warning is a problem (exit 1)
    #[arg(long)]
    pub deny_warnings: bool,
    /// One calibration per vehicle: a finding (exit 1) for each checked pair
    /// further than this from the mean of the same pair over the checked
    /// files: a translation and a rotation with their units (`5mm,0.5deg`; a
    /// bare translation is millimetres, a bare rotation degrees); `audit
    /// spread` shows the fleet
    #[arg(long, value_delimiter = ',', num_args = 1, value_parser = parse_tolerance, value_name = "LENGTH,ANGLE")]
    pub fleet_tolerance: Option<Vec<Tolerance>>,
    #[command(flatten)]
    pub size: FileSizeArgs,
    #[command(flatten)]
    pub xacro: XacroArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

fn parse_code(s: &str) -> std::result::Result<Code, String> {
    Code::from_name(s).ok_or_else(|| {
        format!(
            "expected a diagnostic code ({}), found `{s}`",
            Code::ALL
                .iter()
                .map(|c| c.name())
                .collect::<Vec<_>>()
                .join(", ")
        )
    })
}

fn parse_pair(s: &str) -> std::result::Result<(String, String), String> {
    manifest::parse_pair(s).ok_or_else(|| format!("expected FROM:TO, found `{s}`"))
}

pub fn run(args: &CheckArgs, out: &mut dyn Write) -> Result<i32> {
    let inputs: Vec<PathBuf> = args
        .paths
        .iter()
        .chain(&args.baseline)
        .chain(&args.write_baseline)
        .cloned()
        .collect();
    super::check_output(&args.output, &inputs)?;
    let progress = super::display::TermProgress::new();
    let mut load = LoadOptions::default();
    load.joints = args.joints.positions();
    load.max_file_size = args.size.max_file_size;
    args.xacro.apply(&mut load);
    let drift = DriftTolerances {
        translation_m: args.max_translation_drift.value(),
        rotation_deg: args.max_rotation_drift.value(),
    };
    let mut opts = CheckOptions::new(args.paths.clone())
        .baseline(
            args.baseline.clone(),
            args.write_baseline.clone(),
            args.prune,
        )
        .walk(args.exclude.clone(), args.pairs.clone())
        .gate(
            args.max_lever_arm,
            args.require_zero_pitch,
            drift,
            args.pitch.pitch_tol,
        )
        .policy(args.allow.clone(), args.deny.clone(), args.deny_warnings)
        .load(load);
    if let Some(v) = &args.fleet_tolerance {
        let t = super::args::length_angle("--fleet-tolerance", v)?;
        opts.fleet = Some(DriftTolerances {
            translation_m: t.translation_mm * 1e-3,
            rotation_deg: t.rotation_deg,
        });
    }
    let report = check_with(&opts, &progress)?;
    emit(&report, &args.output, &inputs, out)?;
    Ok(report.exit_code())
}
