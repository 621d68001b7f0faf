//! `audit diff OLD NEW`: each file loaded into its own frame graph (renames
//! applied where they match), every edge compared, and when a frame pair is
//! named (or a rig file declares one) that chain composed in both and the two
//! rig reports compared (what counts as a change: see
//! [`crate::report::diff`]).

use super::load::apply_renames;
use super::rig::{self, RigOptions};
use crate::diagnostic::{Error, Result, Warning};
use crate::formats::{self, LoadOptions};
use crate::frames::{Chain, Edge, FrameGraph};
use crate::geometry::Transform;
use crate::report::diff::{
    BandDiffJson, ChainDiffJson, DiffReport, DiffToleranceJson, EdgeDiffJson, EdgeStatus,
    FamilyDiffJson, OldNew, ReadJson, DIFF_SCHEMA_VERSION,
};
use crate::report::RigReport;
use crate::tolerances::{DUPLICATE_ROTATION_TOL, DUPLICATE_TRANSLATION_TOL, NEAR_HALF_TURN_RAD};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// What to compare and how. `Default`: the command's defaults, no files
/// ([`DiffOptions::new`] names them).
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct DiffOptions {
    /// The old calibration file.
    pub old: PathBuf,
    /// The new one.
    pub new: PathBuf,
    /// `--from` (else the frame pair a rig file declares).
    pub from: Option<String>,
    /// `--to`.
    pub to: Option<String>,
    /// How the files are read (`renames` applied to the files they match).
    pub load: LoadOptions,
    /// How the old file is read beyond `load` (`--key-old`, `--invert-old`).
    pub old_read: SideRead,
    /// How the new file is read (`--key-new`, `--invert-new`).
    pub new_read: SideRead,
    /// Lengths of the bands, zero-pitch tolerance.
    pub rig: RigOptions,
    /// `--tolerance LENGTH,ANGLE`.
    pub tolerance: DiffToleranceJson,
}

/// How one side of a diff is read: one key of a YAML/JSON file with several
/// transforms, and whether its numbers are the pose of the parent in the
/// child (inverted as they are read).
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct SideRead {
    /// `--key-old`/`--key-new` (or `--key` for both).
    pub key: Option<String>,
    /// `--invert-old`/`--invert-new`.
    pub invert: bool,
}

impl DiffOptions {
    /// Compare `old` with `new`, with the command's defaults.
    pub fn new(old: impl Into<PathBuf>, new: impl Into<PathBuf>) -> Self {
        DiffOptions {
            old: old.into(),
            new: new.into(),
            ..DiffOptions::default()
        }
    }
}

impl SideRead {
    fn json(&self) -> ReadJson {
        ReadJson {
            key: self.key.clone(),
            inverted: self.invert,
        }
    }
}

/// One file loaded: its graph and the frame pair it declares (a rig file).
struct Side {
    graph: FrameGraph,
    pair: Option<(String, String)>,
}

fn load_side(
    path: &Path,
    read: &SideRead,
    opts: &DiffOptions,
    matched: &mut [usize],
) -> Result<Side> {
    let load = LoadOptions {
        key: read.key.clone(),
        invert: read.invert,
        ..opts.load.clone()
    };
    let mut loaded = formats::load_file(path, &load)?;
    for (total, n) in matched
        .iter_mut()
        .zip(apply_renames(&opts.load.renames, path, &mut loaded))
    {
        *total += n;
    }
    let pair = loaded
        .rig
        .as_ref()
        .filter(|m| !m.from.is_empty() && !m.to.is_empty())
        .map(|m| (m.from.clone(), m.to.clone()));
    let mut graph = FrameGraph::new();
    graph.add(loaded)?;
    Ok(Side { graph, pair })
}

/// `d_new - d_old` (m) and the angle of `R_old^T R_new` (rad).
fn change(old: &Transform, new: &Transform) -> ([f64; 3], f64) {
    let d = new.translation() - old.translation();
    let angle = old.inverse().compose(new).rotation_angle_axis().0;
    ([d.x, d.y, d.z], angle)
}

fn beyond(tol: &DiffToleranceJson, d: &[f64; 3], angle_rad: f64) -> bool {
    let mm = 1e3 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    mm > tol.translation_mm || angle_rad.to_degrees() > tol.rotation_deg
}

fn place(e: &Edge) -> String {
    e.provenance.location.to_string()
}

/// The edge of `g` joining the same two frames as `e`, and whether it is
/// stored the other way round.
fn counterpart<'a>(g: &'a FrameGraph, e: &Edge) -> Option<(&'a Edge, bool)> {
    if let Some(n) = g.parent_edge(&e.child).filter(|n| n.parent == e.parent) {
        return Some((n, false));
    }
    g.parent_edge(&e.parent)
        .filter(|n| n.parent == e.child)
        .map(|n| (n, true))
}

/// Every edge of either graph compared; `on` holds the `(parent, child)`
/// pairs of both chains (either order).
fn edge_diffs(
    old: &FrameGraph,
    new: &FrameGraph,
    tol: &DiffToleranceJson,
    on: &HashSet<(&str, &str)>,
) -> Vec<EdgeDiffJson> {
    let on_chain =
        |e: &Edge| on.contains(&(&e.parent, &e.child)) || on.contains(&(&e.child, &e.parent));
    let only = |e: &Edge, status: EdgeStatus| EdgeDiffJson {
        on_chain: on_chain(e),
        parent: e.parent.clone(),
        child: e.child.clone(),
        status,
        reversed: false,
        translation_delta_m: None,
        translation_change_mm: None,
        rotation_change_deg: None,
        old_place: (status == EdgeStatus::Removed).then(|| place(e)),
        new_place: (status == EdgeStatus::Added).then(|| place(e)),
        exceeds: false,
    };
    let (mut common, mut removed) = (Vec::new(), Vec::new());
    for e in old.edges() {
        let Some((n, reversed)) = counterpart(new, e) else {
            removed.push(only(e, EdgeStatus::Removed));
            continue;
        };
        let nt = if reversed {
            n.transform.inverse()
        } else {
            n.transform
        };
        let (d, angle) = change(&e.transform, &nt);
        let moved = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let same = moved <= DUPLICATE_TRANSLATION_TOL && angle <= DUPLICATE_ROTATION_TOL;
        common.push(EdgeDiffJson {
            parent: e.parent.clone(),
            child: e.child.clone(),
            status: if same {
                EdgeStatus::Unchanged
            } else {
                EdgeStatus::Changed
            },
            reversed,
            translation_delta_m: Some(d),
            translation_change_mm: Some(1e3 * moved),
            rotation_change_deg: Some(angle.to_degrees()),
            old_place: Some(place(e)),
            new_place: Some(place(n)),
            exceeds: beyond(tol, &d, angle),
            on_chain: on_chain(e) || on_chain(n),
        });
    }
    let added = new
        .edges()
        .iter()
        .filter(|n| counterpart(old, n).is_none())
        .map(|n| only(n, EdgeStatus::Added));
    common.extend(removed);
    common.extend(added);
    common
}

/// `h` changed sign and the rotation change could pass through a half-turn
/// (see `ChainDiffJson::screw_sign_flip_at_half_turn`).
fn sign_flip_at_half_turn(o: &RigReport, n: &RigReport, change_deg: f64) -> bool {
    let (Some(ho), Some(hn)) = (
        o.screw.translation_along_axis_m,
        n.screw.translation_along_axis_m,
    ) else {
        return false;
    };
    let to_half_turn = (180.0 - o.rotation.angle_deg) + (180.0 - n.rotation.angle_deg);
    // Rounding slack: NEAR_HALF_TURN_RAD.
    ho * hn < 0.0 && to_half_turn <= change_deg + NEAR_HALF_TURN_RAD.to_degrees()
}

fn old_new<T>(o: &RigReport, n: &RigReport, f: impl Fn(&RigReport) -> T) -> OldNew<T> {
    OldNew {
        old: f(o),
        new: f(n),
    }
}

fn chain_diff(
    o: &RigReport,
    n: &RigReport,
    told: &Transform,
    tnew: &Transform,
    tol: &DiffToleranceJson,
) -> ChainDiffJson {
    let (d, angle) = change(told, tnew);
    ChainDiffJson {
        translation_m: old_new(o, n, |r| r.transform.translation_m),
        translation_delta_m: d,
        translation_change_mm: 1e3 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt(),
        rotation_change_deg: angle.to_degrees(),
        angle_deg: old_new(o, n, |r| r.rotation.angle_deg),
        lever_arm_m: old_new(o, n, |r| r.lever_arm_m),
        screw_translation_m: old_new(o, n, |r| r.screw.translation_along_axis_m),
        screw_sign_flip_at_half_turn: sign_flip_at_half_turn(o, n, angle.to_degrees()),
        screw_kind: old_new(o, n, |r| r.screw.kind),
        bands: o
            .certificate
            .iter()
            .zip(&n.certificate)
            .map(|(a, b)| BandDiffJson {
                ell_m: a.ell_m,
                band: OldNew {
                    old: a.band,
                    new: b.band,
                },
            })
            .collect(),
        adapted_metric_exists: old_new(o, n, |r| r.adapted_metric.exists),
        detectors: o
            .detectors
            .iter()
            .zip(&n.detectors)
            .map(|(a, b)| FamilyDiffJson {
                family: a.family,
                invariant_on_rig: OldNew {
                    old: a.invariant_on_rig,
                    new: b.invariant_on_rig,
                },
                changed: a.invariant_on_rig != b.invariant_on_rig,
            })
            .collect(),
        exceeds: beyond(tol, &d, angle),
    }
}

/// Why the diff exceeds its tolerance, one sentence each: the common edges
/// moved, and the chain's reasons ([`chain_exceeded`]) or, without a chain,
/// the edges in one file only.
fn exceeded(chain: Option<&ChainDiffJson>, edges: &[EdgeDiffJson]) -> Vec<String> {
    let n = edges.iter().filter(|e| e.exceeds).count();
    let moved = (n > 0).then(|| format!("{n} common edge(s) moved"));
    let Some(chain) = chain else {
        let count = |s: EdgeStatus| edges.iter().filter(|e| e.status == s).count();
        let one_side = [
            (count(EdgeStatus::Removed), "only in OLD"),
            (count(EdgeStatus::Added), "only in NEW"),
        ]
        .into_iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, side)| format!("{n} edge(s) {side}"));
        return moved.into_iter().chain(one_side).collect();
    };
    let mut why = chain_exceeded(chain);
    if let Some(m) = moved {
        why.insert(usize::from(chain.exceeds), m);
    }
    why
}

/// The chain's reasons: it moved, its screw kind or a verdict changed.
fn chain_exceeded(chain: &ChainDiffJson) -> Vec<String> {
    let mut why = Vec::new();
    if chain.exceeds {
        why.push(format!(
            "the chain moved {:.3} mm, {:.4} deg",
            chain.translation_change_mm, chain.rotation_change_deg
        ));
    }
    if chain.screw_kind.old != chain.screw_kind.new {
        why.push(format!(
            "the screw kind changed ({} -> {})",
            chain.screw_kind.old.label(),
            chain.screw_kind.new.label()
        ));
    }
    let flipped: Vec<&str> = chain
        .detectors
        .iter()
        .filter(|f| f.changed)
        .map(|f| f.family.label())
        .collect();
    if !flipped.is_empty() {
        why.push(format!("verdict changed for {}", flipped.join(", ")));
    }
    why
}

/// The frame pair: given, or declared by OLD's (else NEW's) rig file;
/// `None` when neither names one (the whole files are compared).
fn frame_pair(opts: &DiffOptions, old: &Side, new: &Side) -> Result<Option<(String, String)>> {
    match (&opts.from, &opts.to) {
        (Some(f), Some(t)) => Ok(Some((f.clone(), t.clone()))),
        (None, None) => Ok(old.pair.clone().or_else(|| new.pair.clone())),
        _ => Err(Error::usage("give both --from and --to, or neither")),
    }
}

/// The chain `from -> to` composed in both files and compared.
fn compare_chain(
    opts: &DiffOptions,
    (old, new): (&Side, &Side),
    (from, to): (&str, &str),
) -> Result<(Chain, Chain, ChainDiffJson)> {
    let co = old
        .graph
        .transform(from, to)
        .map_err(|e| e.in_file(&opts.old))?;
    let cn = new
        .graph
        .transform(from, to)
        .map_err(|e| e.in_file(&opts.new))?;
    let ro = rig::report(&co, &opts.rig)?;
    let rn = rig::report(&cn, &opts.rig)?;
    let chain = chain_diff(&ro, &rn, &co.transform, &cn.transform, &opts.tolerance);
    Ok((co, cn, chain))
}

/// Compare OLD and NEW; returns the report and the warnings the files and
/// chains raised.
///
/// ```
/// use extrinsic_audit::{diff, DiffOptions, Rename};
///
/// # fn main() -> extrinsic_audit::Result<()> {
/// let root = env!("CARGO_MANIFEST_DIR");
/// // ANYmal D's IMU -> LiDAR extrinsic against a FAST-LIO file written with a
/// // known change (tests/fixtures/diff/gen_expected.py, pytransform3d).
/// let mut opts = DiffOptions::new(
///     format!("{root}/calibrations/anymal-d.urdf"),
///     format!("{root}/tests/fixtures/diff/anymal_d_fastlio.yaml"),
/// );
/// opts.from = Some("imu_link".into());
/// opts.to = Some("lidar".into());
/// // FAST-LIO calls the IMU frame `imu`.
/// let imu = Rename { file: Some("anymal_d_fastlio.yaml".into()), old: "imu".into(), new: "imu_link".into() };
/// opts.load.renames = vec![imu];
/// let (report, _warnings) = diff(&opts)?;
/// let chain = report.chain.as_ref().expect("--from/--to name a chain");
/// assert!((chain.translation_change_mm - 2.2234203889759425).abs() < 1e-9);
/// assert!((chain.rotation_change_deg - 0.2).abs() < 1e-9);
/// // Beyond the default tolerance (1 mm, 0.05 deg): the command exits 1.
/// assert!(!report.exceeded.is_empty());
/// # Ok(())
/// # }
/// ```
pub fn diff(opts: &DiffOptions) -> Result<(DiffReport, Vec<Warning>)> {
    let mut matched = vec![0usize; opts.load.renames.len()];
    let old = load_side(&opts.old, &opts.old_read, opts, &mut matched)?;
    let new = load_side(&opts.new, &opts.new_read, opts, &mut matched)?;
    if let Some(i) = matched.iter().position(|&n| n == 0) {
        let r = &opts.load.renames[i];
        return Err(Error::usage(format!(
            "--rename {}{}={}: expected a frame `{}` in OLD or NEW, found none",
            r.file
                .as_deref()
                .map(|f| format!("{f}:"))
                .unwrap_or_default(),
            r.old,
            r.new,
            r.old
        )));
    }
    let pair = frame_pair(opts, &old, &new)?;
    let chains = match &pair {
        Some((f, t)) => Some(compare_chain(opts, (&old, &new), (f, t))?),
        None => None,
    };
    let on: HashSet<(&str, &str)> = chains
        .iter()
        .flat_map(|(co, cn, _)| co.steps.iter().chain(&cn.steps))
        .map(|s| (s.edge.parent.as_str(), s.edge.child.as_str()))
        .collect();
    let edges = edge_diffs(&old.graph, &new.graph, &opts.tolerance, &on);
    let co_cn = chains.as_ref().map(|(co, cn, _)| (co, cn));
    let mistakes = super::mistakes::in_diff(&old.graph, &new.graph, co_cn, &edges, &opts.tolerance);
    let mut warnings: Vec<Warning> = old.graph.warnings().to_vec();
    warnings.extend(new.graph.warnings().iter().cloned());
    if let Some((co, cn, _)) = &chains {
        warnings.extend(co.warnings.iter().cloned());
        warnings.extend(cn.warnings.iter().cloned());
    }
    let chain = chains.map(|(_, _, c)| c);
    let (from, to) = pair.unzip();
    let report = DiffReport {
        schema_version: DIFF_SCHEMA_VERSION,
        old: opts.old.display().to_string(),
        new: opts.new.display().to_string(),
        old_read: opts.old_read.json(),
        new_read: opts.new_read.json(),
        from,
        to,
        tolerance: opts.tolerance,
        exceeded: exceeded(chain.as_ref(), &edges),
        chain,
        edges,
        mistakes,
    };
    Ok((report, warnings))
}
