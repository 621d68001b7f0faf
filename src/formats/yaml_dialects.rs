//! The YAML dialects, each with what its numbers mean and the frames it yields.
//!
//! - `tf-static-echo`: `rostopic echo /tf_static` (ROS 1) and
//!   `ros2 topic echo /tf_static` (ROS 2) output, several `---` documents with a
//!   `transforms:` list each. Each item: the pose of `child_frame_id` in
//!   `header.frame_id` (`transform.translation` x y z, `transform.rotation`
//!   x y z w), edge `frame_id -> child_frame_id`. A leading `/` is dropped.
//!   The same dump of `/tf` (`ros2 topic echo /tf`) is read the same way: a
//!   transform repeated with the same values is one edge; one that changes
//!   between messages (or changes parent) is kept as a moving frame that only
//!   a query whose path uses it refuses, naming the two messages (an edge off
//!   the queried chain does not block the file).
//! - `fast-lio` (FAST-LIO, FAST-LIVO2 `extrin_calib`, Point-LIO, Faster-LIO):
//!   `extrinsic_T` (3) and `extrinsic_R` (9, row-major). FAST-LIO's README: "the
//!   LiDAR's pose (position and rotation matrix) in IMU body frame", i.e.
//!   `p_imu = R p_lidar + T`: edge `imu -> lidar`.
//! - `lio-sam`: `extrinsicTrans` (3), `extrinsicRot` (9), `extrinsicRPY` (9).
//!   params.yaml: "Extrinsics: T_lb (lidar -> imu)". README: LIO-SAM
//!   "transforms IMU raw data from the IMU frame to the Lidar frame";
//!   `extrinsicRot` is the rotation applied to acceleration and gyro readings
//!   (so `v_lidar = extrinsicRot v_imu`), `extrinsicRPY` the one applied to the
//!   IMU's attitude readings (it "may or may not be the same"; Microstrain
//!   3DM-GX5). The code uses `extrinsicTrans` as the `lidar2Imu` translation. The
//!   tool uses `extrinsicRot` with `extrinsicTrans` as the pose of the IMU in the
//!   LiDAR frame: edge `lidar -> imu` (`audit FILE --from imu --to lidar` gives
//!   the LiDAR pose in the IMU frame). `extrinsicRPY` is not used; a warning says
//!   when it differs from `extrinsicRot`. Users often fill these FAST-LIO-style:
//!   an `assumed-convention` warning says so, `--invert` flips the file.
//! - `coco-lic`: `lidarN: Extrinsics: {Trans, Rot}` ("lidar to imu"): the LiDAR
//!   pose in the IMU frame, edges `imu -> lidarN`.
//! - `slict`: `lidar_extr`, k stacked row-major 4x4 ("Transform of coordinates
//!   in lidar's frame to body"): edge `body -> lidar` (k = 1) or
//!   `body -> lidar0`, `body -> lidar1`, ... The (4,4) entry is SLICT's timestamp
//!   flag (0 or 1) and the bottom row is not used (a warning when it is not
//!   `0 0 0 0|1`).
//! - `tf-tree-yaml` (GrandTour `calibration_latest.yaml`):
//!   `<parent>_to_<child>: {x, y, z, roll, pitch, yaw}` (URDF rpy), the child's
//!   pose in the parent; keys without `_to_` are ignored with a warning.
//! - `matrix-yaml`: keys `T_A_B` or `A_T_B` holding a 4x4 (OpenCV FileStorage
//!   `!!opencv-matrix` `{rows, cols, dt, data}`, a flat list of 16, a list of four
//!   rows, or a 3x4 without the bottom row) or `T_A_B_t_xyz_q_xyzw` (7 numbers):
//!   the pose of B in A (maps B coordinates into A), edge `A -> B`. Kalibr's
//!   `camN: {T_cam_imu, T_cn_cnm1}` name the camera `camN` (and `cam<N-1>`),
//!   the IMU `imu` or `imu0`. A comment `# Units: millimeters` just above a
//!   matrix converts it to metres (GEODE) with a warning. The keys become a
//!   tree plus checked redundant edges, and a key repeated with other values
//!   (GEODE's `T_LiDAR_CamL`) blocks only its own edge: see `matrix_tree`,
//!   which reads it (the shapes are read by `yaml_shapes`).
//! - `quaternion-yaml` (FusionPortable): `quaternion_A_B` (`data: [qw, qx, qy, qz]`,
//!   w first as its comments say) with `translation_A_B`: the pose of B in A
//!   (FusionPortable: "Extrinsics from the sensor (reference) to body_imu
//!   (target)", i.e. `T_sensor_body_imu`), edge `A -> B`, A the first word.
//! - `--key NAME` in any YAML/JSON file picks that one key (a dotted path
//!   `a.b.c` also works) and reads whichever of the shapes above it holds; frames
//!   from a `T_A_B` / `A_T_B` name, else `parent -> child` (see `yaml_keyed`).
//!
//! Each dialect sniffs its own keys ([`Confidence::Keys`], the keys of the
//! file collected once by the input); where a file holds the keys of two
//! dialects, the earlier in the registry reads it. `matrix-yaml` reads what
//! no other format claims ([`Confidence::Fallback`]).
//!
//! OpenCV's `%YAML:1.0` first line is blanked before parsing. A file that is
//! still not YAML (UrbanNav's `KEY:!!opencv-matrix (comment)` with mis-indented
//! fields) is refused with the parser's position and what to fix.

use super::spec::{check_metres, locate_warnings, Confidence, Input, Parsed};
use super::yaml::{Node, Value};
use super::yaml_keyed::{keys, yaml_dialect};
use super::yaml_shapes::{
    err_at, exactly, key_node, key_values, loc_of, mat3, rpy_map, unique_map,
};
use crate::diagnostic::{Code, Error, Result, Warning};
use crate::frames::Edge;
use crate::geometry::se3::{QuatOrder, Transform};
use crate::geometry::uncertainty::{written_precision, Written};
use std::path::Path;

/// A `rostopic echo` / `ros2 topic echo` dump: `transforms:` with child frames.
fn tf_echo(i: &Input) -> Option<Confidence> {
    keys(i.contains("child_frame_id") && i.has_key("transforms"))
}

/// FusionPortable: a key starting `quaternion_`.
fn quaternion_keys(i: &Input) -> Option<Confidence> {
    let text = i.text().unwrap_or("");
    keys(text.lines().any(|l| {
        let t = l.trim_start();
        !t.starts_with('#') && t.starts_with("quaternion_")
    }))
}

/// GrandTour: a top-level key `<parent>_to_<child>` and a `roll` key.
fn tf_tree_keys(i: &Input) -> Option<Confidence> {
    let text = i.text().unwrap_or("");
    let named = text.lines().any(|l| {
        !l.starts_with([' ', '\t', '#']) && l.split(':').next().is_some_and(|k| k.contains("_to_"))
    });
    keys(named && i.has_key("roll"))
}

yaml_dialect!(TF_STATIC_ECHO, "tf-static-echo", false, tf_echo, |d, _, p| parse_tf_echo(d, p), "`rostopic echo /tf_static` / `ros2 topic echo /tf_static` YAML (several documents): child_frame_id pose in header.frame_id");
yaml_dialect!(FAST_LIO, "fast-lio", true, |i| keys(i.has_key("extrinsic_T")), |d, _, p| parse_fast_lio(d, p, FAST_LIO.id), "FAST-LIO / FAST-LIVO2 / Point-LIO `extrinsic_T` + `extrinsic_R` (row-major): the LiDAR pose in the IMU frame, edge imu -> lidar");
yaml_dialect!(LIO_SAM, "lio-sam", true, |i| keys(i.has_key("extrinsicTrans") || i.has_key("extrinsicRot")), |d, _, p| parse_lio_sam(d, p), "LIO-SAM `extrinsicRot` + `extrinsicTrans` (\"T_lb\"): extrinsicRot rotates IMU readings into the LiDAR frame and the code uses extrinsicTrans as lidar2Imu, so the pair is the IMU pose in the LiDAR frame, edge lidar -> imu; extrinsicRPY (attitude only) is not used");
yaml_dialect!(COCO_LIC, "coco-lic", true, |i| keys(i.has_key("Extrinsics") && i.has_key("Trans")), |d, _, p| parse_coco_lic(d, p), "Coco-LIC `lidarN: Extrinsics: {Trans, Rot}` (\"lidar to imu\"): LiDAR pose in the IMU frame, edges imu -> lidarN");
yaml_dialect!(SLICT, "slict", true, |i| keys(i.has_key("lidar_extr")), |d, _, p| parse_slict(d, p), "SLICT `lidar_extr`: stacked row-major 4x4, \"transform of coordinates in lidar's frame to body\": edges body -> lidar (lidar0, lidar1, ... when several); the (4,4) entry is a timestamp flag and the bottom row is not used");
yaml_dialect!(TF_TREE_YAML, "tf-tree-yaml", true, tf_tree_keys, |d, _, p| parse_tf_tree(d, p), "tf-tree YAML (`<parent>_to_<child>: {x, y, z, roll, pitch, yaw}`, GrandTour): child pose in parent, URDF rpy");
yaml_dialect!(QUATERNION_YAML, "quaternion-yaml", true, quaternion_keys, parse_quaternion, "`quaternion_A_B` (qw, qx, qy, qz: w first) + `translation_A_B` blocks (FusionPortable): the pose of B in A, edge A -> B");

/// Keep one edge per child frame: repeats with the same values are one edge;
/// a child whose transform (or parent) changes between messages becomes a
/// floating joint without a value ([`crate::frames::MOVING_TF`]), so that only
/// a query whose path uses it is refused, naming the messages that disagree.
fn scope_changes(edges: Vec<Edge>) -> Vec<Edge> {
    let mut out: Vec<Edge> = Vec::new();
    for e in edges {
        let Some(first) = out.iter_mut().find(|f| f.child == e.child) else {
            out.push(e);
            continue;
        };
        if first.joint.is_some() || (first.parent == e.parent && first.transform == e.transform) {
            continue;
        }
        let line = |x: &Edge| {
            x.provenance
                .location
                .line
                .map_or("?".to_string(), |l| l.to_string())
        };
        let why = if first.parent == e.parent {
            format!(
                "changes between the messages of the dump (lines {} and {})",
                line(first),
                line(&e)
            )
        } else {
            format!(
                "has another parent, {}, at line {} (line {}: {})",
                e.parent,
                line(&e),
                line(first),
                first.parent
            )
        };
        first.joint = Some(Box::new(crate::frames::JointState {
            name: format!("{}{why}", crate::frames::MOVING_TF),
            joint_type: crate::frames::JointType::Floating,
            value: None,
            defaulted: false,
        }));
    }
    out
}

fn parse_tf_echo(docs: &[Node], path: &Path) -> Result<Parsed> {
    let mut out = Parsed::default();
    for d in docs {
        if matches!(d.value, Value::Null) {
            continue;
        }
        let Some(list) = d.get("transforms") else {
            return Err(err_at(
                d,
                format!(
                    "tf_static message: expected `transforms:`, found {}",
                    d.kind()
                ),
            ));
        };
        let Value::Seq(items) = &list.value else {
            return Err(err_at(
                list,
                format!("`transforms`: expected a list, found {}", list.kind()),
            ));
        };
        for it in items {
            let loc = loc_of(path, it);
            let field = |n: &Node, k: &str| -> Result<Node> {
                n.get(k)
                    .cloned()
                    .ok_or_else(|| err_at(n, format!("transform: expected `{k}`, found none")))
            };
            let header = field(it, "header")?;
            let parent = field(&header, "frame_id")?
                .as_str()
                .ok_or_else(|| err_at(&header, "header.frame_id: expected a string".into()))?;
            let child = field(it, "child_frame_id")?
                .as_str()
                .ok_or_else(|| err_at(it, "child_frame_id: expected a string".into()))?;
            let tr = field(it, "transform")?;
            let t = field(&tr, "translation")?;
            let r = field(&tr, "rotation")?;
            let num = |n: &Node, k: &str| -> Result<f64> {
                let v = field(n, k)?;
                v.as_f64().ok_or_else(|| {
                    err_at(&v, format!("`{k}`: expected a number, found {}", v.kind()))
                })
            };
            let d3 = [num(&t, "x")?, num(&t, "y")?, num(&t, "z")?];
            let q = [num(&r, "x")?, num(&r, "y")?, num(&r, "z")?, num(&r, "w")?];
            let mut ws = Vec::new();
            let tf = Transform::from_quaternion(q, QuatOrder::Xyzw, d3, &mut ws)
                .map_err(|e| e.at(&loc))?;
            check_metres(&d3, "transform.translation", &loc, &mut ws);
            locate_warnings(ws, &loc, &mut out.warnings);
            out.edges.push(
                Edge::new(
                    parent.trim_start_matches('/'),
                    child.trim_start_matches('/'),
                    tf,
                    loc,
                    TF_STATIC_ECHO.id,
                    format!("transforms[] {} -> {}", parent, child),
                )
                .with_precision(written_precision(
                    Written::Quat(q, QuatOrder::Xyzw),
                    d3,
                    1.0,
                )),
            );
        }
    }
    out.edges = scope_changes(out.edges);
    Ok(out)
}

/// `extrinsic_T` + `extrinsic_R` as the edge `imu -> lidar` of format `id`
/// (FAST-LIVO's files hold them too).
pub(crate) fn parse_fast_lio(docs: &[Node], path: &Path, id: &'static str) -> Result<Parsed> {
    let m = unique_map(docs, "extrinsic_T")?;
    let tn = m
        .get("extrinsic_T")
        .ok_or_else(|| Error::parse("extrinsic_T missing"))?;
    let rn = m.get("extrinsic_R").ok_or_else(|| {
        err_at(
            m,
            "expected `extrinsic_R` (9 numbers, row-major) next to `extrinsic_T`, found none"
                .into(),
        )
    })?;
    let loc = key_node(m, "extrinsic_T")
        .map(|k| loc_of(path, k))
        .unwrap_or_else(|| loc_of(path, tn));
    let d = exactly::<3>(tn, "extrinsic_T")?;
    let r = exactly::<9>(rn, "extrinsic_R")?;
    let mut out = Parsed::default();
    let mut ws = Vec::new();
    let t = Transform::from_matrix3(mat3(r), d, &mut ws).map_err(|e| e.at(&loc_of(path, rn)))?;
    check_metres(&d, "extrinsic_T", &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    out.edges.push(
        Edge::new("imu", "lidar", t, loc, id, "extrinsic_T + extrinsic_R")
            .with_precision(written_precision(Written::Matrix3(mat3(r)), d, 1.0))
            .with_values(key_values(m, "extrinsic_T", "extrinsic_R")),
    );
    Ok(out)
}

fn parse_lio_sam(docs: &[Node], path: &Path) -> Result<Parsed> {
    let m = unique_map(docs, "extrinsicTrans")?;
    let tn = m
        .get("extrinsicTrans")
        .ok_or_else(|| Error::parse("extrinsicTrans missing"))?;
    let rn = m.get("extrinsicRot").ok_or_else(|| {
        err_at(
            m,
            "expected `extrinsicRot` (9 numbers, row-major) next to `extrinsicTrans`, found none"
                .into(),
        )
    })?;
    let loc = key_node(m, "extrinsicTrans")
        .map(|k| loc_of(path, k))
        .unwrap_or_else(|| loc_of(path, tn));
    let d = exactly::<3>(tn, "extrinsicTrans")?;
    let r = exactly::<9>(rn, "extrinsicRot")?;
    let mut out = Parsed::default();
    let mut ws = Vec::new();
    let t = Transform::from_matrix3(mat3(r), d, &mut ws).map_err(|e| e.at(&loc_of(path, rn)))?;
    check_metres(&d, "extrinsicTrans", &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    if let Some(rpy) = m.get("extrinsicRPY") {
        let v = exactly::<9>(rpy, "extrinsicRPY")?;
        if v.iter().zip(r.iter()).any(|(a, b)| (a - b).abs() > 1e-12) {
            out.warnings.push(
                Warning::new(
                    Code::Ignored,
                    "extrinsicRPY differs from extrinsicRot: LIO-SAM applies it to the IMU's attitude readings only; the tool uses extrinsicRot",
                )
                .at(&loc_of(path, rpy)),
            );
        }
    }
    out.warnings.push(
        Warning::new(
            Code::AssumedConvention,
            "LIO-SAM extrinsicRot + extrinsicTrans read as the IMU pose in the LiDAR frame (edge lidar -> imu), as LIO-SAM's code uses them; many users fill them FAST-LIO-style (LiDAR in IMU): pass --invert for such a file",
        )
        .at(&loc),
    );
    out.edges.push(
        Edge::new(
            "lidar",
            "imu",
            t,
            loc,
            LIO_SAM.id,
            "extrinsicTrans + extrinsicRot",
        )
        .with_precision(written_precision(Written::Matrix3(mat3(r)), d, 1.0)),
    );
    Ok(out)
}

fn parse_coco_lic(docs: &[Node], path: &Path) -> Result<Parsed> {
    let mut out = Parsed::default();
    for d in docs {
        for (k, v) in d.entries() {
            let Some(name) = k.as_str() else { continue };
            let Some(ex) = v.get("Extrinsics") else {
                continue;
            };
            let loc = loc_of(path, k);
            let tn = ex.get("Trans").ok_or_else(|| {
                err_at(
                    ex,
                    format!("{name}.Extrinsics: expected `Trans`, found none"),
                )
            })?;
            let rn = ex.get("Rot").ok_or_else(|| {
                err_at(ex, format!("{name}.Extrinsics: expected `Rot`, found none"))
            })?;
            let dd = exactly::<3>(tn, &format!("{name}.Extrinsics.Trans"))?;
            let r = exactly::<9>(rn, &format!("{name}.Extrinsics.Rot"))?;
            let mut ws = Vec::new();
            let t = Transform::from_matrix3(mat3(r), dd, &mut ws)
                .map_err(|e| e.at(&loc_of(path, rn)))?;
            check_metres(&dd, "Trans", &loc, &mut ws);
            locate_warnings(ws, &loc, &mut out.warnings);
            out.edges.push(
                Edge::new(
                    "imu",
                    name.clone(),
                    t,
                    loc,
                    COCO_LIC.id,
                    format!("{name}.Extrinsics Trans + Rot"),
                )
                .with_precision(written_precision(
                    Written::Matrix3(mat3(r)),
                    dd,
                    1.0,
                )),
            );
        }
    }
    Ok(out)
}

fn parse_slict(docs: &[Node], path: &Path) -> Result<Parsed> {
    let m = unique_map(docs, "lidar_extr")?;
    let n = m
        .get("lidar_extr")
        .ok_or_else(|| Error::parse("lidar_extr missing"))?;
    let loc = key_node(m, "lidar_extr")
        .map(|k| loc_of(path, k))
        .unwrap_or_else(|| loc_of(path, n));
    let v = n.numbers("lidar_extr")?;
    if v.is_empty() || v.len() % 16 != 0 {
        return Err(err_at(
            n,
            format!(
                "lidar_extr: expected 16 numbers per LiDAR (stacked row-major 4x4), found {}",
                v.len()
            ),
        ));
    }
    let k = v.len() / 16;
    let mut out = Parsed::default();
    for i in 0..k {
        let b = &v[16 * i..16 * (i + 1)];
        let r = [[b[0], b[1], b[2]], [b[4], b[5], b[6]], [b[8], b[9], b[10]]];
        let d = [b[3], b[7], b[11]];
        let mut ws = Vec::new();
        let t = Transform::from_matrix3(r, d, &mut ws).map_err(|e| e.at(&loc))?;
        let flag_ok =
            b[12] == 0.0 && b[13] == 0.0 && b[14] == 0.0 && (b[15] == 0.0 || b[15] == 1.0);
        if !flag_ok {
            ws.push(Warning::new(
                Code::Ignored,
                format!(
                    "lidar_extr matrix {i}: bottom row [{}, {}, {}, {}] is not [0, 0, 0, 0|1]; not used (SLICT reads the (4,4) entry as a timestamp flag)",
                    b[12], b[13], b[14], b[15]
                ),
            ));
        }
        check_metres(&d, "lidar_extr translation", &loc, &mut ws);
        locate_warnings(ws, &loc, &mut out.warnings);
        let child = if k == 1 {
            "lidar".to_string()
        } else {
            format!("lidar{i}")
        };
        out.edges.push(
            Edge::new(
                "body",
                child,
                t,
                loc.clone(),
                SLICT.id,
                format!("lidar_extr[{i}]"),
            )
            .with_precision(written_precision(Written::Matrix3(r), d, 1.0)),
        );
    }
    Ok(out)
}

fn parse_tf_tree(docs: &[Node], path: &Path) -> Result<Parsed> {
    let mut out = Parsed::default();
    for d in docs {
        for (k, v) in d.entries() {
            let Some(name) = k.as_str() else { continue };
            let loc = loc_of(path, k);
            if !matches!(v.value, Value::Map(_)) {
                continue;
            }
            let Some((p, c)) = name.split_once("_to_") else {
                out.warnings.push(
                    Warning::new(
                        Code::Ignored,
                        format!(
                            "`{name}` does not name its frames as <parent>_to_<child>; ignored"
                        ),
                    )
                    .at(&loc),
                );
                continue;
            };
            let (t, precision) = rpy_map(v, &name)?;
            let mut ws = Vec::new();
            check_metres(
                &[t.translation().x, t.translation().y, t.translation().z],
                &name,
                &loc,
                &mut ws,
            );
            out.warnings.extend(ws);
            out.edges.push(
                Edge::new(
                    p,
                    c,
                    t,
                    loc,
                    TF_TREE_YAML.id,
                    format!("{name} {{x, y, z, roll, pitch, yaw}}"),
                )
                .with_precision(precision),
            );
        }
    }
    Ok(out)
}

fn parse_quaternion(docs: &[Node], text: &str, path: &Path) -> Result<Parsed> {
    let mut out = Parsed::default();
    let stated_wxyz = text.contains("(qw, qx, qy, qz)") || text.contains("qw, qx, qy, qz");
    for d in docs {
        for (k, v) in d.entries() {
            let Some(name) = k.as_str() else { continue };
            let Some(pair) = name.strip_prefix("quaternion_") else {
                continue;
            };
            let loc = loc_of(path, k);
            let tname = format!("translation_{pair}");
            let tn = d.get(&tname).ok_or_else(|| {
                err_at(
                    k,
                    format!("`{name}`: expected `{tname}` next to it, found none"),
                )
            })?;
            let qv = match v.get("data") {
                Some(data) => exactly::<4>(data, &format!("{name}.data"))?,
                None => exactly::<4>(v, &name)?,
            };
            let tv = match tn.get("data") {
                Some(data) => exactly::<3>(data, &format!("{tname}.data"))?,
                None => exactly::<3>(tn, &tname)?,
            };
            let Some((a, b)) = pair.split_once('_') else {
                return Err(err_at(
                    k,
                    format!("`{name}`: expected quaternion_<from>_<to>, found no second frame"),
                ));
            };
            let mut ws = Vec::new();
            let t = Transform::from_quaternion(qv, QuatOrder::Wxyz, tv, &mut ws)
                .map_err(|e| e.at(&loc))?;
            if !stated_wxyz {
                ws.push(Warning::new(
                    Code::AssumedConvention,
                    format!("`{name}`: quaternion read w first (qw, qx, qy, qz), FusionPortable's order; the file does not state it"),
                ));
            }
            check_metres(&tv, &tname, &loc, &mut ws);
            locate_warnings(ws, &loc, &mut out.warnings);
            out.edges.push(
                Edge::new(
                    a,
                    b,
                    t,
                    loc,
                    QUATERNION_YAML.id,
                    format!("{name} (qw qx qy qz) + {tname}"),
                )
                .with_precision(written_precision(
                    Written::Quat(qv, QuatOrder::Wxyz),
                    tv,
                    1.0,
                )),
            );
        }
    }
    Ok(out)
}
