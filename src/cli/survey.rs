//! `audit survey PATHS...`: one row per rig file, then a summary.

use super::args::{OutputArgs, PitchTolArgs, ReadArgs, SigmaArgs, XacroArgs};
use super::{emit_warned, print_notes, print_warnings};
use clap::Args;
use extrinsic_audit::internals::pipeline::{check_plot_target, write_survey_plot};
use extrinsic_audit::{survey, Code, Result, Severity, SortColumn, SurveyOptions, Warning};
use std::io::Write;
use std::path::PathBuf;

#[derive(Debug, Args, Clone)]
#[command(
    about = "The survey table over a directory of rig files (one row per rig)",
    long_about = "One row per rig (id, sensor, platform, lever arm, rotation angle, screw \
translation, zero pitch, s_max, band at l = 1, adapted metric), then a summary: count, \
lever-arm min / median / max, and how many rigs have nonzero pitch (general screws and pure \
translations: no adapted constant metric exists for them).\n\nRotations below 5 degrees are \
marked `*`: their screw axis is set by calibration noise, so read h with the angle beside it. \
Rotations rounded as published (orthonormal only to their printed digits) are listed in one \
note before the table.",
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
    // The rounded rotations by reference (a fleet can have thousands).
    let (rounded, rest): (Vec<&Warning>, Vec<&Warning>) =
        warnings.iter().partition(|w| rounded_rotation(w));
    let rest: Vec<Warning> = rest.into_iter().cloned().collect();
    print_warnings(&rest);
    match rounded.len() {
        0 => {}
        1 => print_warnings(&[rounded[0].clone()]),
        _ => print_notes(&[rounded_rotations_note(&rounded)]),
    }
    if let Some(plot) = &args.plot {
        write_survey_plot(plot, &args.paths, &report)?;
    }
    emit_warned(&report, &warnings, &args.output, &args.paths, out)?;
    Ok(0)
}

/// A rotation matrix orthonormal only to the rounding of its published
/// digits: a `non-orthonormal-rotation` of severity warning (beyond the
/// rounding tolerance it is an error, and listed on its own).
fn rounded_rotation(w: &Warning) -> bool {
    w.code == Code::NonOrthonormalRotation && w.severity == Severity::Warning
}

/// One line for several rigs whose rotations are rounded as published
/// (issue 33: four warnings were a newcomer's first sight of the survey): how
/// many, how far from orthonormal (the measure each warning states), which
/// files. Every warning stays in `--format json` and in `audit FILE`.
fn rounded_rotations_note(rounded: &[&Warning]) -> String {
    // The measure as se3's message states it: `||R^T R - I||_F = 1.272e-4 (`.
    let measure = |w: &&Warning| {
        let (_, rest) = w.message.split_once("||_F = ")?;
        rest.split_whitespace().next()?.parse::<f64>().ok()
    };
    let values: Vec<f64> = rounded.iter().filter_map(measure).collect();
    let (lo, hi) = values.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &v| {
        (lo.min(v), hi.max(v))
    });
    let mut files: Vec<String> = rounded
        .iter()
        .filter_map(|w| w.location.file.as_ref())
        .map(|f| {
            f.file_stem()
                .map_or_else(|| f.display().to_string(), |s| s.to_string_lossy().into())
        })
        .collect();
    files.dedup();
    let range = if values.is_empty() {
        String::new()
    } else {
        format!(" (||R^T R - I||_F {lo:.1e} to {hi:.1e})")
    };
    format!(
        "{} rigs: rotation rounded as published, orthonormal only to that rounding{range}, projected to the nearest rotation (non-orthonormal-rotation; `audit FILE` shows each): {}",
        rounded.len(),
        first_names(&files, NOTE_NAMES_WIDTH)
    )
}

/// Widest the note's list of files may be (columns): a survey of 10,000
/// files named them all on one line (issue 29).
const NOTE_NAMES_WIDTH: usize = 80;

/// `a, b, c`, or as many names as fit `width` columns with how many are
/// left out (`a, b and 9998 more`); the first name is always given.
fn first_names(names: &[String], width: usize) -> String {
    use unicode_width::UnicodeWidthStr;
    let mut list = String::new();
    for (k, name) in names.iter().enumerate() {
        let longer = if k == 0 {
            name.clone()
        } else {
            format!("{list}, {name}")
        };
        let rest = names.len() - k - 1;
        let shown = if rest == 0 {
            longer.clone()
        } else {
            format!("{longer} and {rest} more")
        };
        if k > 0 && shown.width() > width {
            return format!("{list} and {} more", names.len() - k);
        }
        list = longer;
    }
    list
}

#[cfg(test)]
mod tests {
    use super::*;
    use extrinsic_audit::Location;

    fn rounded(file: &str, measure: f64) -> Warning {
        Warning::new(
            Code::NonOrthonormalRotation,
            format!("rotation is not orthonormal: ||R^T R - I||_F = {measure:e} (rounded)"),
        )
        .at(&Location::file(std::path::Path::new(file)))
    }

    /// 10,000 rounded rotations: the note counts them all and names the
    /// first few, its list within 80 columns (it named every file).
    #[test]
    fn the_rounded_rotations_note_names_a_few_and_counts_the_rest() {
        let ws: Vec<Warning> = (0..10_000)
            .map(|k| rounded(&format!("fleet/d{:03}/rig{k:05}.toml", k / 100), 1e-4))
            .collect();
        let note = rounded_rotations_note(&ws.iter().collect::<Vec<_>>());
        assert!(
            note.starts_with("10000 rigs: rotation rounded as published"),
            "{note}"
        );
        let (_, list) = note.rsplit_once("shows each): ").unwrap();
        assert_eq!(
            list,
            "rig00000, rig00001, rig00002, rig00003, rig00004, rig00005 and 9994 more"
        );
        assert!(list.len() <= 80);
        // A few names that fit are all listed, as before.
        let four: Vec<Warning> = ["a", "b", "c", "d"]
            .iter()
            .map(|f| rounded(&format!("{f}.toml"), 1e-6))
            .collect();
        let four: Vec<&Warning> = four.iter().collect();
        assert!(rounded_rotations_note(&four).ends_with("shows each): a, b, c, d"));
        assert_eq!(first_names(&["x".repeat(90)], 80), "x".repeat(90));
        assert_eq!(
            first_names(&["x".repeat(90), "y".into()], 80),
            format!("{} and 1 more", "x".repeat(90))
        );
    }
}
