//! Typed reports, one per command: `Serialize` for JSON (schemas in
//! docs/schemas, `schema_version` 1), and a [`Report`](crate::document::Report)
//! layout as a [`Document`](crate::document::Document) for the other formats
//! (the frame tree and the survey plot as picture blocks). Reports carry
//! enums, never strings matched later. This module imports the document
//! layer and never `render`: how a format draws a document is not its
//! business.

pub mod check;
mod data;
pub mod detector;
pub mod diff;
pub mod frames;
pub mod mistakes;
pub mod rig;
mod rig_scene;
pub mod run;
pub mod run_scene;
mod run_timeline;
pub mod scan_scene;
pub mod spread;
mod spread_plot;
pub mod survey;
mod survey_plot;

pub use crate::document::SCHEMA_VERSION;
pub use check::CheckReport;
pub use rig::RigReport;
pub use survey::SurveyReport;
