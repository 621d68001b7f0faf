//! File formats -> edges with provenance.
//!
//! Data flow: files -> (this module) edges -> `graph::FrameGraph` -> one
//! `se3::Transform` -> analysis (`certificate`, `metric`) -> `report`.
//!
//! Every loader returns the edges a file yields, each with the place it came
//! from, plus named warnings. Files that carry no frame names get the names listed
//! in DESIGN.md ("Frame names for files that carry none").

use crate::error::{Location, Result, Warning};
use crate::se3::Transform;
use std::collections::BTreeMap;
use std::path::Path;

pub mod rig_toml;

/// Default cap on the size of one input file (bytes); `--max-file-size` changes it.
pub const DEFAULT_MAX_FILE_SIZE: u64 = 16 * 1024 * 1024;

/// The formats the tool reads. `name()` is what `--format`-style options and
/// provenance print.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    Urdf,
    RigToml,
    // Other variants are added by the loaders that read them.
}

impl Format {
    pub fn name(self) -> &'static str {
        match self {
            Format::Urdf => "urdf",
            Format::RigToml => "rig-toml",
        }
    }
}

/// Where an edge's numbers came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    /// File, line, column where known.
    pub location: Location,
    pub format: Format,
    /// The key or element it came from, e.g. `joint "lidar_joint" <origin>` or
    /// `extrinsic_T + extrinsic_R`.
    pub key: String,
}

/// State of a non-fixed joint an edge passes through (URDF).
#[derive(Debug, Clone, PartialEq)]
pub struct JointState {
    pub name: String,
    /// `revolute`, `continuous`, `prismatic`, `floating`, `planar`.
    pub joint_type: String,
    /// The position used (rad or m); `None` when the joint cannot be used until
    /// it is set (floating, planar).
    pub value: Option<f64>,
    /// True when the value is the default (0) rather than set by `--joint`.
    pub defaulted: bool,
}

/// One parent -> child edge: `transform` is the pose of `child` in `parent`.
#[derive(Debug, Clone, PartialEq)]
pub struct Edge {
    pub parent: String,
    pub child: String,
    pub transform: Transform,
    pub provenance: Provenance,
    /// `Some` for non-fixed joints.
    pub joint: Option<JointState>,
}

/// Options that change how files are read.
#[derive(Debug, Clone)]
pub struct LoadOptions {
    /// `--joint NAME=VALUE`.
    pub joints: BTreeMap<String, f64>,
    /// `--key NAME`: pick one key in a YAML/JSON file.
    pub key: Option<String>,
    /// `--invert`: the file stores the other direction.
    pub invert: bool,
    /// `--input-format NAME`: skip detection.
    pub format: Option<Format>,
    /// Refuse files larger than this (bytes).
    pub max_file_size: u64,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            joints: BTreeMap::new(),
            key: None,
            invert: false,
            format: None,
            max_file_size: DEFAULT_MAX_FILE_SIZE,
        }
    }
}

/// Metadata a rig file carries (TOML rig files; see `rig_toml`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RigMeta {
    pub id: String,
    pub sensor: String,
    pub platform: String,
    pub dataset: String,
    /// Body frame and LiDAR frame the survey uses.
    pub from: String,
    pub to: String,
    pub source_repo: String,
    pub source_path: String,
    pub source_commit: String,
    pub licence: String,
    /// Which frame is expressed in which, as the source documents it.
    pub direction: String,
    /// Identity or zero extrinsic (co-located placeholder): kept out of statistics.
    pub placeholder: bool,
    /// `factory`, `dataset-calibration`, `cad-or-nominal`, `third-party-config`
    /// or `placeholder` (rig TOML `[rig] category`; empty when not given).
    pub category: String,
    /// Free-text caveats from the rig file (empty when none).
    pub notes: String,
    /// A web address of the source, when the rig file gives one.
    pub source_url: Option<String>,
    /// Set when this file describes the same rig as another (e.g. a raw-file
    /// sidecar beside the native TOML): kept out of statistics; it must give the
    /// same transform as the rig it names.
    pub duplicate_of: Option<String>,
}

impl RigMeta {
    /// Whether the rig counts in survey statistics: not a placeholder and not a
    /// duplicate of another rig.
    pub fn in_statistics(&self) -> bool {
        !self.placeholder && self.duplicate_of.is_none()
    }
}

/// What one file yields.
#[derive(Debug, Clone, Default)]
pub struct Loaded {
    pub edges: Vec<Edge>,
    pub warnings: Vec<Warning>,
    pub rig: Option<RigMeta>,
}

/// Read one file: detect its format (or use `opts.format`), parse, validate.
pub fn load_file(path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    let _ = (path, opts);
    unimplemented!("formats::load_file is being written")
}
