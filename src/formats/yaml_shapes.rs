//! The transform shapes YAML and JSON files hold, read from parsed nodes:
//! a 4x4 (OpenCV FileStorage `{rows, cols, dt, data}`, 16 numbers, four rows),
//! a 3x4, 7 numbers `t_xyz_q_xyzw`, `{x, y, z, roll, pitch, yaw}` (URDF rpy)
//! or `{x, y, z, qx, qy, qz, qw}`; frame names from a `T_A_B` / `A_T_B` key
//! (the pose of B in A); and the node helpers every YAML and JSON format
//! uses (locations, "exactly N numbers", the one map holding a key).

use super::spec::{check_metres, locate_warnings};
use super::yaml::{Node, Value};
use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::frames::{Edge, ValuesAt};
use crate::geometry::se3::{QuatOrder, Transform};
use crate::geometry::uncertainty::{matrix4_precision, written_precision, Written};
use crate::geometry::EdgePrecision;
use std::path::Path;

/// The id of `matrix-yaml`: `--key NAME` reads a key as it reads a `T_A_B` key
/// in any YAML or JSON dialect, and its edges carry this id.
pub(crate) const MATRIX_YAML_ID: &str = "matrix-yaml";

pub(crate) fn loc_of(path: &Path, n: &Node) -> Location {
    if n.line == 0 {
        Location::file(path)
    } else {
        Location::at(path, n.line, Some(n.column.max(1)))
    }
}

pub(crate) fn err_at(n: &Node, msg: String) -> Error {
    Error::parse(msg).at_line(n.line.max(1), Some(n.column.max(1)))
}

/// All maps (depth-first) that contain `key`.
fn maps_with<'a>(n: &'a Node, key: &str, out: &mut Vec<&'a Node>) {
    match &n.value {
        Value::Map(m) => {
            if !n.get_all(key).is_empty() {
                out.push(n);
            }
            for (_, v) in m {
                maps_with(v, key, out);
            }
        }
        Value::Seq(s) => {
            for v in s {
                maps_with(v, key, out);
            }
        }
        _ => {}
    }
}

pub(crate) fn exactly<const N: usize>(n: &Node, what: &str) -> Result<[f64; N]> {
    let v = n.numbers(what)?;
    if v.len() != N {
        return Err(err_at(
            n,
            format!("{what}: expected {N} numbers, found {}", v.len()),
        ));
    }
    let mut out = [0.0; N];
    out.copy_from_slice(&v);
    Ok(out)
}

pub(crate) fn mat3(v: [f64; 9]) -> [[f64; 3]; 3] {
    [[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]]
}

/// The single map holding `key` (error when several do).
pub(crate) fn unique_map<'a>(docs: &'a [Node], key: &str) -> Result<&'a Node> {
    let mut found = Vec::new();
    for d in docs {
        maps_with(d, key, &mut found);
    }
    match found.len() {
        0 => Err(Error::parse(format!("expected a key `{key}`, found none"))),
        1 => {
            let m = found[0];
            let all = m.get_all(key);
            if all.len() > 1 {
                return Err(err_at(
                    all[1],
                    format!(
                        "`{key}` given twice in one mapping (lines {} and {}): expected one",
                        all[0].line, all[1].line
                    ),
                ));
            }
            Ok(m)
        }
        _ => Err(err_at(
            found[1],
            format!(
                "`{key}` appears {} times (lines {}): expected one; pick one with --key PATH (e.g. a.b.{key})",
                found.len(),
                found
                    .iter()
                    .filter_map(|m| m.get(key).map(|v| v.line.to_string()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
    }
}

/// Where the keys `tkey` (the translation) and `rkey` (the rotation) of `m`
/// are written: a finding about a changed number points at its key's line.
pub(crate) fn key_values(m: &Node, tkey: &str, rkey: &str) -> ValuesAt {
    let at = |key: &str| {
        key_node(m, key)
            .filter(|k| k.line > 0)
            .map(|k| (k.line, k.column.max(1)))
    };
    ValuesAt::new(at(tkey), at(rkey))
}

pub(crate) fn key_node<'a>(m: &'a Node, key: &str) -> Option<&'a Node> {
    m.entries()
        .iter()
        .rev()
        .find(|(k, _)| k.as_str().as_deref() == Some(key))
        .map(|(k, _)| k)
}

/// `{x, y, z, roll, pitch, yaw}` (URDF rpy; a missing one is 0).
pub(crate) fn rpy_map(v: &Node, name: &str) -> Result<(Transform, EdgePrecision)> {
    let num = |k: &str| -> Result<f64> {
        match v.get(k) {
            None => Ok(0.0),
            Some(x) => x.as_f64().ok_or_else(|| {
                err_at(
                    x,
                    format!("{name}.{k}: expected a number, found {}", x.kind()),
                )
            }),
        }
    };
    let d = [num("x")?, num("y")?, num("z")?];
    let rpy = [num("roll")?, num("pitch")?, num("yaw")?];
    let t =
        Transform::from_rpy(rpy, d).map_err(|e| e.at_line(v.line.max(1), Some(v.column.max(1))))?;
    Ok((t, written_precision(Written::Rpy(rpy), d, 1.0)))
}

/// The IMU's name in a Kalibr file: `imu0` when a top-level `imu0` key says
/// so, else `imu`.
pub(crate) fn kalibr_imu(docs: &[Node]) -> &'static str {
    let has_imu0 = docs.iter().any(|d| {
        d.entries()
            .iter()
            .any(|(k, _)| k.as_str().as_deref() == Some("imu0"))
    });
    if has_imu0 {
        "imu0"
    } else {
        "imu"
    }
}

/// Frames of Kalibr key `inner` under block `cam` (`cam1`): `cam`/`cn` is the
/// block's camera, `cnm1` the previous one, `imu` the IMU; `None` when `cam`
/// is not `camN` or `inner` names no frames.
pub(crate) fn kalibr_frames(cam: &str, inner: &str, imu: &str) -> Option<(String, String)> {
    let idx = cam.strip_prefix("cam")?.parse::<usize>().ok()?;
    let (mut a, mut b) = frames_from_key(inner)?;
    for f in [&mut a, &mut b] {
        match f.as_str() {
            "cam" | "cn" => *f = cam.to_string(),
            "cnm1" if idx > 0 => *f = format!("cam{}", idx - 1),
            "imu" => *f = imu.to_string(),
            _ => {}
        }
    }
    Some((a, b))
}

/// Frames named by a key: `T_A_B` / `A_T_B` (pose of B in A).
pub(crate) fn frames_from_key(key: &str) -> Option<(String, String)> {
    let key = key.strip_suffix("_t_xyz_q_xyzw").unwrap_or(key);
    if let Some((a, b)) = key.split_once("_T_") {
        if !a.is_empty() && !b.is_empty() && !b.contains("_T_") {
            return Some((a.to_string(), b.to_string()));
        }
    }
    if let Some(rest) = key.strip_prefix("T_") {
        let parts: Vec<&str> = rest.split('_').collect();
        if parts.len() == 2 && !parts[0].is_empty() && !parts[1].is_empty() {
            return Some((parts[0].to_string(), parts[1].to_string()));
        }
    }
    None
}

/// Read whatever transform shape a node holds, with the rounding of its numbers.
fn read_transform(
    n: &Node,
    key: &str,
    ws: &mut Vec<Warning>,
) -> Result<(Transform, EdgePrecision)> {
    // OpenCV {rows, cols, data}
    if let Some(data) = n.get("data") {
        let v = data.numbers(&format!("{key}.data"))?;
        let rows = n.get("rows").and_then(|x| x.as_f64());
        let cols = n.get("cols").and_then(|x| x.as_f64());
        if let (Some(r), Some(c)) = (rows, cols) {
            if (r * c) as usize != v.len() {
                return Err(err_at(
                    data,
                    format!("{key}: rows x cols = {r} x {c}, expected that many numbers in data, found {}", v.len()),
                ));
            }
        }
        return matrix_from_numbers(&v, data, key, ws);
    }
    if matches!(n.value, Value::Map(_)) {
        if n.get("roll").is_some() || n.get("yaw").is_some() || n.get("x").is_some() {
            if n.get("qw").is_some() || n.get("qx").is_some() {
                let num = |k: &str, def: f64| -> Result<f64> {
                    match n.get(k) {
                        None => Ok(def),
                        Some(x) => x
                            .as_f64()
                            .ok_or_else(|| err_at(x, format!("{key}.{k}: expected a number"))),
                    }
                };
                let q = [
                    num("qx", 0.0)?,
                    num("qy", 0.0)?,
                    num("qz", 0.0)?,
                    num("qw", 1.0)?,
                ];
                let d = [num("x", 0.0)?, num("y", 0.0)?, num("z", 0.0)?];
                let t = Transform::from_quaternion(q, QuatOrder::Xyzw, d, ws)
                    .map_err(|e| e.at_line(n.line.max(1), Some(n.column.max(1))))?;
                return Ok((
                    t,
                    written_precision(Written::Quat(q, QuatOrder::Xyzw), d, 1.0),
                ));
            }
            return rpy_map(n, key);
        }
        return Err(err_at(
            n,
            format!("{key}: expected a 4x4 matrix (16 numbers, four rows, or rows/cols/data), a 3x4 matrix, 7 numbers `t_xyz_q_xyzw` or {{x, y, z, roll, pitch, yaw}}, found a mapping with keys {}",
                n.entries().iter().filter_map(|(k, _)| k.as_str()).collect::<Vec<_>>().join(", ")),
        ));
    }
    let v = n.numbers(key)?;
    if key.ends_with("_t_xyz_q_xyzw") {
        if v.len() != 7 {
            return Err(err_at(
                n,
                format!(
                    "{key}: expected 7 numbers (tx ty tz qx qy qz qw), found {}",
                    v.len()
                ),
            ));
        }
        let (q, d) = ([v[3], v[4], v[5], v[6]], [v[0], v[1], v[2]]);
        let t = Transform::from_quaternion(q, QuatOrder::Xyzw, d, ws)
            .map_err(|e| e.at_line(n.line.max(1), Some(n.column.max(1))))?;
        return Ok((
            t,
            written_precision(Written::Quat(q, QuatOrder::Xyzw), d, 1.0),
        ));
    }
    matrix_from_numbers(&v, n, key, ws)
}

fn matrix_from_numbers(
    v: &[f64],
    n: &Node,
    key: &str,
    ws: &mut Vec<Warning>,
) -> Result<(Transform, EdgePrecision)> {
    let at = |e: Error| e.at_line(n.line.max(1), Some(n.column.max(1)));
    match v.len() {
        16 => {
            let m = [
                [v[0], v[1], v[2], v[3]],
                [v[4], v[5], v[6], v[7]],
                [v[8], v[9], v[10], v[11]],
                [v[12], v[13], v[14], v[15]],
            ];
            let t = Transform::from_matrix4(m, ws).map_err(|e| at(Error { message: format!("{key}: {}", e.message), ..e }))?;
            Ok((t, matrix4_precision(m, 1.0)))
        }
        12 => {
            let r = [[v[0], v[1], v[2]], [v[4], v[5], v[6]], [v[8], v[9], v[10]]];
            let d = [v[3], v[7], v[11]];
            let t = Transform::from_matrix3(r, d, ws)
                .map_err(|e| at(Error { message: format!("{key}: {}", e.message), ..e }))?;
            Ok((t, written_precision(Written::Matrix3(r), d, 1.0)))
        }
        4 => Err(err_at(
            n,
            format!("{key}: 4 numbers without a stated order (x y z w or w x y z?): expected a 4x4 matrix; write the quaternion as {{qx, qy, qz, qw}} (or under a key ending in _t_xyz_q_xyzw), or for FusionPortable-style quaternion_A_B + translation_A_B blocks (w first) pass --input-format quaternion-yaml"),
        )),
        k if k > 16 && k % 16 == 0 => Err(err_at(
            n,
            format!(
                "{key}: {k} numbers = {} stacked 4x4 matrices: expected one; pass --key {key}[i] with i from 0 to {} to pick one",
                k / 16,
                k / 16 - 1
            ),
        )),
        k => Err(err_at(
            n,
            format!("{key}: expected 16 numbers (4x4) or 12 (3x4), found {k}"),
        )),
    }
}

/// Comment lines just above `line` (1-based) mention millimetres?
fn millimetre_comment(text: &str, line: usize) -> bool {
    let lines: Vec<&str> = text.lines().collect();
    let mut i = line.saturating_sub(1);
    while i > 0 {
        i -= 1;
        let t = lines.get(i).map(|s| s.trim()).unwrap_or("");
        if t.is_empty() {
            continue;
        }
        if !t.starts_with('#') {
            return false;
        }
        let l = t.to_lowercase();
        if l.contains("millimet") || l.contains("units: mm") {
            return true;
        }
    }
    false
}

/// One matrix key `k` (holding `v`) read as an edge `frames.0 -> frames.1`
/// (the pose of the second frame in the first) of format `format`, its
/// warnings located at the key.
pub(crate) fn matrix_edge(
    format: &'static str,
    key: &str,
    frames: (String, String),
    (k, v): (&Node, &Node),
    text: &str,
    path: &Path,
    warnings: &mut Vec<Warning>,
) -> Result<Edge> {
    let loc = loc_of(path, k);
    let mut ws = Vec::new();
    let (mut t, mut precision) = read_transform(v, key, &mut ws)?;
    if millimetre_comment(text, k.line) {
        t = t.scaled_translation(1e-3);
        precision = precision.scaled_translation(1e-3);
        ws.push(Warning::new(
            Code::AssumedConvention,
            format!("{key}: the comment above says millimetres; translation converted to metres"),
        ));
    }
    let d = *t.translation();
    check_metres(&[d.x, d.y, d.z], key, &loc, &mut ws);
    locate_warnings(ws, &loc, warnings);
    Ok(Edge::new(frames.0, frames.1, t, loc, format, key.to_string()).with_precision(precision))
}
