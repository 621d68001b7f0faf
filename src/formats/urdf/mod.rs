//! URDF: the kinematic tree of a robot description.
//!
//! Meaning: every top-level `<joint>` is an edge `parent link -> child link`
//! whose transform is the child's pose in the parent: `<origin xyz rpy>` with
//! fixed-axis roll-pitch-yaw, `R = Rz(yaw) Ry(pitch) Rx(roll)`, then the joint's
//! motion. A missing `<origin>` is the identity; a missing `rpy` or `xyz` is zero.
//!
//! Versions, as ROS (urdfdom 6.0) reads them ([`UrdfVersion`]): `<robot version>` is
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
//! Reader: the text is read without a document tree (`stream`, quick-xml
//! events; XML errors still worded by roxmltree), in two passes: the whole
//! text checked and the root, links and any xacro noted, then the joints one
//! at a time, each turned into its edge at once (issue 12: memory per link).
//! Every edge knows the line and column of its `<joint>` element. Only
//! top-level `<link>` and `<joint>` count
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
//! Layout: `stream` reads the XML; `read` turns it into links and raw joints
//! (names, types, origins, axes, mimic); `joints` applies joint values
//! (`--joint`, mimic, defaults) and builds the edges; this file checks the
//! document and the tree.

mod joints;
mod read;
mod stream;

use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::source::LineIndex;
use crate::formats::spec::{Confidence, FormatSpec, LoadOptions, Parsed};
use crate::formats::xacro::markers as xacro;
use crate::formats::xml;
use crate::frames::{Edge, FrameDecl};
use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;

/// Parse URDF text.
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let mut warnings = Vec::new();
    let outline = stream::outline(text, path)?;
    let idx = LineIndex::new(text);
    check_root(&idx, &outline.root)?;
    refuse_xacro(&idx, outline.xacro.as_ref(), path)?;
    let version = read::version(&idx, &outline.root, opts)?;
    let links = read::links(&idx, &outline.links)?;
    let mut builder = joints::Builder::new(opts, outline.joints, SPEC.id);
    let names = read::joints(text, &idx, &links, version, path, &mut warnings, |j| {
        builder.push(j);
        Ok(())
    })?;
    let (edges, edge_warnings) = builder.finish(&names)?;
    drop((names, links));
    warnings.extend(edge_warnings);
    // The joints must form a tree: checked now, with the file's positions,
    // without a second copy of the edges.
    crate::frames::check_tree(&edges)?;
    let (frames, roots) = link_frames(&idx, &outline.links, &edges, path);
    drop(outline);
    root_links(&roots, path, &mut warnings);
    Ok(Parsed {
        edges,
        frames,
        warnings,
        ..Parsed::default()
    })
}

/// The links no joint names, as declared frames (a link a joint names is
/// known to the graph through its edge: issue 12, memory per link), and the
/// links without a parent joint with their lines, both in file order.
fn link_frames(
    idx: &LineIndex,
    links: &[(Option<Cow<'_, str>>, usize)],
    edges: &[Edge],
    path: &Path,
) -> (Vec<FrameDecl>, Vec<(String, usize)>) {
    const CHILD: u8 = 1;
    const PARENT: u8 = 2;
    let mut named: HashMap<&str, u8> = HashMap::with_capacity(edges.len() + 1);
    for e in edges {
        *named.entry(e.parent.as_str()).or_default() |= PARENT;
        *named.entry(e.child.as_str()).or_default() |= CHILD;
    }
    let (mut frames, mut roots) = (Vec::new(), Vec::new());
    for (name, start) in links {
        let name = name.as_deref().unwrap_or("");
        let flags = named.get(name).copied().unwrap_or(0);
        if flags & CHILD != 0 {
            continue;
        }
        let (l, c) = idx.pos(*start);
        roots.push((name.to_string(), l));
        if flags == 0 {
            frames.push(FrameDecl {
                name: name.to_string(),
                location: Location::at(path, l, Some(c)),
            });
        }
    }
    (frames, roots)
}

/// More than one link without a parent joint: ROS refuses the file.
fn root_links(roots: &[(String, usize)], path: &Path, warnings: &mut Vec<Warning>) {
    if roots.len() < 2 {
        return;
    }
    let names: Vec<String> = roots
        .iter()
        .map(|(name, line)| format!("'{name}' (line {line})"))
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
fn check_root(idx: &LineIndex, root: &stream::El) -> Result<()> {
    let (rl, rc) = idx.pos(root.start);
    match root.name {
        "robot" if root.attr("name").is_none() => Err(Error::parse(
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

/// Un-expanded xacro: namespace, elements or `${...}` / `$(...)` in
/// attributes (the first such element, noted by [`stream::outline`]).
fn refuse_xacro(idx: &LineIndex, first: Option<&stream::El>, path: &Path) -> Result<()> {
    let Some(n) = first else { return Ok(()) };
    let (l, c) = idx.pos(n.start);
    Err(Error::parse(format!(
        "this file holds un-expanded xacro (<{}{}>), not URDF: {}",
        if n.xacro_ns { "xacro:" } else { "" },
        n.name,
        xacro::advice(path)
    ))
    .at_line(l, Some(c)))
}

/// URDF.
pub const SPEC: FormatSpec = FormatSpec {
    id: "urdf",
    description: "URDF robot description: each joint <origin> is the child link's pose in the parent link (R = Rz(yaw) Ry(pitch) Rx(roll)); movable joints at 0 unless --joint NAME=VALUE",
    extensions: &[],
    walk: &[".urdf", ".xml"],
    magic: &[],
    sniff: |i| {
        if xml::candidate(i) && i.contains("<robot") {
            Some(Confidence::Certain)
        } else {
            (i.ext() == "urdf").then_some(Confidence::Claim)
        }
    },
    parse: |i, o| parse(i.text()?, i.path(), o),
    checked: true,
};
