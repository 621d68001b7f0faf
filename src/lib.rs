//! extrinsic-audit: what a robot's LiDAR extrinsic does to degeneracy detection.
//!
//! Data flow, one module per stage:
//! files ([`formats`]) -> frame graph ([`frames`]) -> one transform
//! ([`geometry`]) -> analysis ([`analysis`]; [`degeneracy`] for point data) ->
//! typed report ([`report`]) -> its [`document`] -> text, markdown, JSON,
//! pictures ([`render`]).
//! [`pipeline`] runs these stages for each command of the `audit` binary.
//! Conventions (frames, twists, adjoint, quaternion order, rpy) are stated once,
//! in [`geometry::se3`]; docs/ARCHITECTURE.md draws the layers.
//!
//! # Example
//!
//! Load ANYbotics ANYmal C's URDF, compose the pose of its LiDAR in its base
//! frame and analyse it (the README's rig report shows the same numbers):
//!
//! ```
//! use extrinsic_audit::analysis::{analyze, Family};
//! use extrinsic_audit::formats::LoadOptions;
//! use extrinsic_audit::geometry::{PitchTol, ScrewKind};
//! use extrinsic_audit::pipeline::{self, RigOptions};
//! use extrinsic_audit::tolerances::{DEFAULT_ELLS, DEFAULT_PITCH_TOL};
//! use std::path::PathBuf;
//!
//! # fn main() -> extrinsic_audit::diagnostic::Result<()> {
//! let urdf = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/urdf/anymal_c_lidar.urdf");
//! // Files -> one frame graph (no renames; movable joints at 0 unless
//! // `LoadOptions::joints` gives a value).
//! let loaded = pipeline::load(&[urdf], &LoadOptions::default(), &[])?;
//!
//! // Compose base -> lidar: the pose of `lidar` in `base`, p_base = R p_lidar + d,
//! // along base -> lidar_cage -> lidar.
//! let chain = loaded.graph.transform("base", "lidar")?;
//! assert_eq!(chain.steps.len(), 2);
//! let d = chain.transform.translation();
//! assert!((d.x + 0.364).abs() < 1e-12 && d.y.abs() < 1e-12 && (d.z - 0.1422).abs() < 1e-12);
//!
//! // Analyse: lever arm, screw, adjoint, certificate bands, detector verdicts.
//! let rig = analyze(&chain.transform, &DEFAULT_ELLS, DEFAULT_PITCH_TOL)?;
//! assert_eq!(format!("{:.6}", rig.lever_arm_m), "0.390790");
//! assert_eq!(rig.screw.kind, ScrewKind::General); // h = e . d != 0
//! let h = rig.screw.translation_along_axis;
//! assert!(matches!(h, Some(h) if (h + 0.1422).abs() < 1e-9));
//! let invariant: Vec<Family> = rig
//!     .detectors
//!     .iter()
//!     .filter(|v| v.invariant_on_rig)
//!     .map(|v| v.family)
//!     .collect();
//! assert_eq!(invariant, [Family::PointDisplacement]);
//!
//! // The same analysis as the typed report `audit` prints (and serialises).
//! let opts = RigOptions {
//!     ells: DEFAULT_ELLS.to_vec(),
//!     pitch_tol: PitchTol::Auto, // three-way, from the rounding of the digits
//!     sigma: None,               // no --sigma-t / --sigma-r
//!     kappa_lambda: None,
//! };
//! let report = pipeline::report(&chain, &opts)?;
//! assert_eq!(
//!     report.verdict_line(),
//!     "lever arm 0.391 m, h = -0.1422 +- 4.082e-5 m (rounding), pitch nonzero: \
//!      no constant metric is frame-invariant on this rig; only the \
//!      point-displacement metric is. To do: use the point-displacement metric \
//!      (frame-invariant on every rig); no adapted metric M0 exists for this rig."
//! );
//! # Ok(())
//! # }
//! ```

#![warn(missing_docs)]

pub mod analysis;
pub mod baseline;
pub(crate) mod bytes;
pub mod degeneracy;
pub mod diagnostic;
pub mod document;
pub mod formats;
pub mod frames;
pub mod geometry;
pub mod input;
pub mod pipeline;
pub mod progress;
pub mod render;
pub mod report;
pub mod run;
pub mod sanitize;
pub mod tolerances;

// The types most callers need, at the crate root.
pub use analysis::{analyze, Family, RigAnalysis};
pub use diagnostic::{Code, Diagnostic, Error, Location, Result, Severity};
pub use document::Report;
pub use formats::{load_file, Format, LoadOptions};
pub use frames::{Chain, Edge, FrameGraph};
pub use geometry::{Screw, ScrewKind, Transform};
pub use render::OutputFormat;
pub use report::{CheckReport, RigReport, SurveyReport};
