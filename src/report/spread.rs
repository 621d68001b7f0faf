//! `audit spread FILES...`: many calibrations of one frame pair (repeated
//! calibration runs, or one file per vehicle of a fleet): their mean on
//! SE(3), each one's deviation, the per-axis spread, the outliers and what
//! the spread does to the pitch verdict and the certificate bands. JSON in
//! `docs/schemas/spread.schema.json`; the method is stated in
//! [`crate::analysis::spread`] and in the report's `method`.

use crate::analysis::spread::Deviation;
use crate::document::numbers::{degrees, fixed, metres, metres_h, ratio, short, unit, vector};
use crate::document::{data_number, Block, Document, Report, Table};
use crate::geometry::PitchVerdict;
use crate::report::diff::DiffToleranceJson;
use crate::tolerances::OUTLIER_FEW;
use serde::Serialize;

/// `method`: how the mean, the deviations and the outliers are taken.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct MethodJson {
    /// The rotation mean.
    pub rotation_mean: &'static str,
    /// The translation mean.
    pub translation_mean: &'static str,
    /// The deviations' definitions.
    pub deviations: &'static str,
    /// The outlier rule.
    pub outlier_rule: &'static str,
}

/// The method of every spread report.
pub const METHOD: MethodJson = MethodJson {
    rotation_mean: "chordal L2 mean, argmin_M sum ||R_i - M||_F^2 (scipy Rotation.mean): the top eigenvector of sum q_i q_i^T",
    translation_mean: "arithmetic mean of the translations, from-frame coordinates",
    deviations: "rotation: Log(R_i R_mean^T) in from-frame axes, Log(R_mean^T R_i) in to-frame axes (rotation-vector components, not Euler angles); translation: t_i - t_mean in from-frame axes, R_mean^T (t_i - t_mean) in to-frame axes; std with ddof = 1",
    outlier_rule: "Iglewicz-Hoaglin |M| > 3.5 carried to 3-D, rotation and translation separately: per-axis MAD-standardised distance from the component-wise median (from-frame axes) > max(2.749 x median distance, 4.229); MAD floored at 0.01 mm and 0.001 deg; not applied below 3 calibrations",
};

/// `mean`: the mean calibration.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct MeanJson {
    /// Mean translation (m), from-frame coordinates.
    pub translation_m: [f64; 3],
    /// Mean rotation as a quaternion `[x, y, z, w]`, `w >= 0`.
    pub quaternion_xyzw: [f64; 4],
    /// Mean rotation, row-major.
    pub rotation_matrix: [[f64; 3]; 3],
    /// Its rotation angle (deg).
    pub angle_deg: f64,
    /// `|t_mean|` (m).
    pub lever_arm_m: f64,
    /// `(w4 - w3) / w4` of `K = sum q q^T`: near 1 for a tight set.
    pub eigen_gap: f64,
}

/// The spread of one group of deviations.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct AxisJson {
    /// Sample standard deviation per axis (`ddof = 1`); null for one
    /// calibration.
    pub std: Option<[f64; 3]>,
    /// Largest absolute deviation per axis.
    pub max_abs: [f64; 3],
    /// The calibration each largest deviation belongs to.
    pub max_abs_calibration: [String; 3],
    /// Largest norm of a deviation.
    pub norm_max: f64,
}

/// `spread`: per quantity and frame.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SpreadJson {
    /// Rotation (deg), from-frame axes.
    pub rotation_from_deg: AxisJson,
    /// Rotation (deg), to-frame axes.
    pub rotation_to_deg: AxisJson,
    /// Translation (mm), from-frame axes.
    pub translation_from_mm: AxisJson,
    /// Translation (mm), to-frame axes.
    pub translation_to_mm: AxisJson,
}

/// One outlier test (rotation in deg, translation in mm).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct OutlierTestJson {
    /// The component-wise median, from-frame axes.
    pub centre: [f64; 3],
    /// `MAD / 0.6745` per axis, the MAD floored.
    pub robust_sigma: [f64; 3],
    /// The median of the standardised distances.
    pub median_distance: f64,
    /// The limit beyond which a calibration is an outlier.
    pub limit: f64,
}

/// `outliers`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct OutliersJson {
    /// Whether the rule was applied (3 calibrations or more).
    pub tested: bool,
    /// Fewer than 10 calibrations: the robust scale is itself uncertain.
    pub few: bool,
    /// The rotation test.
    pub rotation: Option<OutlierTestJson>,
    /// The translation test.
    pub translation: Option<OutlierTestJson>,
    /// The calibrations flagged, in input order.
    pub names: Vec<String>,
}

/// `without_outliers`: the mean and spread of the others.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SubsetJson {
    /// The calibrations kept.
    pub calibrations: Vec<String>,
    /// Their mean.
    pub mean: MeanJson,
    /// Their spread.
    pub spread: SpreadJson,
}

/// `pitch`: the three-way pitch verdict for the set.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SetPitchJson {
    /// `h = e . t` of the mean (m); null without a rotation.
    pub h_m: Option<f64>,
    /// The standard deviation of the calibrations' `h` (each along the axis
    /// aligned with the mean's), taken as the calibration uncertainty (m);
    /// null for one calibration or without a rotation.
    pub h_spread_m: Option<f64>,
    /// The verdict on `h_m` with `h_spread_m` as its standard uncertainty.
    pub verdict: Option<PitchVerdict>,
    /// How many calibrations have each verdict of their own (from the
    /// rounding of their numbers): zero, nonzero, undecidable.
    pub per_calibration: [usize; 3],
}

/// `bands[i]`: the range of the certificate bands over the calibrations.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct BandRangeJson {
    /// The characteristic length (m).
    pub ell_m: f64,
    /// The lowest lower edge.
    pub low: f64,
    /// The highest upper edge.
    pub high: f64,
}

/// `calibrations[i]`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct CalibrationJson {
    /// Its name: the file name, or the vehicle's folder when the file names
    /// repeat.
    pub name: String,
    /// The file.
    pub file: String,
    /// Its own parent frame: the set's `from`, or the name its
    /// `PATH:FROM:TO` gives the same frame.
    pub from: String,
    /// Its own child frame.
    pub to: String,
    /// Translation (m).
    pub translation_m: [f64; 3],
    /// Rotation `[x, y, z, w]`.
    pub quaternion_xyzw: [f64; 4],
    /// Its deviation from the mean.
    pub deviation: Deviation,
    /// Standardised rotation distance of the outlier rule.
    pub rotation_distance: Option<f64>,
    /// Standardised translation distance of the outlier rule.
    pub translation_distance: Option<f64>,
    /// Flagged by the outlier rule.
    pub outlier: bool,
    /// Beyond the fleet tolerance (`--tolerance`).
    pub exceeds: bool,
    /// `|t|` (m).
    pub lever_arm_m: f64,
    /// `h = e . t` (m), `e` the calibration's screw axis oriented with the
    /// mean's (`e . e_mean >= 0`: on a small rotation the axis, and the sign
    /// of `h`, otherwise follow the noise); null without a rotation.
    pub h_m: Option<f64>,
    /// Its standard uncertainty from the rounding of the numbers (m).
    pub h_uncertainty_m: Option<f64>,
    /// Its own pitch verdict.
    pub pitch_verdict: Option<PitchVerdict>,
    /// The certificate band at each `ell` of `bands`.
    pub bands: Vec<[f64; 2]>,
}

/// The spread report.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SpreadReport {
    /// The JSON schema version (docs/schemas/spread.schema.json).
    pub schema_version: u32,
    /// Parent frame: the first calibration's (each one's own is in
    /// `calibrations`).
    pub from: String,
    /// Child frame: the first calibration's.
    pub to: String,
    /// How everything is computed.
    pub method: MethodJson,
    /// How many calibrations.
    pub count: usize,
    /// Their mean.
    pub mean: MeanJson,
    /// The pitch verdict of the set.
    pub pitch: SetPitchJson,
    /// The spread of the deviations.
    pub spread: SpreadJson,
    /// The outlier rule's result.
    pub outliers: OutliersJson,
    /// The mean and spread without the outliers (when any is flagged).
    pub without_outliers: Option<SubsetJson>,
    /// The range of the certificate bands.
    pub bands: Vec<BandRangeJson>,
    /// The fleet tolerance (`--tolerance LENGTH,ANGLE`), when given.
    pub tolerance: Option<DiffToleranceJson>,
    /// The calibrations beyond it.
    pub exceeded: Vec<String>,
    /// One per calibration, in input order.
    pub calibrations: Vec<CalibrationJson>,
}

/// Rows of the calibrations table shown on a terminal at most: a fleet's
/// other rows are in the CSV and the JSON.
const MAX_SHOWN: usize = 40;

/// Outliers named in the text at most (all are in the table, CSV and JSON).
const MAX_NAMED: usize = 10;

fn mm(x: f64) -> String {
    fixed(x, 2)
}

fn with_index(v: String, i: usize) -> String {
    format!("{v} #{}", i + 1)
}

impl SpreadReport {
    fn index_of(&self, name: &str) -> usize {
        self.calibrations
            .iter()
            .position(|c| c.name == name)
            .unwrap_or(0)
    }

    /// The sentence that opens the report.
    pub fn headline(&self) -> String {
        let s = &self.spread;
        let (t, r) = (&s.translation_from_mm, &s.rotation_to_deg);
        let mut line = format!(
            "{} calibrations of {} -> {}: largest deviation {} mm, {} deg",
            self.count,
            self.from,
            self.to,
            mm(t.norm_max),
            degrees(r.norm_max)
        );
        let o = &self.outliers.names;
        match o.len() {
            0 if self.outliers.tested => line.push_str("; no outlier"),
            0 => {}
            1 => line.push_str(&format!("; outlier: {}", o[0])),
            n => line.push_str(&format!("; {n} outliers")),
        }
        if let Some(tol) = &self.tolerance {
            line.push_str(&format!(
                "; {} beyond {} mm, {} deg",
                self.exceeded.len(),
                short(tol.translation_mm),
                short(tol.rotation_deg)
            ));
        }
        line
    }

    fn mean_table(&self) -> Table {
        let m = &self.mean;
        let mut rows = vec![
            vec!["translation (m)".into(), vector(&m.translation_m, metres)],
            vec!["rotation (xyzw)".into(), vector(&m.quaternion_xyzw, unit)],
            vec!["angle (deg)".into(), degrees(m.angle_deg)],
            vec!["lever arm (m)".into(), metres(m.lever_arm_m)],
        ];
        let p = &self.pitch;
        let h = match (p.h_m, p.h_spread_m) {
            (Some(h), Some(s)) => format!("{} +- {} (spread)", metres_h(h), metres_h(s)),
            (Some(h), None) => metres_h(h),
            _ => "none (no rotation)".into(),
        };
        rows.push(vec!["h of the mean (m)".into(), h]);
        let [z, n, u] = p.per_calibration;
        let verdict = p.verdict.map_or("none", PitchVerdict::name);
        rows.push(vec![
            "pitch".into(),
            format!("{verdict} (each: {z} zero, {n} nonzero, {u} undecidable)"),
        ]);
        for b in &self.bands {
            rows.push(vec![
                format!("bands at l = {} m", short(b.ell_m)),
                format!("{} to {}", ratio(b.low), ratio(b.high)),
            ]);
        }
        Table::new(&["mean", "value"], rows)
    }

    fn spread_table(&self, rotation: bool) -> Table {
        let s = &self.spread;
        let (from, to, f): (_, _, fn(f64) -> String) = if rotation {
            (&s.rotation_from_deg, &s.rotation_to_deg, degrees)
        } else {
            (&s.translation_from_mm, &s.translation_to_mm, mm)
        };
        let row = |axes: &str, a: &AxisJson| {
            let mut r = vec![axes.to_string()];
            for k in 0..3 {
                r.push(a.std.map_or("-".into(), |s| f(s[k])));
            }
            for k in 0..3 {
                let i = self.index_of(&a.max_abs_calibration[k]);
                r.push(with_index(f(a.max_abs[k]), i));
            }
            r
        };
        // "from"/"to", not the frame names: a long name would widen the table.
        let rows = vec![row("from", from), row("to", to)];
        // Narrow numbers: never wrapped (the table fits 80 columns).
        Table::unwrapped(
            &["axes", "std x", "std y", "std z", "max x", "max y", "max z"],
            rows,
        )
    }

    fn calibration_table(&self, shown: &[usize]) -> Table {
        let rows = shown
            .iter()
            .map(|&i| {
                let c = &self.calibrations[i];
                let mut flags = Vec::new();
                if c.outlier {
                    flags.push("outlier");
                }
                if c.exceeds {
                    flags.push("beyond");
                }
                vec![
                    (i + 1).to_string(),
                    c.name.clone(),
                    degrees(c.deviation.angle_deg),
                    mm(c.deviation.distance_mm),
                    c.h_m.map_or("-".into(), metres_h),
                    c.pitch_verdict.map_or("-", PitchVerdict::name).into(),
                    flags.join(", "),
                ]
            })
            .collect();
        Table::new(
            &["#", "calibration", "deg", "mm", "h (m)", "pitch", "flag"],
            rows,
        )
        .one_line(1)
        .compact(&[0, 1, 2, 3, 6])
    }

    /// One row per calibration, one number per column (CSV only), the
    /// columns named as `report::data` names them.
    fn data_table(&self) -> Table {
        let mut header: Vec<String> = ["name", "file"].map(String::from).to_vec();
        let xyz = |p: &str, u: &str| ["x", "y", "z"].map(|a| format!("{p}_{a}_{u}"));
        header.extend(xyz("translation", "m"));
        header.extend(["x", "y", "z", "w"].map(|a| format!("quaternion_{a}")));
        header.extend(xyz("rotation_from", "deg"));
        header.extend(xyz("rotation_to", "deg"));
        header.extend(xyz("translation_from", "mm"));
        header.extend(xyz("translation_to", "mm"));
        for h in [
            "angle_deg",
            "distance_mm",
            "rotation_distance",
            "translation_distance",
            "outlier",
            "exceeds",
            "lever_arm_m",
            "h_m",
            "h_uncertainty_m",
            "pitch_verdict",
        ] {
            header.push(h.into());
        }
        for b in &self.bands {
            let l = short(b.ell_m);
            header.push(format!("band_l{l}_low"));
            header.push(format!("band_l{l}_high"));
        }
        let num = data_number;
        let opt = |x: Option<f64>| x.map_or(String::new(), num);
        let rows = self
            .calibrations
            .iter()
            .map(|c| {
                let d = &c.deviation;
                let mut r = vec![c.name.clone(), c.file.clone()];
                r.extend(c.translation_m.map(num));
                r.extend(c.quaternion_xyzw.map(num));
                for v in [
                    d.rotation_from_deg,
                    d.rotation_to_deg,
                    d.translation_from_mm,
                    d.translation_to_mm,
                ] {
                    r.extend(v.map(num));
                }
                r.extend([num(d.angle_deg), num(d.distance_mm)]);
                r.extend([opt(c.rotation_distance), opt(c.translation_distance)]);
                r.extend([c.outlier.to_string(), c.exceeds.to_string()]);
                r.extend([num(c.lever_arm_m), opt(c.h_m), opt(c.h_uncertainty_m)]);
                r.push(c.pitch_verdict.map_or("", PitchVerdict::name).into());
                for b in &c.bands {
                    r.extend(b.map(num));
                }
                r
            })
            .collect();
        Table {
            header,
            rows,
            data_only: true,
            ..Table::default()
        }
    }

    /// The calibrations that name the pair otherwise (`PATH:FROM:TO`), when
    /// any: the set is named by the first file's pair.
    fn pairs_text(&self) -> Option<String> {
        let other: Vec<String> = self
            .calibrations
            .iter()
            .filter(|c| (&c.from, &c.to) != (&self.from, &self.to))
            .map(|c| format!("{} ({} -> {})", c.name, c.from, c.to))
            .collect();
        if other.is_empty() {
            return None;
        }
        let mut named: Vec<String> = other.iter().take(MAX_NAMED).cloned().collect();
        if other.len() > MAX_NAMED {
            named.push(format!("and {} more", other.len() - MAX_NAMED));
        }
        Some(format!(
            "Frame pairs: the set is named by the first file's, {} -> {}; {} name it otherwise: {}.",
            self.from,
            self.to,
            other.len(),
            named.join(", ")
        ))
    }

    fn outlier_text(&self) -> String {
        let o = &self.outliers;
        if !o.tested {
            return format!(
                "Outliers: not tested (the rule needs 3 calibrations or more; {} given).",
                self.count
            );
        }
        let mut s = if o.names.is_empty() {
            "Outliers: none by the rule.".to_string()
        } else {
            let mut named: Vec<String> = o
                .names
                .iter()
                .take(MAX_NAMED)
                .map(|n| {
                    let c = &self.calibrations[self.index_of(n)];
                    let d = |x: Option<f64>| x.map_or("-".into(), |v| fixed(v, 1));
                    format!(
                        "{n} (distance rotation {}, translation {})",
                        d(c.rotation_distance),
                        d(c.translation_distance)
                    )
                })
                .collect();
            if o.names.len() > MAX_NAMED {
                named.push(format!("and {} more", o.names.len() - MAX_NAMED));
            }
            format!("Outliers: {}.", named.join(", "))
        };
        if let (Some(r), Some(t)) = (&o.rotation, &o.translation) {
            s.push_str(&format!(
                " Limits: rotation {}, translation {} (standardised distance).",
                fixed(r.limit, 2),
                fixed(t.limit, 2)
            ));
        }
        if o.few {
            s.push_str(&format!(
                " Few calibrations ({} < {OUTLIER_FEW}): the robust scale is uncertain \
                 (the rule flags about 8 % of clean calibrations at 5, 2 % at 10).",
                self.count
            ));
        }
        s
    }
}

impl Report for SpreadReport {
    fn document(&self) -> Document {
        let mut doc = Document::new();
        doc.push(Block::Headline {
            text: self.headline(),
            good: self.outliers.names.is_empty() && self.exceeded.is_empty(),
        });
        let note = "Mean: chordal L2 rotation mean (scipy Rotation.mean), arithmetic \
                    translation mean in the from-frame. Rotation deviations are \
                    rotation-vector components (deg), not Euler angles.";
        doc.push(Block::Note {
            text: note.into(),
            markdown: Some(note.into()),
        });
        if let Some(text) = self.pairs_text() {
            doc.text(text);
        }
        doc.section("Mean");
        doc.table(self.mean_table());
        doc.section("Spread of the rotation (deg; max: calibration #)");
        doc.table(self.spread_table(true));
        doc.section("Spread of the translation (mm; max: calibration #)");
        doc.table(self.spread_table(false));
        doc.text(self.outlier_text());
        if let Some(w) = &self.without_outliers {
            let t = &w.spread.translation_from_mm;
            let r = &w.spread.rotation_to_deg;
            doc.text(format!(
                "Without the outliers ({}): mean translation {} m, largest deviation {} mm, {} deg.",
                w.calibrations.len(),
                vector(&w.mean.translation_m, metres),
                mm(t.norm_max),
                degrees(r.norm_max)
            ));
        }
        doc.section("Calibrations (deviation from the mean)");
        let shown: Vec<usize> = if self.count <= MAX_SHOWN {
            (0..self.count).collect()
        } else {
            let c = &self.calibrations;
            (0..self.count)
                .filter(|&i| c[i].outlier || c[i].exceeds)
                .collect()
        };
        if !shown.is_empty() {
            doc.table(self.calibration_table(&shown));
        }
        if shown.len() < self.count {
            doc.text(format!(
                "{} more within the rule and the tolerance: every row is in --format csv and json.",
                self.count - shown.len()
            ));
        }
        doc.table(self.data_table());
        doc
    }
}
