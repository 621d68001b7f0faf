//! `audit FILE... --from A --to B`: the rig report.

use super::{
    emit_warned, parse_ell, parse_joint, parse_kappa, parse_lambda, parse_sigma_r, parse_sigma_t,
    print_warnings,
};
use clap::{Args, ValueEnum};
use extrinsic_audit::diagnostic::{Code, Error, Result, Warning};
use extrinsic_audit::formats::bag::BagOptions;
use extrinsic_audit::formats::{Format, LoadOptions};
use extrinsic_audit::geometry::PitchTol;
use extrinsic_audit::pipeline::{self, Rename, RigOptions};
use extrinsic_audit::render::OutputFormat;
use extrinsic_audit::tolerances::{DEFAULT_ELLS, DEFAULT_MAX_FILE_SIZE};
use std::io::Write;
use std::path::PathBuf;

#[derive(Debug, Args, Clone)]
pub struct AuditArgs {
    /// Files to load into one frame graph (URDF, launch, tf_static dump, YAML, JSON, TOML rig)
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Parent frame: the transform printed is the pose of --to in --from
    #[arg(long, value_name = "FRAME")]
    pub from: Option<String>,
    /// Child frame (e.g. the LiDAR)
    #[arg(long, value_name = "FRAME")]
    pub to: Option<String>,
    /// List the frames and edges the files yield (with file:line), then exit;
    /// --format text, json, dot, mermaid, markdown or svg draws the tree, and
    /// --from/--to highlight their chain
    #[arg(long)]
    pub frames: bool,
    /// Characteristic lengths (m) for the certificate bands
    #[arg(long, value_delimiter = ',', default_values_t = DEFAULT_ELLS, value_parser = parse_ell, allow_hyphen_values = true, value_name = "M,...")]
    pub ell: Vec<f64>,
    /// Detector threshold kappa: with --lambda, does the band certify that lambda cannot cross kappa?
    #[arg(long, requires = "lambda", value_parser = parse_kappa, allow_hyphen_values = true)]
    pub kappa: Option<f64>,
    /// Detector eigenvalue lambda (see --kappa)
    #[arg(long, requires = "kappa", value_parser = parse_lambda, allow_hyphen_values = true)]
    pub lambda: Option<f64>,
    /// Zero-pitch tolerance: `auto` (zero within 3 standard uncertainties of h, the
    /// rounding of the numbers as written plus --sigma-t/--sigma-r) or |h| in m
    #[arg(long, default_value = "auto", value_name = "auto|M")]
    pub pitch_tol: PitchTol,
    /// The calibration's standard uncertainty per edge, translation (m), added to
    /// the rounding of the numbers as written (a rig TOML's own value wins)
    #[arg(long, value_parser = parse_sigma_t, value_name = "M")]
    pub sigma_t: Option<f64>,
    /// The same for rotation (degrees)
    #[arg(long, value_parser = parse_sigma_r, value_name = "DEG")]
    pub sigma_r: Option<f64>,
    /// Set a movable joint's position (rad or m); repeatable
    #[arg(long = "joint", value_parser = parse_joint, value_name = "NAME=VALUE")]
    pub joints: Vec<(String, f64)>,
    /// Rename a frame as it is loaded, in every file or only in FILE (e.g.
    /// `fast_lio.yaml:imu=imu_link` to attach a FAST-LIO extrinsic to a URDF); repeatable
    #[arg(long = "rename", value_parser = parse_rename, value_name = "[FILE:]OLD=NEW")]
    pub renames: Vec<Rename>,
    /// Read only this key of a YAML/JSON file (e.g. T_imu_lidar)
    #[arg(long, value_name = "NAME")]
    pub key: Option<String>,
    /// The file stores the other direction: invert its transforms
    #[arg(long)]
    pub invert: bool,
    /// Skip format detection (see the README's formats table)
    #[arg(long, value_name = "NAME")]
    pub input_format: Option<String>,
    /// Read every URDF as this version (1.0, 1.1 or 1.2) whatever its <robot version>
    /// says: 1.1 applies quat_xyzw, which ROS ignores in a 1.0 file
    #[arg(long, value_name = "X.Y")]
    pub urdf_version: Option<extrinsic_audit::formats::urdf::UrdfVersion>,
    /// Refuse input files larger than this many bytes
    #[arg(long, default_value_t = DEFAULT_MAX_FILE_SIZE, value_name = "BYTES")]
    pub max_file_size: u64,
    /// Output format (dot, mermaid and svg only with --frames)
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
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
    /// Every warning is an error (exit 2 after printing them): for CI runs
    /// that must not pass with a joint outside its limits or a value that
    /// looks like degrees
    #[arg(long, alias = "deny-warnings")]
    pub strict: bool,
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

/// `--xacro native|external`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum XacroMode {
    Native,
    External,
}

/// `--arg NAME=VALUE` (the value is text, as `xacro NAME:=VALUE` takes it).
pub(super) fn parse_xacro_arg(s: &str) -> std::result::Result<(String, String), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=VALUE, found `{s}`"))?;
    let name = name.trim().trim_end_matches(':');
    if name.is_empty() {
        return Err(format!("expected NAME=VALUE, found `{s}`"));
    }
    Ok((name.to_string(), value.to_string()))
}

impl AuditArgs {
    /// How the files are read.
    pub fn load_options(&self) -> Result<LoadOptions> {
        let format = match &self.input_format {
            None => None,
            Some(name) => Some(Format::from_name(name)?),
        };
        Ok(LoadOptions {
            joints: self.joints.iter().cloned().collect(),
            key: self.key.clone(),
            invert: self.invert,
            format,
            max_file_size: self.max_file_size,
            urdf_version: self.urdf_version,
            xacro_args: self.xacro_args.iter().cloned().collect(),
            package_paths: self.package_paths.clone(),
            xacro_external: self.xacro_mode == XacroMode::External,
            bag: self.bag_options(),
            ..LoadOptions::default()
        })
    }
}

impl AuditArgs {
    /// The bag topics: each list given replaces its default.
    fn bag_options(&self) -> BagOptions {
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

/// `--rename [FILE:]OLD=NEW`.
pub fn parse_rename(s: &str) -> std::result::Result<Rename, String> {
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

/// `--strict`: the warnings just printed stop the command.
fn deny_warnings(strict: bool, warnings: &[Warning]) -> Result<()> {
    if !strict || warnings.is_empty() {
        return Ok(());
    }
    let mut codes: Vec<&str> = warnings.iter().map(|w| w.code.name()).collect();
    codes.sort_unstable();
    codes.dedup();
    Err(Error::new(
        Code::WarningsDenied,
        format!(
            "--strict: expected no warnings, found {} ({})",
            warnings.len(),
            codes.join(", ")
        ),
    ))
}

pub fn run(args: &AuditArgs, out: &mut dyn Write) -> Result<i32> {
    let loaded = pipeline::load(&args.files, &args.load_options()?, &args.renames)?;
    print_warnings(loaded.graph.warnings());
    super::print_notes(loaded.graph.notes());
    deny_warnings(args.strict, loaded.graph.warnings())?;
    loaded.check_joint_names(args.joints.iter().map(|(n, _)| n.as_str()))?;
    if args.frames {
        return super::frames::run(
            &loaded,
            args.from.as_deref(),
            args.to.as_deref(),
            args.format,
            out,
        );
    }
    let (from, to) = loaded.frame_pair(args.from.as_deref(), args.to.as_deref())?;
    let chain = loaded.graph.transform(&from, &to)?;
    print_warnings(&chain.warnings);
    super::print_notes(&chain.notes);
    deny_warnings(args.strict, &chain.warnings)?;
    let opts = RigOptions {
        ells: args.ell.clone(),
        pitch_tol: args.pitch_tol,
        sigma: super::user_sigma(args.sigma_t, args.sigma_r),
        kappa_lambda: args.kappa.zip(args.lambda),
    };
    let warnings: Vec<_> = loaded
        .graph
        .warnings()
        .iter()
        .chain(&chain.warnings)
        .cloned()
        .collect();
    emit_warned(
        &pipeline::report(&chain, &opts)?,
        &warnings,
        args.format,
        out,
    )?;
    Ok(0)
}
