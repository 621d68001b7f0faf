//! extrinsic-audit: what a robot's LiDAR extrinsic does to degeneracy detection.

//!
//! Data flow, one module per stage:
//! files (`formats`) -> frame graph (`frames`) -> one transform (`geometry`) ->
//! analysis (`analysis`; `degeneracy` for point data) -> report (`report`, `cli`).

pub mod analysis;
pub mod baseline;
pub mod degeneracy;
pub mod diagnostic;
pub mod formats;
pub mod frames;
pub mod geometry;
pub mod pipeline;
pub mod render;
pub mod report;
pub mod tolerances;
