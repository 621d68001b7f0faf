//! The `matrix-yaml` dialect's keys made into a tree: every `T_A_B` / `A_T_B`
//! key (the pose of B in A, edge `A -> B`, see `yaml_dialects`) and Kalibr's
//! per-camera blocks, then a tree plus checked redundant edges.
//!
//! Kalibr (`camchain.yaml`, `camchain-imucam.yaml`; Kalibr wiki "Yaml
//! formats": `T_cam_imu` is the "IMU extrinsics: transformation from IMU to
//! camera coordinates (T_c_i)", `T_cn_cnm1` the "camera extrinsic
//! transformation, always with respect to the last camera in the chain (e.g.
//! cam1: T_cn_cnm1 = T_c1_c0, takes cam0 to cam1 coordinates)"): so
//! `camN.T_cam_imu` is the pose of the IMU in camN, `camN.T_cn_cnm1` the pose
//! of cam(N-1) in camN. Frames are named from the keys: `cam0`, `cam1`, ...,
//! and the IMU `imu`, or `imu0` when the file has a top-level `imu0` key
//! (Kalibr's IMU configuration names its IMUs `imu0`, `imu1`, ...). A
//! `T_cam_imu` becomes the tree edge `imu -> camN` (its inverse), Kalibr's
//! `T_imu_cam` variant the edge `imu -> camN` as written; a `T_cn_cnm1` that
//! the cameras' IMU edges already connect is a redundant edge `camN ->
//! cam(N-1)` (checked by the frame graph), else a tree edge.
//!
//! Any other key that closes a loop (GEODE) is a redundant edge too, and one
//! whose child already has a parent is added reversed. A key given twice with
//! different values is ambiguous: an `ambiguous-key` warning names both lines
//! and its edges are left out, the rest of the file is read.

use super::spec::{Confidence, Parsed};
use super::yaml::{Node, Value};
use super::yaml_keyed::yaml_dialect;
use super::yaml_shapes::{
    frames_from_key, kalibr_frames, kalibr_imu, loc_of, matrix_edge, MATRIX_YAML_ID,
};
use crate::diagnostic::{Code, Error, Result, Warning};
use crate::frames::{Edge, FrameGraph};
use std::path::Path;

// The dialect read when no other claims the text.
yaml_dialect!(MATRIX_YAML, MATRIX_YAML_ID, true, |_| Some(Confidence::Fallback), parse, "YAML with 4x4 matrices under keys `T_A_B` or `A_T_B` (OpenCV FileStorage `!!opencv-matrix`, VINS-Fusion `body_T_cam0`, plain lists, `T_A_B_t_xyz_q_xyzw`): the pose of B in A, edge A -> B; Kalibr camchain `camN: {T_cam_imu, T_cn_cnm1}`: edges imu -> camN, T_cn_cnm1 checked as a redundant edge; a key that closes a loop is checked, not refused; --key NAME picks one");

/// The layouts the YAML readers know, for the "no transform found" message.
pub const KNOWN_LAYOUTS: &str = "FAST-LIO/Point-LIO `extrinsic_T` + `extrinsic_R`, LIO-SAM `extrinsicTrans` + `extrinsicRot`, iG-LIO `t_imu_lidar` + `R_imu_lidar`, DLIO `baselink2imu`/`baselink2lidar` {t, R}, VINS `extrinsicRotation` + `extrinsicTranslation` or `body_T_cam0`, Coco-LIC `Extrinsics`, SLICT `lidar_extr`, a tf_static dump (`transforms:` with `child_frame_id`), `<parent>_to_<child>: {x, y, z, roll, pitch, yaw}`, `quaternion_A_B` + `translation_A_B`, Kalibr `camN: {T_cam_imu, T_cn_cnm1}`, or 4x4 matrices under keys `T_A_B` / `A_T_B`";

/// One matrix key found in the file.
struct Entry<'a> {
    /// The key as the user names it with `--key` (`cam1.T_cn_cnm1`).
    name: String,
    frames: (String, String),
    key: &'a Node,
    value: &'a Node,
    /// Kalibr `T_cam_imu`: the tree edge is its inverse.
    invert: bool,
    /// Kalibr `T_cn_cnm1`: read after the others, so it closes the loop.
    late: bool,
}

fn collect<'a>(docs: &'a [Node], imu: &str) -> Vec<Entry<'a>> {
    let mut out = Vec::new();
    for d in docs {
        for (k, v) in d.entries() {
            let Some(name) = k.as_str() else { continue };
            if let Some(frames) = frames_from_key(&name) {
                out.push(Entry {
                    name,
                    frames,
                    key: k,
                    value: v,
                    invert: false,
                    late: false,
                });
                continue;
            }
            let Value::Map(inner) = &v.value else {
                continue;
            };
            for (ik, iv) in inner {
                let Some(iname) = ik.as_str() else { continue };
                let Some(frames) = kalibr_frames(&name, &iname, imu) else {
                    continue;
                };
                out.push(Entry {
                    name: format!("{name}.{iname}"),
                    frames,
                    key: ik,
                    value: iv,
                    invert: iname == "T_cam_imu",
                    late: iname == "T_cn_cnm1",
                });
            }
        }
    }
    // Stable: file order within each group.
    out.sort_by_key(|e| e.late);
    out
}

/// Keys given more than once with different values: an `ambiguous-key`
/// warning each, naming the lines; returns the names to leave out.
fn ambiguous(entries: &[Entry], warnings: &mut Vec<Warning>, path: &Path) -> Vec<String> {
    let mut blocked: Vec<String> = Vec::new();
    for (i, e) in entries.iter().enumerate() {
        if blocked.contains(&e.name) || entries[..i].iter().any(|p| p.name == e.name) {
            continue;
        }
        let same: Vec<&Entry> = entries.iter().filter(|o| o.name == e.name).collect();
        if same.len() < 2 || same.iter().all(|o| o.value.value == e.value.value) {
            continue;
        }
        let lines: Vec<String> = same.iter().map(|o| o.key.line.to_string()).collect();
        warnings.push(
            Warning::new(
                Code::AmbiguousKey,
                format!(
                    "`{}` given {} times with different values (lines {}): its edge {} -> {} is left out; the rest of the file is read (copy the right value into a file of its own to use it)",
                    e.name,
                    same.len(),
                    lines.join(" and "),
                    e.frames.0,
                    e.frames.1
                ),
            )
            .at(&loc_of(path, same[1].key)),
        );
        blocked.push(e.name.clone());
    }
    blocked
}

/// `e` reversed: the child's pose in... the parent's pose in the child.
fn reversed(e: &Edge, why: &str) -> Edge {
    let mut r = e.clone();
    std::mem::swap(&mut r.parent, &mut r.child);
    r.transform = e.transform.inverse();
    r.provenance.key = format!("{} ({why})", e.provenance.key);
    r
}

/// Place one edge: a tree edge (reversed when its child has a parent), or a
/// redundant one when the tree already connects its frames.
fn place(g: &mut FrameGraph, e: Edge, out: &mut Parsed) -> Result<()> {
    if e.parent == e.child {
        return Err(Error::frame(format!(
            "`{}`: frame '{}' is its own parent: expected two different frames",
            e.provenance.key, e.parent
        ))
        .at(&e.provenance.location));
    }
    if g.contains(&e.parent) && g.contains(&e.child) && g.transform(&e.parent, &e.child).is_ok() {
        out.redundant.push(e);
        return Ok(());
    }
    if g.parent_edge(&e.child).is_some() {
        let r = reversed(&e, "inverted: its child already has a parent");
        g.add_edge(r.clone())?;
        out.edges.push(r);
        return Ok(());
    }
    g.add_edge(e.clone())?;
    out.edges.push(e);
    Ok(())
}

/// Read every matrix key of a `matrix-yaml` file into a tree plus redundant
/// edges (see the module documentation).
pub fn parse(docs: &[Node], text: &str, path: &Path) -> Result<Parsed> {
    let mut out = Parsed::default();
    let imu = kalibr_imu(docs);
    let entries = collect(docs, imu);
    let blocked = ambiguous(&entries, &mut out.warnings, path);
    let mut g = FrameGraph::new();
    let mut seen: Vec<&str> = Vec::new();
    for en in &entries {
        if blocked.contains(&en.name) || seen.contains(&en.name.as_str()) {
            continue;
        }
        seen.push(&en.name);
        let e = matrix_edge(
            MATRIX_YAML.id,
            &en.name,
            en.frames.clone(),
            (en.key, en.value),
            text,
            path,
            &mut out.warnings,
        )?;
        let e = if en.invert {
            reversed(&e, "inverted: the pose of the camera in the IMU")
        } else {
            e
        };
        place(&mut g, e, &mut out)?;
    }
    if out.edges.is_empty() && out.redundant.is_empty() {
        return Err(no_transform(docs, &blocked));
    }
    Ok(out)
}

/// "No transform found", with the keys seen and the layouts known.
pub fn no_transform(docs: &[Node], blocked: &[String]) -> Error {
    let mut keys: Vec<String> = docs
        .iter()
        .flat_map(|d| d.entries().iter().filter_map(|(k, _)| k.as_str()))
        .collect();
    keys.dedup();
    let total = keys.len();
    keys.truncate(20);
    let seen = match total {
        0 => "no keys (the file holds no mapping)".to_string(),
        n if n > keys.len() => format!("keys {}, ... ({n} in all)", keys.join(", ")),
        _ => format!("keys {}", keys.join(", ")),
    };
    let left_out = if blocked.is_empty() {
        String::new()
    } else {
        format!(
            " ({} left out: given twice with different values)",
            blocked.join(", ")
        )
    };
    Error::parse(format!(
        "no transform found: found {seen}{left_out}; expected one of these layouts: {KNOWN_LAYOUTS}; pass --key NAME to read one key, or --input-format NAME"
    ))
}
