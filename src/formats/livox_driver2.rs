//! `livox-driver2`: livox_ros_driver2's LiDAR configuration JSON
//! (`MID360_config.json`, `HAP_config.json`, mixed configs): `lidar_configs`,
//! one entry per LiDAR, each with `ip`, `pcl_data_type` and
//! `extrinsic_parameter: {roll, pitch, yaw, x, y, z}`.
//!
//! The driver moves every raw point into the published frame, `p_out = R
//! p_raw + t`: the extrinsic is the pose of the LiDAR (its raw point frame)
//! in the message's `frame_id` (a launch parameter, default `livox_frame`):
//! edge `livox_frame -> lidar_<ip with _>` (the suffix the driver puts on
//! per-LiDAR topics; `--rename` renames either). Livox-SDK/livox_ros_driver2
//! @ 13eb05e4e6dd7a765b934d0c5fd6236676a57b49:
//! `src/parse_cfg_file/parse_livox_lidar_cfg.cpp:120-153` reads roll, pitch,
//! yaw with `GetFloat` and x, y, z with `GetInt`; `src/comm/comm.h:214-222`
//! "unit: degree" and "unit: mm"; `src/comm/pub_handler.cpp:336-361` builds
//! `R = Rz(yaw) Ry(pitch) Rx(roll)` entry by entry from the angles in degrees
//! and `:375-377` `point.x = (raw.x * R[0][0] + ... + trans[0]) / 1000.0`;
//! `src/lds_lidar.cpp:163-179` divides x, y, z by 10 (integer division) for
//! `pcl_data_type` 2 (points in cm); `launch_ROS1/msg_MID360.launch:14`
//! `msg_frame_id` default `livox_frame`. Only points are transformed: the
//! extrinsic says nothing about the built-in IMU.
//!
//! Refused: a LiDAR without `extrinsic_parameter` or one of its keys (the
//! driver would use zero silently), x, y, z that are not integers (`GetInt`
//! on a float is undefined in rapidjson).

use super::calib_shapes::{edge, field, name, number, rigid_rpy, top_map};
use super::json::json_documents;
use super::spec::{check_metres, locate_warnings, Confidence, FormatSpec, Input, Parsed};
use super::yaml::{Node, Value};
use super::yaml_shapes::{err_at, loc_of};
use crate::diagnostic::Result;
use std::path::Path;

/// livox_ros_driver2 LiDAR configuration JSON.
pub const LIVOX_DRIVER2: FormatSpec = FormatSpec {
    id: "livox-driver2",
    description: "livox_ros_driver2 config JSON (`lidar_configs[].extrinsic_parameter`: roll pitch yaw in degrees, R = Rz(yaw) Ry(pitch) Rx(roll); x y z integer millimetres): each LiDAR's pose in the published frame, edges livox_frame -> lidar_<ip>",
    extensions: &[],
    walk: &[".json"],
    magic: &[],
    sniff: |i: &Input| (i.trimmed().starts_with('{') && i.contains("\"lidar_configs\"")).then_some(Confidence::Document),
    parse: |i, _| parse(i.text()?, i.path()),
    checked: true,
};

/// An integer as written (no `.` or exponent in the number's text).
fn integer(m: &Node, key: &str, what: &str, text: &str) -> Result<i64> {
    let x = number(m, key, what)?;
    let v = field(m, key, what)?;
    let line = text.lines().nth(v.line.saturating_sub(1)).unwrap_or("");
    let tok: String = line
        .chars()
        .skip(v.column.saturating_sub(1))
        .take_while(|c| !matches!(c, ',' | '}' | ']') && !c.is_whitespace())
        .collect();
    if tok.contains(['.', 'e', 'E']) || x.fract() != 0.0 || x.abs() > i32::MAX as f64 {
        return Err(err_at(v, format!("{what}.{key}: expected an integer number of millimetres (the driver reads it with GetInt), found {tok}")));
    }
    Ok(x as i64)
}

fn parse(text: &str, path: &Path) -> Result<Parsed> {
    let docs = json_documents(text)?;
    let list = field(
        top_map(&docs, "livox_ros_driver2 config")?,
        "lidar_configs",
        "livox_ros_driver2 config",
    )?;
    let Value::Seq(items) = &list.value else {
        return Err(err_at(
            list,
            format!("`lidar_configs`: expected a list, found {}", list.kind()),
        ));
    };
    let mut out = Parsed::default();
    for (i, lc) in items.iter().enumerate() {
        let what = format!("lidar_configs[{i}]");
        let ip = name(lc, "ip", &what)?;
        let ext = lc.get("extrinsic_parameter").ok_or_else(|| err_at(lc, format!("{what}: expected `extrinsic_parameter` {{roll, pitch, yaw, x, y, z}}, found none (the driver would use zero silently)")))?;
        let ew = format!("{what}.extrinsic_parameter");
        let deg = [
            number(ext, "roll", &ew)?,
            number(ext, "pitch", &ew)?,
            number(ext, "yaw", &ew)?,
        ];
        let mm = [
            integer(ext, "x", &ew, text)?,
            integer(ext, "y", &ew, text)?,
            integer(ext, "z", &ew, text)?,
        ];
        let low = lc.get("pcl_data_type").and_then(|v| v.as_f64()) == Some(2.0);
        // pcl_data_type 2: whole centimetres (C integer division truncates).
        let d = mm.map(|v| {
            if low {
                (v / 10) as f64 / 100.0
            } else {
                v as f64 / 1000.0
            }
        });
        // No rounding recorded: the angles were written in degrees.
        let read = (
            rigid_rpy(deg.map(f64::to_radians), d, ext, &ew)?.0,
            Default::default(),
        );
        let loc = loc_of(path, ext);
        let mut ws = Vec::new();
        check_metres(&d, &ew, &loc, &mut ws);
        locate_warnings(ws, &loc, &mut out.warnings);
        let unit = if low {
            "mm, used in whole cm (pcl_data_type 2)"
        } else {
            "mm"
        };
        out.edges.push(edge(
            "livox_frame",
            &format!("lidar_{}", ip.replace('.', "_")),
            read,
            path,
            ext,
            LIVOX_DRIVER2.id,
            format!("{what} ({ip}) extrinsic_parameter (deg, {unit})"),
        ));
    }
    if out.edges.is_empty() {
        return Err(err_at(
            list,
            "`lidar_configs`: expected at least one LiDAR, found none".into(),
        ));
    }
    Ok(out)
}
