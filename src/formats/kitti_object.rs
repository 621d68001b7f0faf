//! `kitti-object`: the per-frame calib files of the KITTI object-detection
//! and tracking benchmarks (`training/calib/000000.txt`): lines `KEY: v1 v2 ...`
//! (the tracking devkit writes `KEY v1 ...` without the colon and the older
//! names `Tr_velo_cam`, `Tr_imu_velo`, `R_rect`).
//!
//! Directions, from the object devkit's readme ("x = P2 * R0_rect *
//! Tr_velo_to_cam * y" projects a Velodyne point y into image 2; `R0_rect` is
//! the rectifying rotation of camera 0, `Tr_imu_to_velo` maps IMU coordinates
//! into Velodyne coordinates):
//! - `Tr_velo_to_cam` (3x4, row-major): `x_cam0 = Tr x_velo`, the Velodyne's
//!   pose in camera 0 (unrectified): edge `cam0 -> velo`;
//! - `Tr_imu_to_velo` (3x4): `x_velo = Tr x_imu`, edge `velo -> imu`;
//! - `R0_rect` (3x3): `x_rect = R0 x_cam0`, the pose of camera 0 in the
//!   rectified camera-0 frame: edge `cam0_rect -> cam0`;
//! - `P1`..`P3` (3x4 = K [I | t]): rectified camera N sees
//!   `x_N = x_cam0_rect + t` with `t = K^-1 P[:, 3]`, so its pose in
//!   `cam0_rect` is `[I | -t]`: edges `cam0_rect -> camN_rect` (rectified
//!   cameras, axes parallel to `cam0_rect`; `P0` is `cam0_rect` itself).
//!
//! The frames are fixed names (the files write none): `velo`, `imu`, `cam0`,
//! `cam0_rect`, `cam1_rect`, `cam2_rect`, `cam3_rect`.

use crate::diagnostic::{Error, Location, Result};
use crate::formats::spec::{
    check_metres, locate_warnings, parse_number, Confidence, FormatSpec, Input, LoadOptions, Parsed,
};
use crate::frames::Edge;
use crate::geometry::se3::Transform;
use nalgebra::{Matrix3, Vector3};
use std::path::Path;

/// One `KEY: numbers` line.
struct Row {
    key: String,
    nums: Vec<f64>,
    line: usize,
}

fn rows(text: &str) -> Result<Vec<Row>> {
    let mut out = Vec::new();
    for (i, l) in text.lines().enumerate() {
        let mut words = l.split_whitespace();
        let Some(first) = words.next() else { continue };
        let key = first.trim_end_matches(':').to_string();
        let nums = words
            .map(|w| {
                parse_number(w).ok_or_else(|| {
                    Error::parse(format!(
                        "{key}: expected numbers, found {:?}",
                        crate::sanitize::clip(w)
                    ))
                    .at_line(i + 1, None)
                })
            })
            .collect::<Result<Vec<f64>>>()?;
        out.push(Row {
            key,
            nums,
            line: i + 1,
        });
    }
    Ok(out)
}

fn find<'a>(rows: &'a [Row], names: &[&str]) -> Option<&'a Row> {
    rows.iter().find(|r| names.contains(&r.key.as_str()))
}

fn expect_len(r: &Row, n: usize, what: &str) -> Result<()> {
    if r.nums.len() == n {
        return Ok(());
    }
    Err(Error::parse(format!(
        "{}: expected {n} numbers ({what}, row-major), found {}",
        r.key,
        r.nums.len()
    ))
    .at_line(r.line, Some(1)))
}

fn edge(
    (parent, child): (&str, &str),
    r: &Row,
    t: Result<Transform>,
    path: &Path,
    out: &mut Parsed,
    ws: Vec<crate::diagnostic::Warning>,
) -> Result<()> {
    let loc = Location::at(path, r.line, Some(1));
    let t = t.map_err(|e| {
        Error {
            message: format!("{}: {}", r.key, e.message),
            ..e
        }
        .at(&loc)
    })?;
    let mut ws = ws;
    let d = *t.translation();
    check_metres(&[d.x, d.y, d.z], &r.key, &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    out.edges.push(Edge::new(
        parent,
        child,
        t,
        loc,
        KITTI_OBJECT.id,
        r.key.clone(),
    ));
    Ok(())
}

fn rigid_3x4(r: &Row, ws: &mut Vec<crate::diagnostic::Warning>) -> Result<Transform> {
    let v = &r.nums;
    Transform::from_matrix3(
        [[v[0], v[1], v[2]], [v[4], v[5], v[6]], [v[8], v[9], v[10]]],
        [v[3], v[7], v[11]],
        ws,
    )
}

/// The pose of rectified camera N in `cam0_rect` from its projection matrix.
fn camera_from_p(r: &Row) -> Result<Transform> {
    let v = &r.nums;
    let k = Matrix3::new(v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10]);
    let p4 = Vector3::new(v[3], v[7], v[11]);
    let t = k.lu().solve(&p4).ok_or_else(|| {
        Error::invalid("projection matrix: its left 3x3 (K) is singular: expected K [I | t]")
    })?;
    Transform::from_translation([-t.x, -t.y, -t.z])
}

/// KITTI object / tracking calib text.
pub fn parse(text: &str, path: &Path, _opts: &LoadOptions) -> Result<Parsed> {
    let rows = rows(text)?;
    let mut out = Parsed::default();
    if let Some(r) = find(&rows, &["R0_rect", "R_rect"]) {
        expect_len(r, 9, "3x3 rotation")?;
        let v = &r.nums;
        let mut ws = Vec::new();
        let t = Transform::from_matrix3(
            [[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]],
            [0.0; 3],
            &mut ws,
        );
        edge(("cam0_rect", "cam0"), r, t, path, &mut out, ws)?;
    }
    for (names, frames) in [
        (&["Tr_velo_to_cam", "Tr_velo_cam"][..], ("cam0", "velo")),
        (&["Tr_imu_to_velo", "Tr_imu_velo"][..], ("velo", "imu")),
    ] {
        if let Some(r) = find(&rows, names) {
            expect_len(r, 12, "3x4 [R | t]")?;
            let mut ws = Vec::new();
            let t = rigid_3x4(r, &mut ws);
            edge(frames, r, t, path, &mut out, ws)?;
        }
    }
    for (key, child) in [
        ("P1", "cam1_rect"),
        ("P2", "cam2_rect"),
        ("P3", "cam3_rect"),
    ] {
        if let Some(r) = find(&rows, &[key]) {
            expect_len(r, 12, "3x4 projection K [I | t]")?;
            edge(
                ("cam0_rect", child),
                r,
                camera_from_p(r),
                path,
                &mut out,
                vec![],
            )?;
        }
    }
    if out.edges.is_empty() {
        return Err(Error::parse(format!(
            "KITTI object calib: expected `Tr_velo_to_cam:`, `Tr_imu_to_velo:`, `R0_rect:` or `P1:`..`P3:` lines, found keys {}",
            rows.iter().map(|r| r.key.as_str()).take(12).collect::<Vec<_>>().join(", ")
        )));
    }
    Ok(out)
}

fn sniff(i: &Input) -> Option<Confidence> {
    let keyed = |k: &str| i.text_head().lines().any(|l| l.trim_start().starts_with(k));
    (keyed("Tr_velo_to_cam") || keyed("Tr_velo_cam") || keyed("Tr_imu_to_velo"))
        .then_some(Confidence::Names)
}

/// KITTI object-detection / tracking calib text.
pub const KITTI_OBJECT: FormatSpec = FormatSpec {
    id: "kitti-object",
    description: "KITTI object/tracking calib (`P0`..`P3`, `R0_rect`, `Tr_velo_to_cam`, `Tr_imu_to_velo`; devkit: x = P2 R0_rect Tr_velo_to_cam y): edges cam0 -> velo, velo -> imu, cam0_rect -> cam0 (R0_rect), cam0_rect -> camN_rect (from PN)",
    extensions: &[],
    walk: &[".txt"],
    magic: &[],
    sniff,
    parse: |i, o| parse(i.text()?, i.path(), o),
    checked: true,
};
