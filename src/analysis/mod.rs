//! Analysis of one rig: the detector families, the adapted constant metric and
//! the per-rig verdicts, from one transform.

pub mod family;
pub mod metric;

pub use family::Family;
pub use metric::{analyze, RigAnalysis};
