//! `autoware-calibration`: Autoware's `sensor_kit_calibration.yaml` and
//! `sensors_calibration.yaml`: `PARENT: {CHILD: {x, y, z, roll, pitch, yaw}}`
//! (metres, radians; child names may hold `/`, e.g. `camera0/camera_link`).
//!
//! The description xacro turns each entry into a fixed joint whose parent
//! link is the top key and whose child link is the inner key, with
//! `<origin xyz="x y z" rpy="roll pitch yaw">`: the pose of CHILD in PARENT,
//! `R = Rz(yaw) Ry(pitch) Rx(roll)` (URDF's fixed-axis rule), edge
//! `PARENT -> CHILD`. autowarefoundation/sample_sensor_kit_launch @
//! 005bf85abdbae00e1102e46cf96047df4fe7d2ec
//! `sample_sensor_kit_description/urdf/sensor_kit.xacro:24` loads the file
//! (`xacro.load_yaml(...sensor_kit_calibration.yaml)`), `:27-35` feeds
//! `calibration['sensor_kit_base_link']['velodyne_top_base_link']['x']` ...
//! `['yaw']` to a sensor macro's `<origin>`, and `:14-17` (and
//! `sensors.xacro:3-16`) write `<joint ...> <origin rpy="${roll} ${pitch}
//! ${yaw}" xyz="${x} ${y} ${z}"/> <parent link="${parent}"/>`;
//! tier4/sensor_component_description @ 03ba094851ec90febfcfc0adb20b64b0e19df7a8
//! `camera_description/urdf/monocular_camera.xacro:7-11` names the child link
//! after the key. Every one of the six values is required (the xacro fails
//! with a KeyError otherwise; never 0 by default).

use super::calib_shapes::{edge, number, rigid_rpy, top_map};
use super::spec::{check_metres, locate_warnings, Input, Parsed};
use super::yaml::{self, Node, Value};
use super::yaml_keyed::{keys, yaml_dialect};
use super::yaml_shapes::{err_at, loc_of};
use crate::diagnostic::Result;
use std::path::Path;

yaml_dialect!(AUTOWARE_CALIBRATION, "autoware-calibration", false, sniff, |d, _, p| parse(d, p), "Autoware sensor_kit_calibration.yaml / sensors_calibration.yaml (`PARENT: {CHILD: {x, y, z, roll, pitch, yaw}}`, m and rad), fed by the description xacro to joint origins: the pose of CHILD in PARENT (URDF rpy), edge PARENT -> CHILD");

const SIX: [&str; 6] = ["x", "y", "z", "roll", "pitch", "yaw"];

/// Every top-level value a mapping of mappings holding `roll`, `pitch` or
/// `yaw` (the YAML is parsed only when the words are there).
fn sniff(i: &Input) -> Option<super::spec::Confidence> {
    if !(i.contains("roll") && i.contains("pitch") && i.contains("yaw")) {
        return None;
    }
    let docs = yaml::parse_documents_shared(i.text().ok()?).ok()?;
    let d = docs.first()?;
    let ok = !d.entries().is_empty()
        && d.entries().iter().all(|(_, v)| {
            !v.entries().is_empty()
                && v.entries()
                    .iter()
                    .all(|(_, e)| ["roll", "pitch", "yaw"].iter().any(|k| e.get(k).is_some()))
        });
    keys(ok)
}

fn parse(docs: &[Node], path: &Path) -> Result<Parsed> {
    let d = top_map(docs, "Autoware calibration")?;
    let mut out = Parsed::default();
    for (pk, children) in d.entries() {
        let parent = pk.as_str().unwrap_or_default();
        if !matches!(children.value, Value::Map(_)) {
            return Err(err_at(
                children,
                format!(
                    "`{parent}`: expected a mapping CHILD: {{x, y, z, roll, pitch, yaw}}, found {}",
                    children.kind()
                ),
            ));
        }
        for (ck, e) in children.entries() {
            let child = ck.as_str().unwrap_or_default();
            let what = format!("{parent}/{child}");
            let mut v = [0.0; 6];
            for (i, k) in SIX.iter().enumerate() {
                v[i] = number(e, k, &what)?;
            }
            let dd = [v[0], v[1], v[2]];
            let read = rigid_rpy([v[3], v[4], v[5]], dd, e, &what)?;
            let loc = loc_of(path, ck);
            let mut ws = Vec::new();
            check_metres(&dd, &what, &loc, &mut ws);
            locate_warnings(ws, &loc, &mut out.warnings);
            out.edges.push(edge(
                parent.trim(),
                child.trim(),
                read,
                path,
                ck,
                AUTOWARE_CALIBRATION.id,
                format!("{what} {{x, y, z, roll, pitch, yaw}}"),
            ));
        }
    }
    Ok(out)
}
