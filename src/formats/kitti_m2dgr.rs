//! Calibration text files.
//!
//! - `kitti-calib`: KITTI raw `calib_imu_to_velo.txt` / `calib_velo_to_cam.txt`:
//!   `R:` 9 numbers row-major, `T:` 3 numbers (m), with `x_B = R x_A + T` for a
//!   file named `calib_A_to_B.txt`: the pose of A in B, edge `B -> A`. A file
//!   with another name yields `target -> source` with an `assumed-convention`
//!   warning that says how to name them (`--rename FILE:source=imu ...`). Other lines (`calib_time:`, `delta_f:`, ...) are ignored.
//! - `m2dgr-txt`: M2DGR `calibration_results.txt`: `%% NAME` headers, then
//!   `% Extrinsic [to LIDAR]` and a `data: [...]` 4x4 or 3x4 (row-major, m): the
//!   sensor's pose in the LiDAR frame (M2DGR's "[to LIDAR]"), edges
//!   `velodyne -> <name>`, the name lower-cased with non-alphanumerics as `_`
//!   (`Handsfree IMU` -> `handsfree_imu`). Blocks that are not extrinsics are
//!   skipped.

use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::spec::{
    check_metres, locate_warnings, parse_number, Confidence, FormatSpec, LoadOptions, Parsed,
};
use crate::frames::Edge;
use crate::geometry::se3::Transform;
use crate::geometry::uncertainty::{written_precision, Written};
use std::path::Path;

fn numbers(s: &str, line: usize, what: &str) -> Result<Vec<f64>> {
    let cleaned = s.replace(['[', ']', ',', '，', ';'], " ");
    cleaned
        .split_whitespace()
        .map(|t| {
            parse_number(t).ok_or_else(|| {
                Error::parse(format!(
                    "{what}: expected numbers, found {:?}",
                    crate::sanitize::clip(t)
                ))
                .at_line(line, None)
            })
        })
        .collect()
}

/// KITTI calib text.
pub fn parse_kitti(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let _ = opts;
    let mut r: Option<(Vec<f64>, usize)> = None;
    let mut t: Option<(Vec<f64>, usize)> = None;
    for (i, l) in text.lines().enumerate() {
        let l = l.trim();
        if let Some(rest) = l.strip_prefix("R:") {
            r = Some((numbers(rest, i + 1, "R")?, i + 1));
        } else if let Some(rest) = l.strip_prefix("T:") {
            t = Some((numbers(rest, i + 1, "T")?, i + 1));
        }
    }
    let (r, rl) =
        r.ok_or_else(|| Error::parse("expected a line `R: r11 r12 ... r33`, found none"))?;
    let (t, tl) = t.ok_or_else(|| Error::parse("expected a line `T: tx ty tz`, found none"))?;
    if r.len() != 9 {
        return Err(
            Error::parse(format!("R: expected 9 numbers, found {}", r.len())).at_line(rl, None),
        );
    }
    if t.len() != 3 {
        return Err(
            Error::parse(format!("T: expected 3 numbers, found {}", t.len())).at_line(tl, None),
        );
    }
    let loc = Location::at(path, rl, Some(1));
    let mut out = Parsed::default();
    let mut ws = Vec::new();
    let tf = Transform::from_matrix3(
        [[r[0], r[1], r[2]], [r[3], r[4], r[5]], [r[6], r[7], r[8]]],
        [t[0], t[1], t[2]],
        &mut ws,
    )
    .map_err(|e| e.at(&loc))?;
    check_metres(&[t[0], t[1], t[2]], "T", &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    let name = path
        .file_name()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let (a, b) = match stem
        .strip_prefix("calib_")
        .and_then(|s| s.split_once("_to_"))
    {
        Some((a, b)) if !a.is_empty() && !b.is_empty() => (a.to_string(), b.to_string()),
        _ => {
            out.warnings.push(
                Warning::new(
                    Code::AssumedConvention,
                    format!(
                        "file name {:?} is not calib_A_to_B.txt: frames named `source` and `target` (x_target = R x_source + T); name them with --rename, e.g. for a copy of calib_imu_to_velo.txt: --rename {name}:source=imu --rename {name}:target=velo",
                        crate::sanitize::clip(&name),
                    ),
                )
                .at(&loc),
            );
            ("source".to_string(), "target".to_string())
        }
    };
    let written = Written::Matrix3([[r[0], r[1], r[2]], [r[3], r[4], r[5]], [r[6], r[7], r[8]]]);
    out.edges.push(
        Edge::new(b, a, tf, loc, KITTI_CALIB.id, "R: + T:").with_precision(written_precision(
            written,
            [t[0], t[1], t[2]],
            1.0,
        )),
    );
    Ok(out)
}

fn slug(s: &str) -> String {
    let mut out = String::new();
    for c in s.trim().chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c.to_ascii_lowercase());
        } else if !out.ends_with('_') && !out.is_empty() {
            out.push('_');
        }
    }
    out.trim_end_matches('_').to_string()
}

/// M2DGR calibration_results.txt.
pub fn parse_m2dgr(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Parsed::default();
    let mut name = String::new();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i].trim();
        if let Some(h) = l.strip_prefix("%%") {
            let h = h.trim();
            if !h.is_empty() {
                name = slug(h);
            }
        }
        if l.starts_with('%') && l.contains("Extrinsic") && l.contains("to LIDAR") {
            // The next `data:` block.
            let mut j = i + 1;
            while j < lines.len() && !lines[j].trim_start().starts_with("data:") {
                if lines[j].trim_start().starts_with("%%") {
                    break;
                }
                j += 1;
            }
            if j < lines.len() && lines[j].trim_start().starts_with("data:") {
                let start = j;
                let mut buf = lines[j].trim_start()["data:".len()..].to_string();
                while !buf.contains(']') && j + 1 < lines.len() {
                    j += 1;
                    buf.push(' ');
                    buf.push_str(lines[j]);
                }
                let v = numbers(&buf, start + 1, &format!("{name} extrinsic data"))?;
                let loc = Location::at(path, start + 1, Some(1));
                let keep = opts.key.as_deref().map(|k| slug(k) == name).unwrap_or(true);
                if keep {
                    let mut ws = Vec::new();
                    let t = match v.len() {
                        16 | 12 => Transform::from_matrix3(
                            [[v[0], v[1], v[2]], [v[4], v[5], v[6]], [v[8], v[9], v[10]]],
                            [v[3], v[7], v[11]],
                            &mut ws,
                        )
                        .map_err(|e| e.at(&loc))?,
                        k => {
                            return Err(Error::parse(format!(
                                "{name} extrinsic: expected 16 (4x4) or 12 (3x4) numbers, found {k}"
                            ))
                            .at(&loc))
                        }
                    };
                    if v.len() == 16
                        && (v[12] != 0.0 || v[13] != 0.0 || v[14] != 0.0 || v[15] != 1.0)
                    {
                        return Err(Error::invalid(format!(
                            "{name} extrinsic: expected bottom row [0, 0, 0, 1], found [{}, {}, {}, {}]",
                            v[12], v[13], v[14], v[15]
                        ))
                        .at(&loc));
                    }
                    check_metres(&[v[3], v[7], v[11]], &name, &loc, &mut ws);
                    locate_warnings(ws, &loc, &mut out.warnings);
                    out.edges.push(
                        Edge::new(
                            "velodyne",
                            if name.is_empty() {
                                "sensor".to_string()
                            } else {
                                name.clone()
                            },
                            t,
                            loc,
                            M2DGR_TXT.id,
                            format!("%% {name}: Extrinsic [to LIDAR] data"),
                        )
                        .with_precision(written_precision(
                            Written::Matrix3([
                                [v[0], v[1], v[2]],
                                [v[4], v[5], v[6]],
                                [v[8], v[9], v[10]],
                            ]),
                            [v[3], v[7], v[11]],
                            1.0,
                        )),
                    );
                }
            }
            i = j;
        }
        i += 1;
    }
    if let Some(k) = &opts.key {
        if out.edges.is_empty() {
            return Err(Error::parse(format!(
                "--key {k}: no `%% {k}` block with an `Extrinsic [to LIDAR]` matrix"
            )));
        }
    }
    Ok(out)
}

/// KITTI calib text.
pub const KITTI_CALIB: FormatSpec = FormatSpec {
    id: "kitti-calib",
    description: "KITTI calib text (`R:` 9 numbers row-major, `T:` 3 numbers; calib_A_to_B.txt maps A coordinates into B): edge B -> A",
    extensions: &[],
    walk: &[".txt"],
    magic: &[],
    sniff: |i| {
        let has = |p: &str| i.text().unwrap_or("").lines().any(|l| l.trim_start().starts_with(p));
        (has("R:") && has("T:")).then_some(Confidence::Lines)
    },
    parse: |i, o| parse_kitti(i.text()?, i.path(), o),
    checked: true,
};

/// M2DGR calibration_results.txt.
pub const M2DGR_TXT: FormatSpec = FormatSpec {
    id: "m2dgr-txt",
    description: "M2DGR calibration_results.txt: `%% NAME` blocks with `% Extrinsic [to LIDAR]` 4x4 or 3x4 `data:`: the sensor's pose in the LiDAR frame, edges velodyne -> <name>",
    extensions: &[],
    walk: &[".txt"],
    magic: &[],
    sniff: |i| (i.contains("% Extrinsic") && i.contains("data:")).then_some(Confidence::Markers),
    parse: |i, o| parse_m2dgr(i.text()?, i.path(), o),
    checked: true,
};
