//! Degeneracy over a recorded run (issue 26): every scan of a bag's
//! `sensor_msgs/PointCloud2` topic, of a KITTI `velodyne/*.bin` sequence or of
//! a folder of point files, through the detector of [`crate::degeneracy`],
//! in the scan's own frame and in the body frames the robot has.
//!
//! Data flow: a [`source`] yields the scans one at a time (a bag through its
//! index, in file order); [`work`] hands them to a pool of threads and gives
//! the outcomes back in scan order, with at most a bounded number of scans
//! in flight; [`scan`] turns one scan (or one pair of scans) into every
//! family's eigenvalues, counts and footprints in every frame; [`summary`]
//! folds the outcomes into the run's summary (intervals, label changes,
//! the timeline) without keeping them. Nothing here holds more than the
//! scans in flight: memory does not grow with the run's length (the bound
//! is stated in `docs/runs.md`).
//!
//! # Conventions
//!
//! - A scan's points are in its own frame, the *scan frame*: the message's
//!   `header.frame_id` (leading `/` dropped, as the bag reader drops it), or
//!   `--lidar-frame` for files that name none.
//! - A body frame `F` is given by its pose `T = (R, d)` in the scan frame (what
//!   `tf2_echo SCAN F` prints: `p_scan = R p_F + d`); the scan is described
//!   about it by congruence, `H_F = A^T H A`, `M_F = A^T M A` with
//!   `A = Ad(T)` ([`crate::degeneracy`]'s conventions). From a bag, `T` is
//!   composed along its `/tf_static` and `/robot_description` tree (and the
//!   extrinsics files given); a rig file (`--rig-frames`) with `T_rig` the
//!   pose of its LiDAR in its body frame gives `T = T_rig^-1` (the scan as if
//!   that rig's LiDAR had recorded it) and, as its pure lever arm, the
//!   translation of `T_rig^-1` without its rotation.
//! - Poses ([`poses`]) are poses of the scan frame in a fixed frame (odom,
//!   world): `P_k` maps scan `k`'s points into it. A pair is the source scan
//!   `j` against the target scan `i < j` (`j = i + step`), its initial guess
//!   the pose of the source frame in the target frame, `G = P_i^-1 P_j`, and
//!   its `H`, `M` are the source's, in the source scan frame (as
//!   `audit degeneracy --target` assembles one pair).
//! - Labels: a family's *decision* is whether any direction is degenerate,
//!   its *count* the number of degenerate directions, its *footprint* the
//!   per-axis flags. A *label change* in frame `F` is a scan whose decision
//!   (count, footprint) differs between the scan frame and `F`.

pub mod frames;
pub mod poses;
pub mod scan;
pub mod source;
pub mod summary;
pub mod work;
