//! `audit survey PATHS...`: one row per rig file, then a summary.

use super::args::{OutputArgs, PitchTolArgs, ReadArgs, SigmaArgs, XacroArgs};
use super::{emit_warned, print_warnings};
use clap::Args;
use extrinsic_audit::internals::pipeline::{check_plot_target, write_survey_plot};
use extrinsic_audit::{survey, Result, SortColumn, SurveyOptions};
use std::io::Write;
use std::path::PathBuf;

#[derive(Debug, Args, Clone)]
#[command(
    long_about = "One row per rig (id, sensor, platform, lever arm, rotation angle, screw \
translation, zero pitch, s_max, band at l = 1, adapted metric), then a summary: count, \
lever-arm min / median / max, and how many rigs have nonzero pitch (general screws and pure \
translations: no adapted constant metric exists for them).\n\nRotations below 1 degree are \
marked `*`: their screw axis is set by calibration noise, so read h with the angle beside it.",
    after_long_help = "Examples:\n  audit survey calibrations/\n  audit survey calibrations/ --sort lever-arm --format markdown\n  audit survey calibrations/geode-*.toml --format csv > geode.csv\n  audit survey robots/ --from base_link --to lidar\n  audit survey robot.urdf:base_link:velodyne other.urdf.xacro:base:os_sensor\n  audit survey calibrations/ --plot survey.svg\n  audit survey kalibr/camchain-imucam.yaml:cam0:cam1 --key cam1 --invert"
)]
pub struct SurveyArgs {
    /// Rig files (*.toml) or directories of them; with --from/--to any file the
    /// tool reads (URDF, xacro, YAML, launch, ...), or PATH:FROM:TO per path
    #[arg(required = true, value_name = "PATH")]
    pub paths: Vec<PathBuf>,
    #[command(flatten)]
    pub output: OutputArgs,
    /// Sort rows by this column (ties by id)
    #[arg(long, value_enum, value_name = "COLUMN")]
    pub sort: Option<SortColumn>,
    #[command(flatten)]
    pub pitch: PitchTolArgs,
    #[command(flatten)]
    pub sigma: SigmaArgs,
    /// Also list placeholder and duplicate rigs (never counted in the summary)
    #[arg(long)]
    pub all: bool,
    /// Frame pair for files that are not rig files (URDF, xacro, YAML,
    /// launch, ...); per file: PATH:FROM:TO
    #[arg(long, value_name = "FRAME", requires = "to")]
    pub from: Option<String>,
    /// See --from
    #[arg(long, value_name = "FRAME", requires = "from")]
    pub to: Option<String>,
    #[command(flatten)]
    pub read: ReadArgs,
    /// Also draw the survey plot (lever arm against |h|, bands against the
    /// characteristic length) to this SVG file
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub xacro: XacroArgs,
}

pub fn run(args: &SurveyArgs, out: &mut dyn Write) -> Result<i32> {
    super::check_output(&args.output, &args.paths)?;
    if let Some(plot) = &args.plot {
        check_plot_target(plot, &args.paths)?;
    }
    let mut opts = SurveyOptions::default();
    opts.paths = args.paths.clone();
    opts.pitch_tol = args.pitch.pitch_tol;
    opts.sigma = args.sigma.user_sigma();
    opts.all = args.all;
    opts.sort = args.sort;
    opts.pair = args.from.clone().zip(args.to.clone());
    args.read.apply(&mut opts.load);
    args.xacro.apply(&mut opts.load);
    let (report, warnings) = survey(&opts)?;
    print_warnings(&warnings);
    if let Some(plot) = &args.plot {
        write_survey_plot(plot, &args.paths, &report)?;
    }
    emit_warned(&report, &warnings, &args.output, &args.paths, out)?;
    Ok(0)
}
