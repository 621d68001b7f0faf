//! `audit survey PATHS...`: one row per rig file, then a summary.
//!
//! A rig file is a TOML rig (native, or a sidecar naming a raw file); it declares
//! the body frame and the LiDAR frame (`from`, `to`). Placeholder rigs (identity
//! or zero extrinsics) are listed only with `--include-placeholders`, and never
//! counted in the summary. "Nonzero pitch" counts every rig without an adapted
//! constant metric: general screws and pure translations (a pure translation is
//! a screw of infinite pitch).

use super::audit::io_err;
use super::{expand_paths, parse_nonneg, print_warnings};
use crate::diagnostic::{Error, Result};
use crate::formats::{self, LoadOptions, RigMeta};
use crate::frames::FrameGraph;
use crate::report::{self, fixed, SurveyJson, SurveyRigJson, SurveySummaryJson, SCHEMA_VERSION};
use crate::tolerances::{NEAR_HALF_TURN_RAD, SMALL_ROTATION_DEG};
use clap::{Args, ValueEnum};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Rotation angle (deg) below which the table marks a rig (`*`): its screw axis,
/// and with it h, is set by calibration noise rather than by the mounting. The
/// rig files own the threshold (see calibrations/README.md).

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum SurveyFormat {
    #[default]
    Table,
    Markdown,
    Json,
    Csv,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SortColumn {
    Id,
    Sensor,
    Platform,
    Dataset,
    LeverArm,
    Angle,
    ScrewTranslation,
    SigmaMax,
}

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
    #[arg(long, value_enum, default_value_t = SurveyFormat::Table)]
    pub format: SurveyFormat,
    /// Sort rows by this column (ties by id)
    #[arg(long, value_enum, value_name = "COLUMN")]
    pub sort: Option<SortColumn>,
    /// Zero-pitch tolerance on |h| (m)
    #[arg(long, default_value_t = crate::tolerances::DEFAULT_PITCH_TOL, value_parser = parse_nonneg, value_name = "M")]
    pub pitch_tol: f64,
    /// Also list placeholder and duplicate rigs (never counted in the summary)
    #[arg(long)]
    pub all: bool,
}

/// A surveyed rig: its metadata and the analysis of `T_from_to`.
#[derive(Debug, Clone)]
pub struct SurveyRow {
    pub meta: RigMeta,
    pub file: PathBuf,
    pub json: SurveyRigJson,
}

fn is_rig_file(p: &Path) -> bool {
    p.extension().is_some_and(|e| e == "toml")
}

/// Load and analyse one rig file.
pub fn survey_rig(path: &Path, pitch_tol: f64) -> Result<SurveyRow> {
    let loaded = formats::load_file(path, &LoadOptions::default())?;
    let meta = loaded.rig.clone().ok_or_else(|| {
        Error::parse("expected a TOML rig file with a [rig] table (see docs/rig-format.md)")
            .in_file(path)
    })?;
    let mut graph = FrameGraph::new();
    graph.add(loaded)?;
    print_warnings(graph.warnings());
    let chain = graph
        .transform(&meta.from, &meta.to)
        .map_err(|e| e.in_file(path))?;
    let rep = report::rig_report(&chain, &[1.0], pitch_tol).map_err(|e| e.in_file(path))?;
    let json = SurveyRigJson {
        id: meta.id.clone(),
        sensor: meta.sensor.clone(),
        platform: meta.platform.clone(),
        dataset: meta.dataset.clone(),
        from: meta.from.clone(),
        to: meta.to.clone(),
        lever_arm_m: rep.lever_arm_m,
        angle_deg: rep.rotation.angle_deg,
        screw_translation_m: rep.screw.translation_along_axis_m,
        zero_pitch: rep.screw.kind == "zero_pitch",
        sigma_max: rep.adjoint.singular_values[0],
        band_l1: rep.certificate[0].band,
        adapted_metric_exists: rep.adapted_metric.exists,
    };
    Ok(SurveyRow {
        meta,
        file: path.to_path_buf(),
        json,
    })
}

/// Median of a non-empty slice (mean of the two middle values for even counts).
pub fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

pub fn summarize(rows: &[SurveyRow]) -> SurveySummaryJson {
    let counted: Vec<&SurveyRow> = rows.iter().filter(|r| r.meta.in_statistics()).collect();
    let levers: Vec<f64> = counted.iter().map(|r| r.json.lever_arm_m).collect();
    SurveySummaryJson {
        count: counted.len(),
        lever_arm_min_m: levers.iter().copied().fold(f64::INFINITY, f64::min),
        lever_arm_median_m: median(&levers),
        lever_arm_max_m: levers.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        nonzero_pitch_count: counted.iter().filter(|r| !r.json.zero_pitch).count(),
    }
}

/// Load every rig under `paths`, sorted as asked.
pub fn collect(args: &SurveyArgs) -> Result<Vec<SurveyRow>> {
    let files = expand_paths(&args.paths, is_rig_file)?;
    if files.is_empty() {
        return Err(Error::usage(format!(
            "no rig files (*.toml) found under {}",
            args.paths
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    let mut rows = Vec::new();
    for f in &files {
        let row = survey_rig(f, args.pitch_tol)?;
        if !row.meta.in_statistics() && !args.all {
            continue;
        }
        rows.push(row);
    }
    rows.sort_by(|a, b| a.json.id.cmp(&b.json.id));
    if let Some(col) = args.sort {
        rows.sort_by(|a, b| {
            let (a, b) = (&a.json, &b.json);
            match col {
                SortColumn::Id => a.id.cmp(&b.id),
                SortColumn::Sensor => a.sensor.cmp(&b.sensor),
                SortColumn::Platform => a.platform.cmp(&b.platform),
                SortColumn::Dataset => a.dataset.cmp(&b.dataset),
                SortColumn::LeverArm => a.lever_arm_m.total_cmp(&b.lever_arm_m),
                SortColumn::Angle => a.angle_deg.total_cmp(&b.angle_deg),
                SortColumn::ScrewTranslation => {
                    let k = |x: &SurveyRigJson| x.screw_translation_m.map(f64::abs).unwrap_or(-1.0);
                    k(a).total_cmp(&k(b))
                }
                SortColumn::SigmaMax => a.sigma_max.total_cmp(&b.sigma_max),
            }
        });
    }
    Ok(rows)
}

const HEADER: [&str; 10] = [
    "id",
    "sensor",
    "platform",
    "lever arm (m)",
    "angle (deg)",
    "screw transl. h (m)",
    "zero pitch",
    "s_max",
    "band at l = 1",
    "adapted metric",
];

fn row_cells(r: &SurveyRow) -> Vec<String> {
    let j = &r.json;
    let small = j.angle_deg > 0.0 && j.angle_deg < SMALL_ROTATION_DEG;
    let mut id = j.id.clone();
    if r.meta.placeholder {
        id.push_str(" (placeholder)");
    } else if let Some(d) = &r.meta.duplicate_of {
        id.push_str(&format!(" (duplicate of {d})"));
    }
    let half_turn = (std::f64::consts::PI - j.angle_deg.to_radians()).abs() < NEAR_HALF_TURN_RAD;
    vec![
        id,
        j.sensor.clone(),
        j.platform.clone(),
        fixed(j.lever_arm_m, 4),
        format!("{}{}", fixed(j.angle_deg, 3), if small { "*" } else { "" }),
        match j.screw_translation_m {
            Some(h) => format!("{}{}", h_str(h), if half_turn { " ±" } else { "" }),
            None => "- (pure transl.)".into(),
        },
        if j.zero_pitch { "yes" } else { "no" }.into(),
        fixed(j.sigma_max, 4),
        format!("[{}, {}]", fixed(j.band_l1[0], 3), fixed(j.band_l1[1], 3)),
        if j.adapted_metric_exists {
            "exists"
        } else {
            "none"
        }
        .into(),
    ]
}

/// h in metres: four decimals, or two significant digits below a millimetre.
fn h_str(h: f64) -> String {
    if h == 0.0 {
        "0".into()
    } else if h.abs() < 1e-3 {
        format!("{h:.1e}")
    } else {
        fixed(h, 4)
    }
}

/// The summary line as printed under the table.
pub fn summary_line(s: &SurveySummaryJson) -> String {
    format!(
        "{} rigs; lever arm min {} m, median {} m, max {} m; {} of {} with nonzero pitch (no adapted constant metric), {} with zero pitch",
        s.count,
        fixed(s.lever_arm_min_m, 4),
        fixed(s.lever_arm_median_m, 4),
        fixed(s.lever_arm_max_m, 4),
        s.nonzero_pitch_count,
        s.count,
        s.count - s.nonzero_pitch_count
    )
}

/// Render the survey in the chosen format.
pub fn render(rows: &[SurveyRow], summary: &SurveySummaryJson, format: SurveyFormat) -> String {
    let cells: Vec<Vec<String>> = rows.iter().map(row_cells).collect();
    let note = format!(
        "* rotation below {SMALL_ROTATION_DEG} deg: the screw axis, and with it h, is set by calibration noise\n\
         ± half-turn within {NEAR_HALF_TURN_RAD:e} rad: the sign of h follows the rounding of the published numbers"
    );
    match format {
        SurveyFormat::Table => format!(
            "{}\n{}\n{}\n",
            report::terminal_table_wrapped(&HEADER, &cells, &[(1, 28), (2, 28)]),
            summary_line(summary),
            note
        ),
        SurveyFormat::Markdown => format!(
            "{}\n{}.\n\n{}\n",
            report::markdown_table(&HEADER, &cells),
            summary_line(summary),
            note.replacen('*', "\\*", 1).replace('\n', "  \n")
        ),
        SurveyFormat::Csv => {
            let header = [
                "id",
                "sensor",
                "platform",
                "dataset",
                "from",
                "to",
                "lever_arm_m",
                "angle_deg",
                "screw_translation_m",
                "zero_pitch",
                "sigma_max",
                "band_l1_lower",
                "band_l1_upper",
                "adapted_metric_exists",
                "placeholder",
            ];
            let rows: Vec<Vec<String>> = rows
                .iter()
                .map(|r| {
                    let j = &r.json;
                    vec![
                        j.id.clone(),
                        j.sensor.clone(),
                        j.platform.clone(),
                        j.dataset.clone(),
                        j.from.clone(),
                        j.to.clone(),
                        format!("{}", j.lever_arm_m),
                        format!("{}", j.angle_deg),
                        j.screw_translation_m
                            .map(|h| format!("{h}"))
                            .unwrap_or_default(),
                        format!("{}", j.zero_pitch),
                        format!("{}", j.sigma_max),
                        format!("{}", j.band_l1[0]),
                        format!("{}", j.band_l1[1]),
                        format!("{}", j.adapted_metric_exists),
                        format!("{}", r.meta.placeholder),
                    ]
                })
                .collect();
            report::csv_table(&header, &rows)
        }
        SurveyFormat::Json => {
            let j = SurveyJson {
                schema_version: SCHEMA_VERSION,
                rigs: rows.iter().map(|r| r.json.clone()).collect(),
                summary: summary.clone(),
            };
            // Plain data of strings, numbers and bools: serialisation cannot fail.
            let mut s = serde_json::to_string_pretty(&j).unwrap_or_default();
            s.push('\n');
            s
        }
    }
}

pub fn run(args: &SurveyArgs, out: &mut dyn Write) -> Result<i32> {
    let rows = collect(args)?;
    let summary = summarize(&rows);
    let text = render(&rows, &summary, args.format);
    out.write_all(text.as_bytes()).map_err(io_err)?;
    Ok(0)
}
