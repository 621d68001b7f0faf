//! `ouster-extrinsics`: the Ouster SDK's `extrinsic_parameters.json`.
//!
//! Layout, as the SDK reads it (ouster-lidar/ouster-sdk
//! `ouster_core/src/open_source.cpp`, `populate_extrinsics`, and writes it
//! (`python/src/ouster/cli/plugins/source.py`, `source_save_extrinsics`), both
//! at commit 46b7bceee7995914e2f3f3facf4d78418335b2d7): an object whose
//! `transforms` list holds one record per sensor,
//! `{source_frame, destination_frame, p_x, p_y, p_z, q_w, q_x, q_y, q_z}`.
//! The SDK builds `sensor_to_body` from each record: rotation from the
//! normalised quaternion **(w, x, y, z)**, translation `p` in metres, and
//! documents that matrix as the "homogeneous transform from sensor frame to
//! body frame" (`ouster_core/include/ouster/core/sensor_info.h`): it maps
//! points of `source_frame` (the sensor, named by its serial number) into
//! `destination_frame` (`world` in every file the SDK writes). So each record
//! is the pose of `source_frame` in `destination_frame`: edge
//! `destination_frame -> source_frame`, both names as written.
//!
//! Also read: a bare record (one object, as the sensor's Perception API
//! returns it) and a top-level list of records. A record without
//! `destination_frame` (the SDK ignores the field) is placed under `world`
//! with an `assumed-convention` warning. Translations are not checked as lever
//! arms: sensors are placed in a site frame, tens of metres apart. A
//! `source_frame` given twice with different values is ambiguous (the SDK
//! silently keeps the last): an `ambiguous-key` warning names both lines and
//! that sensor's edge is left out; `--key SOURCE_FRAME` reads one sensor.

use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::json::json_documents;
use crate::formats::spec::{locate_warnings, Confidence, FormatSpec, Input, LoadOptions, Parsed};
use crate::formats::yaml::{Node, Value};
use crate::formats::yaml_shapes::{err_at, loc_of};
use crate::frames::Edge;
use crate::geometry::se3::{QuatOrder, Transform};
use crate::geometry::uncertainty::{written_precision, Written};
use std::collections::BTreeMap;
use std::path::Path;

/// What a record must hold, for messages.
const RECORD: &str =
    "{source_frame, destination_frame, p_x, p_y, p_z, q_w, q_x, q_y, q_z} (Ouster extrinsic_parameters.json)";

/// The destination frame of every file the SDK writes.
const DEFAULT_DESTINATION: &str = "world";

fn frame_name(rec: &Node, key: &str) -> Result<Option<String>> {
    let Some(v) = rec.get(key) else {
        return Ok(None);
    };
    match &v.value {
        Value::Str(s) if !s.trim().is_empty() => Ok(Some(s.trim().to_string())),
        _ => Err(err_at(
            v,
            format!(
                "`{key}`: expected a frame name (a non-empty string), found {}",
                v.kind()
            ),
        )),
    }
}

fn number(rec: &Node, key: &str) -> Result<f64> {
    let v = rec.get(key).ok_or_else(|| {
        err_at(
            rec,
            format!("record: expected `{key}` (a number), found none; a record is {RECORD}"),
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

/// One record as an edge `destination_frame -> source_frame`.
fn record_edge(rec: &Node, path: &Path, ws: &mut Vec<Warning>) -> Result<Edge> {
    if !matches!(rec.value, Value::Map(_)) {
        return Err(err_at(
            rec,
            format!("record: expected an object {RECORD}, found {}", rec.kind()),
        ));
    }
    let loc = loc_of(path, rec);
    let child = frame_name(rec, "source_frame")?.ok_or_else(|| {
        err_at(
            rec,
            "record: expected `source_frame` (the sensor's serial number or frame name), found none"
                .into(),
        )
    })?;
    let parent = match frame_name(rec, "destination_frame")? {
        Some(p) => p,
        None => {
            ws.push(
                Warning::new(
                    Code::AssumedConvention,
                    format!("record of {child} has no `destination_frame`: placed under `{DEFAULT_DESTINATION}`, the frame every file the Ouster SDK writes names"),
                )
                .at(&loc),
            );
            DEFAULT_DESTINATION.to_string()
        }
    };
    let d = [
        number(rec, "p_x")?,
        number(rec, "p_y")?,
        number(rec, "p_z")?,
    ];
    let q = [
        number(rec, "q_w")?,
        number(rec, "q_x")?,
        number(rec, "q_y")?,
        number(rec, "q_z")?,
    ];
    let mut local = Vec::new();
    let t =
        Transform::from_quaternion(q, QuatOrder::Wxyz, d, &mut local).map_err(|e| e.at(&loc))?;
    locate_warnings(local, &loc, ws);
    Ok(Edge::new(
        parent.as_str(),
        child.as_str(),
        t,
        loc,
        SPEC.id,
        format!("transforms[] {child} in {parent} (p + q w x y z)"),
    )
    .with_precision(written_precision(Written::Quat(q, QuatOrder::Wxyz), d, 1.0)))
}

/// The records of the document: `transforms`, a list, or one bare record.
fn records(doc: &Node) -> Result<Vec<&Node>> {
    match &doc.value {
        Value::Seq(items) => Ok(items.iter().collect()),
        Value::Map(_) => match doc.get("transforms") {
            Some(Node {
                value: Value::Seq(items),
                ..
            }) => Ok(items.iter().collect()),
            Some(other) => Err(err_at(
                other,
                format!(
                    "`transforms`: expected a list of records {RECORD}, found {}",
                    other.kind()
                ),
            )),
            None if doc.get("source_frame").is_some() => Ok(vec![doc]),
            None => {
                let keys: Vec<String> = doc
                    .entries()
                    .iter()
                    .filter_map(|(k, _)| k.as_str())
                    .take(8)
                    .collect();
                Err(err_at(
                    doc,
                    format!(
                        "expected `transforms` (a list of records {RECORD}) or one record, found keys {}",
                        keys.join(", ")
                    ),
                ))
            }
        },
        _ => Err(err_at(
            doc,
            format!(
                "expected an object with `transforms` (Ouster extrinsic_parameters.json), found {}",
                doc.kind()
            ),
        )),
    }
}

/// Keeps one edge per sensor; a sensor given twice with different values is
/// left out with an `ambiguous-key` warning naming both places.
fn resolve_duplicates(edges: Vec<Edge>, out: &mut Parsed) {
    let mut by_child: BTreeMap<String, Vec<Edge>> = BTreeMap::new();
    let mut order = Vec::new();
    for e in edges {
        if !by_child.contains_key(&e.child) {
            order.push(e.child.clone());
        }
        by_child.entry(e.child.clone()).or_default().push(e);
    }
    for child in order {
        let Some(mut recs) = by_child.remove(&child) else {
            continue;
        };
        let first = recs.remove(0);
        let Some(other) = recs
            .iter()
            .find(|e| e.transform != first.transform || e.parent != first.parent)
        else {
            out.edges.push(first);
            continue;
        };
        out.warnings.push(
            Warning::new(
                Code::AmbiguousKey,
                format!(
                    "source_frame {child} is given {} times with different values ({} and {}): its edge is left out; keep one record",
                    recs.len() + 1,
                    where_(&first.provenance.location),
                    where_(&other.provenance.location)
                ),
            )
            .at(&other.provenance.location),
        );
    }
}

fn where_(l: &Location) -> String {
    match l.line {
        Some(n) => format!("line {n}"),
        None => "the file".to_string(),
    }
}

/// Parse an Ouster `extrinsic_parameters.json`.
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let docs = json_documents(text)?;
    let Some(doc) = docs.first() else {
        return Err(Error::parse("empty JSON document"));
    };
    let mut out = Parsed::default();
    let mut edges = Vec::new();
    for rec in records(doc)? {
        if let Some(k) = &opts.key {
            let name = frame_name(rec, "source_frame").ok().flatten();
            if name.as_deref() != Some(k.trim()) {
                continue;
            }
        }
        edges.push(record_edge(rec, path, &mut out.warnings)?);
    }
    resolve_duplicates(edges, &mut out);
    if out.edges.is_empty() {
        let why = match &opts.key {
            Some(k) => format!("no record with source_frame {k}"),
            None if out.warnings.iter().any(|w| w.code == Code::AmbiguousKey) => {
                "every sensor is given twice with different values".to_string()
            }
            None => "no record".to_string(),
        };
        return Err(Error::parse(format!(
            "Ouster extrinsic_parameters.json: {why}; expected `transforms` records {RECORD}"
        )));
    }
    Ok(out)
}

fn sniff(i: &Input) -> Option<Confidence> {
    let head = i.text_head();
    (i.trimmed().starts_with(['{', '['])
        && head.contains("\"source_frame\"")
        && ["\"q_w\"", "\"p_x\"", "\"destination_frame\""]
            .iter()
            .any(|k| head.contains(k)))
    .then_some(Confidence::Document)
}

/// Ouster extrinsic_parameters.json.
pub const SPEC: FormatSpec = FormatSpec {
    id: "ouster-extrinsics",
    description: "Ouster SDK `extrinsic_parameters.json` (`transforms`: `p_x p_y p_z` m + `q_w q_x q_y q_z`, the SDK's sensor_to_body): the pose of `source_frame` (sensor serial) in `destination_frame` (`world`), edges destination_frame -> source_frame; --key SOURCE_FRAME reads one sensor",
    // Not claimed by extension: other `.json` formats share it.
    extensions: &[],
    walk: &[".json"],
    magic: &[],
    sniff,
    parse: |i, o| parse(i.text()?, i.path(), o),
    checked: true,
};
