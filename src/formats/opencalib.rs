//! `opencalib`: OpenCalib (PJLab-ADG/SensorsCalibration) extrinsic JSON:
//! `{"<A>-to-<B>-extrinsic": {"sensor_name", "target_sensor_name",
//! "param": {"sensor_calib": {"rows": 4, "cols": 4, "data": [[4], [4], [4],
//! [4]]}}}}`.
//!
//! The matrix maps `sensor_name` points into `target_sensor_name`: the pose
//! of `sensor_name` in `target_sensor_name`, edge `target_sensor_name ->
//! sensor_name` (names from those fields, not from the key). PJLab-ADG/
//! SensorsCalibration @ 7fe8d46caac040cbcd89cc65e79e5519df01bcd4:
//! `lidar2camera/manual_calib/include/extrinsic_param.hpp:15-38`
//! `LoadExtrinsic` reads the first member of the root, row by row;
//! `lidar2camera/manual_calib/include/projector_lidar.hpp:120`
//! `K * (R_ * oriCloud + T_)` (LiDAR points into the camera);
//! `lidar2lidar/manual_calib/src/run_lidar2lidar.cpp:255` applies the matrix
//! to the source cloud; `lidar2imu/auto_calib/src/run_lidar2imu.cpp:39-54`
//! inverts the `gnss-to-lidar` file into `lidar2imu` and
//! `src/registration.cpp:59-63` composes `Ti * initial_extrinsic` (the LiDAR
//! in the IMU): the same rule. The repository contradicts itself once:
//! `lidar2imu/manual_calib/src/run_lidar2imu.cpp:312-313` uses the same kind
//! of file without the inverse. The tool follows the majority (three tools)
//! and says so in an `assumed-convention` warning on files whose sensors are
//! a GNSS or an IMU, citing both.
//!
//! Only the first member of the root is read, as `LoadExtrinsic` does (an
//! `ignored` warning names the others); a key whose `A-to-B` disagrees with
//! the names gets an `assumed-convention` warning (OpenCalib's own radar
//! sample does this); the matrix must be four rows of four with the bottom
//! row `0 0 0 1`.

use super::calib_shapes::{edge, field, name, rigid16, top_map};
use super::json::json_documents;
use super::spec::{check_metres, locate_warnings, Confidence, FormatSpec, Input, Parsed};
use super::yaml::Value;
use super::yaml_shapes::{err_at, loc_of};
use crate::diagnostic::{Code, Result, Warning};
use std::path::Path;

/// OpenCalib extrinsic JSON.
pub const OPENCALIB: FormatSpec = FormatSpec {
    id: "opencalib",
    description: "OpenCalib (SensorsCalibration) `<A>-to-<B>-extrinsic` JSON (`sensor_calib.data` four rows, maps sensor_name points into target_sensor_name): the pose of sensor_name in target_sensor_name, edge target_sensor_name -> sensor_name",
    extensions: &[],
    walk: &[".json"],
    magic: &[],
    sniff: |i: &Input| (i.trimmed().starts_with('{') && i.contains("\"sensor_calib\"") && i.contains("\"target_sensor_name\"")).then_some(Confidence::Document),
    parse: |i, _| parse(i.text()?, i.path()),
    checked: true,
};

fn parse(text: &str, path: &Path) -> Result<Parsed> {
    let docs = json_documents(text)?;
    let root = top_map(&docs, "OpenCalib extrinsic")?;
    let Some((k, rec)) = root.entries().first() else {
        return Err(err_at(
            root,
            "OpenCalib extrinsic: expected a member `<A>-to-<B>-extrinsic`, found an empty object"
                .into(),
        ));
    };
    let key = &k.as_str().unwrap_or_default();
    let mut out = Parsed::default();
    for (other, _) in &root.entries()[1..] {
        out.warnings.push(
            Warning::new(
                Code::Ignored,
                format!(
                    "`{}`: not read; OpenCalib's LoadExtrinsic reads only the first member ({key})",
                    other.as_str().unwrap_or_default()
                ),
            )
            .at(&loc_of(path, other)),
        );
    }
    let sensor = name(rec, "sensor_name", key)?;
    let target = name(rec, "target_sensor_name", key)?;
    let calib = field(
        field(rec, "param", key)?,
        "sensor_calib",
        &format!("{key}.param"),
    )?;
    let data = field(calib, "data", "sensor_calib")?;
    let rows: Vec<usize> = match &data.value {
        Value::Seq(r) => r
            .iter()
            .map(|x| {
                if let Value::Seq(c) = &x.value {
                    c.len()
                } else {
                    0
                }
            })
            .collect(),
        _ => vec![],
    };
    if rows != [4, 4, 4, 4] {
        return Err(err_at(data, format!("{key}: sensor_calib.data: expected four rows of four numbers, found rows of {rows:?}")));
    }
    let v = data.numbers("sensor_calib.data")?;
    let loc = loc_of(path, k);
    let mut ws = Vec::new();
    let read = rigid16(&v, data, &format!("{key}: sensor_calib.data"), &mut ws)?;
    check_metres(&[v[3], v[7], v[11]], "sensor_calib.data", &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    let named = key
        .strip_suffix("-extrinsic")
        .and_then(|s| s.split_once("-to-"));
    if let Some((a, b)) = named.filter(|(a, b)| (*a, *b) != (sensor.as_str(), target.as_str())) {
        out.warnings.push(Warning::new(Code::AssumedConvention, format!("`{key}` names {a} -> {b}, but sensor_name/target_sensor_name say {sensor} -> {target}: the frames are taken from sensor_name/target_sensor_name, as OpenCalib's tools use them")).at(&loc));
    }
    let inertial = |s: &str| {
        let s = s.to_ascii_lowercase();
        s.contains("gnss") || s.contains("imu") || s.contains("ins")
    };
    if inertial(&sensor) || inertial(&target) {
        out.warnings.push(Warning::new(Code::AssumedConvention, format!("read as the pose of {sensor} in {target}, the rule of OpenCalib's lidar2camera, lidar2lidar and lidar2imu auto_calib (run_lidar2imu.cpp:39-54 inverts it into lidar2imu); its lidar2imu manual_calib (run_lidar2imu.cpp:312-313) uses such a file the other way: pass --invert if yours was written for that tool")).at(&loc));
    }
    out.edges.push(edge(
        &target,
        &sensor,
        read,
        path,
        k,
        OPENCALIB.id,
        format!("{key} sensor_calib"),
    ));
    Ok(out)
}
