//! `euroc-sensor`: EuRoC-style `T_BS: {cols, rows, data}` (the EuRoC MAV
//! dataset's `mav0/<sensor>/sensor.yaml`, Kimera-VIO's camera parameters).
//!
//! `T_BS` is the pose of sensor S in the body B (EuRoC's body is the IMU;
//! `imu0/sensor.yaml` holds the identity), data row-major: edge
//! `body -> SENSOR`. MIT-SPARK/Kimera-VIO @
//! ce8c59b7b273ab5ac29db7e5572e1623760e19c7:
//! `src/frontend/CameraParams.cpp:183-194` `parseBodyPoseCam(...,
//! gtsam::Pose3* body_Pose_cam)` reads `T_BS.data` (its rows/cols CHECKs are
//! commented out, 185-190); `src/utils/UtilsOpenCV.cpp:106-113`
//! `gtsam::Pose3(Eigen::Matrix4d(vector_pose.data()).transpose())` — a
//! column-major map transposed: the data are row-major; `body_Pose_cam` is
//! gtsam's `A_Pose_B` (the pose of B in A), composed as such in
//! `src/frontend/StereoCamera.cpp:60`; `params/Euroc/LeftCameraParams.yaml:5`
//! "Sensor extrinsics wrt. the body-frame".
//!
//! The sensor is named by `camera_id` when present (Kimera: `left_cam`), else
//! by the directory of a `sensor.yaml` (EuRoC: `cam0`, `leica0`), else
//! `sensor`. rows/cols must be 4 and 4 and agree with the data, and the
//! bottom row must be `0 0 0 1` (Kimera only DCHECKs it).

use super::calib_shapes::{cv_matrix, edge, field, rigid16, top_map};
use super::spec::{check_metres, locate_warnings, Parsed};
use super::yaml::Node;
use super::yaml_keyed::{keys, yaml_dialect};
use super::yaml_shapes::{key_node, loc_of};
use crate::diagnostic::Result;
use std::path::Path;

yaml_dialect!(EUROC_SENSOR, "euroc-sensor", false, |i| keys(i.has_key("T_BS") && !i.has_key("imu_params")), |d, _, p| parse(d, p), "EuRoC / Kimera `T_BS: {cols, rows, data}` (row-major 4x4): the sensor's pose in the body (IMU) frame, edge body -> camera_id (or the sensor.yaml's directory, else `sensor`)");

/// The sensor's name: `camera_id`, else the directory of a `sensor.yaml`.
fn sensor_name(d: &Node, path: &Path) -> String {
    if let Some(id) = d
        .get("camera_id")
        .and_then(|v| v.as_str())
        .filter(|s| !s.trim().is_empty())
    {
        return id.trim().to_string();
    }
    let is_sensor_yaml = path.file_name().is_some_and(|n| n == "sensor.yaml");
    match path.parent().and_then(|p| p.file_name()) {
        Some(dir) if is_sensor_yaml => dir.to_string_lossy().into_owned(),
        _ => "sensor".to_string(),
    }
}

fn parse(docs: &[Node], path: &Path) -> Result<Parsed> {
    let d = top_map(docs, "EuRoC sensor.yaml")?;
    let v = field(d, "T_BS", "EuRoC sensor.yaml")?;
    let k = key_node(d, "T_BS").unwrap_or(v);
    let data = cv_matrix(v, 4, 4, "T_BS")?;
    let mut out = Parsed::default();
    let mut ws = Vec::new();
    let read = rigid16(&data, field(v, "data", "T_BS")?, "T_BS", &mut ws)?;
    let loc = loc_of(path, k);
    check_metres(&[data[3], data[7], data[11]], "T_BS", &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    out.edges.push(edge(
        "body",
        &sensor_name(d, path),
        read,
        path,
        k,
        EUROC_SENSOR.id,
        "T_BS {cols, rows, data}".into(),
    ));
    Ok(out)
}
