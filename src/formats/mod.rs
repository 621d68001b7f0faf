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
//!
//! Layout, each layer importing only those below it:
//! - [`spec`], the contract (a leaf): `FormatSpec`, `Confidence`, `Input`
//!   (the bytes, the text on demand, the facts sniffers share),
//!   `LoadOptions`, `Parsed`;
//! - readers shared by several formats: `yaml`, `yaml_shapes` (the transform
//!   shapes of YAML and JSON), `yaml_keyed` (`--key`, the YAML dialects'
//!   spec), `json`, `xml`, `source`, `shell`, `launch_subst`, `arrow_ipc`;
//! - one module per format (or family of dialects), each with its sniffer and
//!   its `FormatSpec`, importing the contract and those readers only (xacro
//!   and bags read URDF too);
//! - [`registry`], the list of formats and detection; then `load`
//!   ([`load_file`], [`load_bytes`], [`load_str`]: detection, parser, the
//!   common checks).

pub mod apollo;
pub mod arrow_ipc;
pub mod autoware;
pub mod av2;
pub mod bag;
pub mod basalt;
pub(crate) mod calib_shapes;
pub mod euroc;
pub mod fast_livo;
pub mod glim;
pub(crate) mod json;
pub mod kitti_m2dgr;
pub mod kitti_object;
pub mod las;
pub mod launch;
pub(crate) mod launch_eval;
pub mod launch_py;
pub mod launch_subst;
pub mod lio_yaml;
pub mod livox_driver2;
mod load;
pub mod matrix_text;
pub mod matrix_tree;
pub mod nuscenes;
pub mod okvis;
pub mod opencalib;
pub mod orb_slam3;
pub mod ouster;
pub mod ouster_extrinsics;
pub(crate) mod pyexpr;
pub mod r3live;
pub mod registry;
pub mod rig_toml;
pub mod shell;
pub mod source;
pub mod spec;
#[cfg(test)]
mod test_edits;
mod toml_subset;
// TODO(issue 10): urdf/mod.rs links to its private `read` and `joints`.
pub mod urdf;
pub mod xacro;
pub mod xml;
pub mod yaml;
pub mod yaml_dialects;
pub(crate) mod yaml_keyed;
mod yaml_node;
pub(crate) mod yaml_shapes;
mod yaml_subset;

pub(crate) use load::load_opened;
pub use load::{detect_file, detect_format, load_bytes, load_file, load_str};
pub use registry::{all_formats, is_calibration_file, FORMATS};
pub use spec::{Assume, BagOptions, Format, LoadOptions, Parsed, Rename, RigMeta, UrdfVersion};
