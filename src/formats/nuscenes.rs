//! `nuscenes-json`: nuScenes `calibrated_sensor.json` (the dataset's schema,
//! nuscenes-devkit `docs/schema_nuscenes.md`): a list of records
//! `{token, sensor_token, translation, rotation, camera_intrinsic}`. "All
//! extrinsic parameters are given with respect to the ego vehicle body
//! frame": `translation` is the sensor's origin in the ego frame (m),
//! `rotation` its orientation as a quaternion **w, x, y, z** (the devkit reads
//! it as `Quaternion(cs['rotation'])`, pyquaternion's w-first order, and maps
//! sensor points into the ego frame with it). So each record is the sensor's
//! pose in the ego frame: edge `ego -> CHANNEL`.
//!
//! Frame names: the channel (`LIDAR_TOP`, `CAM_FRONT`, ...) from the
//! `sensor.json` beside the file (`sensor_token` -> `channel`); without it,
//! `sensor_<first 8 hex digits of sensor_token>` and an `assumed-convention`
//! warning. A channel calibrated more than once with different values (one
//! record per vehicle log) is ambiguous: an `ambiguous-key` warning lists the
//! record tokens and its edges are left out; `--key TOKEN` reads one record.

use crate::diagnostic::{Code, Error, Result, Warning};
use crate::formats::json::json_documents;
use crate::formats::spec::{
    check_metres, locate_warnings, Confidence, FormatSpec, Input, LoadOptions, Parsed,
};
use crate::formats::yaml::{Node, Value};
use crate::formats::yaml_shapes::{err_at, exactly, loc_of};
use crate::frames::Edge;
use crate::geometry::se3::{QuatOrder, Transform};
use std::collections::BTreeMap;
use std::path::Path;

/// Largest `sensor.json` read beside the file (bytes): the dataset's has a
/// dozen records.
const SENSOR_JSON_MAX: u64 = 1 << 20;

fn text_field(n: &Node, key: &str) -> Result<String> {
    n.get(key)
        .and_then(|v| v.as_str())
        .ok_or_else(|| err_at(n, format!("record: expected a string `{key}`, found none")))
}

/// `sensor_token -> channel` from `sensor.json` beside `path`; `None` when
/// there is none. One that is there but not valid JSON (a key given twice
/// included) is an error naming it: its channel names would be a guess.
fn channels(path: &Path) -> Result<Option<BTreeMap<String, String>>> {
    let Some(p) = path.parent().map(|d| d.join("sensor.json")) else {
        return Ok(None);
    };
    if !p.is_file() {
        return Ok(None);
    }
    let text = crate::input::read_text(&p, SENSOR_JSON_MAX, "sensor.json")?;
    let docs = json_documents(&text).map_err(|e| e.in_file(&p))?;
    let Some(Value::Seq(items)) = docs.first().map(|d| &d.value) else {
        return Ok(None);
    };
    Ok(Some(
        items
            .iter()
            .filter_map(|it| Some((it.get("token")?.as_str()?, it.get("channel")?.as_str()?)))
            .collect(),
    ))
}

/// One record as an edge `ego -> frame`.
fn record_edge(
    it: &Node,
    frame: String,
    token: &str,
    path: &Path,
    ws: &mut Vec<Warning>,
) -> Result<Edge> {
    let loc = loc_of(path, it);
    let tn = it.get("translation").ok_or_else(|| {
        err_at(
            it,
            "record: expected `translation` (3 numbers), found none".into(),
        )
    })?;
    let rn = it.get("rotation").ok_or_else(|| {
        err_at(
            it,
            "record: expected `rotation` (quaternion w, x, y, z), found none".into(),
        )
    })?;
    let d = exactly::<3>(tn, "translation")?;
    let q = exactly::<4>(rn, "rotation")?;
    let mut local = Vec::new();
    let t =
        Transform::from_quaternion(q, QuatOrder::Wxyz, d, &mut local).map_err(|e| e.at(&loc))?;
    check_metres(&d, "translation", &loc, &mut local);
    locate_warnings(local, &loc, ws);
    Ok(Edge::new(
        "ego",
        frame,
        t,
        loc,
        NUSCENES.id,
        format!("calibrated_sensor {token} (rotation w x y z + translation)"),
    ))
}

/// nuScenes calibrated_sensor.json.
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let docs = json_documents(text)?;
    let Some(Value::Seq(items)) = docs.first().map(|d| &d.value) else {
        return Err(Error::parse(
            "nuScenes calibrated_sensor.json: expected a list of records, found another value",
        ));
    };
    let names = channels(path)?;
    let mut out = Parsed::default();
    let mut by_frame: BTreeMap<String, Vec<(String, Edge)>> = BTreeMap::new();
    for it in items {
        let token = text_field(it, "token")?;
        if opts.key.as_ref().is_some_and(|k| *k != token) {
            continue;
        }
        let sensor = text_field(it, "sensor_token")?;
        let frame = match names.as_ref().and_then(|m| m.get(&sensor)) {
            Some(c) => c.clone(),
            None => format!("sensor_{}", sensor.chars().take(8).collect::<String>()),
        };
        let e = record_edge(it, frame.clone(), &token, path, &mut out.warnings)?;
        by_frame.entry(frame).or_default().push((token, e));
    }
    if names.is_none() {
        out.warnings.push(Warning::new(
            Code::AssumedConvention,
            "no sensor.json beside calibrated_sensor.json: sensors named sensor_<first 8 digits of sensor_token>; put the dataset's sensor.json beside it for LIDAR_TOP, CAM_FRONT, ...",
        ));
    }
    for (frame, recs) in by_frame {
        let first = &recs[0].1;
        let all_same = recs.iter().all(|(_, e)| e.transform == first.transform);
        if all_same {
            out.edges.push(first.clone());
            continue;
        }
        let tokens: Vec<&str> = recs.iter().map(|(t, _)| t.as_str()).collect();
        out.warnings.push(
            Warning::new(
                Code::AmbiguousKey,
                format!(
                    "{frame} is calibrated {} times with different values (records {}): its edge ego -> {frame} is left out; read one with --key TOKEN",
                    recs.len(),
                    tokens.join(", ")
                ),
            )
            .at(&recs[1].1.provenance.location),
        );
    }
    if out.edges.is_empty() {
        let why = match &opts.key {
            Some(k) => format!("no record with token {k}"),
            None => "no sensor with one calibration".to_string(),
        };
        return Err(Error::parse(format!(
            "nuScenes calibrated_sensor.json: {why}; expected records {{token, sensor_token, translation, rotation}}"
        )));
    }
    Ok(out)
}

fn sniff(i: &Input) -> Option<Confidence> {
    (i.trimmed().starts_with('[') && i.text_head().contains("\"sensor_token\""))
        .then_some(Confidence::Claim)
}

/// nuScenes calibrated_sensor.json.
pub const NUSCENES: FormatSpec = FormatSpec {
    id: "nuscenes-json",
    description: "nuScenes `calibrated_sensor.json` (`translation` + `rotation` w, x, y, z, \"with respect to the ego vehicle body frame\"): the sensor pose in the ego frame, edges ego -> CHANNEL (names from sensor.json beside it); --key TOKEN reads one record",
    extensions: &[],
    walk: &[".json"],
    magic: &[],
    sniff,
    parse: |i, o| parse(i.text()?, i.path(), o),
    checked: true,
};
