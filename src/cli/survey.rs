//! `audit survey PATHS...`: one row per rig file, then a summary.

use super::{emit_warned, parse_sigma_r, parse_sigma_t, print_warnings};
use clap::Args;
use extrinsic_audit::diagnostic::Result;
use extrinsic_audit::geometry::PitchTol;
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
    after_long_help = "Examples:\n  audit survey calibrations/\n  audit survey calibrations/ --sort lever-arm --format markdown\n  audit survey calibrations/geode-*.toml --format csv > geode.csv\n  audit survey robots/ --from base_link --to lidar\n  audit survey robot.urdf:base_link:velodyne other.urdf.xacro:base:os_sensor\n  audit survey calibrations/ --plot survey.svg\n  audit survey kalibr/camchain-imucam.yaml:cam0:cam1 --key cam1 --invert"
)]
pub struct SurveyArgs {
    /// Rig files (*.toml) or directories of them; with --from/--to any file the
    /// tool reads (URDF, xacro, YAML, launch, ...), or PATH:FROM:TO per path
    #[arg(required = true, value_name = "PATH")]
    pub paths: Vec<PathBuf>,
    /// Output format
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
    /// Sort rows by this column (ties by id)
    #[arg(long, value_enum, value_name = "COLUMN")]
    pub sort: Option<SortColumn>,
    /// Zero-pitch tolerance: `auto` (three-way, from the uncertainty of h) or |h| in m
    #[arg(long, default_value = "auto", value_name = "auto|M")]
    pub pitch_tol: PitchTol,
    /// The calibration's standard uncertainty per edge, translation (m), added to
    /// the rounding of the numbers as written (a rig TOML's own value wins)
    #[arg(long, value_parser = parse_sigma_t, value_name = "M")]
    pub sigma_t: Option<f64>,
    /// The same for rotation (degrees)
    #[arg(long, value_parser = parse_sigma_r, value_name = "DEG")]
    pub sigma_r: Option<f64>,
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
    /// Read only this key of each YAML/JSON file (e.g. T_imu_lidar; a file
    /// with several transforms), as the rig report's --key
    #[arg(long, value_name = "NAME")]
    pub key: Option<String>,
    /// The files store the other direction (the pose of the parent in the
    /// child): invert their transforms, as the rig report's --invert (a rig
    /// TOML states its own direction and ignores both)
    #[arg(long)]
    pub invert: bool,
    /// Also draw the survey plot (lever arm against |h|, bands against the
    /// characteristic length) to this SVG file
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Where xacro `$(find pkg)` looks first (as for `audit`); repeatable
    #[arg(long = "package-path", value_name = "DIR")]
    pub package_paths: Vec<PathBuf>,
    /// xacro and launch-file `$(arg NAME)` value (as for `audit`); repeatable
    #[arg(long = "arg", value_parser = super::audit::parse_xacro_arg, value_name = "NAME=VALUE")]
    pub xacro_args: Vec<(String, String)>,
}

pub fn run(args: &SurveyArgs, out: &mut dyn Write) -> Result<i32> {
    if let Some(plot) = &args.plot {
        pipeline::check_plot_target(plot, &args.paths)?;
    }
    let (report, warnings) = pipeline::survey(&SurveyOptions {
        paths: args.paths.clone(),
        pitch_tol: args.pitch_tol,
        sigma: super::user_sigma(args.sigma_t, args.sigma_r),
        all: args.all,
        sort: args.sort,
        pair: args.from.clone().zip(args.to.clone()),
        load: extrinsic_audit::formats::LoadOptions {
            package_paths: args.package_paths.clone(),
            xacro_args: args.xacro_args.iter().cloned().collect(),
            key: args.key.clone(),
            invert: args.invert,
            ..Default::default()
        },
    })?;
    print_warnings(&warnings);
    if let Some(plot) = &args.plot {
        pipeline::write_survey_plot(plot, &args.paths, &report)?;
    }
    emit_warned(&report, &warnings, args.format, out)?;
    Ok(0)
}
