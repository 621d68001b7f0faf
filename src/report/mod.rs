//! Typed reports, one per command: `Serialize` for JSON (schemas in
//! docs/schemas, `schema_version` 1), and a [`crate::render::Report`] layout
//! for the other formats. Reports carry enums, never strings matched later.

pub mod check;
pub mod detector;
pub mod diff;
pub mod frames;
pub mod rig;
pub mod survey;

pub use check::CheckReport;
pub use rig::RigReport;
pub use survey::SurveyReport;

/// The JSON schema version of every report.
pub const SCHEMA_VERSION: u32 = 1;
