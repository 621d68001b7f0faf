//! The contract between the format registry and the formats, a leaf: what a
//! format declares ([`FormatSpec`]), how sure its sniffer is ([`Confidence`]),
//! what its parser is given ([`Input`], [`LoadOptions`]) and what it returns
//! ([`Parsed`]). It imports no format: each format imports it and exports one
//! `FormatSpec` per format it reads; the registry lists them and runs the
//! detection below, knowing nothing of how one format differs from another.
//!
//! Detection, in this order (`formats::registry`):
//! 1. Binary formats (those with [`FormatSpec::magic`]), in registry order: the
//!    first whose magic bytes start the input, whose extension the file name
//!    has, or whose sniffer claims it (a bag folder) reads it, whatever
//!    `--input-format` names unless that is itself a binary format: a text
//!    reader cannot read it, and a container is never read whole.
//! 2. Otherwise the input is decoded as text (`Input::decode`: UTF-8, BOM,
//!    lone CR), and `--input-format` or an extension that one format lists
//!    selects it outright.
//! 3. Otherwise every sniffer rates the text and the highest [`Confidence`]
//!    wins, ties going to the earlier registry entry; detection stops at the
//!    first [`Confidence::Certain`]. Text that looks like XML and is claimed
//!    below [`Confidence::Claim`] is refused naming its root element.

mod input;
mod parsed;
mod urdf_version;

pub use input::Input;
pub(crate) use input::{Includes, ReadBlock, HEAD_BYTES};
pub(crate) use parsed::locate_warnings;
pub use parsed::{check_metres, parse_number, Parsed, RigMeta};
pub use urdf_version::UrdfVersion;

use crate::diagnostic::Result;
use crate::tolerances::DEFAULT_MAX_FILE_SIZE;
use std::collections::BTreeMap;

/// How sure a sniffer is that the input is in its format, lowest first.
/// Detection takes the highest; equal levels go to the earlier registry entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Confidence {
    /// Read when nothing else claims the text: the format most files of no
    /// known dialect hold (`matrix-yaml`).
    Fallback,
    /// The keys of one YAML dialect (FAST-LIO's `extrinsic_T`, a ROS 2 launch
    /// file's `node:`): where two dialects' keys are both present, the earlier
    /// registry entry wins.
    Keys,
    /// Nothing but a file-name extension that other formats share (`.json`).
    Extension,
    /// The line prefixes of a text format (KITTI's `R:` and `T:` lines).
    Lines,
    /// Markers a format's files carry (M2DGR's `% Extrinsic` with `data:`).
    Markers,
    /// Command lines that start a transform publisher
    /// (`rosrun tf static_transform_publisher ...`).
    Commands,
    /// A name only this format's files use (`LaunchDescription`,
    /// `Tr_velo_to_cam`).
    Names,
    /// A JSON document (the text starts with `{` or `[`) of no more specific
    /// kind.
    Json,
    /// A claim on markup or on a record layout (a `.urdf` name, nuScenes
    /// `sensor_token` records): the lowest level at which text that looks like
    /// XML is read; below it, such text is refused naming its root element.
    Claim,
    /// The keys or elements that name one format's documents (Ouster's
    /// `source_frame`, Argoverse 2's `sensor_name` with `tx_m`, a `<launch>`
    /// without publishers).
    Document,
    /// Nothing else reads it: a URDF `<robot>`, a launch file with publishers
    /// or `Extrinsic_Tlb`, a folder a container format owns. Detection stops
    /// at the first sniffer that says so.
    Certain,
}

/// A sniffer: how sure the input is in this format (`None`: not at all).
pub type SniffFn = fn(&Input) -> Option<Confidence>;

/// A parser: the input into edges.
pub type ParseFn = fn(&Input, &LoadOptions) -> Result<Parsed>;

/// One format, as its module declares it (`pub const SPEC: FormatSpec`).
#[derive(Debug)]
pub struct FormatSpec {
    /// What `--input-format` takes and provenance prints (`fast-lio`).
    pub id: &'static str,
    /// One line: what the numbers of this format mean.
    pub description: &'static str,
    /// File-name endings (lower case, without the leading dot) that select
    /// this format outright.
    pub extensions: &'static [&'static str],
    /// File-name endings (with the dot) a directory walk reads as calibration
    /// files that may be in this format (`audit check DIR`); a binary format
    /// that lists some is also walked by its magic bytes and sniffer.
    pub walk: &'static [&'static str],
    /// The bytes files of a binary format start with (any one of them); empty
    /// for a text format.
    pub magic: &'static [&'static [u8]],
    /// How sure the input looks like this format.
    pub sniff: SniffFn,
    /// The parser.
    pub parse: ParseFn,
    /// Whether what the parser returns goes through the common checks (at
    /// least one edge, frame names, the translation bound, `--joint` values
    /// in degrees, `--invert`). `false` for bags alone, which never had them:
    /// their reader applies tf2's rules (an out-of-range transform is left out
    /// with a warning).
    pub checked: bool,
}

impl FormatSpec {
    /// Whether this is a binary format (it declares magic bytes).
    pub fn is_binary(&self) -> bool {
        !self.magic.is_empty()
    }

    /// Whether `head` (the first bytes of an input) starts with one of the
    /// format's magic byte strings.
    pub(crate) fn magic_matches(&self, head: &[u8]) -> bool {
        self.magic.iter().any(|m| head.starts_with(m))
    }
}

/// A format: a handle on its `FormatSpec` (compared by id). `from_name`
/// lives with the list of formats (`formats::registry`).
#[derive(Clone, Copy)]
pub struct Format(pub(crate) &'static FormatSpec);

impl Format {
    /// The id (`urdf`, `fast-lio`, ...).
    pub fn name(self) -> &'static str {
        self.0.id
    }
    /// One line: what the numbers of this format mean.
    pub fn description(self) -> &'static str {
        self.0.description
    }
}

impl PartialEq for Format {
    fn eq(&self, o: &Self) -> bool {
        self.0.id == o.0.id
    }
}
impl Eq for Format {}

impl std::fmt::Debug for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Format({})", self.0.id)
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.0.id)
    }
}

impl From<Format> for &'static str {
    fn from(f: Format) -> &'static str {
        f.0.id
    }
}

/// How files are read into a robot. `Default`: as the command line reads
/// them without flags (detection, no renames, movable joints at 0, the size
/// cap [`DEFAULT_MAX_FILE_SIZE`], the built-in xacro expander).
#[derive(Debug, Clone)]
#[non_exhaustive]
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
    pub urdf_version: Option<UrdfVersion>,
    /// `--xacro external`: expand `.xacro` files with the external program
    /// instead of the built-in expander.
    pub xacro_external: bool,
    /// `--arg NAME=VALUE`: xacro `$(arg NAME)` values (override `xacro:arg`),
    /// and launch-file args (`$(arg NAME)`, `$(var NAME)`, conditions),
    /// overriding the defaults the file declares.
    pub xacro_args: BTreeMap<String, String>,
    /// `--package-path DIR`: where `$(find pkg)` looks first.
    pub package_paths: Vec<std::path::PathBuf>,
    /// `--confine DIR` (repeatable; empty: off): every file read, the files
    /// named on the command line and those a file includes (xacro includes,
    /// `xacro.load_yaml`, `$(find)` packages, rig TOML includes), must lie
    /// below one of these directories once symlinks are resolved; and xacro
    /// reads no environment variable (`$(env)` is refused, `$(optenv)` gives
    /// its default). For a CI gate on files from pull requests.
    pub confine: Vec<std::path::PathBuf>,
    /// Which topics of a bag are read (`--tf-static-topic`, `--tf-topic`,
    /// `--description-topic`).
    pub bag: BagOptions,
    /// `--rename [FILE:]OLD=NEW`: frames renamed as the files are loaded into
    /// one graph. Applied after the parser, which never sees them (the
    /// pipeline's `load`); one that matches no frame is an error there.
    pub renames: Vec<Rename>,
    /// `--assume DIRECTION[:PARENT,CHILD]`: the direction (and, for files that
    /// name none, the frames) of the transforms whose convention cannot be
    /// traced to the code that consumes the file; without it they are refused
    /// (see [`Assume`]).
    pub assume: Option<Assume>,
}

/// `--rename [FILE:]OLD=NEW`: a frame renamed as it is loaded.
#[derive(Debug, Clone, PartialEq)]
pub struct Rename {
    /// Only in files whose path ends with this (`None`: every file).
    pub file: Option<String>,
    /// The name in the file.
    pub old: String,
    /// The name to use.
    pub new: String,
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
            confine: Vec::new(),
            bag: BagOptions::default(),
            renames: Vec::new(),
            assume: None,
        }
    }
}

/// `--assume`: what the user says about a transform whose direction no
/// upstream code fixes (a plain 4x4 text file, OKVIS `imu_params.T_BS`, GLIM
/// `T_lidar_camera`, a `--key` whose name names no frames). A reader never
/// guesses such a direction: without `--assume` it refuses the transform,
/// naming this flag.
///
/// Written `child-in-parent` (the numbers are the pose of the child in the
/// parent, `p_parent = R p_child + t`) or `parent-in-child` (the inverse),
/// optionally followed by `:PARENT,CHILD`, the frames, for files that name
/// none (`--assume child-in-parent:base_link,lidar`). The edge is always
/// `PARENT -> CHILD`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Assume {
    /// The numbers are the pose of the child in the parent (else the inverse).
    pub child_in_parent: bool,
    /// `(parent, child)` when given.
    pub frames: Option<(String, String)>,
}

impl Assume {
    /// Parse `child-in-parent[:PARENT,CHILD]` / `parent-in-child[:PARENT,CHILD]`.
    pub fn parse(s: &str) -> std::result::Result<Assume, String> {
        let (dir, frames) = match s.split_once(':') {
            Some((d, f)) => (d, Some(f)),
            None => (s, None),
        };
        let child_in_parent = match dir.trim() {
            "child-in-parent" => true,
            "parent-in-child" => false,
            other => {
                return Err(format!(
                    "expected child-in-parent or parent-in-child (optionally :PARENT,CHILD), found {:?}",
                    crate::sanitize::clip(other)
                ))
            }
        };
        let frames = match frames {
            None => None,
            Some(f) => {
                let names: Vec<&str> = f.split(',').map(str::trim).collect();
                match names.as_slice() {
                    [p, c] if !p.is_empty() && !c.is_empty() && p != c => {
                        Some((p.to_string(), c.to_string()))
                    }
                    _ => {
                        return Err(format!(
                        "expected two different frame names after ':' (PARENT,CHILD), found {:?}",
                        crate::sanitize::clip(f)
                    ))
                    }
                }
            }
        };
        Ok(Assume {
            child_in_parent,
            frames,
        })
    }

    /// How it is written on the command line.
    pub fn flag(&self) -> String {
        let dir = if self.child_in_parent {
            "child-in-parent"
        } else {
            "parent-in-child"
        };
        match &self.frames {
            Some((p, c)) => format!("--assume {dir}:{p},{c}"),
            None => format!("--assume {dir}"),
        }
    }
}

impl LoadOptions {
    /// Whether reads are confined (`--confine`).
    pub fn confined(&self) -> bool {
        !self.confine.is_empty()
    }

    /// `Err(why)` when `--confine` is given and `path` (symlinks resolved;
    /// for a path that does not exist yet, its parent) is below none of its
    /// directories.
    pub fn check_confined(&self, path: &std::path::Path) -> std::result::Result<(), String> {
        if self.confine.is_empty() {
            return Ok(());
        }
        let real = std::fs::canonicalize(path).or_else(|e| {
            let parent = path.parent().filter(|p| !p.as_os_str().is_empty());
            match (parent, path.file_name()) {
                (Some(d), Some(n)) => std::fs::canonicalize(d).map(|d| d.join(n)),
                (None, Some(n)) => std::env::current_dir().map(|d| d.join(n)),
                _ => Err(e),
            }
        });
        let inside = |real: &std::path::Path| {
            self.confine
                .iter()
                .any(|c| std::fs::canonicalize(c).is_ok_and(|c| real.starts_with(c)))
        };
        match real {
            Ok(r) if inside(&r) => Ok(()),
            Ok(r) => Err(format!(
                "{} is outside the --confine directories ({}): not read",
                if r.as_path() == path {
                    path.display().to_string()
                } else {
                    format!("{} ({})", path.display(), r.display())
                },
                self.confine
                    .iter()
                    .map(|c| c.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
            Err(e) => Err(format!("{}: {e} (checking --confine)", path.display())),
        }
    }
}

/// Which topics of a bag to read (see `formats::bag`).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct BagOptions {
    /// Static transform topics (`tf2_msgs/TFMessage`): default `/tf_static`.
    pub static_topics: Vec<String>,
    /// Dynamic transform topics whose constant transforms are kept: default none
    /// (`/tf` on request).
    pub tf_topics: Vec<String>,
    /// Robot description topics (`std_msgs/String` with a URDF): default
    /// `/robot_description`.
    pub description_topics: Vec<String>,
    /// ROS 2 parameter event topics (`rcl_interfaces/msg/ParameterEvent`),
    /// searched for a string parameter `robot_description` (the way
    /// `robot_state_publisher` holds it): default `/parameter_events`.
    pub parameter_topics: Vec<String>,
}

impl Default for BagOptions {
    fn default() -> Self {
        BagOptions {
            static_topics: vec!["/tf_static".into()],
            tf_topics: Vec::new(),
            description_topics: vec!["/robot_description".into()],
            parameter_topics: vec!["/parameter_events".into()],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Confidence;

    #[test]
    fn confidence_levels_are_ordered_as_declared() {
        use Confidence::*;
        let levels = [
            Fallback, Keys, Extension, Lines, Markers, Commands, Names, Json, Claim, Document,
            Certain,
        ];
        assert!(levels.windows(2).all(|w| w[0] < w[1]));
    }
}
