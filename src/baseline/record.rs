//! A baseline's records as stored (per file, its edges and its checked
//! pairs) and the checks an entry passes when it is read: the leaf that the
//! store and the stream share.

#[cfg(test)]
use std::collections::BTreeMap;

use crate::frames::Edge;
use crate::geometry::Transform;
use serde::{Deserialize, Serialize};

/// A baseline: per file (key: [`encode_key`](super::key::encode_key) of its normalised path relative
/// to the baseline's directory), its record.
#[cfg(test)]
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, Default)]
pub struct Baseline {
    /// Version of this JSON layout; [`read_store`](super::read_store) accepts only 1.
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
