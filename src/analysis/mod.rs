//! Analysis of one rig: the detector families, the adapted constant metric and
//! the per-rig verdicts, from one transform.

pub mod metric;

pub use metric::{analyze, Family, RigAnalysis};
