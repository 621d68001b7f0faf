//! The survey (`audit survey PATHS`): one row per rig, then a summary; JSON in
//! `docs/schemas/survey.schema.json`.
//!
//! The summary counts rigs by the three-way pitch verdict
//! ([`crate::geometry::uncertainty`]): "zero" (identity included), "nonzero"
//! (pure translations included: a screw of infinite pitch) and "undecidable at
//! this precision". Placeholder and duplicate rigs are listed only on request
//! and never counted.

use super::rig::{near_half_turn, small_rotation};
use crate::document::numbers::{degrees, fixed, metres, metres_h, ratio, vector};
use crate::document::SCHEMA_VERSION;
use crate::document::{Columns, Document, Report, Table};
use crate::geometry::uncertainty::UncertaintySource;
use crate::geometry::PitchVerdict;
use crate::tolerances::{NEAR_HALF_TURN_RAD, SMALL_ROTATION_DEG};
use serde::Serialize;

/// One survey row (`rigs[i]` of the survey JSON, README "JSON"): the rig file's
/// metadata and its `[rig] from -> to` transform analysed.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SurveyRigJson {
    /// Rig id (`[rig] id`).
    pub id: String,
    /// What was measured (`[rig] sensor`; for a file that is not a rig
    /// file, the `to` frame).
    pub sensor: String,
    /// What it is mounted on (`[rig] platform`; for a URDF or xacro, its
    /// `<robot name>`; empty when the file names none).
    pub platform: String,
    /// Dataset or project (`[rig] dataset`).
    pub dataset: String,
    /// Body (IMU) frame: the transform is the pose of `to` in `from`.
    pub from: String,
    /// LiDAR frame.
    pub to: String,
    /// Lever arm `||d||` (m).
    pub lever_arm_m: f64,
    /// Rotation angle in `[0, 180]` (deg).
    pub angle_deg: f64,
    /// Screw translation `h = e . d` (m); null without a rotation (identity or
    /// pure translation).
    pub screw_translation_m: Option<f64>,
    /// The screw kind is `zero_pitch` (`|h|` within the pitch tolerance).
    pub zero_pitch: bool,
    /// First-order standard uncertainty of `h` (m); null without a rotation.
    pub screw_translation_uncertainty_m: Option<f64>,
    /// `zero`, `nonzero` or `undecidable` (the identity: `zero`; a pure
    /// translation: `nonzero`, infinite pitch).
    pub pitch_verdict: Option<PitchVerdict>,
    /// `none`, `rounding`, `user` or `both`.
    pub uncertainty_source: UncertaintySource,
    /// Largest singular value of `Ad(T)` (lever arm in metres).
    pub sigma_max: f64,
    /// Certificate band `[s_min^2, s_max^2]` at `l = 1 m`.
    pub band_l1: [f64; 2],
    /// An adapted constant metric exists (identity or zero pitch).
    pub adapted_metric_exists: bool,
}

/// `summary` of the survey JSON, over the rigs counted (placeholders and
/// duplicates excluded).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SurveySummaryJson {
    /// Number of rigs counted.
    pub count: usize,
    /// Smallest lever arm (m); null when no rig is counted.
    pub lever_arm_min_m: f64,
    /// Median lever arm (m; mean of the two middle ones for an even count);
    /// null when no rig is counted.
    pub lever_arm_median_m: f64,
    /// Largest lever arm (m); null when no rig is counted.
    pub lever_arm_max_m: f64,
    /// Counted rigs with a nonzero pitch: verdict `nonzero`, or a pure
    /// translation.
    pub nonzero_pitch_count: usize,
    /// Counted rigs with zero pitch: verdict `zero`, or the identity.
    pub zero_pitch_count: usize,
    /// Counted rigs whose pitch is undecidable at their precision.
    pub undecidable_pitch_count: usize,
}

/// The survey report.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SurveyReport {
    /// Version of this JSON layout (1).
    pub schema_version: u32,
    /// One row per rig, in the order printed (sorted by id, or by `--sort`).
    pub rigs: Vec<SurveyRigJson>,
    /// Statistics over the counted rigs.
    pub summary: SurveySummaryJson,
    /// Per row: placeholder, and the rig it duplicates (for the tables).
    #[serde(skip)]
    pub(crate) marks: Vec<RowMarks>,
}

/// What the table notes beside a rig's id.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RowMarks {
    /// Identity or zero extrinsic.
    pub placeholder: bool,
    /// The id of the rig this one duplicates.
    pub duplicate_of: Option<String>,
}

/// Median of a slice (mean of the two middle values for even counts; NaN
/// when empty).
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

impl SurveyReport {
    /// The report over rows (in the order to print), counting those `counted`.
    pub(crate) fn new(rows: Vec<(SurveyRigJson, RowMarks)>, counted: &[bool]) -> Self {
        let levers: Vec<f64> = rows
            .iter()
            .zip(counted)
            .filter(|(_, c)| **c)
            .map(|(r, _)| r.0.lever_arm_m)
            .collect();
        let by_verdict = |v: PitchVerdict| {
            rows.iter()
                .zip(counted)
                .filter(|(r, c)| **c && verdict_of(&r.0) == v)
                .count()
        };
        let summary = SurveySummaryJson {
            count: levers.len(),
            lever_arm_min_m: levers.iter().copied().fold(f64::INFINITY, f64::min),
            lever_arm_median_m: median(&levers),
            lever_arm_max_m: levers.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            nonzero_pitch_count: by_verdict(PitchVerdict::Nonzero),
            zero_pitch_count: by_verdict(PitchVerdict::Zero),
            undecidable_pitch_count: by_verdict(PitchVerdict::Undecidable),
        };
        let (rigs, marks) = rows.into_iter().unzip();
        SurveyReport {
            schema_version: SCHEMA_VERSION,
            rigs,
            summary,
            marks,
        }
    }

    /// The summary line as printed under the table.
    pub fn summary_line(&self) -> String {
        let s = &self.summary;
        format!(
            "{} rigs; lever arm min {} m, median {} m, max {} m; {} of {} with nonzero pitch (no adapted constant metric), {} with zero pitch, {} undecidable at their precision",
            s.count,
            fixed(s.lever_arm_min_m, 4),
            fixed(s.lever_arm_median_m, 4),
            fixed(s.lever_arm_max_m, 4),
            s.nonzero_pitch_count,
            s.count,
            s.zero_pitch_count,
            s.undecidable_pitch_count
        )
    }

    fn display_table(&self) -> Table {
        let rows = self
            .rigs
            .iter()
            .zip(&self.marks)
            .map(|(j, m)| display_row(j, m))
            .collect();
        // A narrow terminal: one line per rig (id, lever arm, angle, h, zero
        // pitch, band, metric), the id shortened if need be; `--wide` adds
        // sensor, platform, the uncertainty of h and s_max.
        Table::new(&HEADER, rows)
            .bounded(&[(1, 28), (2, 28)])
            .compact(&[0, 3, 4, 5, 7, 9, 10])
            .one_line(0)
    }

    /// The data table (`--format csv`): one row per rig, the JSON's keys as
    /// columns (`band_l1` split into `band_l1_low`, `band_l1_high`), then
    /// `placeholder` and `duplicate_of` (the marks the text table writes
    /// beside the id; the JSON has no such keys).
    fn data_table(&self) -> Table {
        type Row<'r> = (&'r SurveyRigJson, &'r RowMarks);
        let rows: Vec<Row> = self.rigs.iter().zip(&self.marks).collect();
        Columns::<Row>::new()
            .text("id", |r| r.0.id.clone())
            .text("sensor", |r| r.0.sensor.clone())
            .text("platform", |r| r.0.platform.clone())
            .text("dataset", |r| r.0.dataset.clone())
            .text("from", |r| r.0.from.clone())
            .text("to", |r| r.0.to.clone())
            .num("lever_arm_m", |r| r.0.lever_arm_m)
            .num("angle_deg", |r| r.0.angle_deg)
            .num("screw_translation_m", |r| r.0.screw_translation_m)
            .flag("zero_pitch", |r| r.0.zero_pitch)
            .num("screw_translation_uncertainty_m", |r| {
                r.0.screw_translation_uncertainty_m
            })
            .text("pitch_verdict", |r| {
                r.0.pitch_verdict.map_or("", PitchVerdict::name).into()
            })
            .text("uncertainty_source", |r| {
                r.0.uncertainty_source.name().into()
            })
            .num("sigma_max", |r| r.0.sigma_max)
            .vector("band_l1", ["low", "high"], |r| Some(r.0.band_l1))
            .flag("adapted_metric_exists", |r| r.0.adapted_metric_exists)
            .flag("placeholder", |r| r.1.placeholder)
            .text("duplicate_of", |r| {
                r.1.duplicate_of.clone().unwrap_or_default()
            })
            .table(&rows)
    }
}

const HEADER: [&str; 11] = [
    "id",
    "sensor",
    "platform",
    "lever arm (m)",
    "angle (deg)",
    "screw transl. h (m)",
    "u(h) (m)",
    "pitch",
    "s_max",
    "band at l = 1",
    "adapted metric",
];

/// The row's pitch verdict; without a rotation, the identity is `zero` and a
/// pure translation `nonzero` (infinite pitch).
pub fn verdict_of(j: &SurveyRigJson) -> PitchVerdict {
    j.pitch_verdict.unwrap_or(if j.lever_arm_m > 0.0 {
        PitchVerdict::Nonzero
    } else {
        PitchVerdict::Zero
    })
}

fn display_row(j: &SurveyRigJson, m: &RowMarks) -> Vec<String> {
    let mut id = j.id.clone();
    if m.placeholder {
        id.push_str(" (placeholder)");
    } else if let Some(d) = &m.duplicate_of {
        id.push_str(&format!(" (duplicate of {d})"));
    }
    let small = small_rotation(j.angle_deg);
    // A file that names no platform (a YAML, a bag): a dash.
    let or_dash = |s: &str| {
        if s.is_empty() {
            "-".to_string()
        } else {
            s.to_string()
        }
    };
    vec![
        id,
        or_dash(&j.sensor),
        or_dash(&j.platform),
        metres(j.lever_arm_m),
        format!("{}{}", degrees(j.angle_deg), if small { "*" } else { "" }),
        match j.screw_translation_m {
            Some(h) => format!(
                "{}{}",
                metres_h(h),
                if near_half_turn(j.angle_deg.to_radians()) {
                    " ±"
                } else {
                    ""
                }
            ),
            None => "-".into(),
        },
        j.screw_translation_uncertainty_m
            .map(metres_h)
            .unwrap_or_else(|| "-".into()),
        verdict_of(j).name().into(),
        ratio(j.sigma_max),
        vector(&j.band_l1, ratio),
        if j.adapted_metric_exists {
            "exists"
        } else {
            "none"
        }
        .into(),
    ]
}

impl Report for SurveyReport {
    fn document(&self) -> Document {
        let mut doc = Document::new();
        doc.table(self.display_table());
        doc.table(self.data_table());
        doc.text(self.summary_line());
        let mut notes = format!(
            "* rotation below {SMALL_ROTATION_DEG} deg: the screw axis, and with it h, is set by calibration noise\n\
             ± half-turn within {NEAR_HALF_TURN_RAD:e} rad: the sign of h follows the rounding of the published numbers"
        );
        if self.rigs.iter().any(|j| j.screw_translation_m.is_none()) {
            notes.push_str(
                "\n- no rotation: a pure translation has no screw axis and no h (infinite pitch)",
            );
        }
        doc.text(notes);
        doc
    }
}
