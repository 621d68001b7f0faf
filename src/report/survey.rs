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
use crate::document::{Columns, Document, Report, RowSource, Table};
use crate::geometry::uncertainty::UncertaintySource;
use crate::geometry::PitchVerdict;
use crate::tolerances::{NEAR_HALF_TURN_RAD, SMALL_ROTATION_DEG};
use serde::Serialize;
use std::sync::Arc;

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
    pub rigs: SurveyRows,
    /// Statistics over the counted rigs.
    pub summary: SurveySummaryJson,
}

/// What the table notes beside a rig's id.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RowMarks {
    /// Identity or zero extrinsic.
    pub placeholder: bool,
    /// The id of the rig this one duplicates.
    pub duplicate_of: Option<String>,
}

/// The survey's rows, compact (issue 29: a survey of 100,000 files in flat
/// memory): each row's numbers in a fixed record, its texts end to end in
/// one buffer, and the order printed as a permutation of the rows as read.
/// Serialised as the JSON's `rigs` array, each row a [`SurveyRigJson`];
/// shared, so that the report's document streams its tables from it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SurveyRows(Arc<RowStore>);

#[derive(Debug, PartialEq, Default)]
struct RowStore {
    /// Every row's texts, end to end (id, sensor, platform, dataset, from,
    /// to, duplicate_of).
    text: String,
    /// The rows, as read.
    rows: Vec<Compact>,
    /// The rows in the order printed (indices into `rows`).
    order: Vec<u32>,
}

/// The texts of a row, in `RowStore::text` in this order.
const TEXTS: usize = 7;

/// A row's fixed part (about 100 bytes; its texts are in `RowStore::text`).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Compact {
    start: usize,
    lens: [u32; TEXTS],
    lever_arm_m: f64,
    angle_deg: f64,
    h: f64,
    u_h: f64,
    sigma_max: f64,
    band_l1: [f64; 2],
    pitch_verdict: Option<PitchVerdict>,
    uncertainty_source: UncertaintySource,
    flags: u8,
}

const HAS_H: u8 = 1;
const HAS_U: u8 = 2;
const ZERO_PITCH: u8 = 4;
const ADAPTED: u8 = 8;
const PLACEHOLDER: u8 = 16;
const HAS_DUPLICATE: u8 = 32;
const COUNTED: u8 = 64;

/// One row of the survey, borrowed from [`SurveyRows`]: the JSON's row (it
/// serialises as a [`SurveyRigJson`]), its marks, whether it is counted.
#[derive(Debug, Clone, Copy, Serialize)]
pub(crate) struct RigView<'a> {
    pub id: &'a str,
    pub sensor: &'a str,
    pub platform: &'a str,
    pub dataset: &'a str,
    pub from: &'a str,
    pub to: &'a str,
    pub lever_arm_m: f64,
    pub angle_deg: f64,
    pub screw_translation_m: Option<f64>,
    pub zero_pitch: bool,
    pub screw_translation_uncertainty_m: Option<f64>,
    pub pitch_verdict: Option<PitchVerdict>,
    pub uncertainty_source: UncertaintySource,
    pub sigma_max: f64,
    pub band_l1: [f64; 2],
    pub adapted_metric_exists: bool,
    #[serde(skip)]
    pub placeholder: bool,
    #[serde(skip)]
    pub duplicate_of: Option<&'a str>,
    #[serde(skip)]
    pub counted: bool,
}

impl RigView<'_> {
    /// The row as its owned JSON row and marks.
    fn owned(&self) -> (SurveyRigJson, RowMarks) {
        let json = SurveyRigJson {
            id: self.id.into(),
            sensor: self.sensor.into(),
            platform: self.platform.into(),
            dataset: self.dataset.into(),
            from: self.from.into(),
            to: self.to.into(),
            lever_arm_m: self.lever_arm_m,
            angle_deg: self.angle_deg,
            screw_translation_m: self.screw_translation_m,
            zero_pitch: self.zero_pitch,
            screw_translation_uncertainty_m: self.screw_translation_uncertainty_m,
            pitch_verdict: self.pitch_verdict,
            uncertainty_source: self.uncertainty_source,
            sigma_max: self.sigma_max,
            band_l1: self.band_l1,
            adapted_metric_exists: self.adapted_metric_exists,
        };
        let marks = RowMarks {
            placeholder: self.placeholder,
            duplicate_of: self.duplicate_of.map(str::to_string),
        };
        (json, marks)
    }
}

/// The survey's rows as they are read, then put in order
/// ([`SurveyRowsBuilder::finish`]).
#[derive(Debug, Default)]
pub(crate) struct SurveyRowsBuilder(RowStore);

impl SurveyRowsBuilder {
    /// Room for up to `n` rows (the number of files: a row per file at most).
    pub fn with_capacity(n: usize) -> Self {
        SurveyRowsBuilder(RowStore {
            rows: Vec::with_capacity(n),
            ..RowStore::default()
        })
    }
    /// Append a row.
    pub fn push(&mut self, j: &SurveyRigJson, m: &RowMarks, counted: bool) {
        let text = &mut self.0.text;
        let start = text.len();
        let dup = m.duplicate_of.as_deref();
        let texts = [
            j.id.as_str(),
            &j.sensor,
            &j.platform,
            &j.dataset,
            &j.from,
            &j.to,
            dup.unwrap_or(""),
        ];
        let mut lens = [0u32; TEXTS];
        for (l, t) in lens.iter_mut().zip(texts) {
            text.push_str(t);
            // A text is a name or a path read from a file of at most a few
            // hundred megabytes: it fits a u32.
            *l = u32::try_from(t.len()).unwrap_or(u32::MAX);
        }
        let flag = |b: bool, f: u8| if b { f } else { 0 };
        self.0.rows.push(Compact {
            start,
            lens,
            lever_arm_m: j.lever_arm_m,
            angle_deg: j.angle_deg,
            h: j.screw_translation_m.unwrap_or(0.0),
            u_h: j.screw_translation_uncertainty_m.unwrap_or(0.0),
            sigma_max: j.sigma_max,
            band_l1: j.band_l1,
            pitch_verdict: j.pitch_verdict,
            uncertainty_source: j.uncertainty_source,
            flags: flag(j.screw_translation_m.is_some(), HAS_H)
                | flag(j.screw_translation_uncertainty_m.is_some(), HAS_U)
                | flag(j.zero_pitch, ZERO_PITCH)
                | flag(j.adapted_metric_exists, ADAPTED)
                | flag(m.placeholder, PLACEHOLDER)
                | flag(dup.is_some(), HAS_DUPLICATE)
                | flag(counted, COUNTED),
        });
    }
    /// How many rows.
    pub fn len(&self) -> usize {
        self.0.rows.len()
    }
    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.0.rows.is_empty()
    }
    /// Row `i` as read.
    pub fn view(&self, i: usize) -> RigView<'_> {
        self.0.view(i)
    }
    /// Row `i`'s id (the sort's tie-break, without the rest of the row).
    pub fn id(&self, i: usize) -> &str {
        let c = &self.0.rows[i];
        &self.0.text[c.start..c.start + c.lens[0] as usize]
    }
    /// The rows, printed in `order` (a permutation of `0..len()`).
    pub fn finish(mut self, order: Vec<u32>) -> SurveyRows {
        debug_assert_eq!(order.len(), self.0.rows.len());
        self.0.text.shrink_to_fit();
        self.0.rows.shrink_to_fit();
        self.0.order = order;
        SurveyRows(Arc::new(self.0))
    }
}

impl RowStore {
    fn view(&self, i: usize) -> RigView<'_> {
        let c = &self.rows[i];
        let mut at = c.start;
        let mut t = [""; TEXTS];
        for (s, &l) in t.iter_mut().zip(&c.lens) {
            let end = at + l as usize;
            *s = &self.text[at..end];
            at = end;
        }
        let has = |f: u8| c.flags & f != 0;
        RigView {
            id: t[0],
            sensor: t[1],
            platform: t[2],
            dataset: t[3],
            from: t[4],
            to: t[5],
            lever_arm_m: c.lever_arm_m,
            angle_deg: c.angle_deg,
            screw_translation_m: has(HAS_H).then_some(c.h),
            zero_pitch: has(ZERO_PITCH),
            screw_translation_uncertainty_m: has(HAS_U).then_some(c.u_h),
            pitch_verdict: c.pitch_verdict,
            uncertainty_source: c.uncertainty_source,
            sigma_max: c.sigma_max,
            band_l1: c.band_l1,
            adapted_metric_exists: has(ADAPTED),
            placeholder: has(PLACEHOLDER),
            duplicate_of: has(HAS_DUPLICATE).then_some(t[6]),
            counted: has(COUNTED),
        }
    }
}

impl SurveyRows {
    /// How many rows.
    pub fn len(&self) -> usize {
        self.0.order.len()
    }
    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Row `i` in the order printed.
    pub(crate) fn view(&self, i: usize) -> RigView<'_> {
        self.0.view(self.0.order[i] as usize)
    }
    /// Row `i` in the order printed, as its JSON row.
    pub fn get(&self, i: usize) -> Option<SurveyRigJson> {
        (i < self.len()).then(|| self.view(i).owned().0)
    }
    /// The rows in the order printed, each as its JSON row.
    pub fn iter(&self) -> impl Iterator<Item = SurveyRigJson> + '_ {
        (0..self.len()).map(|i| self.view(i).owned().0)
    }
    fn views(&self) -> impl Iterator<Item = RigView<'_>> + '_ {
        (0..self.len()).map(|i| self.view(i))
    }
}

impl Serialize for SurveyRows {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.views())
    }
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
    /// The report over the rows (in the order to print), counting those
    /// marked counted.
    pub(crate) fn new(rigs: SurveyRows) -> Self {
        let levers: Vec<f64> = rigs
            .views()
            .filter(|r| r.counted)
            .map(|r| r.lever_arm_m)
            .collect();
        let mut by_verdict = [0usize; 3];
        for r in rigs.views().filter(|r| r.counted) {
            by_verdict[match verdict_of(&r) {
                PitchVerdict::Nonzero => 0,
                PitchVerdict::Zero => 1,
                PitchVerdict::Undecidable => 2,
            }] += 1;
        }
        let summary = SurveySummaryJson {
            count: levers.len(),
            lever_arm_min_m: levers.iter().copied().fold(f64::INFINITY, f64::min),
            lever_arm_median_m: median(&levers),
            lever_arm_max_m: levers.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            nonzero_pitch_count: by_verdict[0],
            zero_pitch_count: by_verdict[1],
            undecidable_pitch_count: by_verdict[2],
        };
        SurveyReport {
            schema_version: SCHEMA_VERSION,
            rigs,
            summary,
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
        // A narrow terminal: one line per rig (id, lever arm, angle, h, zero
        // pitch, band, metric), the id shortened if need be; `--wide` adds
        // sensor, platform, the uncertainty of h and s_max. The rows are made
        // as they are written (issue 29).
        Table::streamed(&HEADER, Arc::new(DisplayRows(self.rigs.clone())))
            .bounded(&[(1, 28), (2, 28)])
            .compact(&[0, 3, 4, 5, 7, 9, 10])
            .one_line(0)
    }

    /// The data table (`--format csv`): one row per rig, the JSON's keys as
    /// columns (`band_l1` split into `band_l1_low`, `band_l1_high`), then
    /// `placeholder` and `duplicate_of` (the marks the text table writes
    /// beside the id; the JSON has no such keys). Streamed as the display
    /// table is.
    fn data_table(&self) -> Table {
        let columns = data_columns();
        let header = columns.header();
        let header: Vec<&str> = header.iter().map(String::as_str).collect();
        let mut t = Table::streamed(
            &header,
            Arc::new(DataRows {
                rows: self.rigs.clone(),
                columns,
            }),
        );
        t.data_only = true;
        t.wrap = false;
        t
    }
}

/// The survey's display rows, made from the compact rows one at a time.
struct DisplayRows(SurveyRows);

impl RowSource for DisplayRows {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn row(&self, i: usize) -> Vec<String> {
        display_row(&self.0.view(i))
    }
}

/// One data row: the JSON's row and its marks.
type DataRow = (SurveyRigJson, RowMarks);

/// The survey's data rows, made one at a time.
struct DataRows {
    rows: SurveyRows,
    columns: Columns<'static, DataRow>,
}

impl RowSource for DataRows {
    fn len(&self) -> usize {
        self.rows.len()
    }
    fn row(&self, i: usize) -> Vec<String> {
        self.columns.cells(&self.rows.view(i).owned())
    }
}

/// The data table's columns (declared once: the header exists without rows).
fn data_columns() -> Columns<'static, DataRow> {
    Columns::<DataRow>::new()
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
fn verdict_of(j: &RigView) -> PitchVerdict {
    j.pitch_verdict.unwrap_or(if j.lever_arm_m > 0.0 {
        PitchVerdict::Nonzero
    } else {
        PitchVerdict::Zero
    })
}

fn display_row(j: &RigView) -> Vec<String> {
    let mut id = j.id.to_string();
    if j.placeholder {
        id.push_str(" (placeholder)");
    } else if let Some(d) = j.duplicate_of {
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
        or_dash(j.sensor),
        or_dash(j.platform),
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
        if self.rigs.views().any(|j| j.screw_translation_m.is_none()) {
            notes.push_str(
                "\n- no rotation: a pure translation has no screw axis and no h (infinite pitch)",
            );
        }
        doc.text(notes);
        doc
    }
}
