//! `apollo-extrinsics`: Apollo's extrinsics YAML, a `TransformStamped`
//! written as YAML: `header: {frame_id, ...}`, `child_frame_id`,
//! `transform: {translation: {x, y, z}, rotation: {x, y, z, w}}`.
//!
//! ApolloAuto/apollo @ 353c84319dd56c328f293307d9a6460f8f7537aa
//! `modules/transform/static_transform_component.cc` (read through the code
//! index, whose stored text the line numbers count): `ParseFromYaml` (55-85)
//! sets `header.frame_id` and `child_frame_id` from the file (64-67), the
//! translation from `transform.translation.{x,y,z}` (71-73), the rotation
//! from `transform.rotation.{x,y,z,w}` (76-79), and `Init` (25-37)
//! broadcasts them on `/tf_static`: tf's meaning, the pose of
//! `child_frame_id` in `header.frame_id`, edge `frame_id -> child_frame_id`.
//! Apollo perception loads the same files as `ex_lidar2imu` (LiDAR points
//! into the IMU frame `novatel`), consistent with it. A missing key drops the
//! transform in Apollo ("Extrinsic yaml file parse failed"): refused here.

use super::calib_shapes::{edge, field, name, number, rigid_quat, top_map};
use super::spec::{check_metres, locate_warnings, Parsed};
use super::yaml::Node;
use super::yaml_keyed::{keys, yaml_dialect};
use super::yaml_shapes::{key_node, loc_of};
use crate::diagnostic::Result;
use std::path::Path;

yaml_dialect!(APOLLO_EXTRINSICS, "apollo-extrinsics", false, |i| keys((i.has_key("child_frame_id") || i.has_key("header")) && i.has_key("transform") && i.has_key("rotation") && !i.has_key("transforms")), |d, _, p| parse(d, p), "Apollo extrinsics YAML (a TransformStamped: header.frame_id, child_frame_id, transform.translation x y z, transform.rotation x y z w), broadcast on /tf_static by Apollo's transform module: the pose of child_frame_id in frame_id, edge frame_id -> child_frame_id");

fn parse(docs: &[Node], path: &Path) -> Result<Parsed> {
    let d = top_map(docs, "Apollo extrinsics")?;
    let parent = name(
        field(d, "header", "Apollo extrinsics")?,
        "frame_id",
        "header",
    )?;
    let child = name(d, "child_frame_id", "Apollo extrinsics")?;
    let tr = field(d, "transform", "Apollo extrinsics")?;
    let t = field(tr, "translation", "transform")?;
    let r = field(tr, "rotation", "transform")?;
    let dd = [
        number(t, "x", "transform.translation")?,
        number(t, "y", "transform.translation")?,
        number(t, "z", "transform.translation")?,
    ];
    let mut q = [0.0; 4];
    for (i, k) in ["x", "y", "z", "w"].iter().enumerate() {
        q[i] = number(r, k, "transform.rotation")?;
    }
    let k = key_node(d, "transform").unwrap_or(tr);
    let loc = loc_of(path, k);
    let mut out = Parsed::default();
    let mut ws = Vec::new();
    let read = rigid_quat(q, dd, r, "transform.rotation", &mut ws)?;
    check_metres(&dd, "transform.translation", &loc, &mut ws);
    locate_warnings(ws, &loc, &mut out.warnings);
    out.edges.push(edge(
        &parent,
        &child,
        read,
        path,
        k,
        APOLLO_EXTRINSICS.id,
        format!("transform {parent} -> {child}"),
    ));
    Ok(out)
}
