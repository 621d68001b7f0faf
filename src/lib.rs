//! extrinsic-audit: what a robot's LiDAR extrinsic does to degeneracy detection.
//!
//! Under a change of body frame the point-to-plane information matrix `H`
//! transforms by congruence, `H' = Ad(T)^T H Ad(T)`, so a detector's per-axis
//! flags, its eigenvalues and a thresholded decision depend on where the body
//! frame sits relative to the LiDAR; only an equivariant metric (the
//! point-displacement metric `M = sum J_i^T J_i`) gives frame-invariant
//! eigenvalues. This crate answers what that means for a user's own robot and
//! data. The `audit` command, the Python package (`python/`) and Rust programs
//! are all built on the face below: nothing else of the crate is public.
//!
//! # The face
//!
//! - [`Robot::load`]: a robot's calibration files (URDF, xacro, launch files,
//!   TF dumps, bags, LIO/Kalibr YAML, rig TOML, ...) into one frame tree, read
//!   as [`LoadOptions`] says (renames, joint values, xacro arguments and
//!   package paths, keys, inversion, the input format).
//! - [`Robot::transform`] and [`Robot::chain`]: compose the pose of one frame
//!   in another along the tree; [`Transform`] composes, inverts and converts
//!   (matrix, quaternion, rpy, axis-angle, adjoint, screw).
//! - [`Robot::report`]: the rig report of a frame pair ([`RigReport`]: lever
//!   arm, screw pitch, adjoint bands, adapted metric, every detector family's
//!   verdict); [`analyze`] the same analysis of a bare [`Transform`].
//! - [`check`] (and [`check_with`], with progress): the CI gate on
//!   calibration files, against a baseline ([`CheckOptions`], [`CheckReport`]).
//! - [`diff`]: what changed between two calibrations ([`DiffOptions`],
//!   [`DiffReport`]).
//! - [`survey`]: one row per rig over many files ([`SurveyOptions`],
//!   [`SurveyReport`]).
//! - [`spread`]: many calibrations of one frame pair (repeated runs, a
//!   fleet): the mean on SE(3), each one's deviation, the spread per axis,
//!   the outliers, the pitch verdict of the set ([`SpreadOptions`],
//!   [`SpreadReport`]; a tolerance as [`DiffToleranceJson`]).
//! - [`OdometryDetector`]: the user's own odometry's detector (LIO-SAM,
//!   LeGO-LOAM, DCReg, X-ICP, FAST-LIO, ...) on a rig, cited from its source:
//!   [`OdometryDetector::advise`] is the [`DetectorAdvice`] a rig report
//!   carries in [`RigReport::detector`]; [`OdometryDetector::read_config`]
//!   reads the detector's own configuration file (DCReg, X-ICP) as a
//!   [`DetectorConfig`] whose thresholds ([`ConfiguredThreshold`]) its
//!   [`DetectorConfig::advise`] uses.
//! - [`Detector::points`]: every detector family on points held in memory
//!   ([`Points`] of `f64` or `f32` rows, normals estimated when absent).
//! - [`Detector::scan`] (and [`Detector::sweep`], the paper's frame sweep): the
//!   same on a point file, or a scan pair ([`ScanFile`], [`PairOptions`]).
//! - [`Run::open`]: the detector over a recorded run (a bag's PointCloud2
//!   topic, a KITTI sequence, a folder of point files), an iterator of one
//!   [`ScanResult`] per scan or scan pair in run order, in the scan frame
//!   and the robot's body frames ([`RunOptions`]: [`RunScans`],
//!   [`RunFrames`], [`RunDetector`], [`RunPairs`]); [`Run::finish`] the
//!   summary ([`RunReport`]).
//! - [`render()`]: any report as text, markdown, JSON (its schema in
//!   `docs/schemas`), CSV, SARIF or a picture ([`OutputFormat`],
//!   [`RenderOptions`]); [`render_bytes`] and [`render_to`] the same as
//!   bytes or to a writer, MCAP (the 3D scene for Foxglove) included;
//!   [`Robot::frame_tree`] is the frame tree as a report.
//! - [`reports`]: the types of the reports' fields, one module per report, so
//!   that what a program holds has a name; [`document`]: a report laid out
//!   for people ([`Report::document`]: blocks, tables, the frame tree's
//!   graph, plots, the 3D scene), for a program that draws reports its own
//!   way. The parts of the analysis are beside [`Transform`]
//!   ([`Certificates`], [`PitchVerdict`], [`Precision`], [`FamilyVerdict`],
//!   [`AdaptedMetric`], [`FamilySpec`], ...). `#![deny(unnameable_types)]`
//!   keeps it so: every type the face hands out can be named.
//!
//! Every failure is an [`Error`] (a [`Diagnostic`]: a typed [`Code`], the
//! file and line where known, a message saying what was expected and what was
//! found); warnings are the same type ([`Warning`]), returned beside the
//! result. Options structs have `Default` and are `#[non_exhaustive]`: set
//! the fields you need on `Default::default()`, so that a field added later
//! breaks nobody.
//!
//! Conventions (frames, twists, the adjoint, quaternion order, rpy) are those
//! of [`Transform`]; `docs/ARCHITECTURE.md` draws the layers.
//!
//! # Example
//!
//! Load ANYbotics ANYmal C's URDF, compose the pose of its LiDAR in its base
//! frame and report on it (the README's rig report shows the same numbers):
//!
//! ```
//! use extrinsic_audit::{Family, LoadOptions, RigOptions, Robot, ScrewKind};
//!
//! # fn main() -> extrinsic_audit::Result<()> {
//! let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/urdf/anymal_c_lidar.urdf");
//! // Movable joints at 0 unless `LoadOptions::joints` gives a value.
//! let robot = Robot::load(&[urdf], &LoadOptions::default())?;
//!
//! // The pose of `lidar` in `base`, p_base = R p_lidar + d, along
//! // base -> lidar_cage -> lidar.
//! let chain = robot.chain("base", "lidar")?;
//! assert_eq!(chain.steps.len(), 2);
//! let d = chain.transform.translation();
//! assert!((d.x + 0.364).abs() < 1e-12 && d.y.abs() < 1e-12 && (d.z - 0.1422).abs() < 1e-12);
//!
//! // The rig report: lever arm, screw, verdicts.
//! let (report, warnings) = robot.report("base", "lidar", &RigOptions::default())?;
//! assert!(warnings.is_empty());
//! assert_eq!(format!("{:.6}", report.lever_arm_m), "0.390790");
//! assert_eq!(report.screw.kind, ScrewKind::General); // h = e . d != 0
//! let invariant: Vec<Family> = report
//!     .detectors
//!     .iter()
//!     .filter(|v| v.invariant_on_rig)
//!     .map(|v| v.family)
//!     .collect();
//! assert_eq!(invariant, [Family::PointDisplacement]);
//! assert_eq!(
//!     report.verdict_line(),
//!     "lever arm 0.391 m, h = -0.1422 +- 4.082e-5 m (rounding), pitch nonzero: \
//!      no constant metric is frame-invariant on this rig; only the \
//!      point-displacement metric is. To do: use the point-displacement metric \
//!      (frame-invariant on every rig): h = -0.1422 m rules out an adapted \
//!      metric M0, and an eigenvalue threshold tuned in lidar acts in base as \
//!      0.6782 to 1.475 times itself (lever arm 0.391 m, l = 1 m)."
//! );
//! # Ok(())
//! # }
//! ```
//!
//! # `internals`: unstable
//!
//! The hidden module `internals` re-exports the crate's inner parts for the
//! crate's own tests, benchmarks, fuzz targets and examples. It is not part
//! of the face: no stability, no documentation promise; anything in it may
//! change or go in any release. The `audit` binary is a client of the face
//! and takes from `internals` only what is the command line's own business:
//! the defaults and ranges of its flags (`tolerances`) for clap's value
//! parsers, its colours and the wrapping and escaping of what it prints on
//! standard error (`render::Style`, `render::layout`, `sanitize`), the help
//! text that lists the metric families, the survey and spread plots (`--plot`), `check`'s
//! `--pair` syntax, the commands that reproduce the paper's experiments
//! (`tunnel`, `simulate`, `calibrate-threshold`), and for `audit run` (which
//! reads the run through [`Run`]) its record files: the atomic writer, the
//! timeline picture and the MCAP file's transforms.

#![deny(missing_docs)]
// Every type a user can reach through the face (a field, an argument, a
// return value) can also be named: re-exported below or in `internals`.
#![deny(unnameable_types)]

mod analysis;
mod api;
mod baseline;
mod bytes;
mod degeneracy;
mod diagnostic;
mod formats;
mod frames;
mod geometry;
mod input;
mod pipeline;
mod progress;
mod render;
mod report;
mod run;
mod sanitize;
mod stack;
mod tolerances;

// Robots: load, compose, report.
pub use analysis::family::{Calibrated, FamilySpec};
pub use analysis::metric::{AdaptedMetric, AdaptedReason, FamilyVerdict, VerdictReason};
pub use analysis::{analyze, Family, RigAnalysis};
pub use api::Robot;
pub use formats::{Assume, BagOptions, Format, LoadOptions, Rename, UrdfVersion};
pub use frames::{Chain, ChainStep, Edge, JointState, JointType, Provenance, ValuesAt};
pub use geometry::certificate::{AdjointSummary, CertificateEntry, Certificates};
pub use geometry::uncertainty::UncertaintySource;
pub use geometry::{EdgePrecision, PitchVerdict, Precision};
pub use geometry::{PitchTol, QuatOrder, Screw, ScrewKind, Transform, UserSigma};
pub use pipeline::RigOptions;

// The user's own odometry's detector on a rig (`RigReport::detector`).
pub use analysis::detectors::{
    ConfiguredThreshold, Dependence, DetectorAdvice, DetectorConfig, OdometryDetector,
};

// Calibration files: the CI check, the diff, the survey.
pub use baseline::DriftTolerances;
pub use pipeline::{check, check_with, diff, survey, CheckOptions, DiffOptions, SideRead};
pub use pipeline::{spread, SpreadOptions};
pub use pipeline::{SortColumn, SurveyOptions};
pub use report::diff::DiffToleranceJson;

// The detector.
pub use api::{Detector, PairOptions, ScanFile};
pub use pipeline::detector::{Coords, DetectorOptions, InitialGuess, NormalOptions, Points};
pub use progress::{NoProgress, Progress, ProgressFactory};

// A recorded run.
pub use api::{Run, ScanResult};
pub use pipeline::{RunDetector, RunFrames, RunOptions, RunPairs, RunScans};
pub use report::run::RunReport;
pub use run::poses::PoseFormat;
pub use run::source::{ScanBound, ScanWindow};

// Reports and their output.
pub use api::{render, render_bytes, render_to, RenderOptions};
pub use document::Report;
pub use render::OutputFormat;
pub use report::detector::{DegeneracyReport, SweepReport};
pub use report::diff::DiffReport;
pub use report::frames::FramesReport;
pub use report::spread::SpreadReport;
pub use report::{CheckReport, RigReport, SurveyReport};

// The parts of the reports, one module per report, and the document a
// report is laid out as (its blocks, tables and pictures).
pub mod document;
pub mod reports;

// Diagnostics.
pub use diagnostic::{Code, Diagnostic, Error, Location, Result, Severity, Warning};

#[doc(hidden)]
pub mod internals;
