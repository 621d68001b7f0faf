//! Baselines of `audit check`: per file, its edges and its checked frame pairs
//! as they were accepted, and the comparison of a new state against one, as
//! typed diagnostics (`new-file`, `new-edge`, `missing-edge`, `removed-file`,
//! `pair-changed`, `drift`, `verdict-changed`).
//!
//! Keys: a file's path relative to the baseline's directory, normalised (no
//! `.`, no doubled `/`, symlinks resolved while they stay inside the checked
//! root), `/`-separated; bytes that are not UTF-8 and `%` itself are written
//! `%XX` ([`encode_key`]), so that every file name has its own key and the key
//! gives the path back ([`decode_key`]).
//!
//! Drift: the translation difference `||d_now - d_base||` (m) and the angle of
//! `R_base^T R_now` (deg, from the quaternions) against the tolerances given.

use crate::diagnostic::{Code, Diagnostic, Error, Location, Result};
use crate::frames::Edge;
use crate::geometry::Transform;
use crate::tolerances::{DEFAULT_MAX_ROTATION_DRIFT_DEG, DEFAULT_MAX_TRANSLATION_DRIFT};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

mod lock;
pub mod store;
pub mod stream;

pub use lock::{lock_for_write, WriteLock};
pub use store::Store;

/// A baseline: per file (key: [`encode_key`] of its normalised path relative
/// to the baseline's directory), its record.
#[cfg(test)]
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, Default)]
pub struct Baseline {
    /// Version of this JSON layout; [`read_store`] accepts only 1.
    pub schema_version: u32,
    /// One record per calibration file that loaded, keyed by its normalised
    /// path relative to the baseline's directory (see the module doc), sorted.
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
    /// The pair is the one the file declares (a rig file's `[rig] from -> to`),
    /// not a `--pair`; absent in older baselines (false).
    #[serde(default)]
    pub declared: bool,
}

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

/// The key of a relative path: components joined by `/`; `%` and every byte
/// that is not part of valid UTF-8 written `%XX` (upper-case hex). Reversible
/// by [`decode_key`].
pub fn encode_key(rel: &Path) -> String {
    let mut out = String::new();
    for (i, c) in rel.components().enumerate() {
        if i > 0 {
            out.push('/');
        }
        let part = match c {
            Component::ParentDir => "..".as_ref(),
            Component::CurDir => ".".as_ref(),
            other => other.as_os_str(),
        };
        for chunk in os_bytes(part).utf8_chunks() {
            for ch in chunk.valid().chars() {
                if ch == '%' {
                    out.push_str("%25");
                } else {
                    out.push(ch);
                }
            }
            for b in chunk.invalid() {
                out.push_str(&format!("%{b:02X}"));
            }
        }
    }
    out
}

#[cfg(unix)]
fn os_bytes(s: &std::ffi::OsStr) -> &[u8] {
    std::os::unix::ffi::OsStrExt::as_bytes(s)
}
#[cfg(not(unix))]
fn os_bytes(s: &std::ffi::OsStr) -> &[u8] {
    // Elsewhere file names are Unicode (lossy only for unpaired surrogates).
    s.as_encoded_bytes()
}

/// The relative path a key names (the inverse of [`encode_key`]); `None` when
/// the key is not one [`encode_key`] writes (a `%` not followed by two hex
/// digits).
pub fn decode_key(key: &str) -> Option<PathBuf> {
    let b = key.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    #[cfg(unix)]
    {
        Some(PathBuf::from(
            <std::ffi::OsString as std::os::unix::ffi::OsStringExt>::from_vec(out),
        ))
    }
    #[cfg(not(unix))]
    {
        String::from_utf8(out).ok().map(PathBuf::from)
    }
}

/// `target` relative to `dir` (both absolute and normalised): `..` for each
/// component of `dir` past their common prefix.
pub fn relative_to(target: &Path, dir: &Path) -> PathBuf {
    let t: Vec<Component> = target.components().collect();
    let d: Vec<Component> = dir.components().collect();
    let common = t.iter().zip(&d).take_while(|(a, b)| a == b).count();
    let mut out = PathBuf::new();
    for _ in common..d.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c.as_os_str());
    }
    out
}

/// Lexical normalisation of an absolute path: `.` dropped, `..` pops.
pub fn normalise(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other.as_os_str()),
        }
    }
    out
}

fn absolute(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).map_err(|e| Error::io(p, &e))
}

/// The key of `file` in a baseline kept in the directory whose real path is
/// `canon_dir`. `root` is the checked path `file` was found under
/// (`canon_root` its real path): symlinks are resolved when the file they
/// lead to stays inside it; otherwise the file keeps its place in the tree
/// (a link out of the checked root is keyed where it is found).
pub fn key_in(file: &Path, root: &Path, canon_root: &Path, canon_dir: &Path) -> Result<String> {
    let (canon_root, dir) = (canon_root.to_path_buf(), canon_dir);
    let canon = file.canonicalize().map_err(|e| Error::io(file, &e))?;
    let place = if canon.starts_with(&canon_root) {
        canon
    } else {
        // The link leaves the root: keep the path as found under the root.
        let rel = normalise(&absolute(file)?);
        let abs_root = normalise(&absolute(root)?);
        match rel.strip_prefix(&abs_root) {
            Ok(tail) => canon_root.join(tail),
            Err(_) => canon,
        }
    };
    Ok(encode_key(&relative_to(&place, dir)))
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

/// Largest `| ||q|| - 1 |` of a stored quaternion (written as unit to ~1e-16).
const STORED_UNIT_TOL: f64 = 1e-6;

fn validate_transform(entry: &str, t: &BaselineTransform) -> std::result::Result<(), String> {
    let name = format!("{entry} ({} -> {})", t.parent, t.child);
    if let Some(x) = t
        .translation_m
        .iter()
        .chain(&t.quaternion_xyzw)
        .find(|x| !x.is_finite())
    {
        return Err(format!(
            "baseline entry {name}: expected finite numbers, found {x}"
        ));
    }
    let n = t.quaternion_xyzw.iter().map(|x| x * x).sum::<f64>().sqrt();
    if (n - 1.0).abs() > STORED_UNIT_TOL {
        return Err(format!(
            "baseline entry {name}: expected a unit quaternion_xyzw, found norm {n:e} (rewrite the baseline with --write-baseline)"
        ));
    }
    Ok(())
}

pub(crate) fn validate_file(key: &str, rec: &BaselineFile) -> std::result::Result<(), String> {
    for (i, e) in rec.edges.iter().enumerate() {
        validate_transform(&format!("files[{key:?}].edges[{i}]"), e)?;
    }
    for (i, p) in rec.pairs.iter().enumerate() {
        validate_transform(&format!("files[{key:?}].pairs[{i}]"), &p.transform)?;
        if !p.lever_arm_m.is_finite() {
            return Err(format!(
                "baseline entry files[{key:?}].pairs[{i}]: expected a finite lever_arm_m, found {}",
                p.lever_arm_m
            ));
        }
    }
    Ok(())
}

/// Where each edge and pair of a checked file is written: `(parent, child)`
/// (`(from, to)` for a pair) to its location.
pub type Locations = BTreeMap<(String, String), Location>;

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
        let mut l = self
            .locations
            .get(&(a.to_string(), b.to_string()))
            .cloned()
            .unwrap_or_default();
        l.file = Some(self.path.to_path_buf());
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
/// its tolerance.
fn drift(
    what: String,
    now: &BaselineTransform,
    base: &BaselineTransform,
    tol: DriftTolerances,
    at: Location,
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
            ),
        )
        .at(&at),
    )
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
                now.at(&b.parent, &b.child),
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
            at.clone(),
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
