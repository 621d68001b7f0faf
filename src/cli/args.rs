//! The flags several commands share: one struct per group, declared once here
//! and flattened (`#[command(flatten)]`) into each command it applies to, with
//! what the group gives the library (a `LoadOptions` field, a `UserSigma`).
//! Then the value parsers clap calls for single values; their messages follow
//! clap's `invalid value '...' for '--flag'`. Values the library checks in
//! context (`x,y,z`, lists, flag combinations) are parsed by the library.

use clap::{Args, ValueEnum};
use extrinsic_audit::internals::tolerances::{
    DEFAULT_ELLS, DEFAULT_MAX_FILE_SIZE, DEFAULT_TAU, ELL_RANGE_M, KAPPA_RANGE, MAX_JOINT_VALUE,
    MAX_SIGMA_R_DEG, MAX_SIGMA_T_M, MAX_SIM_NOISE_M, SIM_VOXEL_RANGE_M,
};
use extrinsic_audit::{Assume, BagOptions, LoadOptions, OutputFormat, PitchTol, Rename, UserSigma};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// `--format`, `--output`: what every command writes, and where.
#[derive(Debug, Args, Clone)]
pub struct OutputArgs {
    /// Output format (dot, mermaid and svg draw the frame tree, `audit FILE...
    /// --frames`; mcap writes the 3D scene for Foxglove)
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
    /// Write the output to FILE instead of standard output (replaced
    /// atomically; never one of the command's inputs)
    #[arg(long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

/// `--ell`: the characteristic lengths.
#[derive(Debug, Args, Clone)]
pub struct EllArgs {
    /// Characteristic lengths l (m), comma-separated (the certificate bands;
    /// the characteristic length family)
    #[arg(long, value_delimiter = ',', default_values_t = DEFAULT_ELLS, value_parser = parse_ell, allow_hyphen_values = true, value_name = "M,...")]
    pub ell: Vec<f64>,
}

/// `--tau`: the detector's threshold.
#[derive(Debug, Args, Clone)]
pub struct TauArgs {
    /// Point-displacement threshold: an eigenvalue below it is degenerate
    /// (baselines use their calibrated thresholds).
    #[arg(long, default_value_t = DEFAULT_TAU, value_parser = parse_positive, allow_hyphen_values = true)]
    pub tau: f64,
}

/// `--pitch-tol`: when the screw pitch counts as zero.
#[derive(Debug, Args, Clone)]
pub struct PitchTolArgs {
    /// Zero-pitch tolerance: `auto` (three-way: zero within 3 standard
    /// uncertainties of h, from the rounding of the numbers as written plus
    /// --sigma-t/--sigma-r where given) or |h| in m
    #[arg(long, default_value = "auto", value_name = "auto|M")]
    pub pitch_tol: PitchTol,
}

/// `--sigma-t`, `--sigma-r`: the user's calibration uncertainty.
#[derive(Debug, Args, Clone)]
pub struct SigmaArgs {
    /// The calibration's standard uncertainty per edge, translation (m), added to
    /// the rounding of the numbers as written (a rig TOML's own value wins)
    #[arg(long, value_parser = parse_sigma_t, value_name = "M")]
    pub sigma_t: Option<f64>,
    /// The same for rotation (degrees)
    #[arg(long, value_parser = parse_sigma_r, value_name = "DEG")]
    pub sigma_r: Option<f64>,
}

impl SigmaArgs {
    /// One user uncertainty (`None`: neither given).
    pub fn user_sigma(&self) -> Option<UserSigma> {
        (self.sigma_t.is_some() || self.sigma_r.is_some()).then(|| UserSigma {
            sigma_t_m: self.sigma_t.unwrap_or(0.0),
            sigma_r_rad: self.sigma_r.unwrap_or(0.0).to_radians(),
        })
    }
}

/// `--joint`: movable joints' positions.
#[derive(Debug, Args, Clone)]
pub struct JointArgs {
    /// Set a movable joint's position (rad or m) in every file read; repeatable
    #[arg(long = "joint", value_parser = parse_joint, value_name = "NAME=VALUE")]
    pub joints: Vec<(String, f64)>,
}

impl JointArgs {
    /// The positions by joint name (`LoadOptions::joints`).
    pub fn positions(&self) -> BTreeMap<String, f64> {
        self.joints.iter().cloned().collect()
    }
}

/// `--rename`: frames renamed as files load.
#[derive(Debug, Args, Clone)]
pub struct RenameArgs {
    /// Rename a frame as it is loaded, in every file or only in FILE (e.g.
    /// `fast_lio.yaml:imu=imu_link` to attach a FAST-LIO extrinsic to a URDF); repeatable
    #[arg(long = "rename", value_parser = parse_rename, value_name = "[FILE:]OLD=NEW")]
    pub renames: Vec<Rename>,
}

/// `--key`, `--invert`: which transform of a file, in which direction.
#[derive(Debug, Args, Clone)]
pub struct ReadArgs {
    /// Read only this key of each YAML/JSON file (one of several transforms,
    /// e.g. T_imu_lidar)
    #[arg(long, value_name = "NAME")]
    pub key: Option<String>,
    /// The files store the other direction (the pose of the parent in the
    /// child): invert their transforms as they are read (`audit survey` keeps
    /// a rig TOML's own)
    #[arg(long)]
    pub invert: bool,
    /// The direction of transforms no upstream code fixes (a plain 4x4 text
    /// file, OKVIS imu_params.T_BS, GLIM T_lidar_camera, a --key that names no
    /// frames), refused without it: child-in-parent or parent-in-child, with
    /// :PARENT,CHILD for files that name no frames (e.g.
    /// child-in-parent:base_link,lidar: the numbers are the pose of lidar in
    /// base_link)
    #[arg(long, value_parser = parse_assume, value_name = "DIRECTION[:PARENT,CHILD]")]
    pub assume: Option<Assume>,
}

impl ReadArgs {
    /// These options in `load`.
    pub fn apply(&self, load: &mut LoadOptions) {
        load.key = self.key.clone();
        load.invert = self.invert;
        load.assume = self.assume.clone();
    }
}

/// `--assume`: parsed by the library (`formats::Assume::parse`).
fn parse_assume(s: &str) -> Result<Assume, String> {
    Assume::parse(s)
}

/// `--max-file-size`: the cap on every input file.
#[derive(Debug, Args, Clone)]
pub struct FileSizeArgs {
    /// Refuse input files larger than this many bytes
    #[arg(long, default_value_t = DEFAULT_MAX_FILE_SIZE, value_name = "BYTES")]
    pub max_file_size: u64,
}

/// `--arg`, `--package-path`, `--xacro`, `--confine`: how xacro (and launch)
/// files expand, and where reads may go.
#[derive(Debug, Args, Clone)]
pub struct XacroArgs {
    /// xacro and launch-file `$(arg NAME)` value (also `if="$(arg NAME)"` in a
    /// launch file), overriding the file's default; repeatable
    #[arg(long = "arg", value_parser = parse_xacro_arg, value_name = "NAME=VALUE")]
    pub xacro_args: Vec<(String, String)>,
    /// Where xacro `$(find pkg)` looks first: a package directory or a directory
    /// holding packages; repeatable
    #[arg(long = "package-path", value_name = "DIR")]
    pub package_paths: Vec<PathBuf>,
    /// How .xacro files are expanded: `native` (built in) or `external` (the
    /// `xacro` program on PATH)
    #[arg(long = "xacro", value_enum, default_value_t = XacroMode::Native)]
    pub xacro_mode: XacroMode,
    /// Read only files below DIR (symlinks resolved): the inputs, xacro
    /// includes, load_yaml files, $(find) packages, rig TOML includes; xacro
    /// reads no environment variable. For CI on pull requests; repeatable
    #[arg(long = "confine", value_name = "DIR", value_parser = parse_confine)]
    pub confine: Vec<PathBuf>,
}

/// `--confine DIR`: an existing directory.
fn parse_confine(s: &str) -> Result<PathBuf, String> {
    let p = PathBuf::from(s);
    if !p.is_dir() {
        return Err(format!("expected an existing directory, found `{s}`"));
    }
    Ok(p)
}

/// `--xacro native|external`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum XacroMode {
    Native,
    External,
}

impl XacroArgs {
    /// These options in `load`.
    pub fn apply(&self, load: &mut LoadOptions) {
        load.xacro_args = self.xacro_args.iter().cloned().collect();
        load.package_paths = self.package_paths.clone();
        load.xacro_external = self.xacro_mode == XacroMode::External;
        load.confine = self.confine.clone();
    }
}

/// The topics a bag is read from.
#[derive(Debug, Args, Clone)]
pub struct BagArgs {
    /// Bags: a static transform topic (tf2_msgs/TFMessage, named as recorded)
    /// to read instead of /tf_static; repeatable
    #[arg(long = "tf-static-topic", value_name = "TOPIC")]
    pub tf_static_topics: Vec<String>,
    /// Bags: also read this dynamic topic (e.g. /tf), keeping the transforms
    /// that never change over the bag; repeatable
    #[arg(long = "tf-topic", value_name = "TOPIC")]
    pub tf_topics: Vec<String>,
    /// Bags: a std_msgs/String topic holding the URDF, instead of
    /// /robot_description; repeatable
    #[arg(long = "description-topic", value_name = "TOPIC")]
    pub description_topics: Vec<String>,
}

impl BagArgs {
    /// The bag topics: each list given replaces its default.
    pub fn bag_options(&self) -> BagOptions {
        let mut b = BagOptions::default();
        if !self.tf_static_topics.is_empty() {
            b.static_topics = self.tf_static_topics.clone();
        }
        b.tf_topics = self.tf_topics.clone();
        if !self.description_topics.is_empty() {
            b.description_topics = self.description_topics.clone();
        }
        b
    }
}

/// `NAME=VALUE` for `--joint`.
pub fn parse_joint(s: &str) -> Result<(String, f64), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=VALUE, found `{s}`"))?;
    let v: f64 = value
        .trim()
        .parse()
        .map_err(|_| format!("joint `{name}`: expected a number, found `{value}`"))?;
    if !(v.is_finite() && v.abs() <= MAX_JOINT_VALUE) {
        return Err(format!(
            "joint `{name}`: expected a finite number of at most {MAX_JOINT_VALUE:e} in magnitude (rad or m), found `{value}`"
        ));
    }
    Ok((name.trim().to_string(), v))
}

/// `--arg NAME=VALUE` (the value is text, as `xacro NAME:=VALUE` takes it).
pub fn parse_xacro_arg(s: &str) -> Result<(String, String), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=VALUE, found `{s}`"))?;
    let name = name.trim().trim_end_matches(':');
    if name.is_empty() {
        return Err(format!("expected NAME=VALUE, found `{s}`"));
    }
    Ok((name.to_string(), value.to_string()))
}

/// `--rename [FILE:]OLD=NEW`.
pub fn parse_rename(s: &str) -> Result<Rename, String> {
    let (lhs, new) = s
        .rsplit_once('=')
        .ok_or_else(|| format!("expected [FILE:]OLD=NEW, found `{s}`"))?;
    let (file, old) = match lhs.rsplit_once(':') {
        Some((f, o)) => (Some(f.to_string()), o),
        None => (None, lhs),
    };
    if old.is_empty() || new.is_empty() || file.as_deref() == Some("") {
        return Err(format!(
            "expected [FILE:]OLD=NEW with non-empty names, found `{s}`"
        ));
    }
    Ok(Rename {
        file,
        old: old.to_string(),
        new: new.to_string(),
    })
}

/// A number as written, or the message clap prints after the flag.
fn number(s: &str) -> Result<f64, String> {
    s.trim()
        .parse()
        .map_err(|_| format!("expected a number, found `{s}`"))
}

/// A finite number in `[lo, hi]` (the option's name is added by clap).
fn parse_in(s: &str, lo: f64, hi: f64, unit: &str) -> Result<f64, String> {
    let v = number(s)?;
    if !(v.is_finite() && (lo..=hi).contains(&v)) {
        let (lo, hi) = (short(lo), short(hi));
        return Err(format!(
            "expected a finite number from {lo} to {hi}{unit}, found `{s}`"
        ));
    }
    Ok(v)
}

/// A bound as people write it: `0.02`, `1e-100`.
fn short(x: f64) -> String {
    if x == 0.0 || (1e-3..1e4).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `--ell`: a characteristic length in [`ELL_RANGE_M`].
pub fn parse_ell(s: &str) -> Result<f64, String> {
    parse_in(s, ELL_RANGE_M.0, ELL_RANGE_M.1, " m")
}

/// `--kappa`: a detector threshold in [`KAPPA_RANGE`].
pub fn parse_kappa(s: &str) -> Result<f64, String> {
    parse_in(s, KAPPA_RANGE.0, KAPPA_RANGE.1, "")
}

/// `--lambda`: an eigenvalue, 0 to the top of [`KAPPA_RANGE`].
pub fn parse_lambda(s: &str) -> Result<f64, String> {
    parse_in(s, 0.0, KAPPA_RANGE.1, "")
}

/// `--noise` of `simulate`: 0 to [`MAX_SIM_NOISE_M`].
pub fn parse_noise(s: &str) -> Result<f64, String> {
    parse_in(s, 0.0, MAX_SIM_NOISE_M, " m")
}

/// `--voxel` of `simulate`: in [`SIM_VOXEL_RANGE_M`].
pub fn parse_voxel(s: &str) -> Result<f64, String> {
    parse_in(s, SIM_VOXEL_RANGE_M.0, SIM_VOXEL_RANGE_M.1, " m")
}

/// A positive, finite number (`--tau`, `--max-lever-arm`, `--gate`, ...).
pub fn parse_positive(s: &str) -> Result<f64, String> {
    let v = number(s)?;
    if !(v.is_finite() && v > 0.0) {
        return Err(format!("expected a positive finite number, found `{s}`"));
    }
    Ok(v)
}

/// A non-negative, finite number (drift and diff tolerances).
pub fn parse_nonneg(s: &str) -> Result<f64, String> {
    let v = number(s)?;
    if !(v.is_finite() && v >= 0.0) {
        return Err(format!(
            "expected a non-negative finite number, found `{s}`"
        ));
    }
    Ok(v)
}

/// `--sigma-t M`: a calibration's standard uncertainty per edge (m).
fn parse_sigma_t(s: &str) -> Result<f64, String> {
    let v = parse_nonneg(s)?;
    if v > MAX_SIGMA_T_M {
        return Err(format!("expected at most {MAX_SIGMA_T_M} m, found `{s}`"));
    }
    Ok(v)
}

/// `--sigma-r DEG`: a calibration's standard uncertainty per edge (degrees).
fn parse_sigma_r(s: &str) -> Result<f64, String> {
    let v = parse_nonneg(s)?;
    if v > MAX_SIGMA_R_DEG {
        return Err(format!(
            "expected at most {MAX_SIGMA_R_DEG} deg, found `{s}`"
        ));
    }
    Ok(v)
}
