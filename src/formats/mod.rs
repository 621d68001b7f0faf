//! File formats -> edges with provenance.
//!
//! Data flow: files -> (this module) edges -> `graph::FrameGraph` -> one
//! `se3::Transform` -> analysis (`certificate`, `metric`) -> `report`.
//!
//! Every loader returns the edges a file yields, each with the place it came
//! from, plus named warnings. Files that carry no frame names get fixed names
//! (FAST-LIO `imu -> lidar`, LIO-SAM `lidar -> imu`, Ouster `os_sensor -> os_lidar`
//! and `os_sensor -> os_imu`, ...), each stated in its parser's module doc and
//! listed in the README's "Input formats" section.

use crate::diagnostic::{Code, Error, Location, Result, Warning};
pub use crate::frames::{Edge, JointState, JointType, Provenance};
use crate::tolerances::{DEFAULT_MAX_FILE_SIZE, MAX_TRANSLATION_M, METRE_FIELD_WARN_M};
use std::collections::BTreeMap;
use std::path::Path;

pub mod arrow_ipc;
pub mod av2;
pub mod bag;
pub mod kitti_m2dgr;
pub mod kitti_object;
pub mod launch;
pub mod launch_subst;
pub mod lio_yaml;
pub mod matrix_tree;
pub mod nuscenes;
pub mod ouster;
pub mod ouster_extrinsics;
pub mod registry;
pub mod rig_toml;
pub mod shell;
pub mod source;
// TODO(issue 10): urdf/mod.rs links to its private `read` and `joints`.
pub mod urdf;
pub mod xacro;
pub mod xml;

pub use registry::{all_formats, is_calibration_file, Format, FormatSpec, FORMATS};
use source::line_col;
pub mod yaml;
pub mod yaml_dialects;

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
    /// Where to look for the external `xacro` program: a `PATH`-style list;
    /// `None` uses the process's `PATH`.
    pub xacro_search_path: Option<std::ffi::OsString>,
    /// `--urdf-version X.Y`: read every URDF as this version, whatever its
    /// `<robot version>` says (`None`: as declared, 1.0 when absent).
    pub urdf_version: Option<urdf::UrdfVersion>,
    /// `--xacro external`: expand `.xacro` files with the external program
    /// instead of the built-in expander.
    pub xacro_external: bool,
    /// `--arg NAME=VALUE`: xacro `$(arg NAME)` values (override `xacro:arg`),
    /// and launch-file args (`$(arg NAME)`, `$(var NAME)`, conditions),
    /// overriding the defaults the file declares.
    pub xacro_args: BTreeMap<String, String>,
    /// `--package-path DIR`: where `$(find pkg)` looks first.
    pub package_paths: Vec<std::path::PathBuf>,
    /// Which topics of a bag are read (`--tf-static-topic`, `--tf-topic`,
    /// `--description-topic`).
    pub bag: bag::BagOptions,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            joints: BTreeMap::new(),
            key: None,
            invert: false,
            format: None,
            max_file_size: DEFAULT_MAX_FILE_SIZE,
            xacro_search_path: None,
            urdf_version: None,
            xacro_external: false,
            xacro_args: BTreeMap::new(),
            package_paths: Vec::new(),
            bag: bag::BagOptions::default(),
        }
    }
}

/// Metadata a rig file carries (TOML rig files; see `rig_toml`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RigMeta {
    /// Unique rig id (`[rig] id`; the shipped files are named `<id>.toml`).
    pub id: String,
    /// What was measured (`[rig] sensor`), e.g. the LiDAR and IMU models.
    pub sensor: String,
    /// What it is mounted on (`[rig] platform`).
    pub platform: String,
    /// The dataset or project the calibration comes from (`[rig] dataset`).
    pub dataset: String,
    /// Body (IMU) frame the survey reports from: the rig's transform is the
    /// pose of `to` in `from`.
    pub from: String,
    /// LiDAR frame the survey reports to.
    pub to: String,
    /// Source repository, `owner/name` (`[rig.source] repo`).
    pub source_repo: String,
    /// File in that repository the numbers come from, with the table or section
    /// when they sit in prose (`[rig.source] path`).
    pub source_path: String,
    /// Full commit hash of the source (`[rig.source] commit`).
    pub source_commit: String,
    /// The source's licence as far as known (`[rig] licence`).
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
    /// The edges the file yields (each the pose of its child in its parent),
    /// in file order, with provenance.
    pub edges: Vec<Edge>,
    /// Frames declared without an edge (URDF links no joint attaches).
    pub frames: Vec<crate::frames::FrameDecl>,
    /// Named warnings raised while reading (suspicious but usable input).
    pub warnings: Vec<Warning>,
    /// The rig metadata, for TOML rig files (`None` for every other format).
    pub rig: Option<RigMeta>,
    /// Edges that close a loop with `edges` (Kalibr `T_cn_cnm1`): checked
    /// against the tree, not part of it (see `frames::graph`).
    pub redundant: Vec<Edge>,
}

impl From<Loaded> for crate::frames::EdgeSet {
    fn from(l: Loaded) -> Self {
        crate::frames::EdgeSet {
            edges: l.edges,
            frames: l.frames,
            warnings: l.warnings,
            redundant: l.redundant,
        }
    }
}

/// Parse one number as written in a file (also `+1`, `1.`, `.5`, `1e-3`).
/// `nan` / `inf` parse and are refused later by the transform constructors.
pub fn parse_number(s: &str) -> Option<f64> {
    let t = s.trim();
    if t.is_empty() {
        return None;
    }
    t.parse::<f64>().ok()
}

/// Warn about translation components that look like millimetres in a metre field.
pub fn check_metres(d: &[f64; 3], what: &str, loc: &Location, warnings: &mut Vec<Warning>) {
    if d.iter().any(|x| x.abs() > METRE_FIELD_WARN_M) {
        warnings.push(
            Warning::new(
                Code::MillimetresInMetreField,
                format!(
                    "{what} = [{}, {}, {}] m: a component above {METRE_FIELD_WARN_M} m in a field documented as metres; is it in millimetres?",
                    d[0], d[1], d[2]
                ),
            )
            .at(loc),
        );
    }
}

/// Attach the location of a problem to every warning a constructor produced.
pub(crate) fn locate_warnings(ws: Vec<Warning>, loc: &Location, out: &mut Vec<Warning>) {
    out.extend(ws.into_iter().map(|w| w.at(loc)));
}

/// Detect the format from the extension and the content (see [`registry`]).
pub fn detect_format(path: &Path, text: &str) -> Result<Format> {
    registry::detect(path, text)
}

/// Read one file: detect its format (or use `opts.format`), parse, validate.
pub fn load_file(path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    // A FIFO or a device is refused before anything opens it (bag detection
    // reads magic bytes); a bag folder is a directory.
    if !path.is_dir() && !crate::input::is_stdin(path) {
        drop(crate::input::open_regular(path)?);
    }
    // Bags are binary and large: read through their index, never whole.
    if bag::is_bag(path) {
        return bag::load(path, opts);
    }
    let bytes = crate::input::read_bytes(path, opts.max_file_size, "the --max-file-size cap")?;
    load_bytes(bytes, path, opts)
}

/// Read the bytes of one file: an Arrow IPC file (`ARROW1` magic, a
/// `.feather` name or `--input-format av2-feather`) as Argoverse 2's
/// `egovehicle_SE3_sensor` table, anything else as UTF-8 text ([`load_str`]).
pub fn load_bytes(bytes: Vec<u8>, path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    let feather = match opts.format {
        Some(f) => f.name() == av2::AV2_FEATHER.id,
        None => {
            arrow_ipc::is_arrow_file(&bytes)
                || path
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("feather"))
        }
    };
    if !feather {
        // A LAS/LAZ scan given where extrinsics are expected: say what it is
        // and where it is read, rather than "expected UTF-8 text".
        if bytes.starts_with(crate::degeneracy::points::las::MAGIC) {
            return Err(Error::parse(
                "expected a file with transforms (URDF, launch, YAML, JSON, TOML, ...), found a LAS/LAZ point cloud (magic `LASF`); its degeneracy is read by `audit degeneracy FILE --estimate-normals`",
            )
            .in_file(path));
        }
        let text = crate::input::decode(bytes).map_err(|e| e.in_file(path))?;
        return load_str(&text, path, opts);
    }
    let loaded = av2::parse_feather(&bytes, path, opts).map_err(|e| e.in_file(path))?;
    checked(loaded, Format(&av2::AV2_FEATHER), path, opts)
}

/// A `--joint` value above 2 pi on a revolute or continuous joint of these
/// edges looks like degrees: a `degrees-in-radian-field` warning.
fn warn_degrees(edges: &[Edge], opts: &LoadOptions, warnings: &mut Vec<Warning>) {
    use crate::tolerances::DEGREES_LIKE_RAD;
    for e in edges {
        let Some(j) = &e.joint else { continue };
        let Some(&v) = opts.joints.get(&j.name) else {
            continue;
        };
        if matches!(j.joint_type, JointType::Revolute | JointType::Continuous)
            && v.abs() > DEGREES_LIKE_RAD
        {
            warnings.push(
                Warning::new(
                    Code::DegreesInRadianField,
                    format!(
                        "--joint {}={v}: {} joint positions are radians, and |{v}| > 2 pi looks like degrees ({v} deg = {:.6} rad)",
                        crate::sanitize::quote(&j.name),
                        j.joint_type,
                        v.to_radians()
                    ),
                )
                .at(&e.provenance.location),
            );
        }
    }
}

/// A NUL or a line break in a frame or joint name is an error at the edge's
/// place: no ROS name holds one, and a line break would let a name start a
/// line of a report or a CI log.
fn check_names(e: &Edge) -> Result<()> {
    let joint = e.joint.as_ref().map(|j| ("joint", j.name.as_str()));
    let names = [("frame", e.parent.as_str()), ("frame", e.child.as_str())];
    for (what, name) in names.into_iter().chain(joint) {
        let bad = name
            .chars()
            .find(|&c| matches!(c, '\0' | '\n' | '\r' | '\u{85}' | '\u{2028}' | '\u{2029}'));
        if let Some(c) = bad {
            let found = if c == '\0' { "a NUL" } else { "a line break" };
            return Err(Error::parse(format!(
                "{what} name \"{}\" contains {found}: expected a name without control characters",
                crate::sanitize::quote(name)
            ))
            .at(&e.provenance.location));
        }
    }
    Ok(())
}

/// Parse `text` as if read from `path` (the path names the file in provenance
/// and selects the format by extension).
pub fn load_str(text: &str, path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    let text = &*crate::input::normalize(text);
    if text.trim().is_empty() {
        return Err(Error::parse(
            "file is empty: expected a URDF, launch file, calibration YAML/JSON or text",
        )
        .in_file(path));
    }
    let format = match opts.format {
        Some(f) => f,
        None => detect_format(path, text)?,
    };
    let loaded = (format.0.parse)(text, path, opts).map_err(|e| e.in_file(path))?;
    checked(loaded, format, path, opts)
}

/// What every loader's result goes through: at least one edge, names and
/// translations checked, `--joint` degrees warned, `--invert` applied.
fn checked(mut loaded: Loaded, format: Format, path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    if loaded.edges.is_empty() {
        return Err(Error::parse(format!(
            "read as {}: expected at least one transform, found none",
            format.name()
        ))
        .in_file(path));
    }
    for e in loaded.edges.iter().chain(&loaded.redundant) {
        check_names(e).map_err(|err| err.in_file(path))?;
        let d = e.transform.translation();
        if let Some(x) = d.iter().find(|x| x.is_nan() || x.abs() > MAX_TRANSLATION_M) {
            return Err(Error::invalid(format!(
                "edge {} -> {} ({}): translation component {x:e} m: expected at most {MAX_TRANSLATION_M:e} m in magnitude (a sensor extrinsic; check the units)",
                e.parent, e.child, e.provenance.key
            ))
            .at(&e.provenance.location)
            .in_file(path));
        }
    }
    warn_degrees(&loaded.edges, opts, &mut loaded.warnings);
    if opts.invert {
        loaded.edges = loaded.edges.into_iter().map(numbers_inverted).collect();
        loaded.redundant = loaded.redundant.into_iter().map(numbers_inverted).collect();
    }
    Ok(loaded)
}

/// `--invert`: the file's numbers are the pose of the parent in the child, so
/// the edge keeps its frames and takes the inverse transform ([`Edge::inverted`]
/// alone, which also swaps the frames, states the same pose and changes nothing).
fn numbers_inverted(e: Edge) -> Edge {
    let mut e = e.inverted();
    std::mem::swap(&mut e.parent, &mut e.child);
    e
}
