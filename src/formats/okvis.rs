//! `okvis`: OKVIS configuration files: `cameras:` a list of maps each with
//! `T_SC` (16 numbers, row-major), and `imu_params: {T_BS: [16], ...}`.
//!
//! `T_SC` is the pose of camera C in the sensor frame S, which is the IMU:
//! edges `imu -> cam0`, `imu -> cam1`, ... ethz-asl/okvis @
//! f0c9ba472b89f85030cd58dfbae03ceec7817679:
//! `okvis_common/src/VioParametersReader.cpp:573-582` reads `T_SC` with a
//! comma initializer (`T_SC << T_SC_node[0], ..., T_SC_node[15]`: row-major);
//! `okvis_multisensor_processing/src/ThreadedKFVio.cpp:421-422`
//! `T_WC = T_WS * T_SC` (world-from-camera = world-from-IMU x `T_SC`);
//! `okvis_kinematics/include/okvis/kinematics/Transformation.hpp:68-70`
//! "T_AB ... translation r_AB (represented in frame A)".
//!
//! `imu_params.T_BS` ("Transformation from Body frame to IMU (sensor frame
//! S)", `okvis_common/include/okvis/Parameters.hpp:107`) is read and logged
//! (`VioParametersReader.cpp:400-409`) but never used: its direction is not
//! traced to consuming code, so it is read only with `--assume`
//! (`child-in-parent`: the pose of `imu` in `body`, by the `T_AB` naming);
//! without it, it is left out with an `ignored` warning. Fewer than 16
//! numbers (upstream reads zeros past the end) are refused.

use super::calib_shapes::{edge, field, numbers_n, rigid16, top_map, untraced};
use super::spec::{
    check_metres, locate_warnings, Confidence, FormatSpec, Input, LoadOptions, Parsed,
};
use super::yaml::{self, Node, Value};
use super::yaml_shapes::{err_at, key_node, loc_of};
use crate::diagnostic::Result;
use std::path::Path;

/// OKVIS configuration files.
pub const OKVIS: FormatSpec = FormatSpec {
    id: "okvis",
    description: "OKVIS config `cameras: [{T_SC: [16]}]` (row-major): each camera's pose in the sensor (IMU) frame, T_WC = T_WS T_SC, edges imu -> camN; `imu_params.T_BS` is never used by OKVIS: read only with --assume (edge body -> imu)",
    extensions: &[],
    walk: &[".yaml", ".yml"],
    magic: &[],
    sniff: |i: &Input| (i.has_key("cameras") && i.contains("T_SC")).then_some(Confidence::Keys),
    parse: |i, o| parse(&yaml::parse_documents(i.text()?)?, i.path(), o),
    checked: true,
};

/// One 16-number key `key` of map `m` as edge `parent -> child`.
fn matrix_key(
    m: &Node,
    key: &str,
    what: &str,
    (parent, child): (&str, &str),
    path: &Path,
    out: &mut Parsed,
) -> Result<crate::frames::Edge> {
    let v = field(m, key, what)?;
    let k = key_node(m, key).unwrap_or(v);
    let data = numbers_n(v, 16, &format!("{what}.{key}"))?;
    let mut ws = Vec::new();
    let read = rigid16(&data, v, &format!("{what}.{key}"), &mut ws)?;
    let loc = loc_of(path, k);
    check_metres(&[data[3], data[7], data[11]], key, &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    Ok(edge(
        parent,
        child,
        read,
        path,
        k,
        OKVIS.id,
        format!("{what}.{key}"),
    ))
}

fn parse(docs: &[Node], path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let d = top_map(docs, "OKVIS config")?;
    let cams = field(d, "cameras", "OKVIS config")?;
    let Value::Seq(list) = &cams.value else {
        return Err(err_at(
            cams,
            format!(
                "`cameras`: expected a list of camera maps with T_SC, found {}",
                cams.kind()
            ),
        ));
    };
    let mut out = Parsed::default();
    for (i, cam) in list.iter().enumerate() {
        let e = matrix_key(
            cam,
            "T_SC",
            &format!("cameras[{i}]"),
            ("imu", &format!("cam{i}")),
            path,
            &mut out,
        )?;
        out.edges.push(e);
    }
    if let Some(imu) = d.get("imu_params").filter(|m| m.get("T_BS").is_some()) {
        let e = matrix_key(imu, "T_BS", "imu_params", ("body", "imu"), path, &mut out)?;
        let why = "OKVIS reads and logs T_BS but never uses it, so no code fixes its direction";
        if let Some(e) = untraced(opts, e, why, &mut out.warnings)? {
            out.edges.push(e);
        }
    }
    if out.edges.is_empty() {
        return Err(err_at(
            cams,
            "OKVIS config: expected at least one camera with T_SC, found none".into(),
        ));
    }
    Ok(out)
}
