//! `audit run`: the run's summary report (JSON with its schema,
//! `docs/schemas/run.schema.json`; text and markdown that fit 80 columns),
//! and the per-scan records the run streams: one CSV row or one JSON line
//! (`docs/schemas/run-scan.schema.json`) per scan or pair, written as the
//! scans finish, never held. The timeline picture is `run_timeline`.
//!
//! CSV columns (one number per column, empty where there is none; frame
//! names as the run names them, `scan` for the scan frame):
//! `index, time_s, stamp_ns, frame_id, place, status, reason, cells,
//! nonfinite, points, normals`; for pairs `target_index, target_time_s,
//! source_points, target_points, mean_distance_m, guess_x_m, guess_y_m,
//! guess_z_m, guess_roll_rad, guess_pitch_rad, guess_yaw_rad`; then per frame
//! and family `FAMILY@FRAME.lambda1` .. `lambda6` (ascending),
//! `FAMILY@FRAME.threshold`, `FAMILY@FRAME.count`, and per frame
//! `point_displacement@FRAME.footprint_rx` .. `_tz` (0 or 1).

use super::detector::PoseJson;
use crate::degeneracy::MetricRule;
use crate::document::numbers::{ratio, sci};
use crate::document::{Block, Document, Report, Table};
use crate::geometry::Transform;
use crate::run::frames::{FrameGroup, RunFrame};
use crate::run::scan::{FamilyResult, Outcome, ScanMeta, Settings};
use crate::run::source::{ScanBound, ScanWindow};
use crate::run::summary::{Interval, Summary, Timeline};
use serde::Serialize;

/// What a run's records are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RunUnit {
    /// One record per scan.
    Scans,
    /// One record per pair of scans.
    Pairs,
}

impl RunUnit {
    /// `scans` or `scan pairs`.
    pub fn name(self) -> &'static str {
        match self {
            RunUnit::Scans => "scans",
            RunUnit::Pairs => "scan pairs",
        }
    }

    /// `scan 12 (t = 1.200 s)` or `pair 11 -> 12`.
    pub(crate) fn describe(self, scan: &ScanMeta, target: Option<&ScanMeta>) -> String {
        let t = scan
            .time_s
            .map(|t| format!(" (t = {t:.3} s)"))
            .unwrap_or_default();
        match (self, target) {
            (RunUnit::Pairs, Some(tg)) => {
                format!("pair: scan {} against scan {}{t}", scan.index, tg.index)
            }
            _ => format!("scan {}{t}", scan.index),
        }
    }
}

/// The key of a family in records: the family's JSON name, `l=<l>` for a
/// characteristic length (`l=0.25`).
pub fn family_key(rule: &MetricRule) -> String {
    match rule {
        MetricRule::CharacteristicLength(l) => format!("l={l}"),
        _ => rule.family().name().to_string(),
    }
}

/// A family as the records name it.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FamilyHead {
    /// Its key (`point_displacement`, `l=0.25`).
    pub key: String,
    /// The family (JSON name).
    pub family: &'static str,
    /// Its characteristic length (m), for that family.
    pub ell_m: Option<f64>,
    /// Its eigenvalues are compared per point.
    pub per_point: bool,
}

/// A frame as the records name it.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FrameHead {
    /// Its name (`scan`, a tf frame, a rig id, `lever:<id>`).
    pub name: String,
    /// Where it comes from.
    pub group: FrameGroup,
    /// Its pose in the scan frame, when it does not depend on the scan.
    pub pose: Option<PoseJson>,
    /// `||d||` of that pose (m).
    pub lever_arm_m: Option<f64>,
    /// What defined it.
    pub source: String,
}

/// What every record of a run shares: the unit, the frames, the families.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RunHeader {
    /// Scans or pairs.
    pub unit: RunUnit,
    /// The frames (the scan frame first).
    pub frames: Vec<FrameHead>,
    /// The families, in report order.
    pub families: Vec<FamilyHead>,
}

fn pose_json(t: &Transform) -> PoseJson {
    let d = t.translation();
    PoseJson {
        translation_m: [d.x, d.y, d.z],
        rpy_rad: t.rpy(),
    }
}

impl RunHeader {
    /// The header of a run over `frames` with the families `rules`.
    pub fn new(unit: RunUnit, frames: &[RunFrame], rules: &[MetricRule]) -> Self {
        RunHeader {
            unit,
            frames: frames
                .iter()
                .map(|f| FrameHead {
                    name: f.name.clone(),
                    group: f.group,
                    pose: f.fixed.as_ref().map(pose_json),
                    lever_arm_m: f.fixed.as_ref().map(|t| t.translation().norm()),
                    source: f.source.clone(),
                })
                .collect(),
            families: rules
                .iter()
                .map(|r| FamilyHead {
                    key: family_key(r),
                    family: r.family().name(),
                    ell_m: r.fixed_ell(),
                    per_point: r.family().spec().per_point,
                })
                .collect(),
        }
    }

    /// The frames the timeline draws: the scan frame and the named ones
    /// (rig frames are many: they are counted, not drawn).
    pub fn drawn_frames(&self) -> Vec<usize> {
        (0..self.frames.len())
            .filter(|&i| matches!(self.frames[i].group, FrameGroup::Scan | FrameGroup::Named))
            .collect()
    }

    /// Where point displacement is among the families.
    pub fn point_displacement(&self) -> Option<usize> {
        self.families
            .iter()
            .position(|f| f.family == "point_displacement")
    }

    /// The CSV header (see the module docs).
    pub fn csv_header(&self) -> Vec<String> {
        let mut h: Vec<String> = COMMON.iter().map(|s| s.to_string()).collect();
        if self.unit == RunUnit::Pairs {
            h.extend(PAIR.iter().map(|s| s.to_string()));
        }
        for f in &self.frames {
            for k in &self.families {
                for j in 1..=6 {
                    h.push(format!("{}@{}.lambda{j}", k.key, f.name));
                }
                h.push(format!("{}@{}.threshold", k.key, f.name));
                h.push(format!("{}@{}.count", k.key, f.name));
            }
            for a in AXES {
                h.push(format!("point_displacement@{}.footprint_{a}", f.name));
            }
        }
        h
    }

    /// One CSV row of `o` (see the module docs).
    pub fn csv_row(&self, o: &Outcome) -> Vec<String> {
        let s = &o.scan;
        let opt = |x: Option<String>| x.unwrap_or_default();
        let mut r = vec![
            s.index.to_string(),
            opt(s.time_s.map(num)),
            opt(s.stamp_ns.map(|t| t.to_string())),
            s.frame_id.clone().unwrap_or_default(),
            s.place.clone(),
            if o.skipped.is_some() { "skipped" } else { "ok" }.into(),
            opt(o.skipped.as_ref().map(|(w, _)| w.name().to_string())),
            opt(o.cells.map(|c| c.to_string())),
            opt(o.nonfinite.map(|c| c.to_string())),
            if o.skipped.is_some() {
                String::new()
            } else {
                o.points.to_string()
            },
            opt(o.normals.map(|n| format!("{n:?}").to_lowercase())),
        ];
        if self.unit == RunUnit::Pairs {
            let t = o.target.as_ref();
            r.push(opt(t.map(|t| t.index.to_string())));
            r.push(opt(t.and_then(|t| t.time_s).map(num)));
            let p = o.pair.as_ref();
            r.push(opt(p.map(|p| p.stats.source.to_string())));
            r.push(opt(p.map(|p| p.stats.target.to_string())));
            r.push(opt(p.map(|p| num(p.stats.mean_distance))));
            let g = p.map(|p| pose_json(&p.guess));
            for k in 0..3 {
                r.push(opt(g.as_ref().map(|g| num(g.translation_m[k]))));
            }
            for k in 0..3 {
                r.push(opt(g.as_ref().map(|g| num(g.rpy_rad[k]))));
            }
        }
        let pd = self.point_displacement();
        for (f, _) in self.frames.iter().enumerate() {
            let fr = o.frames.get(f).and_then(Option::as_ref);
            for k in 0..self.families.len() {
                let fam = fr.and_then(|v| v.get(k));
                let e = fam.and_then(|x| x.eigenvalues);
                for j in 0..6 {
                    r.push(opt(e.map(|e| num(e[j]))));
                }
                r.push(opt(fam
                    .filter(|x| x.count.is_some())
                    .map(|x| num(x.threshold))));
                r.push(opt(fam.and_then(|x| x.count).map(|c| c.to_string())));
            }
            let fp = fr
                .and_then(|v| pd.and_then(|k| v.get(k)))
                .and_then(|x| x.footprint);
            for a in 0..6 {
                r.push(opt(fp.map(|f| u8::from(f[a]).to_string())));
            }
        }
        r
    }

    /// One JSON line of `o` (`docs/schemas/run-scan.schema.json`).
    pub fn json_line(&self, o: &Outcome) -> ScanRecord {
        let s = &o.scan;
        ScanRecord {
            schema_version: crate::document::SCHEMA_VERSION,
            unit: self.unit,
            index: s.index,
            time_s: s.time_s,
            stamp_ns: s.stamp_ns.and_then(|t| i64::try_from(t).ok()),
            frame_id: s.frame_id.clone(),
            place: s.place.clone(),
            status: if o.skipped.is_some() { "skipped" } else { "ok" },
            reason: o.skipped.as_ref().map(|(w, _)| w.name()),
            message: o.skipped.as_ref().map(|(_, m)| m.clone()),
            cells: o.cells,
            nonfinite: o.nonfinite,
            points: o.skipped.is_none().then_some(o.points),
            normals: o.normals.map(|n| format!("{n:?}").to_lowercase()),
            pair: o.pair.as_ref().map(|p| PairRecord {
                target_index: o.target.as_ref().map_or(0, |t| t.index),
                target_time_s: o.target.as_ref().and_then(|t| t.time_s),
                correspondences: p.stats.matched,
                source_points: p.stats.source,
                target_points: p.stats.target,
                mean_distance_m: p.stats.mean_distance,
                initial_guess: pose_json(&p.guess),
            }),
            frames: self
                .frames
                .iter()
                .enumerate()
                .map(|(f, h)| FrameRecord {
                    frame: h.name.clone(),
                    families: o.frames.get(f).and_then(Option::as_ref).map(|v| {
                        v.iter()
                            .zip(&self.families)
                            .map(|(x, k)| FamilyRecord::of(&k.key, x))
                            .collect()
                    }),
                })
                .collect(),
            warnings: o.warnings.iter().map(|w| w.message.clone()).collect(),
        }
    }
}

const COMMON: [&str; 11] = [
    "index",
    "time_s",
    "stamp_ns",
    "frame_id",
    "place",
    "status",
    "reason",
    "cells",
    "nonfinite",
    "points",
    "normals",
];
const PAIR: [&str; 11] = [
    "target_index",
    "target_time_s",
    "source_points",
    "target_points",
    "mean_distance_m",
    "guess_x_m",
    "guess_y_m",
    "guess_z_m",
    "guess_roll_rad",
    "guess_pitch_rad",
    "guess_yaw_rad",
];
const AXES: [&str; 6] = ["rx", "ry", "rz", "tx", "ty", "tz"];

/// A number for CSV: every digit (shortest round trip), exponent form for
/// the very small and very large.
fn num(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Where a run's records go as the scans finish.
pub trait RunSink {
    /// Before the first record.
    fn begin(&mut self, header: &RunHeader) -> crate::diagnostic::Result<()>;
    /// One record, in run order.
    fn outcome(&mut self, header: &RunHeader, o: &Outcome) -> crate::diagnostic::Result<()>;
    /// The run's frames and transforms, before [`begin`](RunSink::begin)
    /// (`--format mcap` draws them).
    fn frames(
        &mut self,
        _frames: &[crate::run::frames::RunFrame],
        _graph: Option<&crate::frames::FrameGraph>,
    ) -> crate::diagnostic::Result<()> {
        Ok(())
    }
}

/// One JSON line: a scan or a pair.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ScanRecord {
    /// Version of this layout (1).
    pub schema_version: u32,
    /// Scans or pairs.
    pub unit: RunUnit,
    /// The scan's place in the run (a pair's source).
    pub index: usize,
    /// Seconds after the run's first scan.
    pub time_s: Option<f64>,
    /// `header.stamp` (ns).
    pub stamp_ns: Option<i64>,
    /// The scan frame.
    pub frame_id: Option<String>,
    /// Where in the file, or the file.
    pub place: String,
    /// `ok` or `skipped`.
    pub status: &'static str,
    /// Why it was skipped.
    pub reason: Option<&'static str>,
    /// The reason's message.
    pub message: Option<String>,
    /// Cells read.
    pub cells: Option<usize>,
    /// Cells dropped as non-finite.
    pub nonfinite: Option<usize>,
    /// Points in `H` (a pair's correspondences).
    pub points: Option<usize>,
    /// `fields` or `estimated`.
    pub normals: Option<String>,
    /// A pair's matching.
    pub pair: Option<PairRecord>,
    /// Every frame of the run, in the header's order.
    pub frames: Vec<FrameRecord>,
    /// This scan's warnings.
    pub warnings: Vec<String>,
}

/// A pair's matching in a JSON line.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct PairRecord {
    /// The target scan's index.
    pub target_index: usize,
    /// Its time.
    pub target_time_s: Option<f64>,
    /// Source points paired within the gate.
    pub correspondences: usize,
    /// Source points searched.
    pub source_points: usize,
    /// Target points with normals.
    pub target_points: usize,
    /// Mean distance of the pairs (m).
    pub mean_distance_m: f64,
    /// Pose of the source frame in the target frame.
    pub initial_guess: PoseJson,
}

/// One frame of a JSON line.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FrameRecord {
    /// The frame's name.
    pub frame: String,
    /// Every family (null: the scan's transforms do not name the frame).
    pub families: Option<Vec<FamilyRecord>>,
}

/// One family in one frame of a JSON line.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FamilyRecord {
    /// The family's key.
    pub family: String,
    /// Eigenvalues, ascending.
    pub eigenvalues: Option<[f64; 6]>,
    /// Threshold on them.
    pub threshold: f64,
    /// Degenerate directions.
    pub degenerate_count: Option<usize>,
    /// Per-axis footprint (rot x y z, trans x y z).
    pub footprint: Option<[bool; 6]>,
    /// Why there is no answer.
    pub error: Option<String>,
}

impl FamilyRecord {
    fn of(key: &str, x: &FamilyResult) -> Self {
        FamilyRecord {
            family: key.to_string(),
            eigenvalues: x.eigenvalues,
            threshold: x.threshold,
            degenerate_count: x.count,
            footprint: x.footprint,
            error: x.error.clone(),
        }
    }
}

/// What the report says besides the summary.
pub struct RunContext<'a> {
    /// What was read (`run.mcap, topic /points`).
    pub source: String,
    /// The topic.
    pub topic: Option<String>,
    /// Where the poses came from.
    pub poses: Option<String>,
    /// How the scans were processed.
    pub settings: &'a Settings,
    /// Pairs `step` apart.
    pub pair_step: Option<usize>,
    /// Which scans.
    pub window: ScanWindow,
    /// What stopped the read.
    pub damage: Option<String>,
}

/// How the run was processed, in the report.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RunSettingsJson {
    /// Voxel edge (m) for estimated normals (null: none).
    pub voxel_m: Option<f64>,
    /// Normal radius (m).
    pub normal_radius_m: f64,
    /// Fewest neighbours for a normal.
    pub min_neighbours: usize,
    /// At most this many neighbours.
    pub knn: Option<usize>,
    /// Normals estimated even where the scans have them.
    pub estimate_normals: bool,
    /// Pair gate (m).
    pub gate_m: f64,
    /// Point-displacement threshold.
    pub tau: f64,
    /// Pairs `step` apart (null: single scans).
    pub pair_step: Option<usize>,
    /// Every `every`-th scan.
    pub every: usize,
    /// First scan kept (`12` or `1.5s`).
    pub start: Option<String>,
    /// First scan no longer kept.
    pub end: Option<String>,
}

/// Scans left out for one reason.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SkipJson {
    /// The reason (`invalid-cloud`).
    pub reason: &'static str,
    /// How many.
    pub count: usize,
    /// The first one's message.
    pub first_message: String,
    /// Their indices (at most 1000).
    pub indices: Vec<usize>,
}

/// A degenerate interval.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct IntervalJson {
    /// First scan.
    pub start_index: usize,
    /// Last scan.
    pub end_index: usize,
    /// Their times (s).
    pub start_s: Option<f64>,
    /// The last scan's time.
    pub end_s: Option<f64>,
    /// Scans in it.
    pub scans: usize,
    /// Smallest `lambda_min / threshold` in it.
    pub worst_ratio: f64,
    /// Where.
    pub worst_index: usize,
}

impl IntervalJson {
    pub(crate) fn of(i: &Interval) -> Self {
        IntervalJson {
            start_index: i.start,
            end_index: i.end,
            start_s: i.start_s,
            end_s: i.end_s,
            scans: i.scans,
            worst_ratio: i.worst_margin,
            worst_index: i.worst_at,
        }
    }
}

/// One family in one frame over the run.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct DegenerateJson {
    /// The family's key.
    pub family: String,
    /// The frame.
    pub frame: String,
    /// Scans with an answer.
    pub analysed: usize,
    /// Scans declared degenerate.
    pub degenerate: usize,
    /// Intervals in all.
    pub interval_count: usize,
    /// The intervals (at most 1000).
    pub intervals: Vec<IntervalJson>,
    /// The longest.
    pub longest: Option<IntervalJson>,
}

/// Label changes of one family in one body frame (or a group of them).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ChangesJson {
    /// The family's key.
    pub family: String,
    /// The frame (or the group: `named`, `rig`, `lever`).
    pub frame: String,
    /// Frames counted (1 for a frame).
    pub frames: usize,
    /// Scans (times frames) compared.
    pub compared: usize,
    /// The decision changed.
    pub decision: usize,
    /// The count changed.
    pub count: usize,
    /// The footprint changed.
    pub footprint: usize,
    /// Where the decision changed (a frame's; at most 1000).
    pub decision_at: Vec<usize>,
}

/// `audit run`'s summary.
#[derive(Debug, Clone, Serialize)]
pub struct RunReport {
    /// Version of this layout (1).
    pub schema_version: u32,
    /// What was read.
    pub source: String,
    /// The topic (bags).
    pub topic: Option<String>,
    /// Scans or pairs.
    pub unit: RunUnit,
    /// Where the pairs' poses came from.
    pub poses: Option<String>,
    /// How the scans were processed.
    pub settings: RunSettingsJson,
    /// The frames (the scan frame first).
    pub frames: Vec<FrameHead>,
    /// The families.
    pub families: Vec<FamilyHead>,
    /// Records read.
    pub read: usize,
    /// Records analysed.
    pub analysed: usize,
    /// Records analysed where some frame was unknown to the scan's transforms.
    pub frames_missing: usize,
    /// Records skipped, by reason.
    pub skipped: Vec<SkipJson>,
    /// First and last time (s).
    pub span_s: Option<[f64; 2]>,
    /// Per family and frame.
    pub degenerate: Vec<DegenerateJson>,
    /// Per family and body frame: changes against the scan frame.
    pub label_changes: Vec<ChangesJson>,
    /// The same summed over each group of frames.
    pub label_changes_by_group: Vec<ChangesJson>,
    /// Largest relative change of the point-displacement eigenvalues
    /// between the scan frame and a body frame.
    pub point_displacement_max_relative_change: f64,
    /// What stopped the read early.
    pub damage: Option<String>,
    /// The timeline's data (the SVG).
    #[serde(skip)]
    pub(crate) timeline: Timeline,
    /// Intervals of the scan frame, per family (the SVG's shading).
    #[serde(skip)]
    pub(crate) shading: Vec<Vec<Interval>>,
    /// Indices of the drawn frames.
    #[serde(skip)]
    pub(crate) drawn: Vec<usize>,
}

fn bound(b: Option<ScanBound>) -> Option<String> {
    b.map(|b| match b {
        ScanBound::Index(i) => i.to_string(),
        ScanBound::Seconds(s) => format!("{s}s"),
    })
}

impl RunReport {
    /// The report of a run: its header, summary and context.
    pub(crate) fn new(h: &RunHeader, s: &Summary, c: RunContext) -> Self {
        let st = c.settings;
        let settings = RunSettingsJson {
            voxel_m: st.voxel,
            normal_radius_m: st.normals.radius,
            min_neighbours: st.normals.min_neighbours,
            knn: st.normals.knn,
            estimate_normals: st.estimate,
            gate_m: st.gate,
            tau: st.tau,
            pair_step: c.pair_step,
            every: c.window.every,
            start: bound(c.window.start),
            end: bound(c.window.end),
        };
        let skipped = s
            .skipped
            .iter()
            .map(|(w, t)| SkipJson {
                reason: w.name(),
                count: t.count,
                first_message: t.first_message.clone(),
                indices: t.indices.clone(),
            })
            .collect();
        let mut degenerate = Vec::new();
        for (f, fh) in h.frames.iter().enumerate() {
            for (k, kh) in h.families.iter().enumerate() {
                let d = &s.degenerate[f][k];
                degenerate.push(DegenerateJson {
                    family: kh.key.clone(),
                    frame: fh.name.clone(),
                    analysed: d.analysed,
                    degenerate: d.scans,
                    interval_count: d.interval_count,
                    intervals: d.intervals.iter().map(IntervalJson::of).collect(),
                    longest: d.longest.as_ref().map(IntervalJson::of),
                });
            }
        }
        let (label_changes, label_changes_by_group) = changes(h, s);
        RunReport {
            schema_version: crate::document::SCHEMA_VERSION,
            source: c.source,
            topic: c.topic,
            unit: h.unit,
            poses: c.poses,
            settings,
            frames: h.frames.clone(),
            families: h.families.clone(),
            read: s.read,
            analysed: s.analysed,
            frames_missing: s.frames_missing,
            skipped,
            span_s: s.span_s.map(|(a, b)| [a, b]),
            degenerate,
            label_changes,
            label_changes_by_group,
            point_displacement_max_relative_change: s.point_displacement_change,
            damage: c.damage,
            timeline: s.timeline.clone(),
            shading: s.degenerate[0]
                .iter()
                .map(|d| d.intervals.clone())
                .collect(),
            drawn: h.drawn_frames(),
        }
    }

    /// The degenerate entry of a family in a frame.
    pub fn degenerate_in(&self, family: &str, frame: &str) -> Option<&DegenerateJson> {
        self.degenerate
            .iter()
            .find(|d| d.family == family && d.frame == frame)
    }
}

/// Per body frame and per group of frames.
fn changes(h: &RunHeader, s: &Summary) -> (Vec<ChangesJson>, Vec<ChangesJson>) {
    let mut per = Vec::new();
    let mut groups: Vec<ChangesJson> = Vec::new();
    for (f, fh) in h.frames.iter().enumerate().skip(1) {
        for (k, kh) in h.families.iter().enumerate() {
            let c = &s.changes[f][k];
            per.push(ChangesJson {
                family: kh.key.clone(),
                frame: fh.name.clone(),
                frames: 1,
                compared: c.compared,
                decision: c.decision,
                count: c.count,
                footprint: c.footprint,
                decision_at: c.decision_at.clone(),
            });
            let g = fh.group.name();
            match groups
                .iter_mut()
                .find(|x| x.family == kh.key && x.frame == g)
            {
                Some(x) => {
                    x.frames += 1;
                    x.compared += c.compared;
                    x.decision += c.decision;
                    x.count += c.count;
                    x.footprint += c.footprint;
                }
                None => groups.push(ChangesJson {
                    family: kh.key.clone(),
                    frame: g.to_string(),
                    frames: 1,
                    compared: c.compared,
                    decision: c.decision,
                    count: c.count,
                    footprint: c.footprint,
                    decision_at: Vec::new(),
                }),
            }
        }
    }
    (per, groups)
}

/// A family's short name for tables (`l=0.25`, `point displacement`).
fn label(key: &str) -> String {
    if key.starts_with("l=") {
        key.to_string()
    } else {
        key.replace('_', " ").replace("jacobi", "Jacobi")
    }
}

/// `1.200-3.400 s` or `scans 12-34`.
fn span(i: &IntervalJson) -> String {
    match (i.start_s, i.end_s) {
        (Some(a), Some(b)) => format!("{a:.3}-{b:.3} s"),
        _ => format!("scans {}-{}", i.start_index, i.end_index),
    }
}

impl RunReport {
    fn headline(&self) -> String {
        let n = self.unit.name();
        let pd = self.degenerate_in("point_displacement", "scan");
        let deg = match pd {
            Some(d) if d.degenerate > 0 => {
                let l = d.longest.as_ref().map(span).unwrap_or_default();
                format!(
                    "point displacement degenerate in {} ({} interval{}, longest {l})",
                    d.degenerate,
                    d.interval_count,
                    if d.interval_count == 1 { "" } else { "s" }
                )
            }
            _ => "point displacement: nothing degenerate".into(),
        };
        let flips: Vec<String> = self
            .label_changes_by_group
            .iter()
            .filter(|c| c.decision > 0)
            .map(|c| label(&c.family))
            .fold(Vec::new(), |mut v, x| {
                if !v.contains(&x) {
                    v.push(x);
                }
                v
            });
        let changes = if flips.is_empty() {
            "no body frame changes a decision".to_string()
        } else {
            format!("a body frame changes the decision of {}", flips.join(", "))
        };
        format!(
            "{} {n} read, {} analysed; {deg}; {changes}",
            self.read, self.analysed
        )
    }
}

impl Report for RunReport {
    fn document(&self) -> Document {
        let mut doc = Document::new();
        doc.push(Block::Headline {
            text: self.headline(),
            good: self.label_changes_by_group.iter().all(|c| c.decision == 0),
        });
        doc.text(format!(
            "{}{}",
            self.source,
            self.poses
                .as_ref()
                .map(|p| format!("; poses: {p}"))
                .unwrap_or_default()
        ));
        if let Some(d) = &self.damage {
            doc.text(format!("read stopped early: {d}"));
        }
        if !self.skipped.is_empty() {
            doc.section(format!("Skipped {}", self.unit.name()));
            let rows = self
                .skipped
                .iter()
                .map(|s| {
                    vec![
                        s.reason.to_string(),
                        s.count.to_string(),
                        s.indices.first().map_or(String::new(), |i| i.to_string()),
                        s.first_message.clone(),
                    ]
                })
                .collect();
            doc.table(
                Table::new(&["reason", "count", "first", "first message"], rows).compact(&[3]),
            );
        }
        doc.section("Degenerate in the scan frame");
        let rows = self
            .degenerate
            .iter()
            .filter(|d| d.frame == "scan")
            .map(|d| {
                let l = d.longest.as_ref();
                vec![
                    label(&d.family),
                    format!("{}/{}", d.degenerate, d.analysed),
                    d.interval_count.to_string(),
                    l.map(span).unwrap_or_else(|| "-".into()),
                    l.map(|i| ratio(i.worst_ratio))
                        .unwrap_or_else(|| "-".into()),
                ]
            })
            .collect();
        doc.table(Table::new(
            &["family", "degenerate", "intervals", "longest", "min l/thr"],
            rows,
        ));
        self.changes_section(&mut doc);
        doc.push(Block::Note {
            text: format!(
                "point displacement eigenvalues: largest relative change between frames {} (frame-invariant: a body frame changes none of its labels)",
                sci(self.point_displacement_max_relative_change, 1)
            ),
            markdown: None,
        });
        doc
    }
}

impl RunReport {
    fn changes_section(&self, doc: &mut Document) {
        if self.frames.len() < 2 {
            doc.push(Block::Note {
                text: "no body frame: --frame NAME, --all-frames, --rig-frames PATH".into(),
                markdown: None,
            });
            return;
        }
        doc.section("Label changes against the scan frame");
        let rows: Vec<Vec<String>> = self
            .label_changes_by_group
            .iter()
            .map(|c| {
                vec![
                    label(&c.family),
                    format!("{} ({})", c.frame, c.frames),
                    c.compared.to_string(),
                    c.decision.to_string(),
                    c.count.to_string(),
                    c.footprint.to_string(),
                ]
            })
            .collect();
        doc.table(Table::new(
            &[
                "family",
                "frames",
                "compared",
                "decision",
                "count",
                "footprint",
            ],
            rows,
        ));
        let flips: Vec<Vec<String>> = self
            .label_changes
            .iter()
            .filter(|c| c.decision > 0)
            .map(|c| {
                let at: Vec<String> = c.decision_at.iter().take(8).map(usize::to_string).collect();
                let more = if c.decision > 8 { ", ..." } else { "" };
                vec![
                    label(&c.family),
                    c.frame.clone(),
                    c.decision.to_string(),
                    format!("{}{more}", at.join(", ")),
                ]
            })
            .collect();
        if !flips.is_empty() {
            doc.section("Decision changes by frame");
            doc.table(
                Table::new(&["family", "frame", "changes", "where (index)"], flips).compact(&[3]),
            );
        }
    }
}
