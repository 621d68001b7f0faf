//! Frames: edges with provenance, the frame graph (a forest), and chains of
//! edges composed into one transform. Knows no file format.

mod edge;
#[allow(missing_docs)] // TODO(issue 10): document graph.rs, then drop this
mod graph;

pub use edge::{Edge, JointState, JointType, Provenance};
pub use graph::*;
