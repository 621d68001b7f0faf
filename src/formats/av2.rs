//! `av2-feather` and `av2-json`: Argoverse 2's `egovehicle_SE3_sensor` table.
//!
//! The dataset ships the table as an Arrow IPC file (`.feather`), read here
//! through the bounded reader of [`super::arrow_ipc`] (columns `sensor_name`
//! Utf8 or LargeUtf8, the seven numbers Float64; uncompressed, LZ4 or ZSTD;
//! a null in one of them is an error naming the row); the same rows converted
//! to JSON (a list of objects, as pyarrow's `Table.to_pylist()` gives them)
//! are read too. Both give the same edges through one row -> edge function.
//!
//! Meaning, per the av2 API (argoverse/av2-api `src/av2/utils/io.py`,
//! `read_ego_SE3_sensor`, at commit b7321d1f71f6ce0ecdd151f4f2b648338c191edd):
//! each row is `ego_SE3_sensor`, "an SE3 transformation from the sensor
//! reference frame to the egovehicle reference frame": rotation from the
//! quaternion `qw, qx, qy, qz` (scalar first), translation `tx_m, ty_m, tz_m`
//! in metres. So each row is the pose of `sensor_name` in the egovehicle
//! frame: edge `egovehicle -> sensor_name`. A sensor listed twice with
//! different values is ambiguous: an `ambiguous-key` warning names both lines
//! (JSON) or rows (.feather) and its edge is left out; `--key SENSOR_NAME`
//! reads one row. Feather rows carry no line: an edge's place is the file and
//! its key names the row.

use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::arrow_ipc::{self, Column};
use crate::formats::json::json_documents;
use crate::formats::spec::{
    check_metres, locate_warnings, Confidence, FormatSpec, Input, LoadOptions, Parsed,
};
use crate::formats::yaml::{Node, Value};
use crate::formats::yaml_shapes::{err_at, loc_of};
use crate::frames::Edge;
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

/// One row of the table, from either reader.
struct Row {
    name: String,
    q: [f64; 4],
    d: [f64; 3],
    loc: Location,
    /// Where the row is, for messages (`line 3`, `row 3`).
    place: String,
}

/// One JSON row as a [`Row`].
fn json_row(row: &Node, path: &Path) -> Result<Row> {
    if !matches!(row.value, Value::Map(_)) {
        return Err(err_at(
            row,
            format!("row: expected an object {ROW}, found {}", row.kind()),
        ));
    }
    let loc = loc_of(path, row);
    Ok(Row {
        name: sensor_name(row)?,
        q: [
            number(row, "qw")?,
            number(row, "qx")?,
            number(row, "qy")?,
            number(row, "qz")?,
        ],
        d: [
            number(row, "tx_m")?,
            number(row, "ty_m")?,
            number(row, "tz_m")?,
        ],
        place: format!("line {}", loc.line.unwrap_or(0)),
        loc,
    })
}

/// One row as an edge `egovehicle -> sensor_name` (both readers).
fn row_edge(row: Row, format: &'static str, ws: &mut Vec<Warning>) -> Result<(Edge, String)> {
    let Row {
        name,
        q,
        d,
        loc,
        place,
    } = row;
    // A feather row has no line: its messages and key name the row instead.
    let row_of = |m: &str| match loc.line {
        Some(_) => m.to_string(),
        None => format!("{place} ({name}): {m}"),
    };
    let key = match loc.line {
        Some(_) => format!("egovehicle_SE3_sensor {name} (q w x y z + t m)"),
        None => format!("egovehicle_SE3_sensor {name} ({place}, q w x y z + t m)"),
    };
    let mut local = Vec::new();
    let t = Transform::from_quaternion(q, QuatOrder::Wxyz, d, &mut local).map_err(|mut e| {
        e.message = row_of(&e.message);
        e.at(&loc)
    })?;
    check_metres(&d, "tx_m, ty_m, tz_m", &loc, &mut local);
    for w in &mut local {
        w.message = row_of(&w.message);
    }
    locate_warnings(local, &loc, ws);
    let edge = Edge::new(EGO, name.as_str(), t, loc, format, key)
        .with_precision(written_precision(Written::Quat(q, QuatOrder::Wxyz), d, 1.0));
    Ok((edge, place))
}

/// Keeps one edge per sensor; a sensor listed twice with different values is
/// left out with an `ambiguous-key` warning naming both places.
fn resolve_duplicates(edges: Vec<(Edge, String)>, out: &mut Parsed) {
    let mut by_child: BTreeMap<String, Vec<(Edge, String)>> = BTreeMap::new();
    let mut order = Vec::new();
    for e in edges {
        if !by_child.contains_key(&e.0.child) {
            order.push(e.0.child.clone());
        }
        by_child.entry(e.0.child.clone()).or_default().push(e);
    }
    for child in order {
        let Some(mut rows) = by_child.remove(&child) else {
            continue;
        };
        let (first, first_at) = rows.remove(0);
        let Some((other, other_at)) = rows.iter().find(|e| e.0.transform != first.transform) else {
            out.edges.push(first);
            continue;
        };
        let places = match (first_at.split_once(' '), other_at.split_once(' ')) {
            (Some((w, a)), Some((_, b))) => format!("{w}s {a} and {b}"),
            _ => format!("{first_at} and {other_at}"),
        };
        out.warnings.push(
            Warning::new(
                Code::AmbiguousKey,
                format!(
                    "sensor {child} is listed {} times with different values ({places}): its edge {EGO} -> {child} is left out; keep one row",
                    rows.len() + 1,
                ),
            )
            .at(&other.provenance.location),
        );
    }
}

/// The edges of `rows` (those `--key` selects), duplicates resolved.
fn finish(rows: Vec<Row>, what: &str, format: &'static str, opts: &LoadOptions) -> Result<Parsed> {
    let mut out = Parsed::default();
    let mut edges = Vec::new();
    for row in rows {
        if opts.key.as_deref().is_some_and(|k| k.trim() != row.name) {
            continue;
        }
        edges.push(row_edge(row, format, &mut out.warnings)?);
    }
    resolve_duplicates(edges, &mut out);
    if out.edges.is_empty() {
        let why = match &opts.key {
            Some(k) => format!("no row with sensor_name {k}"),
            None if !out.warnings.is_empty() => "every sensor is listed twice".to_string(),
            None => "no row".to_string(),
        };
        return Err(Error::parse(format!(
            "Argoverse 2 egovehicle_SE3_sensor {what}: {why}; expected rows {ROW}"
        )));
    }
    Ok(out)
}

/// Parse Argoverse 2 `egovehicle_SE3_sensor` rows (JSON).
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let docs = json_documents(text)?;
    let Some(Value::Seq(rows)) = docs.first().map(|d| &d.value) else {
        return Err(Error::parse(format!(
            "Argoverse 2 egovehicle_SE3_sensor JSON: expected a list of rows {ROW}, found another value"
        )));
    };
    let mut read = Vec::new();
    for row in rows {
        if let Some(k) = &opts.key {
            if sensor_name(row).ok().as_deref() != Some(k.trim()) {
                continue;
            }
        }
        read.push(json_row(row, path)?);
    }
    finish(read, "JSON", AV2_JSON.id, opts)
}

fn sniff(i: &Input) -> Option<Confidence> {
    let head = i.text_head();
    (i.trimmed().starts_with('[') && head.contains("\"sensor_name\"") && head.contains("\"tx_m\""))
        .then_some(Confidence::Document)
}

/// Argoverse 2 egovehicle_SE3_sensor rows as JSON.
pub const AV2_JSON: FormatSpec = FormatSpec {
    id: "av2-json",
    description: "Argoverse 2 `egovehicle_SE3_sensor` rows as JSON (the .feather table converted: `sensor_name`, `qw qx qy qz`, `tx_m ty_m tz_m`, the av2 API's ego_SE3_sensor): the sensor pose in the egovehicle frame, edges egovehicle -> sensor_name; --key SENSOR_NAME reads one row",
    // Not claimed by extension: other `.json` formats share it.
    extensions: &[],
    walk: &[".json"],
    magic: &[],
    sniff,
    parse: |i, o| parse(i.text()?, i.path(), o),
    checked: true,
};

/// The table's columns: name and whether it holds text.
const COLUMNS: [(&str, bool); 8] = [
    ("sensor_name", true),
    ("qw", false),
    ("qx", false),
    ("qy", false),
    ("qz", false),
    ("tx_m", false),
    ("ty_m", false),
    ("tz_m", false),
];

/// Value `r` of a string column (`None`: null or another type).
fn text_at(col: &Column, r: usize) -> Option<&str> {
    match col {
        Column::Str(v) => v.get(r)?.as_deref(),
        Column::F64(_) => None,
    }
}

/// Row `r` (0-based) of the Arrow table as a [`Row`]; a null is an error.
/// The columns come in [`COLUMNS`] order: `sensor_name`, then the numbers.
fn feather_row(cols: &[(String, Column)], r: usize, path: &Path) -> Result<Row> {
    let null = |c: &str| {
        Error::parse(format!(
            "row {}: `{c}` is null: expected a value; a row is {ROW}",
            r + 1
        ))
    };
    let Some(((_, names), numbers)) = cols.split_first() else {
        return Err(null("sensor_name"));
    };
    let name = text_at(names, r).ok_or_else(|| null("sensor_name"))?.trim();
    if name.is_empty() {
        return Err(Error::parse(format!(
            "row {}: `sensor_name`: expected a non-empty string, found an empty one",
            r + 1
        )));
    }
    let mut nums = [0.0; 7];
    for ((c, col), slot) in numbers.iter().zip(nums.iter_mut()) {
        *slot = match col {
            Column::F64(v) => v.get(r).copied().flatten(),
            Column::Str(_) => None,
        }
        .ok_or_else(|| null(c))?;
    }
    Ok(Row {
        name: name.to_string(),
        q: [nums[0], nums[1], nums[2], nums[3]],
        d: [nums[4], nums[5], nums[6]],
        loc: Location::file(path),
        place: format!("row {}", r + 1),
    })
}

/// Parse an Argoverse 2 `egovehicle_SE3_sensor.feather` file (its bytes).
/// With `--key`, only the rows of that sensor are read (as for JSON rows).
pub fn parse_feather(bytes: &[u8], path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let table = arrow_ipc::read_columns(bytes, &COLUMNS, opts.max_file_size)?;
    let wanted = |r: usize| {
        opts.key.as_deref().is_none_or(|k| {
            let name = table.columns.first().and_then(|(_, c)| text_at(c, r));
            name.map(str::trim) == Some(k.trim())
        })
    };
    let rows = (0..table.rows)
        .filter(|&r| wanted(r))
        .map(|r| feather_row(&table.columns, r, path))
        .collect::<Result<Vec<_>>>()?;
    finish(rows, "table (.feather)", AV2_FEATHER.id, opts)
}

/// Argoverse 2 egovehicle_SE3_sensor.feather (Arrow IPC file).
pub const AV2_FEATHER: FormatSpec = FormatSpec {
    id: "av2-feather",
    description: "Argoverse 2 `egovehicle_SE3_sensor.feather` (Arrow IPC file, uncompressed, LZ4 or ZSTD: `sensor_name`, `qw qx qy qz`, `tx_m ty_m tz_m`, the av2 API's ego_SE3_sensor): the sensor pose in the egovehicle frame, edges egovehicle -> sensor_name; --key SENSOR_NAME reads one row",
    extensions: &["feather"],
    walk: &[".feather"],
    magic: &[arrow_ipc::MAGIC],
    sniff: |_| None,
    parse: |i, o| parse_feather(i.bytes()?, i.path(), o),
    checked: true,
};
