//! URDF: the kinematic tree of a robot description.
//!
//! Meaning: every top-level `<joint>` is an edge `parent link -> child link`
//! whose transform is the child's pose in the parent: `<origin xyz rpy>` with
//! fixed-axis roll-pitch-yaw, `R = Rz(yaw) Ry(pitch) Rx(roll)`, then the joint's
//! motion. A missing `<origin>` is the identity; a missing `rpy` or `xyz` is zero.
//!
//! Versions, as ROS (urdfdom 6.0) reads them ([`version`]): `<robot version>` is
//! 1.0 when absent, must be `x.y` and 1.0 to 1.2, else the file is refused at
//! the `<robot>` line. URDF 1.1's `quat_xyzw` (x y z w order) is applied only
//! from 1.1 (or with `--urdf-version 1.1`); in a 1.0 file ROS ignores it,
//! so the pose reported ignores it too, with a `quat-xyzw-ignored` warning. An
//! origin giving both `rpy` and `quat_xyzw` is refused in every version
//! (urdfdom refuses it in 1.1 and silently keeps `rpy` in 1.0).
//!
//! Every `<link>` is a frame: a link no joint attaches is a root of its own
//! (ROS refuses a file with two root links; here a `refused-by-ros` warning
//! says so and the connected links can still be audited).
//!
//! Other rules by which urdfdom refuses a file without its poses being in
//! doubt (a revolute or prismatic joint without `<limit>`; before 1.2 a
//! `<limit>` without `effort` or `velocity`, from 1.2 one without `lower` or
//! `upper`) also give a `refused-by-ros` warning, not an error:
//! the audit reads poses. Differences from urdfdom are listed, with reasons,
//! in docs/urdf-differences.md and checked by the conformance suite.
//!
//! Joints: `fixed` as given. `revolute` / `continuous` rotate about `<axis>`
//! (default `1 0 0`, normalised with a `non-unit-axis` warning when it is not a
//! unit vector; a zero axis on a movable joint is an error, on a fixed joint it
//! is ignored), `prismatic` translates along it. They sit at position 0 unless
//! `--joint NAME=VALUE` (rad or m) sets them; paths through joints at 0 carry a
//! `joint-at-default` warning. A position outside the joint's `<limit lower
//! upper>` is used as given, as robot_state_publisher does (it does not clamp),
//! with a `joint-outside-limit` warning; `--joint` naming a fixed joint is an
//! error. `<mimic joint multiplier offset>` joints follow
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
//! Layout: `read` turns the XML into links and raw joints (names, types,
//! origins, axes, mimic); `joints` applies joint values (`--joint`, mimic,
//! defaults) and builds the edges; this file checks the document and the tree.

mod joints;
mod read;
pub mod version;

pub use version::UrdfVersion;

use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::registry::FormatSpec;
use crate::formats::source::LineIndex;
use crate::formats::{xacro, xml, LoadOptions, Loaded};
use crate::frames::{Edge, FrameDecl, FrameGraph};
use std::collections::HashMap;
use std::path::Path;

/// Parse URDF text.
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    let mut warnings = Vec::new();
    // The XML tree is dropped before the tree check below: on a large robot it
    // is the largest allocation (issue 12: memory per link).
    let (edges, frames) = {
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
        let version = read::version(&idx, root, opts)?;
        let links = read::links(&idx, root)?;
        let raw = read::joints(&idx, root, &links, version, path, &mut warnings)?;
        let edges = joints::edges(&idx, &raw, opts, &mut warnings)?;
        (edges, link_frames(&idx, &links, path))
    };
    // The joints must form a tree: check now, with the file's positions (the
    // graph is dropped at once; the pipeline builds its own).
    {
        let mut g = FrameGraph::new();
        for e in &edges {
            g.add_edge(e.clone())?;
        }
    }
    root_links(&edges, &frames, path, &mut warnings);
    Ok(Loaded {
        edges,
        frames,
        warnings,
        ..Loaded::default()
    })
}

/// Every `<link>` as a declared frame, in file order.
fn link_frames(idx: &LineIndex, links: &Links, path: &Path) -> Vec<FrameDecl> {
    let mut v: Vec<FrameDecl> = links
        .iter()
        .map(|(name, node)| {
            let (l, c) = xml::pos_of(idx, *node);
            FrameDecl {
                name: name.clone(),
                location: Location::at(path, l, Some(c)),
            }
        })
        .collect();
    v.sort_by_key(|f| f.location.line);
    v
}

/// More than one link without a parent joint: ROS refuses the file.
fn root_links(edges: &[Edge], frames: &[FrameDecl], path: &Path, warnings: &mut Vec<Warning>) {
    let children: std::collections::HashSet<&str> =
        edges.iter().map(|e| e.child.as_str()).collect();
    let roots: Vec<&FrameDecl> = frames
        .iter()
        .filter(|f| !children.contains(f.name.as_str()))
        .collect();
    if roots.len() < 2 {
        return;
    }
    let names: Vec<String> = roots
        .iter()
        .map(|f| format!("'{}' (line {})", f.name, f.location.line.unwrap_or(0)))
        .collect();
    warnings.push(
        Warning::new(
            Code::RefusedByRos,
            format!(
                "{} links have no parent joint: {}; ROS (urdfdom) refuses a URDF with more than one root link (\"Two root links found\"); each is listed as its own tree and only links joined by joints can be audited",
                roots.len(),
                names.join(", ")
            ),
        )
        .at(&Location::file(path)),
    );
}

/// The root element must be `<robot>`; an `<sdf>` root gets its own advice.
fn check_root(idx: &LineIndex, root: roxmltree::Node) -> Result<()> {
    let (rl, rc) = xml::pos_of(idx, root);
    match root.tag_name().name() {
        "robot" if root.attribute("name").is_none() => Err(Error::parse(
            "<robot> without a name: expected <robot name=\"...\"> (ROS refuses a robot without a name)",
        )
        .at_line(rl, Some(rc))),
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
            Some(crate::formats::registry::CERTAIN)
        } else {
            (s.ext == "urdf").then_some(80)
        }
    },
    parse,
};
