//! Pictures of the frame tree (`audit FILE --frames --format dot|mermaid|svg`),
//! drawn from a [`FramesReport`]. Every edge is labelled with its translation
//! (m, 0.1 mm), its rotation as URDF roll-pitch-yaw (deg, 0.001 deg), its joint
//! type and `file:line`; the `--from` -> `--to` chain is drawn in red.
//!
//! Frame names and paths come from files: hostile input. Each format escapes
//! them its own way (DOT quoted strings, Mermaid entity codes, XML
//! entities), after [`crate::sanitize::visible`] has turned control and
//! bidirectional characters into visible escapes.

mod dot;
mod mermaid;
mod svg;

pub use dot::dot;
pub use mermaid::mermaid;
pub use svg::svg;

use crate::render::numbers::fixed;
use crate::report::frames::FrameEdgeJson;
use crate::sanitize;

/// Colour of the highlighted chain in every picture.
const CHAIN_COLOUR: &str = "#c0392b";

/// A number in degrees to 0.001 deg, trailing zeros cut.
fn deg(x: f64) -> String {
    let s = fixed(x, 3);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

/// `file:line` of an edge, the file as given (visible, not escaped for any
/// format yet).
fn place(e: &FrameEdgeJson) -> String {
    let mut s = if e.file.is_empty() {
        "<input>".to_string()
    } else {
        e.file.clone()
    };
    if let Some(l) = e.line {
        s.push_str(&format!(":{l}"));
    }
    sanitize::visible(&s, false).into_owned()
}

/// The edge's label lines: translation, rotation, joint and place.
fn label_lines(e: &FrameEdgeJson) -> [String; 3] {
    let d = e.translation_m.map(|x| fixed(x, 4));
    let r = e.rpy_deg.map(deg);
    let joint = match &e.joint_name {
        Some(n) => format!("{} joint {}", e.joint_type, sanitize::visible(n, false)),
        None => e.joint_type.clone(),
    };
    [
        format!("xyz [{}, {}, {}] m", d[0], d[1], d[2]),
        format!("rpy [{}, {}, {}] deg", r[0], r[1], r[2]),
        format!("{joint}, {}", place(e)),
    ]
}

/// A frame name, visible (control characters as escapes).
fn name(s: &str) -> String {
    sanitize::visible(s, false).into_owned()
}
