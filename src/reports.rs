//! The parts of the face's reports, one module per report: the types of
//! their public fields, so that a program can name what it holds (in a
//! `match`, a function signature, a struct of its own). Each is the Rust
//! side of a JSON object of the report's schema (`docs/schemas/`), with the
//! same field names. The reports themselves are at the crate root
//! ([`RigReport`](crate::RigReport), [`CheckReport`](crate::CheckReport),
//! ...); how a report is laid out for people is [`crate::document`].
//!
//! Nothing here is constructed by a program: the reports are built by the
//! face's functions and read through their fields.
//!
//! ```
//! use extrinsic_audit::document::Block;
//! use extrinsic_audit::reports::rig::ScrewJson;
//! use extrinsic_audit::{LoadOptions, PitchVerdict, Report, RigOptions, Robot};
//!
//! // A function of the program's own over one part of a report.
//! fn screw_translation_m(s: &ScrewJson) -> Option<f64> {
//!     s.translation_along_axis_m
//! }
//!
//! # fn main() -> extrinsic_audit::Result<()> {
//! let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/urdf/anymal_c_lidar.urdf");
//! let robot = Robot::load(&[urdf], &LoadOptions::default())?;
//! let (report, _) = robot.report("base", "lidar", &RigOptions::default())?;
//! // The LiDAR turns about -z and sits 0.1422 m above `base`: h = e . d.
//! let h = screw_translation_m(&report.screw).expect("a rotation");
//! assert!((h + 0.1422).abs() < 1e-12, "{h}");
//! assert_eq!(report.screw.pitch_verdict, Some(PitchVerdict::Nonzero));
//! // The same report laid out for people opens with its verdict line.
//! match &report.document().blocks[0] {
//!     Block::Headline { text, .. } => assert_eq!(*text, report.verdict_line()),
//!     other => panic!("not a headline: {other:?}"),
//! }
//! # Ok(())
//! # }
//! ```

/// The rig report ([`RigReport`](crate::RigReport), `audit FILE... --from A
/// --to B`; `docs/schemas/rig-report.schema.json`).
pub mod rig {
    pub use crate::report::rig::{
        AdaptedMetricJson, AdjointJson, CertificateJson, DetectorJson, KappaCheckJson,
        RotationJson, ScrewJson, SourceJson, TransformJson, UncertaintyJson,
    };
}

/// The CI check ([`CheckReport`](crate::CheckReport), `audit check`;
/// `docs/schemas/check.schema.json`).
pub mod check {
    pub use crate::report::check::BaselineChanges;
}

/// The survey ([`SurveyReport`](crate::SurveyReport), `audit survey`;
/// `docs/schemas/survey.schema.json`).
pub mod survey {
    pub use crate::report::survey::{SurveyRigJson, SurveyRows, SurveySummaryJson};
}

/// The diff of two calibrations ([`DiffReport`](crate::DiffReport), `audit
/// diff`; `docs/schemas/diff.schema.json`); its tolerance is
/// [`DiffToleranceJson`](crate::DiffToleranceJson).
pub mod diff {
    pub use crate::analysis::mistakes::Direction;
    pub use crate::report::diff::{
        BandDiffJson, ChainDiffJson, EdgeDiffJson, EdgeStatus, FamilyDiffJson, OldNew, ReadJson,
    };
    pub use crate::report::mistakes::MistakeJson;
}

/// The frame tree ([`FramesReport`](crate::FramesReport), `audit FILE...
/// --frames`; `docs/schemas/frames.schema.json`).
pub mod frames {
    pub use crate::report::frames::{ChainFramesJson, FrameEdgeJson, FrameJson};
}

/// The spread of many calibrations of one pair
/// ([`SpreadReport`](crate::SpreadReport), `audit spread`;
/// `docs/schemas/spread.schema.json`).
pub mod spread {
    pub use crate::analysis::spread::Deviation;
    pub use crate::report::spread::{
        AxisJson, BandRangeJson, CalibrationJson, MeanJson, MethodJson, OutlierTestJson,
        OutliersJson, SetPitchJson, SpreadJson, SubsetJson,
    };
}

/// The detector on a scan or pair ([`DegeneracyReport`](crate::DegeneracyReport),
/// `audit degeneracy`) and its frame sweep ([`SweepReport`](crate::SweepReport),
/// `audit sweep`; `docs/schemas/degeneracy.schema.json`,
/// `degeneracy-sweep.schema.json`).
pub mod detector {
    pub use crate::report::detector::{
        FamilyEigen, MatricesJson, NormalsJson, PairJson, PoseJson, RigDecisionJson, SubspaceJson,
        SweepFamilyJson, TwistScrewJson,
    };
}

/// A recorded run's summary ([`RunReport`](crate::RunReport), `audit run`;
/// `docs/schemas/run.schema.json`).
pub mod run {
    pub use crate::report::run::{
        ChangesJson, DegenerateJson, FamilyHead, FrameHead, IntervalJson, RunSettingsJson, RunUnit,
        SkipJson,
    };
    pub use crate::run::frames::FrameGroup;
}
