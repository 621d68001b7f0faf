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

/// A tolerance as written on the command line: a number with its unit, or a
/// bare number (its option says which unit a bare number is in).
///
/// One convention for every tolerance of `check` and `diff` (issue 33:
/// `check` took metres, `diff` millimetres, and neither said it in the
/// value): lengths `m`, `cm`, `mm`; angles `deg`, `rad`, `mrad`; no space
/// needed (`5mm`, `0.5 deg`). Kept in the units the options hold: metres and
/// degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tolerance {
    /// A length (m).
    Length(f64),
    /// An angle (deg).
    Angle(f64),
    /// No unit written.
    Bare(f64),
}

/// The units a tolerance may carry, with their factor to metres or degrees.
const LENGTH_UNITS: [(&str, f64); 3] = [("mm", 1e-3), ("cm", 1e-2), ("m", 1.0)];
const ANGLE_UNITS: [(&str, f64); 3] = [
    ("mrad", 0.180 / std::f64::consts::PI),
    ("rad", 180.0 / std::f64::consts::PI),
    ("deg", 1.0),
];

/// `5mm`, `0.05deg`, `1e-3 m`, `2`: a non-negative finite tolerance.
pub fn parse_tolerance(s: &str) -> Result<Tolerance, String> {
    let t = s.trim();
    let split = |units: &[(&'static str, f64)]| {
        units.iter().find_map(|&(u, f)| {
            let num = t.strip_suffix(u)?.trim_end();
            (!num.is_empty() && !num.ends_with(|c: char| c.is_alphabetic())).then_some((num, f))
        })
    };
    let (kind, num, f) = if let Some((n, f)) = split(&LENGTH_UNITS) {
        (Tolerance::Length as fn(f64) -> Tolerance, n, f)
    } else if let Some((n, f)) = split(&ANGLE_UNITS) {
        (Tolerance::Angle as fn(f64) -> Tolerance, n, f)
    } else {
        (Tolerance::Bare as fn(f64) -> Tolerance, t, 1.0)
    };
    let v = parse_nonneg(num).map_err(|_| {
        format!("expected a non-negative number with an optional unit (m, cm, mm; deg, rad, mrad), found `{s}`")
    })?;
    Ok(kind(v * f))
}

impl Tolerance {
    /// As a length in metres; a bare number is in `bare_unit` metres (1 for
    /// metres, 1e-3 for millimetres).
    pub fn metres(self, bare_unit: f64) -> Result<f64, String> {
        match self {
            Tolerance::Length(m) => Ok(m),
            Tolerance::Bare(v) => Ok(v * bare_unit),
            Tolerance::Angle(_) => Err("expected a length (m, cm, mm), found an angle".into()),
        }
    }
    /// As an angle in degrees (a bare number is degrees).
    pub fn degrees(self) -> Result<f64, String> {
        match self {
            Tolerance::Angle(d) | Tolerance::Bare(d) => Ok(d),
            Tolerance::Length(_) => {
                Err("expected an angle (deg, rad, mrad), found a length".into())
            }
        }
    }
}

/// As written back (clap's defaults in `--help`): lengths in millimetres,
/// angles in degrees; [`parse_tolerance`] reads it back to the same value.
impl std::fmt::Display for Tolerance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Tolerance::Length(m) => write!(f, "{}mm", m * 1e3),
            Tolerance::Angle(d) => write!(f, "{d}deg"),
            Tolerance::Bare(v) => write!(f, "{v}"),
        }
    }
}

/// `LENGTH,ANGLE` (`5mm,0.5deg`; a bare length is millimetres, a bare
/// angle degrees) as the library's tolerance (mm, deg): `diff --tolerance`,
/// `spread --tolerance`, `check --fleet-tolerance`.
pub fn length_angle(
    flag: &str,
    v: &[Tolerance],
) -> extrinsic_audit::Result<extrinsic_audit::DiffToleranceJson> {
    let usage = |e: String| extrinsic_audit::Error::usage(format!("{flag}{e}"));
    let [length, angle] = v[..] else {
        return Err(usage(format!(
            ": expected LENGTH,ANGLE (two values, e.g. 1mm,0.05deg), found {} value(s)",
            v.len()
        )));
    };
    let mm = length
        .metres(1e-3)
        .map_err(|e| usage(format!(" translation: {e}")))?
        * 1e3;
    let deg = angle
        .degrees()
        .map_err(|e| usage(format!(" rotation: {e}")))?;
    Ok(extrinsic_audit::DiffToleranceJson {
        translation_mm: mm,
        rotation_deg: deg,
    })
}

/// A length tolerance whose bare number is metres (`check`): always a
/// [`Tolerance::Length`], so that `--help` shows its default with its unit.
pub fn parse_length_m(s: &str) -> Result<Tolerance, String> {
    parse_tolerance(s)?.metres(1.0).map(Tolerance::Length)
}

/// A positive length whose bare number is metres (`check --max-lever-arm`).
pub fn parse_positive_length_m(s: &str) -> Result<f64, String> {
    match parse_length_m(s)? {
        Tolerance::Length(v) if v > 0.0 => Ok(v),
        _ => Err(format!("expected a positive length, found `{s}`")),
    }
}

/// An angle tolerance whose bare number is degrees: always a
/// [`Tolerance::Angle`].
pub fn parse_angle_deg(s: &str) -> Result<Tolerance, String> {
    parse_tolerance(s)?.degrees().map(Tolerance::Angle)
}

impl Tolerance {
    /// The number in the unit its kind is kept in (metres, degrees).
    pub fn value(self) -> f64 {
        match self {
            Tolerance::Length(v) | Tolerance::Angle(v) | Tolerance::Bare(v) => v,
        }
    }
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

#[cfg(test)]
mod tolerance_tests {
    use super::*;

    #[test]
    fn tolerances_read_their_units() {
        let t = |s| parse_tolerance(s).unwrap();
        assert_eq!(t("5mm"), Tolerance::Length(5e-3));
        assert_eq!(t(" 0.5 cm"), Tolerance::Length(5e-3));
        assert_eq!(t("0.001m"), Tolerance::Length(1e-3));
        assert_eq!(t("0.05deg"), Tolerance::Angle(0.05));
        assert_eq!(t("2"), Tolerance::Bare(2.0));
        for one_mrad in ["1mrad", "1e-3rad", "0.001 rad"] {
            let Tolerance::Angle(d) = t(one_mrad) else {
                panic!("{one_mrad}")
            };
            assert!((d - 0.057_295_779_5).abs() < 1e-9, "{one_mrad}: {d}");
        }
        assert_eq!(parse_length_m("1mm"), Ok(Tolerance::Length(1e-3)));
        assert_eq!(parse_length_m("0.001"), Ok(Tolerance::Length(1e-3)));
        assert_eq!(parse_angle_deg("0.05"), Ok(Tolerance::Angle(0.05)));
        // Each default is shown with its unit and reads back to itself.
        for t in [Tolerance::Length(1e-3), Tolerance::Angle(0.05)] {
            assert_eq!(parse_tolerance(&t.to_string()), Ok(t), "{t}");
        }
        assert!(parse_length_m("1deg").is_err());
        assert!(parse_angle_deg("5mm").is_err());
        for bad in ["", "mm", "-1mm", "1 km", "1mmm", "inf", "1e400m", "nan deg"] {
            assert!(parse_tolerance(bad).is_err(), "{bad:?}");
        }
    }
}
