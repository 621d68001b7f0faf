//! extrinsic-audit: what a robot's LiDAR extrinsic does to degeneracy detection.
//!
//! Data flow, one module per stage:
//! files (`formats`) -> frame graph (`graph`) -> one transform (`se3`) ->
//! analysis (`certificate`, `metric`; `detector` and `scene` for point data) ->
//! report (`report`, `cli`).

pub mod detector;
pub mod error;
pub mod formats;
pub mod graph;
pub mod metric;
pub mod points;
pub mod scene;
pub mod se3;
pub mod threshold;
/// Temporary glue for the detector commands (the lead wires `cli` properly).
pub mod cli {
    pub mod calibrate_threshold;
    pub mod degeneracy;
    pub mod simulate;
    pub mod tunnel;
}
