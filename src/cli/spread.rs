//! `audit spread PATH[:FROM:TO]... [--from A --to B]`: many calibrations of
//! one frame pair. Exit 1 when `--tolerance` is given and a calibration lies beyond it.

use super::args::{
    length_angle, parse_tolerance, EllArgs, JointArgs, OutputArgs, PitchTolArgs, ReadArgs,
    Tolerance, XacroArgs,
};
use super::{emit_warned, print_warnings};
use clap::Args;
use extrinsic_audit::internals::pipeline::{check_spread_plot_target, write_spread_plot};
use extrinsic_audit::{spread, Result, SpreadOptions};
use std::io::Write;
use std::path::PathBuf;

#[derive(Debug, Args, Clone)]
#[command(
    about = "Many calibrations of one frame pair: mean, spread, outliers (repeat runs, fleets)",
    long_about = "Reads N calibrations of one frame pair (repeated calibration runs, or one \
file per vehicle of a fleet; any formats the tool reads, folders walked) and reports: the mean \
on SE(3) (the chordal L2 rotation mean, as scipy's Rotation.mean, and the arithmetic mean of \
the translations in the from-frame); each calibration's deviation from it, per axis in mm and \
degrees, in the from-frame and in the to-frame axes (rotation deviations are rotation-vector \
components, not Euler angles); the spread per axis (sample standard deviation, and the largest \
deviation with the calibration it belongs to); the outliers by a robust rule (Iglewicz and \
Hoaglin's modified z-score carried to three dimensions; uncertain below 10 calibrations, not \
applied below 3); the pitch verdict of each calibration and of the set, the spread of h taken \
as the calibration uncertainty; the range of the certificate bands.\n\nA calibration is named \
by its file name, or by its folder when the file names repeat (vehicles/v001/sensors_calibration.yaml \
is `v001`).\n\nFrame pairs: a file's pair is its own PATH:FROM:TO, else --from/--to, else the \
pair a rig file declares, else its only edge. Files not given as PATH:FROM:TO must agree on \
one pair; a file given as PATH:FROM:TO may name it otherwise (the same frames under other \
names). The report is named by the first file's pair and lists each calibration's own. \
PATH:FROM:TO is split from the right (an argument that exists as a path is a path).\n\nExit status: 1 when --tolerance is given and a calibration deviates from the \
mean by more than it (the fleet gate); 0 otherwise; 2 on bad input.",
    after_long_help = "Examples:\n  audit spread run1/lidar_imu.yaml run2/lidar_imu.yaml run3/lidar_imu.yaml\n  audit spread run1/calib.yaml run2/calib.yaml:imu_link:velodyne\n  audit spread kalibr/*/camchain-imucam.yaml --key cam0 --from imu --to cam0\n  audit spread vehicles/ --from base_link --to velodyne_top --tolerance 5,0.5\n  audit spread vehicles/ --from base_link --to lidar --format csv > fleet.csv"
)]
pub struct SpreadArgs {
    /// Calibration files, or folders walked for them; PATH:FROM:TO composes
    /// that path's files FROM -> TO (the same pair under other names)
    #[arg(required = true, value_name = "PATH[:FROM:TO]")]
    pub paths: Vec<PathBuf>,
    /// Parent frame (else the pair a rig file declares, or a file's one edge)
    #[arg(long, value_name = "FRAME", requires = "to")]
    pub from: Option<String>,
    /// Child frame
    #[arg(long, value_name = "FRAME", requires = "from")]
    pub to: Option<String>,
    /// Largest deviation from the mean that passes: a translation and a
    /// rotation with their units (`5mm,0.5deg`; a bare translation is
    /// millimetres, a bare rotation degrees); a calibration beyond it exits 1
    #[arg(long, value_delimiter = ',', num_args = 1, value_parser = parse_tolerance, value_name = "LENGTH,ANGLE")]
    pub tolerance: Option<Vec<Tolerance>>,
    /// Also draw the spread plot (each calibration's deviation per axis, the
    /// outliers named) to this SVG file
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub ell: EllArgs,
    #[command(flatten)]
    pub pitch: PitchTolArgs,
    #[command(flatten)]
    pub joints: JointArgs,
    #[command(flatten)]
    pub read: ReadArgs,
    #[command(flatten)]
    pub xacro: XacroArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

pub fn run(args: &SpreadArgs, out: &mut dyn Write) -> Result<i32> {
    let tolerance = match &args.tolerance {
        Some(v) => Some(length_angle("--tolerance", v)?),
        None => None,
    };
    let mut opts = SpreadOptions::default();
    for p in &args.paths {
        match p.to_str() {
            Some(arg) => opts.add_input(arg)?,
            // Not UTF-8: a path, never split.
            None => opts.paths.push(p.clone()),
        }
    }
    super::check_output(&args.output, &opts.paths)?;
    if let Some(plot) = &args.plot {
        check_spread_plot_target(plot, &opts.paths)?;
    }
    opts.from = args.from.clone();
    opts.to = args.to.clone();
    opts.load.joints = args.joints.positions();
    args.read.apply(&mut opts.load);
    args.xacro.apply(&mut opts.load);
    opts.rig.ells = args.ell.ell.clone();
    opts.rig.pitch_tol = args.pitch.pitch_tol;
    opts.tolerance = tolerance;
    let (report, warnings) = spread(&opts)?;
    print_warnings(&warnings);
    if let Some(plot) = &args.plot {
        write_spread_plot(plot, &opts.paths, &report)?;
    }
    emit_warned(&report, &warnings, &args.output, &opts.paths, out)?;
    Ok(if report.exceeded.is_empty() { 0 } else { 1 })
}
