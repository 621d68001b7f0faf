//! `orb-slam3`: ORB-SLAM3 settings files (OpenCV FileStorage YAML,
//! `!!opencv-matrix` `{rows, cols, dt, data}`, data row-major).
//!
//! Which reader ORB-SLAM3 applies depends on `File.version`
//! (UZ-SLAMLab/ORB_SLAM3 @ 4452a3c4ab75b1cde34e5505a36ec3f9edcdc4c4,
//! `src/System.cc:77-78`: `node.string() == "1.0"` selects `Settings`):
//!
//! - `File.version: "1.0"`: `IMU.T_b_c1` (4x4, `src/Settings.cc:422-423`,
//!   into `Tbc_`) and `Stereo.T_c1_c2` (4x4, `src/Settings.cc:342-343`, into
//!   `Tlr_`);
//! - no `File.version`: `Tbc` (4x4, `src/Tracking.cc:1306`, `1322-1324`,
//!   "Left camera to Imu Transform (Tbc)", an explicitly row-major Eigen map)
//!   and `Tlr` (3x4 required: `src/Tracking.cc:1054-1061` refuses other
//!   sizes, `1096` `mTlr = Converter::toSophus(cvTlr)`).
//!
//! Direction: `Tbc` is the pose of the left camera `c1` in the body `b` (the
//! IMU): `src/ImuTypes.cc:403-404` `mTcb = mTbc.inverse()` and
//! `src/Frame.cc:465` `mTcw = mImuCalib.mTcb * Tbw` (camera-from-world =
//! camera-from-body x body-from-world): edge `b -> c1`. `Tlr` is the pose of
//! the right camera in the left one, `src/Frame.cc:1179`
//! `twc = mRwc * mTlr.translation() + mOw`: edge `c1 -> c2`. Metres. The
//! frames are named as the keys name them: `b` (the IMU), `c1`, `c2`.
//!
//! Keys of the other generation are not read by ORB-SLAM3 and not here (an
//! `ignored` warning names them). Sizes other than those the code requires,
//! and data lengths other than rows x cols, are refused.

use super::calib_shapes::{cv_matrix, edge, field, rigid16, rigid_rt, top_map};
use super::spec::{locate_warnings, Parsed};
use super::yaml::Node;
use super::yaml_keyed::{keys, yaml_dialect};
use super::yaml_shapes::{key_node, loc_of};
use crate::diagnostic::{Code, Result, Warning};
use std::path::Path;

yaml_dialect!(ORB_SLAM3, "orb-slam3", false, |i| keys(["IMU.T_b_c1", "Stereo.T_c1_c2", "Tbc", "Tlr"].iter().any(|k| i.has_key(k))), |d, _, p| parse(d, p), "ORB-SLAM3 settings (`!!opencv-matrix`, row-major): `IMU.T_b_c1` / `Tbc` the left camera's pose in the body (IMU), edge b -> c1; `Stereo.T_c1_c2` / `Tlr` (3x4) the right camera's pose in the left, edge c1 -> c2; File.version \"1.0\" selects the key names, as ORB-SLAM3 does");

/// The keys one generation reads: (key, parent, child, rows).
const V1: &[(&str, &str, &str, usize)] = &[
    ("IMU.T_b_c1", "b", "c1", 4),
    ("Stereo.T_c1_c2", "c1", "c2", 4),
];
const V0: &[(&str, &str, &str, usize)] = &[("Tbc", "b", "c1", 4), ("Tlr", "c1", "c2", 3)];

fn parse(docs: &[Node], path: &Path) -> Result<Parsed> {
    let d = top_map(docs, "ORB-SLAM3 settings")?;
    let v1 = d.get("File.version").and_then(|v| v.as_str()).as_deref() == Some("1.0");
    let (read, other, why) = if v1 {
        (V1, V0, "File.version is \"1.0\": ORB-SLAM3's Settings reads IMU.T_b_c1 and Stereo.T_c1_c2 only")
    } else {
        (V0, V1, "no File.version \"1.0\": ORB-SLAM3 reads this file with its pre-1.0 parser, which reads Tbc and Tlr only")
    };
    let mut out = Parsed::default();
    for &(key, _, _, _) in other {
        if let Some(k) = key_node(d, key) {
            out.warnings.push(
                Warning::new(Code::Ignored, format!("`{key}` is not read: {why}"))
                    .at(&loc_of(path, k)),
            );
        }
    }
    for &(key, parent, child, rows) in read {
        let (Some(k), Some(v)) = (key_node(d, key), d.get(key)) else {
            continue;
        };
        let data = cv_matrix(v, rows, 4, key)?;
        let mut ws = Vec::new();
        let at = field(v, "data", key)?;
        let r = if rows == 4 {
            rigid16(&data, at, key, &mut ws)?
        } else {
            let rot = [
                data[0], data[1], data[2], data[4], data[5], data[6], data[8], data[9], data[10],
            ];
            rigid_rt(&rot, &[data[3], data[7], data[11]], at, key, &mut ws)?
        };
        locate_warnings(ws, &loc_of(path, k), &mut out.warnings);
        out.edges.push(edge(
            parent,
            child,
            r,
            path,
            k,
            ORB_SLAM3.id,
            format!("{key} (!!opencv-matrix)"),
        ));
    }
    if out.edges.is_empty() {
        let names: Vec<&str> = read.iter().map(|k| k.0).collect();
        return Err(crate::diagnostic::Error::parse(format!(
            "ORB-SLAM3 settings: expected {} ({why}), found neither",
            names.join(" or ")
        )));
    }
    Ok(out)
}
