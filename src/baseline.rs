//! Baselines of `audit check`: per file, its edges and its checked frame pairs
//! as they were accepted, and the comparison of a new state against one, as
//! typed diagnostics (`new-file`, `new-edge`, `missing-edge`, `drift`,
//! `verdict-changed`).
//!
//! Drift: the translation difference `||d_now - d_base||` (m) and the angle of
//! `R_base^T R_now` (deg, from the quaternions) against the tolerances given.

use crate::diagnostic::{Code, Diagnostic, Error, Location, Result};
use crate::frames::Edge;
use crate::geometry::Transform;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// A baseline: per file (key: the path as checked, `/`-separated), its record.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, Default)]
pub struct Baseline {
    /// Version of this JSON layout; [`read`] accepts only 1.
    pub schema_version: u32,
    /// One record per calibration file that loaded, keyed by its path as
    /// checked (`/`-separated), sorted by path.
    pub files: BTreeMap<String, BaselineFile>,
}

/// One file's record.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, Default)]
pub struct BaselineFile {
    /// Every edge the file yields, each as stored (pose of child in parent).
    pub edges: Vec<BaselineTransform>,
    /// The frame pairs checked in this file: the rig file's `[rig] from -> to`
    /// and each `--pair FROM:TO` whose frames the file has.
    pub pairs: Vec<BaselinePair>,
}

/// A transform as stored: pose of `child` in `parent`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct BaselineTransform {
    /// The frame the pose is expressed in (`from` for a pair).
    pub parent: String,
    /// The frame whose pose it is (`to` for a pair).
    pub child: String,
    /// `d` (m): the origin of `child` in `parent` coordinates.
    pub translation_m: [f64; 3],
    /// `R` as a unit quaternion `[x, y, z, w]`, `w >= 0`.
    pub quaternion_xyzw: [f64; 4],
}

/// A checked frame pair: its transform and verdicts.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct BaselinePair {
    #[serde(flatten)]
    /// The composed transform `from -> to` (flattened into this object:
    /// `parent` is `from`, `child` is `to`).
    pub transform: BaselineTransform,
    /// `||d||` (m) of the composed transform.
    pub lever_arm_m: f64,
    /// The screw kind's JSON name (`identity`, `pure_translation`,
    /// `zero_pitch`, `general`; [`ScrewKind::name`](crate::geometry::se3::ScrewKind::name)).
    pub screw_kind: String,
    /// The screw kind is `zero_pitch` (a rotation with `|h|` within the pitch
    /// tolerance; the identity does not count).
    pub zero_pitch: bool,
    /// An adapted constant metric exists for this pair (identity or zero pitch).
    pub adapted_metric_exists: bool,
}

/// Drift tolerances.
#[derive(Debug, Clone, Copy)]
pub struct Tolerances {
    /// On translations (m).
    pub translation_m: f64,
    /// On rotations (deg).
    pub rotation_deg: f64,
}

impl BaselineTransform {
    /// The stored form of `t` between `parent` and `child`.
    pub fn new(parent: &str, child: &str, t: &Transform) -> Self {
        let d = t.translation();
        BaselineTransform {
            parent: parent.to_string(),
            child: child.to_string(),
            translation_m: [d.x, d.y, d.z],
            quaternion_xyzw: t.quaternion_xyzw(),
        }
    }
    /// The stored form of an edge.
    pub fn of_edge(e: &Edge) -> Self {
        Self::new(&e.parent, &e.child, &e.transform)
    }
}

/// Angle (deg) between two rotations given as quaternions.
fn quat_angle_deg(a: [f64; 4], b: [f64; 4]) -> f64 {
    let dot: f64 = a.iter().zip(b.iter()).map(|(x, y)| x * y).sum();
    let na: f64 = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    let nb: f64 = b.iter().map(|x| x * x).sum::<f64>().sqrt();
    let c = (dot.abs() / (na * nb)).min(1.0);
    (2.0 * c.acos()).to_degrees()
}

/// Read a baseline written by `audit check --write-baseline`.
pub fn read(path: &Path) -> Result<Baseline> {
    let text = crate::input::read_text(
        path,
        crate::tolerances::MAX_BASELINE_FILE_SIZE,
        "the baseline size cap",
    )?;
    let b: Baseline = serde_json::from_str(&text).map_err(|e| {
        Error::new(
            Code::Io,
            format!("expected a baseline written by `audit check --write-baseline`, found: {e}"),
        )
        .in_file(path)
        .at_line(e.line(), Some(e.column()))
    })?;
    if b.schema_version != 1 {
        return Err(Error::new(
            Code::Io,
            format!(
                "expected baseline schema_version 1, found {}",
                b.schema_version
            ),
        )
        .in_file(path));
    }
    Ok(b)
}

fn finding(code: Code, file: &str, message: String) -> Diagnostic {
    Diagnostic::new(code, message).at(&Location::file(file))
}

fn drift(
    what: String,
    now: &BaselineTransform,
    base: &BaselineTransform,
    tol: Tolerances,
    file: &str,
    out: &mut Vec<Diagnostic>,
) {
    let dt = (0..3)
        .map(|k| (now.translation_m[k] - base.translation_m[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    let dr = quat_angle_deg(now.quaternion_xyzw, base.quaternion_xyzw);
    if dt > tol.translation_m || dr > tol.rotation_deg {
        out.push(finding(
            Code::Drift,
            file,
            format!(
                "{what}: moved {dt:.6} m (tolerance {} m) and {dr:.4} deg (tolerance {} deg) since the baseline",
                tol.translation_m, tol.rotation_deg
            ),
        ));
    }
}

fn same_edge(a: &BaselineTransform, b: &BaselineTransform) -> bool {
    a.parent == b.parent && a.child == b.child
}

fn verdict(p: &BaselinePair) -> String {
    format!(
        "screw {}, zero pitch {}, adapted metric {}",
        p.screw_kind,
        p.zero_pitch,
        if p.adapted_metric_exists {
            "exists"
        } else {
            "none"
        }
    )
}

/// Compare one file's record with the baseline's.
pub fn compare_file(
    file: &str,
    now: &BaselineFile,
    base: &BaselineFile,
    tol: Tolerances,
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for b in &base.edges {
        match now.edges.iter().find(|e| same_edge(e, b)) {
            Some(e) => drift(
                format!("edge {} -> {}", b.parent, b.child),
                e,
                b,
                tol,
                file,
                &mut out,
            ),
            None => out.push(finding(
                Code::MissingEdge,
                file,
                format!(
                    "edge {} -> {} is in the baseline but no longer in the file",
                    b.parent, b.child
                ),
            )),
        }
    }
    for e in now
        .edges
        .iter()
        .filter(|e| !base.edges.iter().any(|b| same_edge(e, b)))
    {
        out.push(finding(
            Code::NewEdge,
            file,
            format!(
                "edge {} -> {} is not in the baseline (accept it with --write-baseline)",
                e.parent, e.child
            ),
        ));
    }
    for b in &base.pairs {
        let Some(p) = now
            .pairs
            .iter()
            .find(|p| same_edge(&p.transform, &b.transform))
        else {
            continue;
        };
        let (from, to) = (&b.transform.parent, &b.transform.child);
        drift(
            format!("{from} -> {to}"),
            &p.transform,
            &b.transform,
            tol,
            file,
            &mut out,
        );
        if verdict(p) != verdict(b) {
            out.push(finding(
                Code::VerdictChanged,
                file,
                format!(
                    "{from} -> {to}: verdict changed from ({}) to ({})",
                    verdict(b),
                    verdict(p)
                ),
            ));
        }
    }
    out
}

/// Compare a whole state with a baseline: per file, or `new-file`.
pub fn compare(now: &Baseline, base: &Baseline, tol: Tolerances) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for (file, rec) in &now.files {
        match base.files.get(file) {
            Some(b) => out.extend(compare_file(file, rec, b, tol)),
            None => out.push(finding(
                Code::NewFile,
                file,
                "file is not in the baseline (accept it with --write-baseline)".into(),
            )),
        }
    }
    out
}
