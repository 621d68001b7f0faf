//! `r3live`: R3LIVE's `r3live_vio` block, `camera_ext_R` (9 numbers,
//! row-major) and `camera_ext_t` (3, metres).
//!
//! hku-mars/r3live @ f04db809922cceb646feb4837bdea0520b908a1f:
//! `r3live/src/r3live_vio.cpp:441-447` reads the two keys and aborts on sizes
//! other than 9 and 3; `:459-460` maps the rotation row-major
//! (`Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>`); `:205-206`
//! stores them as `state.rot_ext_i2c`, `state.pos_ext_i2c`; `:660-661`
//! `t_c2w = R_imu * pos_ext_i2c + t_imu; R_c2w = R_imu * rot_ext_i2c` — the
//! camera's world pose is the IMU's composed with `(R, t)`: the pose of the
//! camera in the IMU (R3LIVE's state frame), edge `imu -> camera`. (The
//! shipped comment says "camera-LiDAR": on its Avia the IMU and LiDAR axes
//! coincide, but the code composes the numbers with the IMU pose.)

use super::calib_shapes::{edge, field, numbers_n, rigid_rt};
use super::spec::{check_metres, locate_warnings, Parsed};
use super::yaml::Node;
use super::yaml_keyed::{keys, yaml_dialect};
use super::yaml_shapes::{key_node, loc_of, unique_map};
use crate::diagnostic::Result;
use std::path::Path;

yaml_dialect!(R3LIVE, "r3live", false, |i| keys(i.has_key("camera_ext_R") || i.has_key("camera_ext_t")), |d, _, p| parse(d, p), "R3LIVE `r3live_vio: {camera_ext_R (row-major), camera_ext_t}`: the camera pose in the IMU (state) frame, as r3live_vio.cpp composes it, edge imu -> camera");

fn parse(docs: &[Node], path: &Path) -> Result<Parsed> {
    let m = unique_map(docs, "camera_ext_R")?;
    let k = key_node(m, "camera_ext_R").unwrap_or(m);
    let r = numbers_n(field(m, "camera_ext_R", "r3live_vio")?, 9, "camera_ext_R")?;
    let t = numbers_n(field(m, "camera_ext_t", "r3live_vio")?, 3, "camera_ext_t")?;
    let mut out = Parsed::default();
    let mut ws = Vec::new();
    let read = rigid_rt(&r, &t, m, "camera_ext_R + camera_ext_t", &mut ws)?;
    let loc = loc_of(path, k);
    check_metres(&[t[0], t[1], t[2]], "camera_ext_t", &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    out.edges.push(edge(
        "imu",
        "camera",
        read,
        path,
        k,
        R3LIVE.id,
        "r3live_vio camera_ext_R + camera_ext_t".into(),
    ));
    Ok(out)
}
