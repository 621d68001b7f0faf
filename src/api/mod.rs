//! The library's face: the few types a program holds (a [`Robot`], a
//! [`Detector`]) and how a report is written ([`render`]). Everything else
//! the crate root re-exports is defined where it belongs (options and reports
//! in `pipeline` and `report`, geometry in `geometry`); this module holds
//! what exists only for callers, on top of `pipeline`.

mod detector;
mod output;
mod robot;
mod run;

pub use detector::{Detector, PairOptions, ScanFile};
pub use output::{render, render_bytes, render_to, RenderOptions};
pub use robot::Robot;
pub use run::{run_transforms, scan_record, Run, ScanResult};
