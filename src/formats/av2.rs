//! `av2-json`: Argoverse 2's `egovehicle_SE3_sensor` table as JSON rows.
//!
//! The dataset ships the table as an Arrow IPC (`.feather`) file, which the
//! tool does not read (README: the Rust Arrow reader panics and aborts on
//! corrupted files); its rows converted to JSON (a list of objects, as
//! pyarrow's `Table.to_pylist()` gives them) are read here.
//!
//! Meaning, per the av2 API (argoverse/av2-api `src/av2/utils/io.py`,
//! `read_ego_SE3_sensor`, at commit b7321d1f71f6ce0ecdd151f4f2b648338c191edd):
//! each row is `ego_SE3_sensor`, "an SE3 transformation from the sensor
//! reference frame to the egovehicle reference frame": rotation from the
//! quaternion `qw, qx, qy, qz` (scalar first), translation `tx_m, ty_m, tz_m`
//! in metres. So each row is the pose of `sensor_name` in the egovehicle
//! frame: edge `egovehicle -> sensor_name`. A sensor listed twice with
//! different values is ambiguous: an `ambiguous-key` warning names both lines
//! and its edge is left out; `--key SENSOR_NAME` reads one row.

use crate::diagnostic::{Code, Error, Result, Warning};
use crate::formats::registry::{FormatSpec, Sniff};
use crate::formats::yaml::{self, Node, Value};
use crate::formats::yaml_dialects::{err_at, loc_of};
use crate::formats::{check_metres, locate_warnings, Edge, LoadOptions, Loaded};
use crate::geometry::se3::{QuatOrder, Transform};
use crate::geometry::uncertainty::{written_precision, Written};
use std::collections::BTreeMap;
use std::path::Path;

/// What a row must hold, for messages.
const ROW: &str =
    "{sensor_name, qw, qx, qy, qz, tx_m, ty_m, tz_m} (Argoverse 2 egovehicle_SE3_sensor rows)";

/// The parent frame of every row (the av2 API's name for the vehicle frame).
const EGO: &str = "egovehicle";

fn number(row: &Node, key: &str) -> Result<f64> {
    let v = row.get(key).ok_or_else(|| {
        err_at(
            row,
            format!("row: expected `{key}` (a number), found none; a row is {ROW}"),
        )
    })?;
    match &v.value {
        Value::Num(n) => Ok(*n),
        _ => Err(err_at(
            v,
            format!("`{key}`: expected a number, found {}", v.kind()),
        )),
    }
}

fn sensor_name(row: &Node) -> Result<String> {
    match row.get("sensor_name").map(|v| (v, &v.value)) {
        Some((_, Value::Str(s))) if !s.trim().is_empty() => Ok(s.trim().to_string()),
        Some((v, _)) => Err(err_at(
            v,
            format!(
                "`sensor_name`: expected a non-empty string, found {}",
                v.kind()
            ),
        )),
        None => Err(err_at(
            row,
            format!("row: expected `sensor_name`, found none; a row is {ROW}"),
        )),
    }
}

/// One row as an edge `egovehicle -> sensor_name`.
fn row_edge(row: &Node, path: &Path, ws: &mut Vec<Warning>) -> Result<Edge> {
    if !matches!(row.value, Value::Map(_)) {
        return Err(err_at(
            row,
            format!("row: expected an object {ROW}, found {}", row.kind()),
        ));
    }
    let loc = loc_of(path, row);
    let name = sensor_name(row)?;
    let q = [
        number(row, "qw")?,
        number(row, "qx")?,
        number(row, "qy")?,
        number(row, "qz")?,
    ];
    let d = [
        number(row, "tx_m")?,
        number(row, "ty_m")?,
        number(row, "tz_m")?,
    ];
    let mut local = Vec::new();
    let t =
        Transform::from_quaternion(q, QuatOrder::Wxyz, d, &mut local).map_err(|e| e.at(&loc))?;
    check_metres(&d, "tx_m, ty_m, tz_m", &loc, &mut local);
    locate_warnings(local, &loc, ws);
    Ok(Edge::new(
        EGO,
        name.as_str(),
        t,
        loc,
        AV2_JSON.id,
        format!("egovehicle_SE3_sensor {name} (q w x y z + t m)"),
    )
    .with_precision(written_precision(Written::Quat(q, QuatOrder::Wxyz), d, 1.0)))
}

/// Keeps one edge per sensor; a sensor listed twice with different values is
/// left out with an `ambiguous-key` warning naming both lines.
fn resolve_duplicates(edges: Vec<Edge>, out: &mut Loaded) {
    let mut by_child: BTreeMap<String, Vec<Edge>> = BTreeMap::new();
    let mut order = Vec::new();
    for e in edges {
        if !by_child.contains_key(&e.child) {
            order.push(e.child.clone());
        }
        by_child.entry(e.child.clone()).or_default().push(e);
    }
    for child in order {
        let Some(mut rows) = by_child.remove(&child) else {
            continue;
        };
        let first = rows.remove(0);
        let Some(other) = rows.iter().find(|e| e.transform != first.transform) else {
            out.edges.push(first);
            continue;
        };
        let line = |e: &Edge| e.provenance.location.line.unwrap_or(0);
        out.warnings.push(
            Warning::new(
                Code::AmbiguousKey,
                format!(
                    "sensor {child} is listed {} times with different values (lines {} and {}): its edge {EGO} -> {child} is left out; keep one row",
                    rows.len() + 1,
                    line(&first),
                    line(other)
                ),
            )
            .at(&other.provenance.location),
        );
    }
}

/// Parse Argoverse 2 `egovehicle_SE3_sensor` rows (JSON).
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    if let Err(e) = serde_json::from_str::<serde_json::Value>(text) {
        let msg = e.to_string();
        let msg = msg.split(" at line ").next().unwrap_or("").to_string();
        return Err(Error::parse(format!("not valid JSON: {msg}"))
            .at_line(e.line().max(1), Some(e.column().max(1))));
    }
    let docs = yaml::parse_documents(&text.replace('\t', " "))?;
    let Some(Value::Seq(rows)) = docs.first().map(|d| &d.value) else {
        return Err(Error::parse(format!(
            "Argoverse 2 egovehicle_SE3_sensor JSON: expected a list of rows {ROW}, found another value"
        )));
    };
    let mut out = Loaded::default();
    let mut edges = Vec::new();
    for row in rows {
        if let Some(k) = &opts.key {
            if sensor_name(row).ok().as_deref() != Some(k.trim()) {
                continue;
            }
        }
        edges.push(row_edge(row, path, &mut out.warnings)?);
    }
    resolve_duplicates(edges, &mut out);
    if out.edges.is_empty() {
        let why = match &opts.key {
            Some(k) => format!("no row with sensor_name {k}"),
            None if !out.warnings.is_empty() => "every sensor is listed twice".to_string(),
            None => "no row".to_string(),
        };
        return Err(Error::parse(format!(
            "Argoverse 2 egovehicle_SE3_sensor JSON: {why}; expected rows {ROW}"
        )));
    }
    Ok(out)
}

fn sniff(s: &Sniff) -> Option<u8> {
    (s.trimmed.starts_with('[')
        && s.head.contains("\"sensor_name\"")
        && s.head.contains("\"tx_m\""))
    .then_some(85)
}

/// Argoverse 2 egovehicle_SE3_sensor rows as JSON.
pub const AV2_JSON: FormatSpec = FormatSpec {
    id: "av2-json",
    description: "Argoverse 2 `egovehicle_SE3_sensor` rows as JSON (the .feather table converted: `sensor_name`, `qw qx qy qz`, `tx_m ty_m tz_m`, the av2 API's ego_SE3_sensor): the sensor pose in the egovehicle frame, edges egovehicle -> sensor_name; --key SENSOR_NAME reads one row",
    // Not claimed by extension: other `.json` formats share it.
    extensions: &[],
    walk: &[".json"],
    sniff,
    parse,
};
