//! Frames: edges with provenance, the frame graph (a forest), and chains of
//! edges composed into one transform. Knows no file format.

mod children;
mod edge;
mod graph;
mod keyed;
mod names;

pub use edge::{Edge, JointState, JointType, Provenance, ValuesAt};
pub use graph::*;
