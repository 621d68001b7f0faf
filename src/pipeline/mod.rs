//! The pipeline the commands call: files -> frame graph (with renames and
//! joint values) -> chain -> rig report; the survey over rig files; the check
//! of calibration files against a baseline. The CLI parses arguments, calls
//! these and picks a renderer; nothing here prints.

mod check;
mod cleanup;
pub mod detector;
mod diff;
pub mod files;
mod fleet;
mod load;
pub mod manifest;
mod mistakes;
mod odometry_config;
mod output;
mod parallel;
mod rig;
pub mod run;
mod run_options;
mod spread;
mod survey;
pub mod walk;

pub use check::{check, check_with, CheckOptions};
pub use diff::{diff, DiffOptions, SideRead};
pub use files::write_atomic;
pub use load::{load, Loaded};
pub use output::{check_output_target, check_plot_target, write_survey_plot};
pub use rig::{report, RigOptions};
pub use run_options::{RunDetector, RunFrames, RunOptions, RunPairs, RunScans};
pub use spread::{check_spread_plot_target, spread, write_spread_plot, SpreadOptions};
pub use survey::{survey, SortColumn, SurveyOptions};
