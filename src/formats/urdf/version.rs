//! The URDF version a file is read as: `<robot version>` as urdfdom reads
//! it, or `--urdf-version`. A leaf below the readers of joints and origins,
//! which both ask it.

use super::lines::Lines;
use super::stream::{err_at, El};
use crate::diagnostic::Result;
use crate::formats::spec::{LoadOptions, UrdfVersion};

/// The version a file is read as: declared (`None` when absent) and used.
#[derive(Debug, Clone, Copy)]
pub(super) struct Version {
    pub declared: Option<UrdfVersion>,
    pub used: UrdfVersion,
}

impl Version {
    pub(super) fn declared_text(&self) -> String {
        match self.declared {
            Some(v) => format!("declares version {v}"),
            None => "declares no version (1.0)".to_string(),
        }
    }
}

/// `<robot version>` read as urdfdom reads it (refused at the `<robot>` line
/// when malformed or unsupported), then `--urdf-version` if given.
pub(super) fn version(idx: &Lines, root: &El, opts: &LoadOptions) -> Result<Version> {
    let declared = match root.attr("version") {
        None => None,
        Some(s) => Some(UrdfVersion::parse(s).map_err(|m| {
            err_at(
                idx,
                root,
                format!("<robot version>: {m}; ROS (urdfdom) refuses this file"),
            )
        })?),
    };
    let used = opts.urdf_version.or(declared).unwrap_or(UrdfVersion::V1_0);
    Ok(Version { declared, used })
}
