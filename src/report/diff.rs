//! `audit diff OLD NEW`: what changed between two calibrations, per edge and
//! for the `--from` -> `--to` chain when there is one; JSON in
//! `docs/schemas/diff.schema.json`.
//!
//! A change is `|d_new - d_old|` (mm) for a translation and the angle of
//! `R_old^T R_new` (deg) for a rotation, both in the parent frame of the edge
//! (of `from` for the chain). With a chain (`--from/--to`, or the pair a rig
//! file declares) the diff exceeds its tolerance when a common edge or the
//! chain moves by more than `--tolerance`, or when a verdict changes (screw
//! kind, adapted metric, any family); edges only in one file are listed but
//! do not by themselves exceed it (two formats rarely share edges: a URDF
//! against a Kalibr YAML, compared on one chain). Without a chain the whole
//! files are compared: it exceeds when a common edge moves beyond the
//! tolerance or an edge is in one file only (issue 33).

use crate::analysis::Family;
use crate::document::numbers::{fixed, short};
use crate::document::{Document, Report, Table};
use crate::geometry::ScrewKind;
use crate::tolerances::{DEFAULT_DIFF_ROTATION_TOL_DEG, DEFAULT_DIFF_TRANSLATION_TOL_MM};
use serde::Serialize;

/// `schema_version` of the diff JSON: 2 since `from`, `to` and `chain` are
/// null when the whole files are compared (no chain).
pub const DIFF_SCHEMA_VERSION: u32 = 2;

/// A value in OLD and in NEW.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct OldNew<T> {
    /// In OLD.
    pub old: T,
    /// In NEW.
    pub new: T,
}

/// `tolerance`: what counts as a change. `Default`:
/// [`DEFAULT_DIFF_TRANSLATION_TOL_MM`], [`DEFAULT_DIFF_ROTATION_TOL_DEG`].
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct DiffToleranceJson {
    /// On a translation change (mm).
    pub translation_mm: f64,
    /// On a rotation change (deg).
    pub rotation_deg: f64,
}

impl Default for DiffToleranceJson {
    fn default() -> Self {
        DiffToleranceJson {
            translation_mm: DEFAULT_DIFF_TRANSLATION_TOL_MM,
            rotation_deg: DEFAULT_DIFF_ROTATION_TOL_DEG,
        }
    }
}

/// How an edge of one file compares with the other's.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum EdgeStatus {
    /// In both, the same transform (within the duplicate-edge tolerances).
    Unchanged,
    /// In both, a different transform.
    Changed,
    /// Only in NEW.
    Added,
    /// Only in OLD.
    Removed,
}

impl EdgeStatus {
    /// Its name, as the JSON (serde) and the CSV write it.
    pub fn name(self) -> &'static str {
        match self {
            EdgeStatus::Unchanged => "unchanged",
            EdgeStatus::Changed => "changed",
            EdgeStatus::Added => "added",
            EdgeStatus::Removed => "removed",
        }
    }
}

/// `edges[i]`: one edge, as OLD stores it (NEW's when added).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct EdgeDiffJson {
    /// Parent frame.
    pub parent: String,
    /// Child frame.
    pub child: String,
    /// How it compares.
    pub status: EdgeStatus,
    /// NEW stores the edge the other way round (child -> parent); compared
    /// after inverting it.
    pub reversed: bool,
    /// `d_new - d_old` (m); null unless in both.
    pub translation_delta_m: Option<[f64; 3]>,
    /// `|d_new - d_old|` (mm); null unless in both.
    pub translation_change_mm: Option<f64>,
    /// Angle of `R_old^T R_new` (deg); null unless in both.
    pub rotation_change_deg: Option<f64>,
    /// `file:line:col` in OLD; null when only in NEW.
    pub old_place: Option<String>,
    /// `file:line:col` in NEW; null when only in OLD.
    pub new_place: Option<String>,
    /// The change is beyond the tolerance.
    pub exceeds: bool,
    /// The edge is on the `from -> to` chain of OLD or of NEW.
    pub on_chain: bool,
}

/// `chain.bands[i]`: the certificate band at one characteristic length.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct BandDiffJson {
    /// Characteristic length (m).
    pub ell_m: f64,
    /// `[s_min^2, s_max^2]` in OLD and NEW.
    pub band: OldNew<[f64; 2]>,
}

/// `chain.detectors[i]`: one family's verdict in OLD and NEW.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FamilyDiffJson {
    /// The family's JSON name.
    pub family: Family,
    /// Invariant on the rig, in OLD and NEW.
    pub invariant_on_rig: OldNew<bool>,
    /// The verdict differs.
    pub changed: bool,
}

/// `chain`: the composed `from -> to` transform of each file and its analysis.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ChainDiffJson {
    /// `d` (m).
    pub translation_m: OldNew<[f64; 3]>,
    /// `d_new - d_old` (m).
    pub translation_delta_m: [f64; 3],
    /// `|d_new - d_old|` (mm).
    pub translation_change_mm: f64,
    /// Angle of `R_old^T R_new` (deg).
    pub rotation_change_deg: f64,
    /// Rotation angle (deg).
    pub angle_deg: OldNew<f64>,
    /// Lever arm `||d||` (m).
    pub lever_arm_m: OldNew<f64>,
    /// Screw translation `h` (m); null without a rotation.
    pub screw_translation_m: OldNew<Option<f64>>,
    /// `h` changed sign, and both rotations are close enough to a half-turn
    /// that turning through it explains the flip (180 - angle_old + 180 -
    /// angle_new <= the rotation change): the axis `e` flips there, and
    /// `h = e . d` with it, so compare `|h|`.
    pub screw_sign_flip_at_half_turn: bool,
    /// Screw kind.
    pub screw_kind: OldNew<ScrewKind>,
    /// One band per characteristic length.
    pub bands: Vec<BandDiffJson>,
    /// An adapted constant metric exists.
    pub adapted_metric_exists: OldNew<bool>,
    /// One entry per family, in the family table's order.
    pub detectors: Vec<FamilyDiffJson>,
    /// The chain's transform moved beyond the tolerance.
    pub exceeds: bool,
}

/// The diff report.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct DiffReport {
    /// Version of this JSON layout (2: `from`, `to` and `chain` may be null).
    pub schema_version: u32,
    /// OLD, as named on the command line.
    pub old: String,
    /// NEW, as named on the command line.
    pub new: String,
    /// How OLD was read, when not plainly (`--key-old`, `--invert-old`).
    #[serde(skip_serializing_if = "ReadJson::is_plain")]
    pub old_read: ReadJson,
    /// How NEW was read, when not plainly (`--key-new`, `--invert-new`).
    #[serde(skip_serializing_if = "ReadJson::is_plain")]
    pub new_read: ReadJson,
    /// The frame the chain is expressed in; null when the whole files are
    /// compared.
    pub from: Option<String>,
    /// The frame whose pose it is; null with `from`.
    pub to: Option<String>,
    /// What counts as a change.
    pub tolerance: DiffToleranceJson,
    /// The chain in both files; null when the whole files are compared.
    pub chain: Option<ChainDiffJson>,
    /// Every edge of either file: common ones first (OLD's order), then
    /// removed, then added.
    pub edges: Vec<EdgeDiffJson>,
    /// Why the diff exceeds its tolerance, one sentence each; empty when it
    /// does not (exit 0; otherwise exit 1).
    pub exceeded: Vec<String>,
    /// The convention mistakes that reconcile the chain or a changed edge
    /// (`crate::analysis::mistakes`); empty when none does.
    pub mistakes: Vec<crate::report::mistakes::MistakeJson>,
}

/// How one file of a diff was read beyond its format's own rules.
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct ReadJson {
    /// The one key read of a YAML/JSON file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub key: Option<String>,
    /// The numbers were read as the pose of the parent in the child.
    pub inverted: bool,
}

impl ReadJson {
    /// Read as the format says, whole.
    pub fn is_plain(&self) -> bool {
        self.key.is_none() && !self.inverted
    }

    /// ` (key NAME, inverted)`, or nothing when read plainly.
    fn note(&self) -> String {
        let mut parts = Vec::new();
        if let Some(k) = &self.key {
            parts.push(format!("key {k}"));
        }
        if self.inverted {
            parts.push("inverted".to_string());
        }
        if parts.is_empty() {
            String::new()
        } else {
            format!(" ({})", parts.join(", "))
        }
    }
}

fn opt_m(h: Option<f64>) -> String {
    h.map_or("-".into(), |h| fixed(h, 4))
}

fn band(b: [f64; 2]) -> String {
    format!("[{}, {}]", fixed(b[0], 4), fixed(b[1], 4))
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

impl DiffReport {
    fn chain_table(c: &ChainDiffJson) -> Table {
        let d = |o: f64, n: f64, dec: usize| vec![fixed(o, dec), fixed(n, dec), fixed(n - o, dec)];
        let mut rows = vec![
            [
                vec![
                    "translation change (mm)".to_string(),
                    String::new(),
                    String::new(),
                ],
                vec![fixed(c.translation_change_mm, 3)],
            ]
            .concat(),
            [
                vec![
                    "rotation change (deg)".to_string(),
                    String::new(),
                    String::new(),
                ],
                vec![fixed(c.rotation_change_deg, 4)],
            ]
            .concat(),
            [
                vec!["lever arm (m)".to_string()],
                d(c.lever_arm_m.old, c.lever_arm_m.new, 4),
            ]
            .concat(),
            [
                vec!["rotation angle (deg)".to_string()],
                d(c.angle_deg.old, c.angle_deg.new, 3),
            ]
            .concat(),
        ];
        let (ho, hn) = (c.screw_translation_m.old, c.screw_translation_m.new);
        let dh = ho.zip(hn).map_or("-".into(), |(o, n)| {
            if c.screw_sign_flip_at_half_turn {
                format!(
                    "|h| {} (sign flips at the half-turn)",
                    fixed(n.abs() - o.abs(), 4)
                )
            } else {
                fixed(n - o, 4)
            }
        });
        rows.push(vec![
            "screw translation h (m)".into(),
            opt_m(ho),
            opt_m(hn),
            dh,
        ]);
        rows.push(vec![
            "screw kind".into(),
            c.screw_kind.old.label().into(),
            c.screw_kind.new.label().into(),
            changed(c.screw_kind.old != c.screw_kind.new),
        ]);
        for b in &c.bands {
            rows.push(vec![
                format!("band at l = {} m", short(b.ell_m)),
                band(b.band.old),
                band(b.band.new),
                String::new(),
            ]);
        }
        rows.push(vec![
            "adapted metric exists".into(),
            yes(c.adapted_metric_exists.old).into(),
            yes(c.adapted_metric_exists.new).into(),
            changed(c.adapted_metric_exists.old != c.adapted_metric_exists.new),
        ]);
        Table::new(&["quantity", "old", "new", "change"], rows)
    }

    fn family_table(c: &ChainDiffJson) -> Table {
        let rows = c
            .detectors
            .iter()
            .map(|f| {
                vec![
                    f.family.label().to_string(),
                    yes(f.invariant_on_rig.old).into(),
                    yes(f.invariant_on_rig.new).into(),
                    changed(f.changed),
                ]
            })
            .collect();
        Table::new(
            &["family", "invariant (old)", "invariant (new)", "change"],
            rows,
        )
    }

    fn edge_table(&self) -> Option<Table> {
        let rows: Vec<Vec<String>> = self
            .edges
            .iter()
            .filter(|e| {
                e.status == EdgeStatus::Changed
                    || (e.status != EdgeStatus::Unchanged && (e.on_chain || self.chain.is_none()))
            })
            .map(|e| {
                let status = match e.status {
                    EdgeStatus::Changed if e.exceeds => "changed (beyond tolerance)",
                    s => s.name(),
                };
                let mark = if e.on_chain { " (chain)" } else { "" };
                vec![
                    format!("{} -> {}{mark}", e.parent, e.child),
                    status.to_string(),
                    e.translation_change_mm.map_or("-".into(), |x| fixed(x, 3)),
                    e.rotation_change_deg.map_or("-".into(), |x| fixed(x, 4)),
                    e.old_place.clone().unwrap_or_else(|| "-".into()),
                    e.new_place.clone().unwrap_or_else(|| "-".into()),
                ]
            })
            .collect();
        (!rows.is_empty()).then(|| {
            Table::new(
                &[
                    "edge",
                    "status",
                    "translation change (mm)",
                    "rotation change (deg)",
                    "old",
                    "new",
                ],
                rows,
            )
        })
    }

    /// `A -> B` for a chain, `every edge` for whole files.
    fn what(&self) -> String {
        match (&self.from, &self.to) {
            (Some(f), Some(t)) => format!("{f} -> {t}"),
            _ => "every edge".to_string(),
        }
    }

    fn headline(&self) -> String {
        let tol = format!(
            "{} mm, {} deg",
            short(self.tolerance.translation_mm),
            short(self.tolerance.rotation_deg)
        );
        let what = self.what();
        if !self.exceeded.is_empty() {
            let why = self.exceeded.join("; ");
            return match self.chain {
                Some(_) => format!("{what}: {why} beyond the tolerance ({tol})"),
                None => format!("{what}: {why} (tolerance {tol})"),
            };
        }
        match &self.chain {
            Some(c) => format!(
                "{what}: no change beyond the tolerance ({tol}); chain moved {} mm, {} deg",
                fixed(c.translation_change_mm, 3),
                fixed(c.rotation_change_deg, 4)
            ),
            None => format!(
                "{what}: no change beyond the tolerance ({tol}); {} edges in both files",
                self.edges.len()
            ),
        }
    }
}

fn changed(c: bool) -> String {
    if c {
        "changed".into()
    } else {
        String::new()
    }
}

impl Report for DiffReport {
    fn document(&self) -> Document {
        let mut doc = Document::new();
        doc.push(crate::document::Block::Headline {
            text: self.headline(),
            good: self.exceeded.is_empty(),
        });
        doc.text(format!(
            "old: {}{}\nnew: {}{}",
            self.old,
            self.old_read.note(),
            self.new,
            self.new_read.note()
        ));
        if let Some(c) = &self.chain {
            doc.section(format!("Chain {}", self.what()));
            doc.table(Self::chain_table(c));
        }
        if !self.mistakes.is_empty() {
            doc.section("Convention mistake");
            doc.text(crate::report::mistakes::lines(&self.mistakes).join("\n"));
        }
        if let Some(c) = &self.chain {
            doc.section("Detector families");
            doc.table(Self::family_table(c));
        }
        doc.section("Edges");
        let n = |s: EdgeStatus| self.edges.iter().filter(|e| e.status == s).count();
        doc.text(format!(
            "{} unchanged, {} changed, {} removed, {} added",
            n(EdgeStatus::Unchanged),
            n(EdgeStatus::Changed),
            n(EdgeStatus::Removed),
            n(EdgeStatus::Added)
        ));
        if let Some(t) = self.edge_table() {
            doc.table(t);
        }
        let off = self
            .edges
            .iter()
            .filter(|e| matches!(e.status, EdgeStatus::Added | EdgeStatus::Removed) && !e.on_chain)
            .count();
        if off > 0 && self.chain.is_some() {
            doc.text(format!(
                "{off} edges off the chain are in only one file (listed in --format json)"
            ));
        }
        doc.table(self.data_table());
        doc
    }
}
