//! `audit check PATHS...`: CI checks on calibration files.
//!
//! Per file: it parses; rotations are orthonormal, quaternions unit, units
//! plausible (the loaders' named warnings for these are findings here); the
//! frames it references exist and connect. Against a baseline: no edge or declared
//! frame pair drifted beyond the tolerances, none appeared or vanished, and no
//! verdict (screw kind, zero pitch, adapted metric) changed.
//!
//! Exit 0 when clean, 1 when a finding of severity `error` was made, 2 on usage
//! errors or unreadable input (a path that does not exist, an unreadable
//! baseline). A file that exists but does not parse is a finding (1).

use super::audit::io_err;
use super::{expand_paths, parse_nonneg, parse_positive, write_atomic};
use crate::diagnostic::{Error, ErrorKind, Result, Warning, WarningCode};
use crate::formats::{self, Edge, LoadOptions};
use crate::frames::FrameGraph;
use crate::geometry::se3::Transform;
use crate::report;
use crate::tolerances::{
    DEFAULT_MAX_FILE_SIZE, DEFAULT_MAX_ROTATION_DRIFT_DEG, DEFAULT_MAX_TRANSLATION_DRIFT,
};
use clap::{Args, ValueEnum};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum CheckFormat {
    #[default]
    Text,
    Json,
    Github,
}

#[derive(Debug, Args, Clone)]
#[command(
    long_about = "Checks calibration files in CI: every file parses; rotations are orthonormal; \
quaternions are unit; units are plausible (no millimetres in a metre field); the frames each \
rig declares, and every --pair, exist and connect. With --baseline: no transform drifted by more \
than the tolerances, none appeared or disappeared, and no verdict (screw kind, zero pitch, \
adapted metric) changed.\n\nExit codes: 0 clean, 1 problems found, 2 usage error or unreadable input.",
    after_long_help = "Examples:\n  audit check calibrations/\n  audit check calibrations/ --write-baseline calibrations/baseline.json\n  audit check calibrations/ --baseline calibrations/baseline.json --format github\n  audit check robot.urdf --pair base_link:lidar --max-lever-arm 0.5 --require-zero-pitch\n  audit check calibrations/ --allow non-orthonormal-rotation"
)]
pub struct CheckArgs {
    /// Calibration files or directories of them
    #[arg(required = true, value_name = "PATH")]
    pub paths: Vec<PathBuf>,
    /// Compare against this baseline (written earlier with --write-baseline)
    #[arg(long, value_name = "FILE")]
    pub baseline: Option<PathBuf>,
    /// Write the current state as a baseline (atomically: temporary file, then rename)
    #[arg(long, value_name = "FILE")]
    pub write_baseline: Option<PathBuf>,
    /// Also check this frame pair wherever both frames exist (FROM:TO); repeatable
    #[arg(long = "pair", value_parser = parse_pair, value_name = "FROM:TO")]
    pub pairs: Vec<(String, String)>,
    /// A problem when a checked pair's lever arm exceeds this (m)
    #[arg(long, value_parser = parse_positive, value_name = "M")]
    pub max_lever_arm: Option<f64>,
    /// A problem when a checked pair does not have zero screw pitch
    #[arg(long)]
    pub require_zero_pitch: bool,
    /// Drift tolerance on translations against the baseline (m)
    #[arg(long, default_value_t = DEFAULT_MAX_TRANSLATION_DRIFT, value_parser = parse_nonneg, value_name = "M")]
    pub max_translation_drift: f64,
    /// Drift tolerance on rotations against the baseline (deg)
    #[arg(long, default_value_t = DEFAULT_MAX_ROTATION_DRIFT_DEG, value_parser = parse_nonneg, value_name = "DEG")]
    pub max_rotation_drift: f64,
    /// Zero-pitch tolerance on |h| (m)
    #[arg(long, default_value_t = crate::tolerances::DEFAULT_PITCH_TOL, value_parser = parse_nonneg, value_name = "M")]
    pub pitch_tol: f64,
    /// Set a movable joint's position (rad or m); repeatable
    #[arg(long = "joint", value_parser = super::parse_joint, value_name = "NAME=VALUE")]
    pub joints: Vec<(String, f64)>,
    /// Accept this named warning (e.g. non-orthonormal-rotation for published
    /// numbers rounded to a few digits): reported, but not a problem; repeatable
    #[arg(long = "allow", value_name = "WARNING", value_parser = parse_warning_code)]
    pub allow: Vec<WarningCode>,
    /// Refuse (as a problem) calibration files larger than this
    #[arg(long, default_value_t = DEFAULT_MAX_FILE_SIZE, value_name = "BYTES")]
    pub max_file_size: u64,
    /// Output format (github: workflow-command annotations)
    #[arg(long, value_enum, default_value_t = CheckFormat::Text)]
    pub format: CheckFormat,
}

/// The checked files for a message: all of them up to 5, then a count.
fn checked_list(files: &[PathBuf]) -> String {
    let mut v: Vec<String> = files
        .iter()
        .take(5)
        .map(|f| f.display().to_string())
        .collect();
    if files.len() > 5 {
        v.push(format!("and {} more", files.len() - 5));
    }
    v.join(", ")
}

fn parse_warning_code(s: &str) -> std::result::Result<WarningCode, String> {
    WarningCode::ALL
        .iter()
        .copied()
        .find(|c| c.name() == s)
        .ok_or_else(|| {
            format!(
                "expected a warning name ({}), found `{s}`",
                WarningCode::ALL
                    .iter()
                    .map(|c| c.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })
}

fn parse_pair(s: &str) -> std::result::Result<(String, String), String> {
    match s.split_once(':') {
        Some((a, b)) if !a.is_empty() && !b.is_empty() => Ok((a.to_string(), b.to_string())),
        _ => Err(format!("expected FROM:TO, found `{s}`")),
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, PartialOrd, Ord)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Error,
    Warning,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Finding {
    pub severity: Severity,
    /// Stable name, e.g. `parse`, `non-unit-quaternion`, `drift`, `verdict-changed`.
    pub code: String,
    pub file: String,
    pub line: Option<usize>,
    pub message: String,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CheckJson {
    pub schema_version: u32,
    pub files_checked: usize,
    pub problems: usize,
    pub warnings: usize,
    pub findings: Vec<Finding>,
}

/// A baseline: per file, its edges and its checked pairs.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, Default)]
pub struct Baseline {
    pub schema_version: u32,
    pub files: BTreeMap<String, BaselineFile>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, Default)]
pub struct BaselineFile {
    pub edges: Vec<BaselineTransform>,
    pub pairs: Vec<BaselinePair>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct BaselineTransform {
    pub parent: String,
    pub child: String,
    pub translation_m: [f64; 3],
    pub quaternion_xyzw: [f64; 4],
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct BaselinePair {
    #[serde(flatten)]
    pub transform: BaselineTransform,
    pub lever_arm_m: f64,
    pub screw_kind: String,
    pub zero_pitch: bool,
    pub adapted_metric_exists: bool,
}

/// Files the checker reads from a directory.
fn is_calibration_file(p: &Path) -> bool {
    let name = p
        .file_name()
        .map(|n| n.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    if name.starts_with('.') {
        return false;
    }
    [
        ".urdf",
        ".xacro",
        ".launch",
        ".xml",
        ".yaml",
        ".yml",
        ".json",
        ".toml",
        ".txt",
        ".launch.py",
    ]
    .iter()
    .any(|ext| name.ends_with(ext))
        || crate::formats::bag::is_bag(p)
}

fn key_of(p: &Path) -> String {
    p.to_string_lossy().replace('\\', "/")
}

/// Warnings that are findings in a check (the input is suspicious, not just noted).
fn warning_is_problem(code: WarningCode) -> bool {
    matches!(
        code,
        WarningCode::NonOrthonormalRotation
            | WarningCode::NonUnitQuaternion
            | WarningCode::MillimetresInMetreField
    )
}

struct Checker<'a> {
    args: &'a CheckArgs,
    findings: Vec<Finding>,
}

impl Checker<'_> {
    fn push(
        &mut self,
        severity: Severity,
        code: &str,
        file: &str,
        line: Option<usize>,
        message: String,
    ) {
        self.findings.push(Finding {
            severity,
            code: code.to_string(),
            file: file.to_string(),
            line,
            message,
        });
    }

    fn push_error(&mut self, file: &str, e: &Error) {
        let line = e.location.line;
        let code = match e.kind {
            ErrorKind::Parse => "parse",
            ErrorKind::Invalid => "invalid",
            ErrorKind::Frame => "frames",
            ErrorKind::Limit => "limit",
            ErrorKind::Io => "io",
            ErrorKind::Usage => "usage",
        };
        self.push(Severity::Error, code, file, line, e.message.clone());
    }

    fn push_warning(&mut self, file: &str, w: &Warning) {
        let sev = if warning_is_problem(w.code) && !self.args.allow.contains(&w.code) {
            Severity::Error
        } else {
            Severity::Warning
        };
        self.push(sev, w.code.name(), file, w.location.line, w.message.clone());
    }

    /// Check one file; returns its baseline record when it loaded.
    fn check_file(
        &mut self,
        path: &Path,
        pairs_found: &mut [bool],
    ) -> Result<Option<BaselineFile>> {
        let file = key_of(path);
        let opts = LoadOptions {
            joints: self.args.joints.iter().cloned().collect(),
            max_file_size: self.args.max_file_size,
            ..LoadOptions::default()
        };
        let loaded = match formats::load_file(path, &opts) {
            Ok(l) => l,
            Err(e) if e.kind == ErrorKind::Io => return Err(e),
            Err(e) => {
                self.push_error(&file, &e);
                return Ok(None);
            }
        };
        let rig_pair = loaded
            .rig
            .as_ref()
            .filter(|m| !m.from.is_empty() && !m.to.is_empty())
            .map(|m| (m.from.clone(), m.to.clone(), true));
        let mut graph = FrameGraph::new();
        if let Err(e) = graph.add(loaded) {
            self.push_error(&file, &e);
            return Ok(None);
        }
        for w in graph.warnings() {
            self.push_warning(&file, w);
        }
        let frames = graph.frames();
        let mut record = BaselineFile {
            edges: graph.edges().iter().map(baseline_edge).collect(),
            pairs: Vec::new(),
        };
        let mut pairs: Vec<(String, String, bool)> = rig_pair.into_iter().collect();
        for (i, (a, b)) in self.args.pairs.iter().enumerate() {
            if frames.contains(a) && frames.contains(b) {
                pairs_found[i] = true;
                pairs.push((a.clone(), b.clone(), false));
            }
        }
        for (from, to, declared) in pairs {
            let chain = match graph.transform(&from, &to) {
                Ok(c) => c,
                Err(e) => {
                    let mut e = e;
                    if declared {
                        e.message =
                            format!("frames the rig declares ({from} -> {to}): {}", e.message);
                    }
                    self.push_error(&file, &e);
                    continue;
                }
            };
            for w in &chain.warnings {
                self.push_warning(&file, w);
            }
            let rep = match report::rig_report(&chain, &[1.0], self.args.pitch_tol) {
                Ok(r) => r,
                Err(e) => {
                    self.push_error(&file, &e);
                    continue;
                }
            };
            let line = chain
                .steps
                .last()
                .and_then(|s| s.edge.provenance.location.line);
            if let Some(max) = self.args.max_lever_arm {
                if rep.lever_arm_m > max {
                    self.push(
                        Severity::Error,
                        "lever-arm",
                        &file,
                        line,
                        format!(
                            "{from} -> {to}: lever arm {:.6} m exceeds --max-lever-arm {max} m",
                            rep.lever_arm_m
                        ),
                    );
                }
            }
            let zero_pitch = rep.screw.kind == "zero_pitch" || rep.screw.kind == "identity";
            if self.args.require_zero_pitch && !zero_pitch {
                let h = rep
                    .screw
                    .translation_along_axis_m
                    .map(|h| format!("screw translation h = {h:.6e} m"))
                    .unwrap_or_else(|| "a pure translation (infinite pitch)".into());
                self.push(
                    Severity::Error,
                    "nonzero-pitch",
                    &file,
                    line,
                    format!(
                        "{from} -> {to}: expected zero screw pitch (|h| <= {:e} m), found {h}",
                        self.args.pitch_tol
                    ),
                );
            }
            record.pairs.push(BaselinePair {
                transform: baseline_transform(&from, &to, &chain.transform),
                lever_arm_m: rep.lever_arm_m,
                screw_kind: rep.screw.kind.clone(),
                zero_pitch: rep.screw.kind == "zero_pitch",
                adapted_metric_exists: rep.adapted_metric.exists,
            });
        }
        Ok(Some(record))
    }

    /// Compare one file's record with the baseline's.
    fn compare(&mut self, file: &str, now: &BaselineFile, base: &BaselineFile) {
        let (tmax, rmax) = (
            self.args.max_translation_drift,
            self.args.max_rotation_drift,
        );
        let drift = |me: &mut Self, what: String, a: &BaselineTransform, b: &BaselineTransform| {
            let dt = ((a.translation_m[0] - b.translation_m[0]).powi(2)
                + (a.translation_m[1] - b.translation_m[1]).powi(2)
                + (a.translation_m[2] - b.translation_m[2]).powi(2))
            .sqrt();
            let dr = quat_angle_deg(a.quaternion_xyzw, b.quaternion_xyzw);
            if dt > tmax || dr > rmax {
                me.push(
                    Severity::Error,
                    "drift",
                    file,
                    None,
                    format!(
                        "{what}: moved {dt:.6} m (tolerance {tmax} m) and {dr:.4} deg (tolerance {rmax} deg) since the baseline"
                    ),
                );
            }
        };
        for b in &base.edges {
            match now
                .edges
                .iter()
                .find(|e| e.parent == b.parent && e.child == b.child)
            {
                Some(e) => drift(self, format!("edge {} -> {}", b.parent, b.child), e, b),
                None => self.push(
                    Severity::Error,
                    "missing-edge",
                    file,
                    None,
                    format!(
                        "edge {} -> {} is in the baseline but no longer in the file",
                        b.parent, b.child
                    ),
                ),
            }
        }
        for e in &now.edges {
            if !base
                .edges
                .iter()
                .any(|b| e.parent == b.parent && e.child == b.child)
            {
                self.push(
                    Severity::Error,
                    "new-edge",
                    file,
                    None,
                    format!(
                        "edge {} -> {} is not in the baseline (accept it with --write-baseline)",
                        e.parent, e.child
                    ),
                );
            }
        }
        for b in &base.pairs {
            let Some(p) = now.pairs.iter().find(|p| {
                p.transform.parent == b.transform.parent && p.transform.child == b.transform.child
            }) else {
                continue;
            };
            drift(
                self,
                format!("{} -> {}", b.transform.parent, b.transform.child),
                &p.transform,
                &b.transform,
            );
            let verdict = |p: &BaselinePair| {
                format!(
                    "screw {}, zero pitch {}, adapted metric {}",
                    p.screw_kind,
                    p.zero_pitch,
                    if p.adapted_metric_exists {
                        "exists"
                    } else {
                        "none"
                    }
                )
            };
            if p.screw_kind != b.screw_kind
                || p.zero_pitch != b.zero_pitch
                || p.adapted_metric_exists != b.adapted_metric_exists
            {
                self.push(
                    Severity::Error,
                    "verdict-changed",
                    file,
                    None,
                    format!(
                        "{} -> {}: verdict changed from ({}) to ({})",
                        b.transform.parent,
                        b.transform.child,
                        verdict(b),
                        verdict(p)
                    ),
                );
            }
        }
    }
}

fn baseline_transform(parent: &str, child: &str, t: &Transform) -> BaselineTransform {
    let d = t.translation();
    BaselineTransform {
        parent: parent.to_string(),
        child: child.to_string(),
        translation_m: [d.x, d.y, d.z],
        quaternion_xyzw: t.quaternion_xyzw(),
    }
}

fn baseline_edge(e: &Edge) -> BaselineTransform {
    baseline_transform(&e.parent, &e.child, &e.transform)
}

/// Angle (deg) between two rotations given as quaternions.
fn quat_angle_deg(a: [f64; 4], b: [f64; 4]) -> f64 {
    let dot: f64 = a.iter().zip(b.iter()).map(|(x, y)| x * y).sum();
    let na: f64 = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    let nb: f64 = b.iter().map(|x| x * x).sum::<f64>().sqrt();
    let c = (dot.abs() / (na * nb)).min(1.0);
    (2.0 * c.acos()).to_degrees()
}

pub fn read_baseline(path: &Path) -> Result<Baseline> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, &e))?;
    let b: Baseline = serde_json::from_str(&text).map_err(|e| {
        Error::new(
            ErrorKind::Io,
            format!("expected a baseline written by `audit check --write-baseline`, found: {e}"),
        )
        .in_file(path)
        .at_line(e.line(), Some(e.column()))
    })?;
    if b.schema_version != 1 {
        return Err(Error::new(
            ErrorKind::Io,
            format!(
                "expected baseline schema_version 1, found {}",
                b.schema_version
            ),
        )
        .in_file(path));
    }
    Ok(b)
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// Escape a GitHub workflow-command value (`%`, CR, LF; and in properties `:` `,`).
fn gh_escape(s: &str, property: bool) -> String {
    let mut o = s
        .replace('%', "%25")
        .replace('\r', "%0D")
        .replace('\n', "%0A");
    if property {
        o = o.replace(':', "%3A").replace(',', "%2C");
    }
    o
}

pub fn run(args: &CheckArgs, out: &mut dyn Write) -> Result<i32> {
    let baseline = args.baseline.as_deref().map(read_baseline).transpose()?;
    let mut files = expand_paths(&args.paths, is_calibration_file)?;
    files.retain(|f| {
        ![&args.baseline, &args.write_baseline]
            .iter()
            .any(|b| b.as_deref().is_some_and(|b| same_file(f, b)))
    });
    if files.is_empty() {
        return Err(Error::usage(
            "no calibration files found under the given paths",
        ));
    }
    let mut ck = Checker {
        args,
        findings: Vec::new(),
    };
    let mut pairs_found = vec![false; args.pairs.len()];
    let mut current = Baseline {
        schema_version: 1,
        files: BTreeMap::new(),
    };
    for f in &files {
        if let Some(rec) = ck.check_file(f, &mut pairs_found)? {
            current.files.insert(key_of(f), rec);
        }
    }
    for (i, found) in pairs_found.iter().enumerate() {
        if !found {
            let (a, b) = &args.pairs[i];
            ck.push(
                Severity::Error,
                "frames",
                "",
                None,
                format!(
                    "--pair {a}:{b}: no checked file has both frames (checked: {})",
                    checked_list(&files)
                ),
            );
        }
    }
    if let Some(base) = &baseline {
        for (file, rec) in &current.files {
            match base.files.get(file) {
                Some(b) => ck.compare(file, rec, b),
                None => ck.push(
                    Severity::Error,
                    "new-file",
                    file,
                    None,
                    "file is not in the baseline (accept it with --write-baseline)".into(),
                ),
            }
        }
    }
    if let Some(path) = &args.write_baseline {
        // Never write an empty or partial baseline: a serialisation error is
        // an error, not "".
        let mut text = serde_json::to_string_pretty(&current).map_err(|e| {
            Error::new(ErrorKind::Io, format!("cannot serialise the baseline: {e}")).in_file(path)
        })?;
        text.push('\n');
        write_atomic(path, text.as_bytes())?;
    }
    let problems = ck
        .findings
        .iter()
        .filter(|f| f.severity == Severity::Error)
        .count();
    let warnings = ck.findings.len() - problems;
    let text = match args.format {
        CheckFormat::Json => {
            let j = CheckJson {
                schema_version: 1,
                files_checked: files.len(),
                problems,
                warnings,
                findings: ck.findings.clone(),
            };
            let mut s = serde_json::to_string_pretty(&j).unwrap_or_default();
            s.push('\n');
            s
        }
        CheckFormat::Github => {
            let mut s = String::new();
            for f in &ck.findings {
                let kind = match f.severity {
                    Severity::Error => "error",
                    Severity::Warning => "warning",
                };
                let mut props = Vec::new();
                if !f.file.is_empty() {
                    props.push(format!("file={}", gh_escape(&f.file, true)));
                }
                if let Some(l) = f.line {
                    props.push(format!("line={l}"));
                }
                props.push(format!("title={}", gh_escape(&f.code, true)));
                s.push_str(&format!(
                    "::{kind} {}::{}\n",
                    props.join(","),
                    gh_escape(&f.message, false)
                ));
            }
            s.push_str(&summary_text(files.len(), problems, warnings));
            s
        }
        CheckFormat::Text => {
            let mut s = String::new();
            for f in &ck.findings {
                let kind = match f.severity {
                    Severity::Error => "error",
                    Severity::Warning => "warning",
                };
                let place = match (f.file.is_empty(), f.line) {
                    (true, _) => String::new(),
                    (false, Some(l)) => format!("{}:{l}: ", f.file),
                    (false, None) => format!("{}: ", f.file),
                };
                s.push_str(&format!("{place}{kind}[{}]: {}\n", f.code, f.message));
            }
            s.push_str(&summary_text(files.len(), problems, warnings));
            s
        }
    };
    out.write_all(text.as_bytes()).map_err(io_err)?;
    Ok(if problems > 0 { 1 } else { 0 })
}

fn summary_text(files: usize, problems: usize, warnings: usize) -> String {
    format!(
        "checked {files} file{}: {problems} problem{}, {warnings} warning{}\n",
        if files == 1 { "" } else { "s" },
        if problems == 1 { "" } else { "s" },
        if warnings == 1 { "" } else { "s" }
    )
}
