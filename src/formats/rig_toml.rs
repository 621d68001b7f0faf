//! The tool's own TOML rig format (see calibrations/README.md).
//!
//! Placeholder so that `formats::load_file` compiles on this branch; the TOML rig
//! parser is written on another branch and replaces this file at merge.

use crate::error::{Error, Result};
use crate::formats::{LoadOptions, Loaded};
use std::path::Path;

/// Parse a TOML rig file.
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    let _ = (text, opts);
    Err(Error::parse("TOML rig files are not readable in this build").in_file(path))
}
