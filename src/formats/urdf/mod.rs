//! URDF: the kinematic tree of a robot description.
//!
//! Meaning: every top-level `<joint>` is an edge `parent link -> child link`
//! whose transform is the child's pose in the parent: `<origin xyz rpy>` with
//! fixed-axis roll-pitch-yaw, `R = Rz(yaw) Ry(pitch) Rx(roll)`, then the joint's
//! motion. A missing `<origin>` is the identity; a missing `rpy` or `xyz` is zero.
//!
//! Versions, as ROS (urdfdom 6.0) reads them ([`UrdfVersion`](crate::formats::spec::UrdfVersion)): `<robot version>` is
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
//! events; XML errors still worded by roxmltree), in one pass (issue 29):
//! the whole text checked, the root, links and any xacro noted, and the
//! joints read one at a time, each turned into its edge at once (issue 12:
//! memory per link); the error a file gets is settled at the end, in the
//! order of the checks (`document`).
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
//! Layout: `stream` reads the XML (`values`: attribute values; `lines`:
//! offsets to lines and columns; `names`: the name lookups); `read` turns
//! it into raw joints (names, types, axes, limits, mimic; `origin`: numbers
//! and origins); `joints` applies joint values (`--joint`, mimic, defaults)
//! and builds the edges; `document` holds the pass together, checks the
//! document and the tree and settles the error.

mod document;
mod joints;
mod lines;
mod names;
mod origin;
mod read;
mod stream;
mod values;
mod version;

use crate::diagnostic::Result;
use crate::formats::spec::{Confidence, FormatSpec, LoadOptions, Parsed};
use crate::formats::xml;
use lines::Lines;
use std::path::Path;

/// Parse URDF text.
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let idx = Lines::new(text);
    let mut doc = document::Document::new(text, &idx, path, opts, SPEC.id);
    stream::read(text, path, |item| {
        doc.add(item);
        Ok(())
    })?;
    doc.finish()
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
