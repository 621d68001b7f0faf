//! Ouster sensor metadata JSON.
//!
//! Meaning: `lidar_to_sensor_transform` and `imu_to_sensor_transform` are
//! 16-element row-major 4x4 matrices in **millimetres**, each the pose of its
//! frame in the sensor frame (maps lidar / imu coordinates into `os_sensor`).
//! Edges (ouster-ros frame names): `os_sensor -> os_lidar` and
//! `os_sensor -> os_imu`, translations converted to metres. Both layouts are read:
//! the legacy flat one (firmware <= 2.x, keys at the top level) and the nested one
//! (firmware 3.x, under `lidar_intrinsics` / `imu_intrinsics`); the first
//! occurrence of each key wins. Other JSON files are read with `--key NAME`
//! (see `yaml_dialects`): JSON is read through the YAML reader, which keeps
//! line numbers.

use crate::diagnostic::{Error, Location, Result};
use crate::formats::json::json_documents;
use crate::formats::spec::{locate_warnings, Confidence, FormatSpec, LoadOptions, Parsed};
use crate::formats::yaml::{Node, Value};
use crate::formats::{matrix_tree, yaml_keyed};
use crate::frames::Edge;
use crate::geometry::se3::Transform;
use crate::geometry::uncertainty::matrix4_precision;
use std::path::Path;

fn find<'a>(n: &'a Node, key: &str) -> Option<(&'a Node, &'a Node)> {
    match &n.value {
        Value::Map(m) => {
            for (k, v) in m {
                if k.as_str().as_deref() == Some(key) {
                    return Some((k, v));
                }
            }
            m.iter().find_map(|(_, v)| find(v, key))
        }
        Value::Seq(s) => s.iter().find_map(|v| find(v, key)),
        _ => None,
    }
}

/// Parse Ouster metadata (or any JSON with `--key`).
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let docs = json_documents(text)?;
    let Some(doc) = docs.first() else {
        return Err(Error::parse("empty JSON document"));
    };
    if let Some(key) = &opts.key {
        return yaml_keyed::parse_keyed(&docs, key, text, path, opts.assume.as_ref());
    }
    let mut out = Parsed::default();
    for (key, child) in [
        ("lidar_to_sensor_transform", "os_lidar"),
        ("imu_to_sensor_transform", "os_imu"),
    ] {
        let Some((k, v)) = find(doc, key) else {
            continue;
        };
        let loc = Location::at(path, k.line.max(1), Some(k.column.max(1)));
        let nums = v.numbers(key).map_err(|e| e.at(&loc))?;
        if nums.len() != 16 {
            return Err(Error::parse(format!(
                "{key}: expected 16 numbers (row-major 4x4, mm), found {}",
                nums.len()
            ))
            .at(&loc));
        }
        let m = [
            [nums[0], nums[1], nums[2], nums[3]],
            [nums[4], nums[5], nums[6], nums[7]],
            [nums[8], nums[9], nums[10], nums[11]],
            [nums[12], nums[13], nums[14], nums[15]],
        ];
        let mut ws = Vec::new();
        let t = Transform::from_matrix4(m, &mut ws)
            .map_err(|e| {
                Error {
                    message: format!("{key}: {}", e.message),
                    ..e
                }
                .at(&loc)
            })?
            .scaled_translation(1e-3);
        locate_warnings(ws, &loc, &mut out.warnings);
        out.edges.push(
            Edge::new(
                "os_sensor",
                child,
                t,
                loc,
                SPEC.id,
                format!("{key} (mm -> m)"),
            )
            .with_precision(matrix4_precision(m, 1e-3)),
        );
    }
    if out.edges.is_empty() {
        // Not Ouster metadata: matrices under T_A_B / A_T_B keys are read as in YAML.
        return matrix_tree::parse(&docs, text, path).map_err(|e| {
            Error {
                message: format!(
                    "JSON without `lidar_to_sensor_transform` or `imu_to_sensor_transform` (Ouster sensor metadata), `transforms` records with `source_frame` (Ouster extrinsic_parameters.json), rows with `sensor_name` + `tx_m` (Argoverse 2) or nuScenes `sensor_token` records; {}",
                    e.message
                ),
                ..e
            }
        });
    }
    Ok(out)
}

/// Ouster sensor metadata JSON.
pub const SPEC: FormatSpec = FormatSpec {
    id: "ouster-json",
    description: "Ouster sensor metadata JSON (legacy flat or nested): `lidar_to_sensor_transform` / `imu_to_sensor_transform`, row-major 4x4 in millimetres, converted to metres: edges os_sensor -> os_lidar and os_sensor -> os_imu",
    // Not claimed by extension: nuScenes' `.json` lists sniff higher. Any
    // other `.json` (or text that starts like JSON) is read here.
    extensions: &[],
    walk: &[".json"],
    magic: &[],
    sniff: |i| {
        if i.trimmed().starts_with(['{', '[']) {
            Some(Confidence::Json)
        } else {
            (i.ext() == "json").then_some(Confidence::Extension)
        }
    },
    parse: |i, o| parse(i.text()?, i.path(), o),
    checked: true,
};
