//! Baselines of `audit check`: per file, its edges and its checked frame pairs
//! as they were accepted, and the comparison of a new state against one, as
//! typed diagnostics (`new-file`, `new-edge`, `missing-edge`, `removed-file`,
//! `pair-changed`, `drift`, `verdict-changed`).
//!
//! Keys: a file's path relative to the baseline's directory, normalised (no
//! `.`, no doubled `/`, symlinks resolved while they stay inside the checked
//! root), `/`-separated; bytes that are not UTF-8 and `%` itself are written
//! `%XX` ([`encode_key`](key::encode_key)), so that every file name has its
//! own key and the key gives the path back ([`decode_key`]).
//!
//! Drift: the translation difference `||d_now - d_base||` (m) and the angle of
//! `R_base^T R_now` (deg, from the quaternions) against the tolerances given.

use crate::analysis::mistakes::{explain, MistakeTol};
use crate::diagnostic::{Code, Diagnostic, Error, Location, Result};
use crate::frames::ValuesAt;
use crate::geometry::se3::{QuatOrder, Transform};
use crate::tolerances::{DEFAULT_MAX_ROTATION_DRIFT_DEG, DEFAULT_MAX_TRANSLATION_DRIFT};
use std::collections::BTreeMap;
use std::path::Path;

mod key;
mod lock;
mod record;
pub mod store;
pub mod stream;

pub use key::{decode_key, key_in};
pub use lock::{lock_for_write, WriteLock};
pub use record::{BaselineFile, BaselinePair, BaselineTransform};
pub use store::Store;

/// How far a transform may drift from its baseline before `check` reports
/// it. `Default`: [`DEFAULT_MAX_TRANSLATION_DRIFT`] and
/// [`DEFAULT_MAX_ROTATION_DRIFT_DEG`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriftTolerances {
    /// On translations (m).
    pub translation_m: f64,
    /// On rotations (deg).
    pub rotation_deg: f64,
}

impl Default for DriftTolerances {
    fn default() -> Self {
        DriftTolerances {
            translation_m: DEFAULT_MAX_TRANSLATION_DRIFT,
            rotation_deg: DEFAULT_MAX_ROTATION_DRIFT_DEG,
        }
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

/// Whether `path` holds an `audit check` baseline (a `.json` file whose top
/// level is an object with `schema_version` and `files`): a directory walk
/// skips it, so that a baseline kept beside the calibrations is not read as one.
pub fn is_baseline_file(path: &Path) -> bool {
    if !path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        return false;
    }
    stream::looks_like_baseline(path)
}

/// Read a baseline written by `audit check --write-baseline` into a compact
/// [`Store`] (a fleet's baseline held at about 200 bytes per file). Refused
/// (an error naming the entry, exit 2): not JSON, a `schema_version` other
/// than 1, an entry with a missing or mistyped field, a non-finite number,
/// or a quaternion that is not unit (a zero quaternion would switch the
/// rotation drift check off).
pub fn read_store(path: &Path) -> Result<Store> {
    let mut store = Store::new();
    stream::read_each(path, |key, rec| store.insert(&key, &rec))?;
    refuse_twice(path, store.finish())?;
    Ok(store)
}

/// A key given twice is refused: which record would count is not for a
/// gate to guess.
fn refuse_twice(path: &Path, key: Option<String>) -> Result<()> {
    match key {
        Some(k) => Err(Error::invalid(format!(
            "baseline entry files[{k:?}]: given twice, expected each file once (rewrite the baseline with --write-baseline)"
        ))
        .in_file(path)),
        None => Ok(()),
    }
}

/// Where each edge and pair of a checked file is written: `(parent, child)`
/// (`(from, to)` for a pair) to its location and where its numbers are (a
/// pair's: its edge's, when it is one edge).
pub type Locations = BTreeMap<(String, String), (Location, ValuesAt)>;

/// One checked file: how findings name it, its record, where its values are.
#[derive(Debug, Clone)]
pub struct CheckedFile<'a> {
    /// The path as checked (findings name it).
    pub path: &'a Path,
    /// Its current record.
    pub record: &'a BaselineFile,
    /// Where its edges and pairs are written.
    pub locations: &'a Locations,
}

impl CheckedFile<'_> {
    fn at(&self, a: &str, b: &str) -> Location {
        self.located(a, b, |(l, _)| l.clone())
    }

    /// Where the translation's numbers (`translation`) or the rotation's of
    /// `a -> b` are written; the edge's own location where not known.
    fn at_value(&self, a: &str, b: &str, translation: bool) -> Location {
        self.located(a, b, |(l, v)| v.locate(l, translation))
    }

    /// The entry of `a -> b` made a location by `pick`, in this file.
    fn located(
        &self,
        a: &str,
        b: &str,
        pick: impl Fn(&(Location, ValuesAt)) -> Location,
    ) -> Location {
        let mut l = self
            .locations
            .get(&(a.to_string(), b.to_string()))
            .map(pick)
            .unwrap_or_default();
        l.file = Some(self.path.into());
        l
    }
}

fn mm(x: f64) -> String {
    format!("{:.3} mm", x * 1e3)
}

fn vec_mm(v: [f64; 3]) -> String {
    format!(
        "[{:.3}, {:.3}, {:.3}] mm",
        v[0] * 1e3,
        v[1] * 1e3,
        v[2] * 1e3
    )
}

/// The drift finding of one transform, if it moved beyond a tolerance: old ->
/// new translation (mm) and the rotation angle between them (deg), each with
/// its tolerance; located where the translation's numbers are written when
/// the translation moved beyond its tolerance, else the rotation's.
fn drift(
    what: String,
    now: &BaselineTransform,
    base: &BaselineTransform,
    tol: DriftTolerances,
    file: &CheckedFile,
) -> Option<Diagnostic> {
    let dt = (0..3)
        .map(|k| (now.translation_m[k] - base.translation_m[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    let dr = quat_angle_deg(now.quaternion_xyzw, base.quaternion_xyzw);
    let (over_t, over_r) = (dt > tol.translation_m, dr > tol.rotation_deg);
    if !over_t && !over_r {
        return None;
    }
    let exceeded = match (over_t, over_r) {
        (true, true) => "both tolerances",
        (true, false) => "the translation tolerance",
        _ => "the rotation tolerance",
    };
    let mistake = mistake(base, now, tol).map_or(String::new(), |s| format!("; {s}"));
    Some(
        Diagnostic::new(
            Code::Drift,
            format!(
                "{what} drifted since the baseline beyond {exceeded}: translation {} -> {} moved {} (tolerance {}); rotation moved {dr:.4} deg (tolerance {} deg); quaternion_xyzw {:?} -> {:?}",
                vec_mm(base.translation_m),
                vec_mm(now.translation_m),
                mm(dt),
                mm(tol.translation_m),
                tol.rotation_deg,
                round6(base.quaternion_xyzw),
                round6(now.quaternion_xyzw),
            ) + &mistake,
        )
        .at(&file.at_value(&now.parent, &now.child, over_t)),
    )
}

/// The convention mistake that maps the baseline onto the file now within
/// the drift tolerances (`crate::analysis::mistakes`, issue 30), as a
/// sentence; `None` when none does (a recalibration, not a mistake).
fn mistake(
    base: &BaselineTransform,
    now: &BaselineTransform,
    tol: DriftTolerances,
) -> Option<String> {
    let read = |t: &BaselineTransform| {
        Transform::from_quaternion(
            t.quaternion_xyzw,
            QuatOrder::Xyzw,
            t.translation_m,
            &mut Vec::new(),
        )
        .ok()
    };
    let tol = MistakeTol {
        translation_mm: tol.translation_m * 1e3,
        rotation_deg: tol.rotation_deg,
    };
    explain(&read(base)?, &read(now)?, &tol).sentence("the baseline", "the file")
}

fn round6(q: [f64; 4]) -> [f64; 4] {
    q.map(|x| (x * 1e6).round() / 1e6 + 0.0)
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

fn finding(code: Code, at: Location, message: String) -> Diagnostic {
    Diagnostic::new(code, message).at(&at)
}

/// Compare one file's edges with the baseline's.
fn compare_edges(
    now: &CheckedFile,
    base: &BaselineFile,
    tol: DriftTolerances,
    out: &mut Vec<Diagnostic>,
) {
    for b in &base.edges {
        match now.record.edges.iter().find(|e| same_edge(e, b)) {
            Some(e) => out.extend(drift(
                format!("edge {} -> {}", b.parent, b.child),
                e,
                b,
                tol,
                now,
            )),
            None => out.push(finding(
                Code::MissingEdge,
                Location::file(now.path),
                format!(
                    "edge {} -> {} is in the baseline but no longer in the file",
                    b.parent, b.child
                ),
            )),
        }
    }
    for e in now
        .record
        .edges
        .iter()
        .filter(|e| !base.edges.iter().any(|b| same_edge(e, b)))
    {
        out.push(finding(
            Code::NewEdge,
            now.at(&e.parent, &e.child),
            format!(
                "edge {} -> {} is not in the baseline (accept it with --write-baseline)",
                e.parent, e.child
            ),
        ));
    }
}

/// A baseline pair no longer checked: `pair-changed`, naming the pair the
/// file declares now when there is one.
fn pair_gone(now: &CheckedFile, base: &BaselineFile, b: &BaselinePair) -> Diagnostic {
    let (from, to) = (&b.transform.parent, &b.transform.child);
    let replacement = now.record.pairs.iter().find(|p| {
        p.declared == b.declared
            && !base
                .pairs
                .iter()
                .any(|q| same_edge(&q.transform, &p.transform))
    });
    match replacement {
        Some(p) => finding(
            Code::PairChanged,
            now.at(&p.transform.parent, &p.transform.child),
            format!(
                "the checked frame pair changed from {from} -> {to} (baseline) to {} -> {} (now): the old pair is no longer compared; accept with --write-baseline",
                p.transform.parent, p.transform.child
            ),
        ),
        None => finding(
            Code::PairChanged,
            Location::file(now.path),
            format!(
                "frame pair {from} -> {to} is in the baseline but no longer checked in this file"
            ),
        ),
    }
}

/// Compare one file's record with the baseline's.
pub fn compare_file(
    now: &CheckedFile,
    base: &BaselineFile,
    tol: DriftTolerances,
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    compare_edges(now, base, tol, &mut out);
    for b in &base.pairs {
        let Some(p) = now
            .record
            .pairs
            .iter()
            .find(|p| same_edge(&p.transform, &b.transform))
        else {
            out.push(pair_gone(now, base, b));
            continue;
        };
        let (from, to) = (&b.transform.parent, &b.transform.child);
        let at = now.at(from, to);
        out.extend(drift(
            format!("{from} -> {to}"),
            &p.transform,
            &b.transform,
            tol,
            now,
        ));
        if verdict(p) != verdict(b) {
            out.push(finding(
                Code::VerdictChanged,
                at,
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

/// `new-file`: a checked file without an entry in the baseline.
pub fn new_file(path: &Path) -> Diagnostic {
    finding(
        Code::NewFile,
        Location::file(path),
        "file is not in the baseline (accept it with --write-baseline)".into(),
    )
}

/// `removed-file` for the entry `key` of a baseline kept in `dir` that was
/// not checked, when its file no longer exists (a subset run checks fewer
/// files: their entries are skipped).
pub fn removed_file(key: &str, dir: &Path) -> Option<Diagnostic> {
    let path = dir.join(decode_key(key)?);
    if std::fs::symlink_metadata(&path).is_ok() {
        return None;
    }
    Some(finding(
        Code::RemovedFile,
        Location::file(&path),
        format!(
            "file {key:?} is in the baseline but no longer exists (accept with --write-baseline --prune)"
        ),
    ))
}
