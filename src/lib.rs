//! extrinsic-audit: what a robot's LiDAR extrinsic does to degeneracy detection.
//!
//! Data flow, one module per stage:
//! files (`formats`) -> frame graph (`graph`) -> one transform (`se3`) ->
//! analysis (`certificate`, `metric`; `detector`, `scene`, `points` and
//! `threshold` for point data) -> report (`report`, `cli`).

pub mod certificate;
pub mod cli;
pub mod detector;
pub mod error;
pub mod formats;
pub mod graph;
pub mod metric;
pub mod points;
pub mod report;
pub mod scene;
pub mod se3;
pub mod threshold;
