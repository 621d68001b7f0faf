//! The YAML dialects, each with what its numbers mean and the frames it yields.
//!
//! - `tf-static-echo`: `rostopic echo /tf_static` (ROS 1) and
//!   `ros2 topic echo /tf_static` (ROS 2) output, several `---` documents with a
//!   `transforms:` list each. Each item: the pose of `child_frame_id` in
//!   `header.frame_id` (`transform.translation` x y z, `transform.rotation`
//!   x y z w), edge `frame_id -> child_frame_id`. A leading `/` is dropped.
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
//!   (GEODE's `T_LiDAR_CamL`) blocks only its own edge: see `matrix_tree`.
//! - `quaternion-yaml` (FusionPortable): `quaternion_A_B` (`data: [qw, qx, qy, qz]`,
//!   w first as its comments say) with `translation_A_B`: the pose of B in A
//!   (FusionPortable: "Extrinsics from the sensor (reference) to body_imu
//!   (target)", i.e. `T_sensor_body_imu`), edge `A -> B`, A the first word.
//! - `--key NAME` in any YAML/JSON file picks that one key (a dotted path
//!   `a.b.c` also works) and reads whichever of the shapes above it holds; frames
//!   from a `T_A_B` / `A_T_B` name, else `parent -> child`.
//!
//! OpenCV's `%YAML:1.0` first line is blanked before parsing. A file that is
//! still not YAML (UrbanNav's `KEY:!!opencv-matrix (comment)` with mis-indented
//! fields) is refused with the parser's position and what to fix.

use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::registry::{FormatSpec, Sniff};
use crate::formats::yaml::{self, Node, Value};
use crate::formats::{check_metres, locate_warnings, Edge, LoadOptions, Loaded};
use crate::geometry::se3::{QuatOrder, Transform};
use crate::geometry::uncertainty::{matrix4_precision, written_precision, Written};
use crate::geometry::EdgePrecision;
use std::path::Path;

/// A non-comment line that starts (after indentation) with `key:`.
pub(crate) fn has_key_line(text: &str, key: &str) -> bool {
    text.lines().any(|l| {
        let t = l.trim_start();
        !t.starts_with('#')
            && t.strip_prefix(key)
                .map(|r| r.trim_start().starts_with(':'))
                .unwrap_or(false)
    })
}

/// The id of the YAML dialect the keys present name (`matrix-yaml` when
/// none does).
pub fn dialect(text: &str) -> &'static str {
    if text.contains("child_frame_id") && has_key_line(text, "transforms") {
        return TF_STATIC_ECHO.id;
    }
    if text.contains("static_transform_publisher")
        && (has_key_line(text, "exec")
            || has_key_line(text, "- node")
            || has_key_line(text, "node"))
    {
        return crate::formats::launch::LAUNCH_YAML.id;
    }
    if has_key_line(text, "extrinsic_T") {
        return FAST_LIO.id;
    }
    if has_key_line(text, "extrinsicTrans") || has_key_line(text, "extrinsicRot") {
        return LIO_SAM.id;
    }
    if let Some(id) = crate::formats::lio_yaml::dialect(text) {
        return id;
    }
    if has_key_line(text, "lidar_extr") {
        return SLICT.id;
    }
    if has_key_line(text, "Extrinsics") && has_key_line(text, "Trans") {
        return COCO_LIC.id;
    }
    if text.lines().any(|l| {
        let t = l.trim_start();
        !t.starts_with('#') && t.starts_with("quaternion_")
    }) {
        return QUATERNION_YAML.id;
    }
    if text.lines().any(|l| {
        !l.starts_with([' ', '\t', '#'])
            && l.split(':')
                .next()
                .map(|k| k.contains("_to_"))
                .unwrap_or(false)
    }) && has_key_line(text, "roll")
    {
        return TF_TREE_YAML.id;
    }
    MATRIX_YAML.id
}

pub(crate) fn loc_of(path: &Path, n: &Node) -> Location {
    if n.line == 0 {
        Location::file(path)
    } else {
        Location::at(path, n.line, Some(n.column.max(1)))
    }
}

pub(crate) fn err_at(n: &Node, msg: String) -> Error {
    Error::parse(msg).at_line(n.line.max(1), Some(n.column.max(1)))
}

/// All maps (depth-first) that contain `key`.
fn maps_with<'a>(n: &'a Node, key: &str, out: &mut Vec<&'a Node>) {
    match &n.value {
        Value::Map(m) => {
            if !n.get_all(key).is_empty() {
                out.push(n);
            }
            for (_, v) in m {
                maps_with(v, key, out);
            }
        }
        Value::Seq(s) => {
            for v in s {
                maps_with(v, key, out);
            }
        }
        _ => {}
    }
}

pub(crate) fn exactly<const N: usize>(n: &Node, what: &str) -> Result<[f64; N]> {
    let v = n.numbers(what)?;
    if v.len() != N {
        return Err(err_at(
            n,
            format!("{what}: expected {N} numbers, found {}", v.len()),
        ));
    }
    let mut out = [0.0; N];
    out.copy_from_slice(&v);
    Ok(out)
}

pub(crate) fn mat3(v: [f64; 9]) -> [[f64; 3]; 3] {
    [[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]]
}

/// The single map holding `key` (error when several do).
pub(crate) fn unique_map<'a>(docs: &'a [Node], key: &str) -> Result<&'a Node> {
    let mut found = Vec::new();
    for d in docs {
        maps_with(d, key, &mut found);
    }
    match found.len() {
        0 => Err(Error::parse(format!("expected a key `{key}`, found none"))),
        1 => {
            let m = found[0];
            let all = m.get_all(key);
            if all.len() > 1 {
                return Err(err_at(
                    all[1],
                    format!(
                        "`{key}` given twice in one mapping (lines {} and {}): expected one",
                        all[0].line, all[1].line
                    ),
                ));
            }
            Ok(m)
        }
        _ => Err(err_at(
            found[1],
            format!(
                "`{key}` appears {} times (lines {}): expected one; pick one with --key PATH (e.g. a.b.{key})",
                found.len(),
                found
                    .iter()
                    .filter_map(|m| m.get(key).map(|v| v.line.to_string()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
    }
}

pub(crate) fn key_node<'a>(m: &'a Node, key: &str) -> Option<&'a Node> {
    m.entries()
        .iter()
        .rev()
        .find(|(k, _)| k.as_str().as_deref() == Some(key))
        .map(|(k, _)| k)
}

pub(crate) type DocsParser = fn(&[Node], &str, &Path) -> Result<Loaded>;

/// Parse YAML text with one dialect's reader; `--key` reads one key instead
/// (except in tf_static dumps, whose keys are not transforms).
pub(crate) fn parse_with(
    read: DocsParser,
    keyed: bool,
    text: &str,
    path: &Path,
    opts: &LoadOptions,
) -> Result<Loaded> {
    let docs = yaml::parse_documents(text).map_err(|e| explain_yaml_error(e, text))?;
    if let (Some(key), true) = (&opts.key, keyed) {
        return parse_keyed(&docs, key, text, path);
    }
    read(&docs, text, path)
}

macro_rules! dialect {
    ($name:ident, $id:literal, $keyed:literal, $read:expr, $desc:literal) => {
        #[doc = $desc]
        pub const $name: FormatSpec = FormatSpec {
            id: $id,
            description: $desc,
            extensions: &[],
            walk: &[".yaml", ".yml"],
            sniff: |s: &Sniff| (s.yaml_dialect() == $id).then_some(10),
            parse: |text, path, opts| parse_with($read, $keyed, text, path, opts),
        };
    };
}

dialect!(TF_STATIC_ECHO, "tf-static-echo", false, |d, _, p| parse_tf_echo(d, p), "`rostopic echo /tf_static` / `ros2 topic echo /tf_static` YAML (several documents): child_frame_id pose in header.frame_id");
dialect!(FAST_LIO, "fast-lio", true, |d, _, p| parse_fast_lio(d, p), "FAST-LIO / FAST-LIVO2 / Point-LIO `extrinsic_T` + `extrinsic_R` (row-major): the LiDAR pose in the IMU frame, edge imu -> lidar");
dialect!(LIO_SAM, "lio-sam", true, |d, _, p| parse_lio_sam(d, p), "LIO-SAM `extrinsicRot` + `extrinsicTrans` (\"T_lb\"): extrinsicRot rotates IMU readings into the LiDAR frame and the code uses extrinsicTrans as lidar2Imu, so the pair is the IMU pose in the LiDAR frame, edge lidar -> imu; extrinsicRPY (attitude only) is not used");
dialect!(COCO_LIC, "coco-lic", true, |d, _, p| parse_coco_lic(d, p), "Coco-LIC `lidarN: Extrinsics: {Trans, Rot}` (\"lidar to imu\"): LiDAR pose in the IMU frame, edges imu -> lidarN");
dialect!(SLICT, "slict", true, |d, _, p| parse_slict(d, p), "SLICT `lidar_extr`: stacked row-major 4x4, \"transform of coordinates in lidar's frame to body\": edges body -> lidar (lidar0, lidar1, ... when several); the (4,4) entry is a timestamp flag and the bottom row is not used");
dialect!(TF_TREE_YAML, "tf-tree-yaml", true, |d, _, p| parse_tf_tree(d, p), "tf-tree YAML (`<parent>_to_<child>: {x, y, z, roll, pitch, yaw}`, GrandTour): child pose in parent, URDF rpy");
dialect!(MATRIX_YAML, "matrix-yaml", true, parse_matrices, "YAML with 4x4 matrices under keys `T_A_B` or `A_T_B` (OpenCV FileStorage `!!opencv-matrix`, VINS-Fusion `body_T_cam0`, plain lists, `T_A_B_t_xyz_q_xyzw`): the pose of B in A, edge A -> B; Kalibr camchain `camN: {T_cam_imu, T_cn_cnm1}`: edges imu -> camN, T_cn_cnm1 checked as a redundant edge; a key that closes a loop is checked, not refused; --key NAME picks one");
dialect!(QUATERNION_YAML, "quaternion-yaml", true, parse_quaternion, "`quaternion_A_B` (qw, qx, qy, qz: w first) + `translation_A_B` blocks (FusionPortable): the pose of B in A, edge A -> B");

fn explain_yaml_error(e: Error, text: &str) -> Error {
    if text.contains("!!opencv-matrix") || text.trim_start().starts_with("%YAML:") {
        let msg = format!(
            "{} (OpenCV FileStorage file that is not valid YAML: write each matrix as `KEY: !!opencv-matrix` with `rows`, `cols`, `dt`, `data` indented alike and comments after `#`; or copy the one matrix you need into a file of its own and pass --key NAME)",
            e.message
        );
        Error { message: msg, ..e }
    } else {
        e
    }
}

fn parse_tf_echo(docs: &[Node], path: &Path) -> Result<Loaded> {
    let mut out = Loaded::default();
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
    Ok(out)
}

fn parse_fast_lio(docs: &[Node], path: &Path) -> Result<Loaded> {
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
    let mut out = Loaded::default();
    let mut ws = Vec::new();
    let t = Transform::from_matrix3(mat3(r), d, &mut ws).map_err(|e| e.at(&loc_of(path, rn)))?;
    check_metres(&d, "extrinsic_T", &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    out.edges.push(
        Edge::new(
            "imu",
            "lidar",
            t,
            loc,
            FAST_LIO.id,
            "extrinsic_T + extrinsic_R",
        )
        .with_precision(written_precision(Written::Matrix3(mat3(r)), d, 1.0)),
    );
    Ok(out)
}

fn parse_lio_sam(docs: &[Node], path: &Path) -> Result<Loaded> {
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
    let mut out = Loaded::default();
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

fn parse_coco_lic(docs: &[Node], path: &Path) -> Result<Loaded> {
    let mut out = Loaded::default();
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

fn parse_slict(docs: &[Node], path: &Path) -> Result<Loaded> {
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
    let mut out = Loaded::default();
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

fn rpy_map(v: &Node, name: &str) -> Result<(Transform, EdgePrecision)> {
    let num = |k: &str| -> Result<f64> {
        match v.get(k) {
            None => Ok(0.0),
            Some(x) => x.as_f64().ok_or_else(|| {
                err_at(
                    x,
                    format!("{name}.{k}: expected a number, found {}", x.kind()),
                )
            }),
        }
    };
    let d = [num("x")?, num("y")?, num("z")?];
    let rpy = [num("roll")?, num("pitch")?, num("yaw")?];
    let t =
        Transform::from_rpy(rpy, d).map_err(|e| e.at_line(v.line.max(1), Some(v.column.max(1))))?;
    Ok((t, written_precision(Written::Rpy(rpy), d, 1.0)))
}

fn parse_tf_tree(docs: &[Node], path: &Path) -> Result<Loaded> {
    let mut out = Loaded::default();
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

/// Frames named by a key: `T_A_B` / `A_T_B` (pose of B in A).
pub fn frames_from_key(key: &str) -> Option<(String, String)> {
    let key = key.strip_suffix("_t_xyz_q_xyzw").unwrap_or(key);
    if let Some((a, b)) = key.split_once("_T_") {
        if !a.is_empty() && !b.is_empty() && !b.contains("_T_") {
            return Some((a.to_string(), b.to_string()));
        }
    }
    if let Some(rest) = key.strip_prefix("T_") {
        let parts: Vec<&str> = rest.split('_').collect();
        if parts.len() == 2 && !parts[0].is_empty() && !parts[1].is_empty() {
            return Some((parts[0].to_string(), parts[1].to_string()));
        }
    }
    None
}

/// Read whatever transform shape a node holds, with the rounding of its numbers.
fn read_transform(
    n: &Node,
    key: &str,
    ws: &mut Vec<Warning>,
) -> Result<(Transform, EdgePrecision)> {
    // OpenCV {rows, cols, data}
    if let Some(data) = n.get("data") {
        let v = data.numbers(&format!("{key}.data"))?;
        let rows = n.get("rows").and_then(|x| x.as_f64());
        let cols = n.get("cols").and_then(|x| x.as_f64());
        if let (Some(r), Some(c)) = (rows, cols) {
            if (r * c) as usize != v.len() {
                return Err(err_at(
                    data,
                    format!("{key}: rows x cols = {r} x {c}, expected that many numbers in data, found {}", v.len()),
                ));
            }
        }
        return matrix_from_numbers(&v, data, key, ws);
    }
    if matches!(n.value, Value::Map(_)) {
        if n.get("roll").is_some() || n.get("yaw").is_some() || n.get("x").is_some() {
            if n.get("qw").is_some() || n.get("qx").is_some() {
                let num = |k: &str, def: f64| -> Result<f64> {
                    match n.get(k) {
                        None => Ok(def),
                        Some(x) => x
                            .as_f64()
                            .ok_or_else(|| err_at(x, format!("{key}.{k}: expected a number"))),
                    }
                };
                let q = [
                    num("qx", 0.0)?,
                    num("qy", 0.0)?,
                    num("qz", 0.0)?,
                    num("qw", 1.0)?,
                ];
                let d = [num("x", 0.0)?, num("y", 0.0)?, num("z", 0.0)?];
                let t = Transform::from_quaternion(q, QuatOrder::Xyzw, d, ws)
                    .map_err(|e| e.at_line(n.line.max(1), Some(n.column.max(1))))?;
                return Ok((
                    t,
                    written_precision(Written::Quat(q, QuatOrder::Xyzw), d, 1.0),
                ));
            }
            return rpy_map(n, key);
        }
        return Err(err_at(
            n,
            format!("{key}: expected a 4x4 matrix (16 numbers, four rows, or rows/cols/data), a 3x4 matrix, 7 numbers `t_xyz_q_xyzw` or {{x, y, z, roll, pitch, yaw}}, found a mapping with keys {}",
                n.entries().iter().filter_map(|(k, _)| k.as_str()).collect::<Vec<_>>().join(", ")),
        ));
    }
    let v = n.numbers(key)?;
    if key.ends_with("_t_xyz_q_xyzw") {
        if v.len() != 7 {
            return Err(err_at(
                n,
                format!(
                    "{key}: expected 7 numbers (tx ty tz qx qy qz qw), found {}",
                    v.len()
                ),
            ));
        }
        let (q, d) = ([v[3], v[4], v[5], v[6]], [v[0], v[1], v[2]]);
        let t = Transform::from_quaternion(q, QuatOrder::Xyzw, d, ws)
            .map_err(|e| e.at_line(n.line.max(1), Some(n.column.max(1))))?;
        return Ok((
            t,
            written_precision(Written::Quat(q, QuatOrder::Xyzw), d, 1.0),
        ));
    }
    matrix_from_numbers(&v, n, key, ws)
}

fn matrix_from_numbers(
    v: &[f64],
    n: &Node,
    key: &str,
    ws: &mut Vec<Warning>,
) -> Result<(Transform, EdgePrecision)> {
    let at = |e: Error| e.at_line(n.line.max(1), Some(n.column.max(1)));
    match v.len() {
        16 => {
            let m = [
                [v[0], v[1], v[2], v[3]],
                [v[4], v[5], v[6], v[7]],
                [v[8], v[9], v[10], v[11]],
                [v[12], v[13], v[14], v[15]],
            ];
            let t = Transform::from_matrix4(m, ws).map_err(|e| at(Error { message: format!("{key}: {}", e.message), ..e }))?;
            Ok((t, matrix4_precision(m, 1.0)))
        }
        12 => {
            let r = [[v[0], v[1], v[2]], [v[4], v[5], v[6]], [v[8], v[9], v[10]]];
            let d = [v[3], v[7], v[11]];
            let t = Transform::from_matrix3(r, d, ws)
                .map_err(|e| at(Error { message: format!("{key}: {}", e.message), ..e }))?;
            Ok((t, written_precision(Written::Matrix3(r), d, 1.0)))
        }
        4 => Err(err_at(
            n,
            format!("{key}: 4 numbers without a stated order (x y z w or w x y z?): expected a 4x4 matrix; write the quaternion as {{qx, qy, qz, qw}} (or under a key ending in _t_xyz_q_xyzw), or for FusionPortable-style quaternion_A_B + translation_A_B blocks (w first) pass --input-format quaternion-yaml"),
        )),
        k if k > 16 && k % 16 == 0 => Err(err_at(
            n,
            format!(
                "{key}: {k} numbers = {} stacked 4x4 matrices: expected one; pass --key {key}[i] with i from 0 to {} to pick one",
                k / 16,
                k / 16 - 1
            ),
        )),
        k => Err(err_at(
            n,
            format!("{key}: expected 16 numbers (4x4) or 12 (3x4), found {k}"),
        )),
    }
}

/// Comment lines just above `line` (1-based) mention millimetres?
fn millimetre_comment(text: &str, line: usize) -> bool {
    let lines: Vec<&str> = text.lines().collect();
    let mut i = line.saturating_sub(1);
    while i > 0 {
        i -= 1;
        let t = lines.get(i).map(|s| s.trim()).unwrap_or("");
        if t.is_empty() {
            continue;
        }
        if !t.starts_with('#') {
            return false;
        }
        let l = t.to_lowercase();
        if l.contains("millimet") || l.contains("units: mm") {
            return true;
        }
    }
    false
}

/// One matrix key read as an edge `frames.0 -> frames.1` (the pose of the
/// second frame in the first), its warnings located at the key.
pub(crate) fn matrix_edge(
    key: &str,
    frames: (String, String),
    v: &Node,
    k: &Node,
    text: &str,
    path: &Path,
    warnings: &mut Vec<Warning>,
) -> Result<Edge> {
    let loc = loc_of(path, k);
    let mut ws = Vec::new();
    let (mut t, mut precision) = read_transform(v, key, &mut ws)?;
    if millimetre_comment(text, k.line) {
        t = t.scaled_translation(1e-3);
        precision = precision.scaled_translation(1e-3);
        ws.push(Warning::new(
            Code::AssumedConvention,
            format!("{key}: the comment above says millimetres; translation converted to metres"),
        ));
    }
    let d = *t.translation();
    check_metres(&[d.x, d.y, d.z], key, &loc, &mut ws);
    locate_warnings(ws, &loc, warnings);
    Ok(
        Edge::new(frames.0, frames.1, t, loc, MATRIX_YAML.id, key.to_string())
            .with_precision(precision),
    )
}

pub(crate) fn parse_matrices(docs: &[Node], text: &str, path: &Path) -> Result<Loaded> {
    crate::formats::matrix_tree::parse(docs, text, path)
}

fn parse_quaternion(docs: &[Node], text: &str, path: &Path) -> Result<Loaded> {
    let mut out = Loaded::default();
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

fn find_key<'a>(n: &'a Node, key: &str, out: &mut Vec<(&'a Node, &'a Node)>) {
    match &n.value {
        Value::Map(m) => {
            for (k, v) in m {
                if k.as_str().as_deref() == Some(key) {
                    out.push((k, v));
                }
                find_key(v, key, out);
            }
        }
        Value::Seq(s) => {
            for v in s {
                find_key(v, key, out);
            }
        }
        _ => {}
    }
}

/// `--key NAME`: one key anywhere (or a dotted path from the top).
pub fn parse_keyed(docs: &[Node], key: &str, text: &str, path: &Path) -> Result<Loaded> {
    // `NAME[i]`: the i-th of stacked 4x4 matrices under NAME.
    let (key, index) = match key.strip_suffix(']').and_then(|k| k.rsplit_once('[')) {
        Some((k, i)) => match i.trim().parse::<usize>() {
            Ok(i) => (k, Some(i)),
            Err(_) => {
                return Err(Error::usage(format!(
                    "--key {key}: expected NAME or NAME[i] with i a number, found [{i}]"
                )))
            }
        },
        None => (key, None),
    };
    let (k, v) = find_one_key(docs, key)?;
    let picked;
    let v = match index {
        None => v,
        Some(i) => {
            picked = stacked_matrix(v, key, i)?;
            &picked
        }
    };
    let last = key.rsplit('.').next().unwrap_or(key);
    let mut out = Loaded::default();
    // Kalibr `camN.T_cam_imu`: frames named from the block (camN, imu).
    let block = key.rsplit('.').nth(1);
    let imu = crate::formats::matrix_tree::kalibr_imu(docs);
    let kalibr = block.and_then(|cam| crate::formats::matrix_tree::kalibr_frames(cam, last, imu));
    let frames = match kalibr.or_else(|| frames_from_key(last)) {
        Some(f) => f,
        None => {
            out.warnings.push(
                Warning::new(
                    Code::AssumedConvention,
                    format!("--key {key}: the name does not say which frames (T_A_B or A_T_B); frames named `parent` -> `child`, the value read as the child's pose in the parent"),
                )
                .at(&loc_of(path, k)),
            );
            ("parent".to_string(), "child".to_string())
        }
    };
    let label = match index {
        Some(i) => format!("{key}[{i}]"),
        None => key.to_string(),
    };
    let e = matrix_edge(&label, frames, v, k, text, path, &mut out.warnings)?;
    out.edges.push(e);
    Ok(out)
}

/// The value under a dotted path (`a.b.c`) in one document.
fn dotted<'a>(d: &'a Node, key: &str) -> Option<(&'a Node, &'a Node)> {
    let parts: Vec<&str> = key.split('.').collect();
    let mut cur = d;
    let mut hit = None;
    for (i, p) in parts.iter().enumerate() {
        let (k, v) = cur
            .entries()
            .iter()
            .rev()
            .find(|(k, _)| k.as_str().as_deref() == Some(*p))?;
        if i + 1 == parts.len() {
            hit = Some((k, v));
        }
        cur = v;
    }
    hit
}

/// The one value of `key` (a dotted path, or a key anywhere); several equal
/// values are one, different ones are an error naming their lines.
fn find_one_key<'a>(docs: &'a [Node], key: &str) -> Result<(&'a Node, &'a Node)> {
    let mut found: Vec<(&Node, &Node)> = Vec::new();
    for d in docs {
        if key.contains('.') {
            found.extend(dotted(d, key));
        }
        if found.is_empty() {
            find_key(d, key, &mut found);
        }
    }
    if found.is_empty() {
        let names: Vec<String> = docs
            .iter()
            .flat_map(|d| d.entries().iter().filter_map(|(k, _)| k.as_str()))
            .map(|s| s.to_string())
            .collect();
        return Err(Error::parse(format!(
            "--key {key}: no such key in this file; top-level keys: {}",
            names.join(", ")
        )));
    }
    if found.len() > 1 && !found.windows(2).all(|w| w[0].1.value == w[1].1.value) {
        return Err(err_at(
            found[1].0,
            format!(
                "--key {key}: the key appears {} times with different values (lines {}): the file is ambiguous; copy the right one into a file of its own",
                found.len(),
                found.iter().map(|(k, _)| k.line.to_string()).collect::<Vec<_>>().join(", ")
            ),
        ));
    }
    Ok(found[0])
}

/// The `i`-th of stacked 4x4 matrices under `key`, as its top 3x4 (stacked
/// files use the (4,4) entry as a flag).
fn stacked_matrix(v: &Node, key: &str, i: usize) -> Result<Node> {
    let nums = v.numbers(key)?;
    let count = nums.len() / 16;
    if nums.len() % 16 != 0 || i >= count {
        return Err(err_at(
            v,
            format!(
                "--key {key}[{i}]: expected at least {} stacked 4x4 matrices (16 numbers each), found {} numbers",
                i + 1,
                nums.len()
            ),
        ));
    }
    let b = &nums[16 * i..16 * (i + 1)];
    if !(b[12] == 0.0 && b[13] == 0.0 && b[14] == 0.0 && (b[15] == 0.0 || b[15] == 1.0)) {
        return Err(err_at(
            v,
            format!(
                "--key {key}[{i}]: expected bottom row [0, 0, 0, 1] (or SLICT's [0, 0, 0, 0] flag), found [{}, {}, {}, {}]",
                b[12], b[13], b[14], b[15]
            ),
        ));
    }
    Ok(Node {
        value: Value::Seq(
            nums[16 * i..16 * i + 12]
                .iter()
                .map(|x| Node {
                    value: Value::Num(*x),
                    line: v.line,
                    column: v.column,
                })
                .collect(),
        ),
        line: v.line,
        column: v.column,
    })
}
