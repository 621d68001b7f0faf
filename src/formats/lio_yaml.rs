//! YAML dialects of LiDAR- and visual-inertial odometry packages that write a
//! rotation and a translation under their own keys. Frame names are fixed
//! (the files do not write them), so one command works for every user:
//!
//! - `ig-lio` (iG-LIO, zijiechenrobotics/ig_lio `config/*.yaml`): `t_imu_lidar`
//!   (3) and `R_imu_lidar` (9, row-major). The name reads as the project's
//!   `T_A_B` keys do (see `yaml_dialects`, `matrix-yaml`): the pose of the
//!   LiDAR in the IMU frame, `p_imu = R p_lidar + t`. Its `ncd.yaml` agrees:
//!   `t = [-0.006253, 0.011775, ...]` with `R = diag(-1, -1, 1)` is the
//!   Ouster OS1's IMU offset in the sensor frame ([6.253, -11.775, 7.645] mm)
//!   seen from the IMU. Edge `imu -> lidar`.
//! - `dlio` (DLIO, vectr-ucla/direct_lidar_inertial_odometry `cfg/dlio.yaml`):
//!   `extrinsics: {baselink2imu: {t, R}, baselink2lidar: {t, R}}`, `R`
//!   row-major (ROS 2 parameter files flatten them: `extrinsics/baselink2imu/t`,
//!   `extrinsics/baselink2imu/R`, ...). DLIO's odom.cc builds `baselink2lidar_T` from `t` and `R` and
//!   maps each scan with `T_prior * baselink2lidar_T` (LiDAR points into
//!   base_link, then the world): the LiDAR pose in base_link; `baselink2imu`
//!   likewise the IMU pose in base_link. Edges `base_link -> imu` and
//!   `base_link -> lidar`.
//! - `vins-mono` (VINS-Mono `config/*/*.yaml`, OpenCV FileStorage):
//!   `extrinsicRotation` (3x3 `!!opencv-matrix`) and `extrinsicTranslation`
//!   (3x1). Its comments: "Rotation from camera frame to imu frame, imu^R_cam",
//!   "Translation from camera frame to imu frame, imu^T_cam": the camera pose
//!   in the IMU frame, edge `imu -> camera`. VINS-Fusion's `body_T_cam0`,
//!   `body_T_cam1` ("cam0 to body") are `A_T_B` keys, read by `matrix-yaml`
//!   as edges `body -> cam0`, `body -> cam1`.

use super::spec::{check_metres, locate_warnings, Confidence, Input, Parsed};
use super::yaml::Node;
use super::yaml_keyed::{keys, yaml_dialect};
use super::yaml_shapes::{err_at, exactly, key_node, key_values, loc_of, mat3, unique_map};
use crate::diagnostic::{Error, Result};
use crate::frames::Edge;
use crate::geometry::se3::Transform;
use std::path::Path;

/// DLIO: `baselink2imu` or `baselink2lidar`, nested or flattened (ROS 2).
fn dlio_keys(i: &Input) -> Option<Confidence> {
    let key = |k: &str| i.has_key(k) || i.has_key(&format!("extrinsics/{k}/t"));
    keys(key("baselink2imu") || key("baselink2lidar"))
}

yaml_dialect!(IG_LIO, "ig-lio", true, |i| keys(i.has_key("t_imu_lidar") && i.has_key("R_imu_lidar")), |d, _, p| parse_ig_lio(d, p), "iG-LIO `t_imu_lidar` + `R_imu_lidar` (row-major): the LiDAR pose in the IMU frame, edge imu -> lidar");
yaml_dialect!(DLIO, "dlio", true, dlio_keys, |d, _, p| parse_dlio(d, p), "DLIO `extrinsics: {baselink2imu, baselink2lidar}: {t, R}` (row-major): the IMU and LiDAR poses in base_link, edges base_link -> imu, base_link -> lidar");
yaml_dialect!(VINS_MONO, "vins-mono", true, |i| keys(i.has_key("extrinsicRotation") && i.has_key("extrinsicTranslation")), |d, _, p| parse_vins_mono(d, p), "VINS-Mono `extrinsicRotation` + `extrinsicTranslation` (OpenCV matrices, \"imu^R_cam\", \"imu^T_cam\"): the camera pose in the IMU frame, edge imu -> camera");

/// The numbers of a list or of an OpenCV matrix's `data`.
fn numbers<const N: usize>(n: &Node, what: &str) -> Result<[f64; N]> {
    match n.get("data") {
        Some(data) => exactly::<N>(data, &format!("{what}.data")),
        None => exactly::<N>(n, what),
    }
}

/// One edge from a translation key and a row-major rotation key of map `m`.
fn rt_edge(
    m: &Node,
    (tkey, rkey): (&str, &str),
    (parent, child): (&str, &str),
    id: &'static str,
    path: &Path,
    out: &mut Parsed,
) -> Result<()> {
    let tn = m
        .get(tkey)
        .ok_or_else(|| err_at(m, format!("expected `{tkey}` (3 numbers), found none")))?;
    let rn = m.get(rkey).ok_or_else(|| {
        err_at(
            m,
            format!("expected `{rkey}` (9 numbers, row-major) next to `{tkey}`, found none"),
        )
    })?;
    let loc = key_node(m, tkey)
        .map(|k| loc_of(path, k))
        .unwrap_or_else(|| loc_of(path, tn));
    let d = numbers::<3>(tn, tkey)?;
    let r = numbers::<9>(rn, rkey)?;
    let mut ws = Vec::new();
    let t = Transform::from_matrix3(mat3(r), d, &mut ws).map_err(|e| {
        Error {
            message: format!("{rkey}: {}", e.message),
            ..e
        }
        .at(&loc_of(path, rn))
    })?;
    check_metres(&d, tkey, &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    out.edges.push(
        Edge::new(parent, child, t, loc, id, format!("{tkey} + {rkey}"))
            .with_values(key_values(m, tkey, rkey)),
    );
    Ok(())
}

fn parse_ig_lio(docs: &[Node], path: &Path) -> Result<Parsed> {
    let m = unique_map(docs, "t_imu_lidar")?;
    let mut out = Parsed::default();
    rt_edge(
        m,
        ("t_imu_lidar", "R_imu_lidar"),
        ("imu", "lidar"),
        IG_LIO.id,
        path,
        &mut out,
    )?;
    Ok(out)
}

fn parse_dlio(docs: &[Node], path: &Path) -> Result<Parsed> {
    let mut out = Parsed::default();
    for (key, child) in [("baselink2imu", "imu"), ("baselink2lidar", "lidar")] {
        // ROS 2 parameter files flatten the block: `extrinsics/KEY/t`, `/R`.
        let (tflat, rflat) = (format!("extrinsics/{key}/t"), format!("extrinsics/{key}/R"));
        if let Ok(m) = unique_map(docs, &tflat) {
            rt_edge(
                m,
                (&tflat, &rflat),
                ("base_link", child),
                DLIO.id,
                path,
                &mut out,
            )?;
            continue;
        }
        let Ok(m) = unique_map(docs, key) else {
            continue;
        };
        let Some(block) = m.get(key) else { continue };
        let mut one = Parsed::default();
        rt_edge(
            block,
            ("t", "R"),
            ("base_link", child),
            DLIO.id,
            path,
            &mut one,
        )
        .map_err(|e| Error {
            message: format!("{key}: {}", e.message),
            ..e
        })?;
        for mut e in one.edges {
            e.provenance.key = format!("{key}.t + {key}.R");
            out.edges.push(e);
        }
        out.warnings.extend(one.warnings);
    }
    if out.edges.is_empty() {
        return Err(Error::parse(
            "DLIO: expected `baselink2imu` or `baselink2lidar` with `t` and `R`, found neither",
        ));
    }
    Ok(out)
}

fn parse_vins_mono(docs: &[Node], path: &Path) -> Result<Parsed> {
    let m = unique_map(docs, "extrinsicRotation")?;
    let mut out = Parsed::default();
    rt_edge(
        m,
        ("extrinsicTranslation", "extrinsicRotation"),
        ("imu", "camera"),
        VINS_MONO.id,
        path,
        &mut out,
    )?;
    Ok(out)
}
