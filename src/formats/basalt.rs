//! `basalt-calib`: Basalt's calibration JSON (cereal):
//! `{"value0": {"T_imu_cam": [{px, py, pz, qx, qy, qz, qw}, ...], ...}}`,
//! one entry per camera in camera order.
//!
//! `T_imu_cam[i]` is the pose of camera i in the IMU, `p_i = T_ic p_c`:
//! edges `imu -> cam0`, `imu -> cam1`, ... VladyslavUsenko/basalt-headers-mirror
//! @ a585db348a84e6f2219b8619e2fc26e8ad04e037:
//! `include/basalt/calibration/calibration.hpp:101-104` "Point in camera
//! coordinate frame p_c can be transformed to the point in IMU coordinate
//! frame as p_i = T_{ic} p_c" (`T_i_c`); `include/basalt/serialization/
//! headers_serialization.h:244` serialises `T_i_c` as `"T_imu_cam"`;
//! `include/basalt/serialization/eigen_io.h:190-197` writes `px py pz` from
//! the translation and `qx qy qz qw` straight into Sophus's storage (x, y, z,
//! w), not normalised on load: a quaternion whose norm is off 1 by more than
//! the rounding tolerance (`tolerances::QUATERNION_ROUNDING_TOL`) is refused,
//! since Basalt would use it as written. Metres.

use super::calib_shapes::{edge, field, number, rigid_quat, top_map};
use super::json::json_documents;
use super::spec::{check_metres, locate_warnings, Confidence, FormatSpec, Input, Parsed};
use super::yaml::Value;
use super::yaml_shapes::{err_at, key_node, loc_of};
use crate::diagnostic::Result;
use crate::tolerances::QUATERNION_ROUNDING_TOL;
use std::path::Path;

/// Basalt calibration JSON.
pub const BASALT_CALIB: FormatSpec = FormatSpec {
    id: "basalt-calib",
    description: "Basalt calibration JSON (`value0.T_imu_cam`: px py pz + qx qy qz qw per camera): camera i's pose in the IMU, p_i = T_ic p_c, edges imu -> camN",
    extensions: &[],
    walk: &[".json"],
    magic: &[],
    sniff: |i: &Input| (i.trimmed().starts_with('{') && i.contains("\"T_imu_cam\"")).then_some(Confidence::Document),
    parse: |i, _| parse(i.text()?, i.path()),
    checked: true,
};

const KEYS: [&str; 7] = ["px", "py", "pz", "qx", "qy", "qz", "qw"];

fn parse(text: &str, path: &Path) -> Result<Parsed> {
    let docs = json_documents(text)?;
    let v0 = field(
        top_map(&docs, "Basalt calibration")?,
        "value0",
        "Basalt calibration",
    )?;
    let cams = field(v0, "T_imu_cam", "value0")?;
    let Value::Seq(list) = &cams.value else {
        return Err(err_at(cams, format!("value0.T_imu_cam: expected a list of poses {{px, py, pz, qx, qy, qz, qw}}, found {}", cams.kind())));
    };
    let k = key_node(v0, "T_imu_cam").unwrap_or(cams);
    let mut out = Parsed::default();
    for (i, p) in list.iter().enumerate() {
        let what = format!("T_imu_cam[{i}]");
        let mut v = [0.0; 7];
        for (j, key) in KEYS.iter().enumerate() {
            v[j] = number(p, key, &what)?;
        }
        let q = [v[3], v[4], v[5], v[6]];
        let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        if (norm - 1.0).abs() > QUATERNION_ROUNDING_TOL {
            return Err(err_at(p, format!("{what}: quaternion norm {norm:.6}, expected 1 within {QUATERNION_ROUNDING_TOL} (Basalt copies it into Sophus unnormalised)")));
        }
        let d = [v[0], v[1], v[2]];
        let mut ws = Vec::new();
        let read = rigid_quat(q, d, p, &what, &mut ws)?;
        let loc = loc_of(path, p);
        check_metres(&d, &what, &loc, &mut ws);
        locate_warnings(ws, &loc, &mut out.warnings);
        out.edges.push(edge(
            "imu",
            &format!("cam{i}"),
            read,
            path,
            p,
            BASALT_CALIB.id,
            what,
        ));
    }
    if out.edges.is_empty() {
        return Err(err_at(
            k,
            "value0.T_imu_cam: expected at least one camera pose, found an empty list".into(),
        ));
    }
    Ok(out)
}
