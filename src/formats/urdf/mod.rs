//! URDF: the kinematic tree of a robot description.
//!
//! Meaning: every top-level `<joint>` is an edge `parent link -> child link`
//! whose transform is the child's pose in the parent: `<origin xyz rpy>` with
//! fixed-axis roll-pitch-yaw, `R = Rz(yaw) Ry(pitch) Rx(roll)`, then the joint's
//! motion. A missing `<origin>` is the identity; a missing `rpy` or `xyz` is zero.
//! URDF 1.1's `quat_xyzw` attribute is read, in x y z w order (a file giving both
//! `rpy` and `quat_xyzw` is refused).
//!
//! Joints: `fixed` as given. `revolute` / `continuous` rotate about `<axis>`
//! (default `1 0 0`, normalised with a `non-unit-axis` warning when it is not a
//! unit vector; a zero axis on a movable joint is an error, on a fixed joint it
//! is ignored), `prismatic` translates along it. They sit at position 0 unless
//! `--joint NAME=VALUE` (rad or m) sets them; paths through joints at 0 carry a
//! `joint-at-default` warning. `<mimic joint multiplier offset>` joints follow
//! their master: `value = multiplier * master + offset`. `floating` and
//! `planar` joints have no pose in the file: a path through one is refused
//! unless `--joint NAME=0` puts it at its origin (a floating pose needs six
//! numbers: give it as a static transform instead).
//!
//! Reader: the tree is read with roxmltree, so every edge knows the line and
//! column of its `<joint>` element. Only top-level `<link>` and `<joint>` count
//! (Husky's `<transmission>` blocks hold decoy `<joint>` elements). Several
//! `<material>` in one `<visual>` (Unitree B2/Go2) do not matter. Checked: the
//! root element is `<robot>` (an `<sdf>` root is refused), names are unique,
//! joints name declared links, numbers are finite, the joints form a tree (no
//! cycle, one parent per link).
//!
//! Why not urdf-rs for reading: urdf-rs 0.10 keeps no positions, hides the XML
//! parser's errors, rejects files ROS reads (duplicate `<material>`), drops
//! `quat_xyzw` silently and accepts NaN, cycles, duplicate links and two parents.
//! The test suite uses it as an independent cross-check on the corpus files it
//! reads.
//!
//! A file named `.urdf` that still holds xacro (`xacro:` elements or namespace,
//! `${...}`, `$(...)`) is refused with the advice of [`super::xacro`]: it is
//! never parsed as URDF.
//!
//! Layout: [`read`] turns the XML into links and raw joints (names, types,
//! origins, axes, mimic); [`joints`] applies joint values (`--joint`, mimic,
//! defaults) and builds the edges; this file checks the document and the tree.

mod joints;
mod read;

use crate::diagnostic::{Error, Result};
use crate::formats::registry::FormatSpec;
use crate::formats::source::LineIndex;
use crate::formats::{xacro, xml, LoadOptions, Loaded};
use crate::frames::FrameGraph;
use std::collections::HashMap;
use std::path::Path;

/// Parse URDF text.
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    let doc = match roxmltree::Document::parse_with_options(text, xml::parse_options()) {
        Ok(d) => d,
        Err(e) if xacro::has_markers(text) => {
            let _ = e;
            return Err(Error::parse(format!(
                "this file holds un-expanded xacro, not URDF: {}",
                xacro::advice(path)
            )));
        }
        Err(e) => return Err(xml::error(&e, text)),
    };
    let idx = LineIndex::new(text);
    let root = doc.root_element();
    check_root(&idx, root)?;
    refuse_xacro(&idx, &doc, path)?;
    let mut warnings = Vec::new();
    let links = read::links(&idx, root)?;
    let raw = read::joints(&idx, root, &links, path, &mut warnings)?;
    let edges = joints::edges(&idx, &raw, opts, &mut warnings)?;
    // The joints must form a tree: check now, with the file's positions.
    let mut g = FrameGraph::new();
    for e in &edges {
        g.add_edge(e.clone())?;
    }
    Ok(Loaded {
        edges,
        warnings,
        rig: None,
    })
}

/// The root element must be `<robot>`; an `<sdf>` root gets its own advice.
fn check_root(idx: &LineIndex, root: roxmltree::Node) -> Result<()> {
    let (rl, rc) = xml::pos_of(idx, root);
    match root.tag_name().name() {
        "robot" => Ok(()),
        "sdf" => Err(Error::parse(
            "root element is <sdf>: this is an SDF (Gazebo) file, expected a URDF <robot>; convert it to URDF first",
        )
        .at_line(rl, Some(rc))),
        other => Err(Error::parse(format!(
            "root element is <{other}>: expected a URDF <robot>"
        ))
        .at_line(rl, Some(rc))),
    }
}

/// Un-expanded xacro: namespace, elements or `${...}` / `$(...)` in attributes.
fn refuse_xacro(idx: &LineIndex, doc: &roxmltree::Document, path: &Path) -> Result<()> {
    for n in doc.descendants().filter(|n| n.is_element()) {
        let is_xacro_el = n
            .tag_name()
            .namespace()
            .map(|ns| ns.contains("xacro"))
            .unwrap_or(false);
        let has_expr = n
            .attributes()
            .any(|a| a.value().contains("${") || a.value().contains("$("));
        if is_xacro_el || has_expr {
            let (l, c) = xml::pos_of(idx, n);
            return Err(Error::parse(format!(
                "this file holds un-expanded xacro (<{}{}>), not URDF: {}",
                if is_xacro_el { "xacro:" } else { "" },
                n.tag_name().name(),
                xacro::advice(path)
            ))
            .at_line(l, Some(c)));
        }
    }
    Ok(())
}

/// Links by name, for the joints' parent and child checks.
pub(crate) type Links<'a> = HashMap<String, roxmltree::Node<'a, 'a>>;

/// URDF.
pub const SPEC: FormatSpec = FormatSpec {
    id: "urdf",
    description: "URDF robot description: each joint <origin> is the child link's pose in the parent link (R = Rz(yaw) Ry(pitch) Rx(roll)); movable joints at 0 unless --joint NAME=VALUE",
    extensions: &[],
    walk: &[".urdf", ".xml"],
    sniff: |s| {
        if s.xml_candidate() && s.text.contains("<robot") {
            Some(90)
        } else {
            (s.ext == "urdf").then_some(80)
        }
    },
    parse,
};
