//! What the calibration formats of issue 28 share: numbers read strictly (a
//! missing key is an error, never a default of 0), matrices of a stated size
//! (OpenCV `{rows, cols, data}`, a flat row-major list, four rows of four),
//! each read into a checked [`Transform`] with the rounding of its numbers,
//! and the rule for a transform whose direction no upstream code fixes
//! ([`untraced`]: refused unless `--assume` says which).

use super::spec::{Assume, LoadOptions};
use super::yaml::{Node, Value};
use super::yaml_shapes::{err_at, loc_of};
use crate::diagnostic::{Code, Error, Result, Warning};
use crate::frames::Edge;
use crate::geometry::se3::{QuatOrder, Transform};
use crate::geometry::uncertainty::{matrix4_precision, written_precision, Written};
use crate::geometry::EdgePrecision;
use std::path::Path;

/// A transform as read, with the rounding of the numbers it was read from.
pub(crate) type Read = (Transform, EdgePrecision);

/// The value under `key` in map `m`, or an error naming `what` and the key.
pub(crate) fn field<'a>(m: &'a Node, key: &str, what: &str) -> Result<&'a Node> {
    m.get(key).ok_or_else(|| {
        err_at(
            m,
            format!("{what}: expected `{key}`, found none (no default is assumed)"),
        )
    })
}

/// A number under `key`: a YAML/JSON number, not a string.
pub(crate) fn number(m: &Node, key: &str, what: &str) -> Result<f64> {
    let v = field(m, key, what)?;
    match &v.value {
        Value::Num(x) => Ok(*x),
        _ => Err(err_at(
            v,
            format!(
                "{what}.{key}: expected a number, found {}{}",
                v.kind(),
                match &v.value {
                    Value::Str(s) => format!(" {:?}", crate::sanitize::clip(s)),
                    _ => String::new(),
                }
            ),
        )),
    }
}

/// A frame name under `key`: a non-empty string.
pub(crate) fn name(m: &Node, key: &str, what: &str) -> Result<String> {
    let v = field(m, key, what)?;
    match &v.value {
        Value::Str(s) if !s.trim().is_empty() => Ok(s.trim().to_string()),
        _ => Err(err_at(
            v,
            format!(
                "{what}.{key}: expected a frame name (a non-empty string), found {}",
                v.kind()
            ),
        )),
    }
}

/// Exactly `n` numbers in list `v` (nested rows flattened).
pub(crate) fn numbers_n(v: &Node, n: usize, what: &str) -> Result<Vec<f64>> {
    let x = v.numbers(what)?;
    if x.len() != n {
        return Err(err_at(
            v,
            format!("{what}: expected {n} numbers, found {}", x.len()),
        ));
    }
    Ok(x)
}

/// A row-major 4x4 (16 numbers): bottom row `0 0 0 1`, rotation checked.
pub(crate) fn rigid16(v: &[f64], at: &Node, what: &str, ws: &mut Vec<Warning>) -> Result<Read> {
    let m = [
        [v[0], v[1], v[2], v[3]],
        [v[4], v[5], v[6], v[7]],
        [v[8], v[9], v[10], v[11]],
        [v[12], v[13], v[14], v[15]],
    ];
    let t = Transform::from_matrix4(m, ws).map_err(|e| located(e, at, what))?;
    Ok((t, matrix4_precision(m, 1.0)))
}

/// A rotation (9 numbers, row-major) and a translation (3).
pub(crate) fn rigid_rt(
    r: &[f64],
    d: &[f64],
    at: &Node,
    what: &str,
    ws: &mut Vec<Warning>,
) -> Result<Read> {
    let r = [[r[0], r[1], r[2]], [r[3], r[4], r[5]], [r[6], r[7], r[8]]];
    let d = [d[0], d[1], d[2]];
    let t = Transform::from_matrix3(r, d, ws).map_err(|e| located(e, at, what))?;
    Ok((t, written_precision(Written::Matrix3(r), d, 1.0)))
}

/// A translation and a quaternion x, y, z, w (normalised with a warning when
/// it is not unit, as `Transform::from_quaternion` does).
pub(crate) fn rigid_quat(
    q: [f64; 4],
    d: [f64; 3],
    at: &Node,
    what: &str,
    ws: &mut Vec<Warning>,
) -> Result<Read> {
    let t =
        Transform::from_quaternion(q, QuatOrder::Xyzw, d, ws).map_err(|e| located(e, at, what))?;
    Ok((
        t,
        written_precision(Written::Quat(q, QuatOrder::Xyzw), d, 1.0),
    ))
}

/// URDF roll, pitch, yaw (rad): `R = Rz(yaw) Ry(pitch) Rx(roll)`.
pub(crate) fn rigid_rpy(rpy: [f64; 3], d: [f64; 3], at: &Node, what: &str) -> Result<Read> {
    let t = Transform::from_rpy(rpy, d).map_err(|e| located(e, at, what))?;
    Ok((t, written_precision(Written::Rpy(rpy), d, 1.0)))
}

fn located(e: Error, at: &Node, what: &str) -> Error {
    Error {
        message: format!("{what}: {}", e.message),
        ..e
    }
    .at_line(at.line.max(1), Some(at.column.max(1)))
}

/// An OpenCV FileStorage matrix `{rows, cols, data}` of exactly `rows` x
/// `cols` (what the consuming code requires), its data row-major.
pub(crate) fn cv_matrix(n: &Node, rows: usize, cols: usize, what: &str) -> Result<Vec<f64>> {
    if !matches!(n.value, Value::Map(_)) {
        return Err(err_at(
            n,
            format!(
                "{what}: expected an OpenCV matrix {{rows, cols, data}}, found {}",
                n.kind()
            ),
        ));
    }
    let r = number(n, "rows", what)?;
    let c = number(n, "cols", what)?;
    if (r, c) != (rows as f64, cols as f64) {
        return Err(err_at(
            n,
            format!("{what}: expected rows {rows} cols {cols}, found rows {r} cols {c}"),
        ));
    }
    numbers_n(
        field(n, "data", what)?,
        rows * cols,
        &format!("{what}.data"),
    )
}

/// The first document of a file, which must be a mapping.
pub(crate) fn top_map<'a>(docs: &'a [Node], what: &str) -> Result<&'a Node> {
    match docs.first() {
        Some(d) if matches!(d.value, Value::Map(_)) => Ok(d),
        Some(d) => Err(err_at(
            d,
            format!("{what}: expected a mapping at the top, found {}", d.kind()),
        )),
        None => Err(Error::parse(format!("{what}: the file is empty"))),
    }
}

/// An edge `parent -> child` read from `key` (at node `k`).
pub(crate) fn edge(
    parent: &str,
    child: &str,
    read: Read,
    path: &Path,
    k: &Node,
    format: &'static str,
    key: String,
) -> Edge {
    Edge::new(parent, child, read.0, loc_of(path, k), format, key).with_precision(read.1)
}

/// The numbers are the pose of `parent` in `child` (the file's own
/// direction): kept as the edge `child -> parent` inverted, so that the edge
/// reads `parent -> child` where the tree needs it (`label` says so).
pub(crate) fn stored_inverted(e: Edge, label: String) -> Edge {
    let mut e = e.inverted();
    e.provenance.key = label;
    e
}

/// A transform whose direction no consuming code fixes, between frames the
/// file names (`parent`, `child`, the pose of `child` in `parent` by the
/// file's naming): with `--assume` it is read as the user says; without, it
/// is left out with an `ignored` warning naming the flag. `Err` when
/// `--assume` gives frames (they are for files that name none).
pub(crate) fn untraced(
    opts: &LoadOptions,
    e: Edge,
    why: &str,
    out: &mut Vec<Warning>,
) -> Result<Option<Edge>> {
    let Some(a) = &opts.assume else {
        out.push(
            Warning::new(
                Code::Ignored,
                format!(
                    "{}: {why}; left out: pass --assume child-in-parent (the pose of {} in {}) or --assume parent-in-child to read it",
                    e.provenance.key, e.child, e.parent
                ),
            )
            .at(&e.provenance.location),
        );
        return Ok(None);
    };
    if a.frames.is_some() {
        return Err(Error::usage(format!(
            "{}: the file names its frames ({} -> {}): expected --assume child-in-parent or parent-in-child without frame names (rename with --rename)",
            a.flag(),
            e.parent,
            e.child
        )));
    }
    Ok(Some(assumed(a, e)))
}

/// Edge `e` (as written: the pose of its child in its parent) read in the
/// direction `--assume` gives, its provenance saying so.
pub(crate) fn assumed(a: &Assume, e: Edge) -> Edge {
    let label = format!("{} (direction from {})", e.provenance.key, a.flag());
    if a.child_in_parent {
        let mut e = e;
        e.provenance.key = label;
        return e;
    }
    // The numbers are the pose of the parent in the child: the same frames,
    // the inverse transform (as `--invert` does).
    let mut inv = e.inverted();
    std::mem::swap(&mut inv.parent, &mut inv.child);
    inv.provenance.key = label;
    inv
}
