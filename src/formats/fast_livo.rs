//! `fast-livo`: FAST-LIVO and FAST-LIVO2 configurations with the camera
//! extrinsic `Rcl` (9 numbers, row-major) + `Pcl` (3, metres) beside the
//! LiDAR-IMU `extrinsic_T` + `extrinsic_R` (read as `fast-lio` reads them:
//! the LiDAR in the IMU, edge `imu -> lidar`). FAST-LIVO: `mapping:
//! {extrinsic_T, extrinsic_R}` and `camera: {Rcl, Pcl}`; FAST-LIVO2 all four
//! in `extrin_calib:`.
//!
//! `Rcl, Pcl` is the pose of the LiDAR in the camera,
//! `p_camera = Rcl p_lidar + Pcl`. hku-mars/FAST-LIVO @ dcebf84f38df004668930fbc8e2ec72ba0256000:
//! `src/laserMapping.cpp:1126-1129` reads `camera/Pcl`, `camera/Rcl`;
//! `include/common_lib.h:42-43`, `225-228` `Rcl << MAT_FROM_ARRAY(R)`
//! (row-major); `src/lidar_selection.cpp:35-38` `Pli = -rot.transpose() *
//! transl; Rli = rot.transpose()` (the IMU in the LiDAR) and `:44-45`
//! `Rci = Rcl * Rli; Pci = Rcl * Pli + Pcl` — `T_ci = T_cl T_li`, so
//! `(Rcl, Pcl)` maps LiDAR points into the camera; `:782-783` confirms
//! `T_ci` is camera-from-IMU. hku-mars/FAST-LIVO2 @
//! 0d2c0346107b75b59934975adec9a6eeeb913c64: `src/LIVMapper.cpp:104-107`
//! reads `extrin_calib/Pcl`, `extrin_calib/Rcl`; `src/vio.cpp:29-39` and
//! `:57-58` the same composition.
//!
//! The LiDAR already has the IMU as parent, so the camera edge is stored the
//! other way: `lidar -> camera`, the inverse of `(Rcl, Pcl)` (the provenance
//! says so). `Rcl` without `Pcl` (upstream reads past an empty vector) and
//! other sizes are refused. A file without `Rcl`/`Pcl` (FAST-LIVO2's
//! HILTI22.yaml keeps them in the camera file) is read by `fast-lio`.

use super::calib_shapes::{edge, numbers_n, rigid_rt, stored_inverted};
use super::spec::{check_metres, locate_warnings, Parsed};
use super::yaml::Node;
use super::yaml_dialects::parse_fast_lio;
use super::yaml_keyed::{keys, yaml_dialect};
use super::yaml_shapes::{err_at, key_node, loc_of, unique_map};
use crate::diagnostic::Result;
use std::path::Path;

yaml_dialect!(FAST_LIVO, "fast-livo", false, |i| keys(i.has_key("extrinsic_T") && (i.has_key("Rcl") || i.has_key("Pcl"))), |d, _, p| parse(d, p), "FAST-LIVO / FAST-LIVO2 `extrinsic_T` + `extrinsic_R` (the LiDAR in the IMU, edge imu -> lidar) with `Rcl` (row-major) + `Pcl`: the LiDAR pose in the camera (p_camera = Rcl p_lidar + Pcl), stored as lidar -> camera");

fn parse(docs: &[Node], path: &Path) -> Result<Parsed> {
    let mut out = parse_fast_lio(docs, path, FAST_LIVO.id)?;
    let m = unique_map(docs, "Rcl").or_else(|_| unique_map(docs, "Pcl"))?;
    let Some(rn) = m.get("Rcl") else {
        return Err(err_at(
            m,
            "expected `Rcl` (9 numbers, row-major) next to `Pcl`, found none".into(),
        ));
    };
    let pn = m.get("Pcl").ok_or_else(|| err_at(m, "expected `Pcl` (3 numbers) next to `Rcl`, found none (FAST-LIVO would read past an empty vector)".into()))?;
    let r = numbers_n(rn, 9, "Rcl")?;
    let t = numbers_n(pn, 3, "Pcl")?;
    let k = key_node(m, "Rcl").unwrap_or(rn);
    let loc = loc_of(path, k);
    let mut ws = Vec::new();
    let read = rigid_rt(&r, &t, rn, "Rcl + Pcl", &mut ws)?;
    check_metres(&[t[0], t[1], t[2]], "Pcl", &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    let e = edge(
        "camera",
        "lidar",
        read,
        path,
        k,
        FAST_LIVO.id,
        String::new(),
    );
    out.edges.push(stored_inverted(
        e,
        "Rcl + Pcl (the LiDAR in the camera), stored inverted as lidar -> camera".into(),
    ));
    Ok(out)
}
