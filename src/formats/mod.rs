//! File formats -> edges with provenance.
//!
//! Data flow: files -> (this module) edges -> `graph::FrameGraph` -> one
//! `se3::Transform` -> analysis (`certificate`, `metric`) -> `report`.
//!
//! Every loader returns the edges a file yields, each with the place it came
//! from, plus named warnings. Files that carry no frame names get the names listed
//! in DESIGN.md ("Frame names for files that carry none").

use crate::diagnostic::{Error, ErrorKind, Location, Result, Warning, WarningCode};
pub use crate::frames::{Edge, JointState, JointType, Provenance};
use crate::tolerances::{DEFAULT_MAX_FILE_SIZE, MAX_TRANSLATION_M, METRE_FIELD_WARN_M};
use std::collections::BTreeMap;
use std::path::Path;

pub mod kitti_m2dgr;
pub mod launch;
pub mod ouster;
pub mod rig_toml;
pub mod source;
pub mod urdf;
pub mod xacro;
pub mod xml;

use source::{line_col, LineIndex};
pub mod yaml;
pub mod yaml_dialects;

/// The formats the tool reads. `name()` is what `--input-format` takes and what
/// provenance prints; [`all_formats`] says what each one's numbers mean.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    Urdf,
    Xacro,
    LaunchXml,
    LaunchYaml,
    LaunchPy,
    StaticTfCommands,
    TfStaticEcho,
    FastLio,
    LioSam,
    LioLivoxLaunch,
    CocoLic,
    Slict,
    TfTreeYaml,
    MatrixYaml,
    QuaternionYaml,
    OusterJson,
    KittiCalib,
    M2dgrTxt,
    RigToml,
}

const ALL_FORMATS: &[(Format, &str)] = &[
    (Format::Urdf, "URDF robot description: each joint <origin> is the child link's pose in the parent link (R = Rz(yaw) Ry(pitch) Rx(roll)); movable joints at 0 unless --joint NAME=VALUE"),
    (Format::Xacro, "xacro macro file: expanded by the built-in expander (--arg NAME=VALUE, --package-path DIR for $(find)), then read as URDF; edges point at the line in the xacro source"),
    (Format::LaunchXml, "ROS 1 / ROS 2 launch XML: static_transform_publisher nodes (x y z yaw pitch roll | x y z qx qy qz qw, or ROS 2 --flags): child pose in parent"),
    (Format::LaunchYaml, "ROS 2 launch YAML: static_transform_publisher nodes with literal args; child pose in parent"),
    (Format::LaunchPy, "ROS 2 Python launch: literal `arguments=[...]` of static_transform_publisher Nodes; anything not literal is refused"),
    (Format::StaticTfCommands, "command lines saved as text (rosrun tf / ros2 run tf2_ros static_transform_publisher ...): child pose in parent"),
    (Format::TfStaticEcho, "`rostopic echo /tf_static` / `ros2 topic echo /tf_static` YAML (several documents): child_frame_id pose in header.frame_id"),
    (Format::FastLio, "FAST-LIO / FAST-LIVO2 / Point-LIO `extrinsic_T` + `extrinsic_R` (row-major): the LiDAR pose in the IMU frame, edge imu -> lidar"),
    (Format::LioSam, "LIO-SAM `extrinsicRot` + `extrinsicTrans` (\"T_lb\"): extrinsicRot rotates IMU readings into the LiDAR frame and the code uses extrinsicTrans as lidar2Imu, so the pair is the IMU pose in the LiDAR frame, edge lidar -> imu; extrinsicRPY (attitude only) is not used"),
    (Format::LioLivoxLaunch, "LIO-Livox launch `<rosparam param=\"Extrinsic_Tlb\">` 4x4 row-major: read as the LiDAR pose in the IMU frame (FAST-LIO sign, as mid360.launch uses), edge imu -> lidar; the direction is assumed (--invert flips it)"),
    (Format::CocoLic, "Coco-LIC `lidarN: Extrinsics: {Trans, Rot}` (\"lidar to imu\"): LiDAR pose in the IMU frame, edges imu -> lidarN"),
    (Format::Slict, "SLICT `lidar_extr`: stacked row-major 4x4, \"transform of coordinates in lidar's frame to body\": edges body -> lidar (lidar0, lidar1, ... when several); the (4,4) entry is a timestamp flag and the bottom row is not used"),
    (Format::TfTreeYaml, "tf-tree YAML (`<parent>_to_<child>: {x, y, z, roll, pitch, yaw}`, GrandTour): child pose in parent, URDF rpy"),
    (Format::MatrixYaml, "YAML with 4x4 matrices under keys `T_A_B` or `A_T_B` (OpenCV FileStorage `!!opencv-matrix`, Kalibr `T_cam_imu`, plain lists, `T_A_B_t_xyz_q_xyzw`): the pose of B in A, edge A -> B; --key NAME picks one"),
    (Format::QuaternionYaml, "`quaternion_A_B` (qw, qx, qy, qz: w first) + `translation_A_B` blocks (FusionPortable): the pose of B in A, edge A -> B"),
    (Format::OusterJson, "Ouster sensor metadata JSON (legacy flat or nested): `lidar_to_sensor_transform` / `imu_to_sensor_transform`, row-major 4x4 in millimetres, converted to metres: edges os_sensor -> os_lidar and os_sensor -> os_imu"),
    (Format::KittiCalib, "KITTI calib text (`R:` 9 numbers row-major, `T:` 3 numbers; calib_A_to_B.txt maps A coordinates into B): edge B -> A"),
    (Format::M2dgrTxt, "M2DGR calibration_results.txt: `%% NAME` blocks with `% Extrinsic [to LIDAR]` 4x4 or 3x4 `data:`: the sensor's pose in the LiDAR frame, edges velodyne -> <name>"),
    (Format::RigToml, "the tool's own TOML rig file (see calibrations/README.md)"),
];

/// Every format with a one-line description of what its numbers mean.
pub fn all_formats() -> &'static [(Format, &'static str)] {
    ALL_FORMATS
}

impl Format {
    pub fn name(self) -> &'static str {
        match self {
            Format::Urdf => "urdf",
            Format::Xacro => "xacro",
            Format::LaunchXml => "launch-xml",
            Format::LaunchYaml => "launch-yaml",
            Format::LaunchPy => "launch-py",
            Format::StaticTfCommands => "static-tf-commands",
            Format::TfStaticEcho => "tf-static-echo",
            Format::FastLio => "fast-lio",
            Format::LioSam => "lio-sam",
            Format::LioLivoxLaunch => "lio-livox-launch",
            Format::CocoLic => "coco-lic",
            Format::Slict => "slict",
            Format::TfTreeYaml => "tf-tree-yaml",
            Format::MatrixYaml => "matrix-yaml",
            Format::QuaternionYaml => "quaternion-yaml",
            Format::OusterJson => "ouster-json",
            Format::KittiCalib => "kitti-calib",
            Format::M2dgrTxt => "m2dgr-txt",
            Format::RigToml => "rig-toml",
        }
    }

    /// The format named `name` (as printed by [`Format::name`]); the error lists
    /// the names.
    pub fn from_name(name: &str) -> Result<Format> {
        let n = name.trim().to_ascii_lowercase().replace('_', "-");
        ALL_FORMATS
            .iter()
            .find(|(f, _)| f.name() == n)
            .map(|(f, _)| *f)
            .ok_or_else(|| {
                Error::usage(format!(
                    "unknown input format '{name}': expected one of {}",
                    ALL_FORMATS
                        .iter()
                        .map(|(f, _)| f.name())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })
    }

    /// One line: what the numbers of this format mean.
    pub fn description(self) -> &'static str {
        ALL_FORMATS
            .iter()
            .find(|(f, _)| *f == self)
            .map(|(_, d)| *d)
            .unwrap_or("")
    }
}

impl From<Format> for &'static str {
    fn from(f: Format) -> &'static str {
        f.name()
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
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
    /// Where to look for the external `xacro` program: a `PATH`-style list;
    /// `None` uses the process's `PATH`.
    pub xacro_search_path: Option<std::ffi::OsString>,
    /// `--xacro external`: expand `.xacro` files with the external program
    /// instead of the built-in expander.
    pub xacro_external: bool,
    /// `--arg NAME=VALUE`: xacro `$(arg NAME)` values (override `xacro:arg`).
    pub xacro_args: BTreeMap<String, String>,
    /// `--package-path DIR`: where `$(find pkg)` looks first.
    pub package_paths: Vec<std::path::PathBuf>,
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
            xacro_external: false,
            xacro_args: BTreeMap::new(),
            package_paths: Vec::new(),
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

impl From<Loaded> for crate::frames::EdgeSet {
    fn from(l: Loaded) -> Self {
        crate::frames::EdgeSet {
            edges: l.edges,
            warnings: l.warnings,
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
                WarningCode::MillimetresInMetreField,
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

fn extension(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    for multi in [
        ".launch.xml",
        ".launch.yaml",
        ".launch.yml",
        ".launch.py",
        ".urdf.xacro",
    ] {
        if name.ends_with(multi) {
            return multi[1..].to_string();
        }
    }
    path.extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default()
}

/// Detect the format from the extension and the content.
pub fn detect_format(path: &Path, text: &str) -> Result<Format> {
    let ext = extension(path);
    let head: String = text.chars().take(4096).collect();
    let trimmed = text.trim_start_matches('\u{feff}').trim_start();
    let looks_xml = trimmed.starts_with('<');
    match ext.as_str() {
        "xacro" | "urdf.xacro" => return Ok(Format::Xacro),
        "toml" => return Ok(Format::RigToml),
        "json" => return Ok(Format::OusterJson),
        "py" | "launch.py" => return Ok(Format::LaunchPy),
        "launch.yaml" | "launch.yml" => return Ok(Format::LaunchYaml),
        _ => {}
    }
    if looks_xml || matches!(ext.as_str(), "urdf" | "xml" | "launch" | "launch.xml") {
        if text.contains("<robot") {
            return Ok(Format::Urdf);
        }
        if text.contains("<launch") {
            if text.contains("static_transform_publisher") {
                return Ok(Format::LaunchXml);
            }
            if text.contains("Extrinsic_Tlb") {
                return Ok(Format::LioLivoxLaunch);
            }
            return Ok(Format::LaunchXml);
        }
        if ext == "urdf" {
            return Ok(Format::Urdf);
        }
        if looks_xml {
            return Err(match roxmltree::Document::parse_with_options(text, xml::parse_options()) {
                Ok(doc) => {
                    let root = doc.root_element();
                    let (l, c) = LineIndex::new(text).pos(root.range().start);
                    Error::parse(format!(
                        "root element is <{}>: expected a URDF <robot> or a ROS <launch> file; pass --input-format NAME to force a format",
                        root.tag_name().name()
                    ))
                    .at_line(l, Some(c))
                }
                Err(e) => xml::error(&e, text),
            }
            .in_file(path));
        }
    }
    if trimmed.starts_with('{') {
        return Ok(Format::OusterJson);
    }
    if ext == "py" || head.contains("LaunchDescription") {
        return Ok(Format::LaunchPy);
    }
    if text.lines().any(|l| {
        let l = l.trim_start();
        !l.starts_with('#')
            && !l.starts_with('%')
            && (l.starts_with("rosrun") || l.starts_with("ros2 run"))
            && l.contains("static_transform_publisher")
    }) && !text.contains("!!opencv-matrix")
    {
        return Ok(Format::StaticTfCommands);
    }
    if text.contains("% Extrinsic") && text.contains("data:") {
        return Ok(Format::M2dgrTxt);
    }
    if text.lines().any(|l| l.trim_start().starts_with("R:"))
        && text.lines().any(|l| l.trim_start().starts_with("T:"))
    {
        return Ok(Format::KittiCalib);
    }
    // YAML dialects: decided on the parsed keys.
    Ok(yaml_dialects::sniff(text))
}

/// Read one file: detect its format (or use `opts.format`), parse, validate.
pub fn load_file(path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, &e))?;
    if meta.is_dir() {
        return Err(Error::new(ErrorKind::Io, "is a directory: expected a file").in_file(path));
    }
    if meta.len() > opts.max_file_size {
        return Err(Error::limit(format!(
            "file is {} bytes: expected at most {} bytes (the --max-file-size cap)",
            meta.len(),
            opts.max_file_size
        ))
        .in_file(path));
    }
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, &e))?;
    let text = match String::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            let off = e.utf8_error().valid_up_to();
            let valid = std::str::from_utf8(&e.as_bytes()[..off]).unwrap_or("");
            let (line, col) = line_col(valid, off);
            return Err(Error::parse(format!(
                "expected UTF-8 text, found byte 0x{:02x} (binary file?)",
                e.as_bytes().get(off).copied().unwrap_or(0)
            ))
            .in_file(path)
            .at_line(line, Some(col)));
        }
    };
    load_str(&text, path, opts)
}

/// Parse `text` as if read from `path` (the path names the file in provenance
/// and selects the format by extension).
pub fn load_str(text: &str, path: &Path, opts: &LoadOptions) -> Result<Loaded> {
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
    let mut loaded = match format {
        Format::Urdf => urdf::parse(text, path, opts),
        Format::Xacro => xacro::parse(text, path, opts),
        Format::LaunchXml => launch::parse_launch_xml(text, path, opts),
        Format::LioLivoxLaunch => launch::parse_lio_livox(text, path, opts),
        Format::LaunchYaml => launch::parse_launch_yaml(text, path, opts),
        Format::LaunchPy => launch::parse_launch_py(text, path, opts),
        Format::StaticTfCommands => launch::parse_commands(text, path, opts),
        Format::OusterJson => ouster::parse(text, path, opts),
        Format::KittiCalib => kitti_m2dgr::parse_kitti(text, path, opts),
        Format::M2dgrTxt => kitti_m2dgr::parse_m2dgr(text, path, opts),
        Format::RigToml => rig_toml::parse(text, path, opts),
        Format::TfStaticEcho
        | Format::FastLio
        | Format::LioSam
        | Format::CocoLic
        | Format::Slict
        | Format::TfTreeYaml
        | Format::MatrixYaml
        | Format::QuaternionYaml => yaml_dialects::parse(format, text, path, opts),
    }
    .map_err(|e| e.in_file(path))?;
    if loaded.edges.is_empty() {
        return Err(Error::parse(format!(
            "read as {}: expected at least one transform, found none",
            format.name()
        ))
        .in_file(path));
    }
    for e in &loaded.edges {
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
    if opts.invert {
        loaded.edges = loaded.edges.into_iter().map(Edge::inverted).collect();
    }
    Ok(loaded)
}
