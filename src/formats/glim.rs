//! `glim-sensors`: GLIM's `config_sensors.json`, JSON with `//` and `/* */`
//! comments: `{"sensors": {"T_lidar_imu": [x, y, z, qx, qy, qz, qw],
//! "T_lidar_camera": [...], ...}}` (TUM order, metres).
//!
//! koide3/glim @ 1007fecd3389b44a4c2f278035bd57ceba459fee:
//! `src/glim/util/config.cpp:21` `nlohmann::json::parse(ifs, nullptr, true,
//! true)` (comments ignored); `include/glim/util/config_impl.hpp:67-78` takes
//! exactly 7 numbers, the translation first and
//! `Eigen::Quaternion<T>(in.data() + 3).normalized()` (x, y, z, w); `config/config_sensors.json:30-32` "T_lidar_imu
//! transforms points in the imu frame into the lidar frame ... p_lidar =
//! T_lidar_imu * p_imu"; `src/glim/odometry/odometry_estimation_imu.cpp:38`
//! reads it and `src/glim/odometry/estimation_frame.cpp:56` composes
//! `T_world_imu = T_world_lidar * T_lidar_imu`: the pose of the IMU in the
//! LiDAR, edge `lidar -> imu`.
//!
//! A value that is not 7 numbers becomes the identity in GLIM, silently
//! (`config_impl.hpp:147-153` warns "not found" and returns the default):
//! refused here. `T_lidar_camera` is not used by GLIM's core code (only
//! extension modules read it): its direction is not traced to consuming code,
//! so it is read only with `--assume` (`child-in-parent`: the camera in the
//! LiDAR, by the `T_A_B` naming); without it, it is left out with an
//! `ignored` warning.
//!
//! Comments are blanked before the one JSON reader (`formats::json`) reads
//! the text, keeping every line and column, so a JSON error points at the
//! file as written; a `/*` never closed is refused.

use super::calib_shapes::{edge, field, numbers_n, rigid_quat, top_map, untraced};
use super::json::json_documents;
use super::spec::{
    check_metres, locate_warnings, Confidence, FormatSpec, Input, LoadOptions, Parsed,
};
use super::yaml_shapes::{key_node, loc_of};
use crate::diagnostic::{Error, Result};
use std::path::Path;

/// GLIM config_sensors.json.
pub const GLIM_SENSORS: FormatSpec = FormatSpec {
    id: "glim-sensors",
    description: "GLIM `config_sensors.json` (JSON with comments; `sensors.T_lidar_imu`: x y z qx qy qz qw, \"p_lidar = T_lidar_imu * p_imu\"): the IMU pose in the LiDAR, edge lidar -> imu; `T_lidar_camera` is not used by GLIM's core: read only with --assume (edge lidar -> camera)",
    extensions: &[],
    walk: &[".json"],
    magic: &[],
    sniff: |i: &Input| (i.trimmed().starts_with('{') && i.contains("\"T_lidar_imu\"")).then_some(Confidence::Document),
    parse: |i, o| parse(i.text()?, i.path(), o),
    checked: true,
};

/// `text` with every `//` and `/* */` comment outside strings replaced by
/// blanks (newlines kept), as nlohmann's `ignore_comments` skips them.
pub fn strip_json_comments(text: &str) -> Result<String> {
    let b = text.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let (mut i, mut in_str) = (0, false);
    let blank = |c: u8| if c == b'\n' { b'\n' } else { b' ' };
    while i < b.len() {
        let c = b[i];
        if in_str {
            out.push(c);
            if c == b'\\' && i + 1 < b.len() {
                out.push(b[i + 1]);
                i += 1;
            } else if c == b'"' {
                in_str = false;
            }
            i += 1;
        } else if c == b'"' {
            in_str = true;
            out.push(c);
            i += 1;
        } else if b[i..].starts_with(b"//") {
            while i < b.len() && b[i] != b'\n' {
                out.push(b' ');
                i += 1;
            }
        } else if b[i..].starts_with(b"/*") {
            let Some(end) = text[i + 2..].find("*/") else {
                let line = text[..i].matches('\n').count() + 1;
                return Err(
                    Error::parse("block comment `/*` never closed: expected `*/`")
                        .at_line(line, None),
                );
            };
            let stop = i + 2 + end + 2;
            out.extend(b[i..stop].iter().map(|&c| blank(c)));
            i = stop;
        } else {
            out.push(c);
            i += 1;
        }
    }
    // Only ASCII bytes were replaced, by ASCII: still UTF-8.
    Ok(String::from_utf8(out).unwrap_or_default())
}

/// The keys read: (key, child, traced).
const KEYS: [(&str, &str, bool); 2] = [
    ("T_lidar_imu", "imu", true),
    ("T_lidar_camera", "camera", false),
];

fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let docs = json_documents(&strip_json_comments(text)?)?;
    let s = field(
        top_map(&docs, "GLIM config_sensors.json")?,
        "sensors",
        "GLIM config_sensors.json",
    )?;
    let mut out = Parsed::default();
    for (key, child, traced) in KEYS {
        let Some(v) = s.get(key) else { continue };
        let k = key_node(s, key).unwrap_or(v);
        let n = numbers_n(v, 7, &format!("sensors.{key} (x y z qx qy qz qw; GLIM would silently use the identity for any other length)"))?;
        let d = [n[0], n[1], n[2]];
        let mut ws = Vec::new();
        let read = rigid_quat([n[3], n[4], n[5], n[6]], d, v, key, &mut ws)?;
        let loc = loc_of(path, k);
        check_metres(&d, key, &loc, &mut ws);
        locate_warnings(ws, &loc, &mut out.warnings);
        let e = edge(
            "lidar",
            child,
            read,
            path,
            k,
            GLIM_SENSORS.id,
            format!("sensors.{key}"),
        );
        if traced {
            out.edges.push(e);
        } else if let Some(e) = untraced(
            opts,
            e,
            "GLIM's core code never reads it, so no code fixes its direction",
            &mut out.warnings,
        )? {
            out.edges.push(e);
        }
    }
    if out.edges.is_empty() {
        return Err(Error::parse("GLIM config_sensors.json: expected `sensors.T_lidar_imu` (7 numbers), found none read (T_lidar_camera needs --assume)"));
    }
    Ok(out)
}
