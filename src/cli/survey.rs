//! `audit survey PATHS...`: one row per rig file, then a summary.

use super::{emit_warned, parse_nonneg, print_warnings};
use clap::Args;
use extrinsic_audit::diagnostic::Result;
use extrinsic_audit::pipeline::{self, SortColumn, SurveyOptions};
use extrinsic_audit::render::OutputFormat;
use std::io::Write;
use std::path::PathBuf;

#[derive(Debug, Args, Clone)]
#[command(
    long_about = "One row per rig (id, sensor, platform, lever arm, rotation angle, screw \
translation, zero pitch, s_max, band at l = 1, adapted metric), then a summary: count, \
lever-arm min / median / max, and how many rigs have nonzero pitch (general screws and pure \
translations: no adapted constant metric exists for them).\n\nRotations below 1 degree are \
marked `*`: their screw axis is set by calibration noise, so read h with the angle beside it.",
    after_long_help = "Examples:\n  audit survey calibrations/\n  audit survey calibrations/ --sort lever-arm --format markdown\n  audit survey calibrations/geode-*.toml --format csv > geode.csv"
)]
pub struct SurveyArgs {
    /// Rig files or directories of them (*.toml)
    #[arg(required = true, value_name = "PATH")]
    pub paths: Vec<PathBuf>,
    /// Output format
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
    /// Sort rows by this column (ties by id)
    #[arg(long, value_enum, value_name = "COLUMN")]
    pub sort: Option<SortColumn>,
    /// Zero-pitch tolerance on |h| (m)
    #[arg(long, default_value_t = extrinsic_audit::tolerances::DEFAULT_PITCH_TOL, value_parser = parse_nonneg, value_name = "M")]
    pub pitch_tol: f64,
    /// Also list placeholder and duplicate rigs (never counted in the summary)
    #[arg(long)]
    pub all: bool,
}

pub fn run(args: &SurveyArgs, out: &mut dyn Write) -> Result<i32> {
    let (report, warnings) = pipeline::survey(&SurveyOptions {
        paths: args.paths.clone(),
        pitch_tol: args.pitch_tol,
        all: args.all,
        sort: args.sort,
    })?;
    print_warnings(&warnings);
    emit_warned(&report, &warnings, args.format, out)?;
    Ok(0)
}
