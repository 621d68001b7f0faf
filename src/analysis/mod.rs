//! Analysis of one rig: the detector families, the adapted constant metric and
//! the per-rig verdicts, from one transform.

pub mod detectors;
pub mod family;
pub mod metric;
pub mod mistakes;
pub mod spread;

pub use family::Family;
pub use metric::{analyze, RigAnalysis};
