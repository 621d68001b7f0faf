//! `audit check`: the files found (`walk`) are grouped into robots (each
//! directory's `audit.toml`, else one file each, `manifest`); each robot's
//! files load into one frame graph; every file parses; rotations are
//! orthonormal, quaternions unit, units plausible (the readers' warnings, at
//! the severity of the policy in docs/check.md); the frames each rig
//! declares, every `--pair` and the manifest's pairs exist and connect;
//! optional lever-arm and zero-pitch rules; against a baseline, drift, pairs,
//! removed files and verdicts (`crate::baseline`).
//!
//! A file that exists but does not parse is a finding; an unreadable file, a
//! malformed baseline or a refused `--write-baseline` target is an error
//! (exit 2), raised before anything is written.

use super::files::{dir_of, same_file, unsafe_target, write_atomic};
use super::load::apply_renames;
use super::manifest;
use super::walk::{walk, Found};
use crate::baseline::{
    self, Baseline, BaselineFile, BaselinePair, BaselineTransform, CheckedFile, DriftTolerances,
    Locations,
};
use crate::diagnostic::{Code, Diagnostic, Error, Location, Result, Severity, Warning};
use crate::formats::{self, LoadOptions, Rename};
use crate::frames::FrameGraph;
use crate::geometry::{PitchTol, PitchVerdict, ScrewKind};
use crate::progress::{NoProgress, Progress};
use crate::report::check::BaselineChanges;
use crate::report::rig::{rig_report, Judgement};
use crate::report::CheckReport;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What `audit check` is asked to check. `Default`: the command's defaults,
/// no paths.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct CheckOptions {
    /// Calibration files or directories of them.
    pub paths: Vec<PathBuf>,
    /// Compare against this baseline.
    pub baseline: Option<PathBuf>,
    /// Write the current state as a baseline: the checked files' entries
    /// added or updated, the others kept unless `prune`.
    pub write_baseline: Option<PathBuf>,
    /// With `write_baseline`: drop the entries of files not checked this run.
    pub prune: bool,
    /// Globs of files and directories the walk skips (`--exclude`).
    pub exclude: Vec<String>,
    /// Also check these frame pairs wherever both frames exist.
    pub pairs: Vec<(String, String)>,
    /// A finding when a checked pair's lever arm exceeds this (m).
    pub max_lever_arm: Option<f64>,
    /// A finding when a checked pair does not have zero screw pitch.
    pub require_zero_pitch: bool,
    /// Drift tolerances against the baseline.
    pub drift: DriftTolerances,
    /// `--pitch-tol`: `auto` or a tolerance on `|h|` (m).
    pub pitch_tol: PitchTol,
    /// How files are read (joint values, size cap; renames come from each
    /// directory's `audit.toml`, per robot: `renames` here is refused).
    pub load: LoadOptions,
    /// Codes accepted: reported at severity warning, never a problem.
    pub allow: Vec<Code>,
    /// Codes refused: reported at severity error.
    pub deny: Vec<Code>,
    /// Every warning is a problem (`--deny-warnings`).
    pub deny_warnings: bool,
}

impl CheckOptions {
    /// The severity policy (docs/check.md): `--allow CODE` makes a warning,
    /// `--deny CODE` and `--deny-warnings` make an error; otherwise the
    /// diagnostic's own severity (a reader's warning raised to an error beyond
    /// rounding), and a unit mistake is always an error in a check.
    pub fn severity(&self, d: &Diagnostic) -> Severity {
        if self.allow.contains(&d.code) {
            Severity::Warning
        } else if self.deny.contains(&d.code)
            || (self.deny_warnings && d.severity == Severity::Warning)
            || CHECK_ERRORS.contains(&d.code)
        {
            Severity::Error
        } else {
            d.severity
        }
    }
}

/// Reader warnings that are errors in a check whatever their size: a unit
/// mistake is never rounding.
pub const CHECK_ERRORS: &[Code] = &[Code::MillimetresInMetreField];

/// The checked files for a message: all of them up to 5, then a count.
fn checked_list(files: &[Found]) -> String {
    let mut v: Vec<String> = files
        .iter()
        .take(5)
        .map(|f| f.path.display().to_string())
        .collect();
    if files.len() > 5 {
        v.push(format!("and {} more", files.len() - 5));
    }
    v.join(", ")
}

/// Files loaded into one frame graph (a robot of the manifest, or one file).
#[derive(Debug, Clone, Default)]
pub struct Robot {
    /// The manifest's name (`None`: a file on its own).
    pub name: Option<String>,
    /// Its files, in load order.
    pub files: Vec<Found>,
    /// Frames renamed as the files are loaded.
    pub renames: Vec<Rename>,
    /// Frame pairs to check besides the rig files' declared ones.
    pub pairs: Vec<(String, String)>,
}

/// A robot's graph as its files load: the declared pairs (with the index of
/// the declaring file's state), how many frames each rename changed, how many
/// files loaded.
struct RobotGraph {
    graph: FrameGraph,
    declared: Vec<(String, String, usize)>,
    renamed: Vec<usize>,
    states: usize,
}

/// One checked file's state: its record and where its values are written.
struct FileState {
    found: Found,
    record: BaselineFile,
    locations: Locations,
}

struct Checker<'a> {
    opts: &'a CheckOptions,
    findings: Vec<Diagnostic>,
    pairs_found: Vec<bool>,
    /// One step per file read.
    progress: &'a dyn Progress,
}

fn loc_of(l: &Location) -> Location {
    Location {
        file: None,
        line: l.line,
        column: l.column,
    }
}

impl Checker<'_> {
    /// A reader's error as a finding on `file`.
    fn error(&mut self, file: &Path, e: &Error) {
        self.findings
            .push(e.clone().with_severity(Severity::Error).in_file(file));
    }

    fn warning(&mut self, file: &Path, w: &Warning) {
        self.findings.push(w.clone().in_file(file));
    }

    fn push(&mut self, code: Code, at: Location, message: String) {
        self.findings.push(Diagnostic::new(code, message).at(&at));
    }

    /// Load one file of a robot into its graph; its state when it loaded.
    fn load_into(
        &mut self,
        robot: &Robot,
        f: &Found,
        acc: &mut RobotGraph,
    ) -> Result<Option<FileState>> {
        self.progress.advance(1);
        let index = acc.states;
        if formats::launch::holds_no_calibration(&f.path, self.opts.load.max_file_size) {
            self.findings.push(
                Diagnostic::new(
                    Code::Ignored,
                    "launch file without static_transform_publisher or Extrinsic_Tlb: no calibration in it, not read",
                )
                .at(&Location::file(&f.path)),
            );
            return Ok(None);
        }
        let mut loaded = match formats::load_file(&f.path, &self.opts.load) {
            Ok(l) => l,
            Err(e) if e.code == Code::Io => return Err(e),
            Err(e) => {
                self.error(&f.path, &e);
                return Ok(None);
            }
        };
        for (n, hits) in
            acc.renamed
                .iter_mut()
                .zip(apply_renames(&robot.renames, &f.path, &mut loaded))
        {
            *n += hits;
        }
        if let Some(m) = loaded
            .rig
            .as_ref()
            .filter(|m| !m.from.is_empty() && !m.to.is_empty())
        {
            acc.declared.push((m.from.clone(), m.to.clone(), index));
        }
        let mut locations = Locations::new();
        for e in &loaded.edges {
            locations.insert(
                (e.parent.clone(), e.child.clone()),
                loc_of(&e.provenance.location),
            );
        }
        let record = BaselineFile {
            edges: loaded
                .edges
                .iter()
                .map(BaselineTransform::of_edge)
                .collect(),
            pairs: Vec::new(),
        };
        for w in &loaded.warnings {
            self.warning(&f.path, w);
        }
        // Edge by edge: a conflict (the same edge with other values in another
        // file, a cycle, two parents) is a finding naming both places; the
        // file's other edges still load.
        for e in loaded.edges {
            if let Err(err) = acc.graph.add_edge(e) {
                self.error(&f.path, &err);
            }
        }
        Ok(Some(FileState {
            found: f.clone(),
            record,
            locations,
        }))
    }

    /// Check one robot: its files into one graph, then its pairs.
    fn check_robot(&mut self, robot: &Robot) -> Result<Vec<FileState>> {
        let mut acc = RobotGraph {
            graph: FrameGraph::new(),
            declared: Vec::new(),
            renamed: vec![0; robot.renames.len()],
            states: 0,
        };
        let mut states: Vec<FileState> = Vec::new();
        for f in &robot.files {
            if let Some(st) = self.load_into(robot, f, &mut acc)? {
                states.push(st);
                acc.states += 1;
            }
        }
        if let Some(i) = acc.renamed.iter().position(|&n| n == 0) {
            let r = &robot.renames[i];
            return Err(Error::usage(format!(
                "audit.toml: robot {:?}: rename {} -> {}: expected a frame `{}` in {}, found none",
                robot.name.as_deref().unwrap_or(""),
                r.old,
                r.new,
                r.old,
                r.file.as_deref().unwrap_or("its files")
            )));
        }
        let RobotGraph {
            graph, declared, ..
        } = acc;
        let Some(first) = states.first() else {
            return Ok(states);
        };
        let first_path = first.found.path.clone();
        for w in graph.warnings().to_vec() {
            let file = w
                .location
                .file
                .clone()
                .unwrap_or_else(|| first_path.clone());
            self.warning(&file, &w);
        }
        let frames = graph.frames();
        let mut pairs: Vec<(String, String, bool, usize)> = declared
            .into_iter()
            .map(|(a, b, i)| (a, b, true, i))
            .collect();
        for (a, b) in &robot.pairs {
            pairs.push((a.clone(), b.clone(), false, 0));
        }
        for (i, (a, b)) in self.opts.pairs.iter().enumerate() {
            if frames.contains(a) && frames.contains(b) {
                self.pairs_found[i] = true;
                pairs.push((a.clone(), b.clone(), false, 0));
            }
        }
        for (from, to, declared, i) in pairs {
            let st = &mut states[i];
            if let Some((p, at)) = self.check_pair(&graph, &st.found.path, &from, &to, declared) {
                st.locations.insert((from.clone(), to.clone()), at);
                st.record.pairs.push(p);
            }
        }
        Ok(states)
    }

    /// The rules on one frame pair; its baseline record (and the line of its
    /// last edge) when it composes.
    fn check_pair(
        &mut self,
        graph: &FrameGraph,
        file: &Path,
        from: &str,
        to: &str,
        declared: bool,
    ) -> Option<(BaselinePair, Location)> {
        let chain = match graph.transform(from, to) {
            Ok(c) => c,
            Err(mut e) => {
                if declared {
                    e.message = format!("frames the rig declares ({from} -> {to}): {}", e.message);
                }
                self.error(file, &e);
                return None;
            }
        };
        for w in &chain.warnings {
            self.warning(file, w);
        }
        let rep = match rig_report(
            &chain,
            &[1.0],
            &Judgement {
                pitch_tol: self.opts.pitch_tol,
                user: None,
            },
        ) {
            Ok(r) => r,
            Err(e) => {
                self.error(file, &e);
                return None;
            }
        };
        let at = chain
            .steps
            .last()
            .map(|s| loc_of(&s.edge.provenance.location))
            .unwrap_or_default();
        let mut here = at.clone();
        here.file = Some(file.to_path_buf());
        if let Some(max) = self.opts.max_lever_arm.filter(|m| rep.lever_arm_m > *m) {
            self.push(
                Code::LeverArm,
                here.clone(),
                format!(
                    "{from} -> {to}: lever arm {:.6} m exceeds --max-lever-arm {max} m",
                    rep.lever_arm_m
                ),
            );
        }
        // The three-way verdict: `undecidable` does not pass the gate.
        let zero_pitch = rep.screw.kind == ScrewKind::Identity
            || rep.screw.pitch_verdict == Some(PitchVerdict::Zero);
        if self.opts.require_zero_pitch && !zero_pitch {
            let h = match (rep.screw.translation_along_axis_m, rep.screw.pitch_verdict) {
                (Some(h), Some(v)) => format!(
                    "screw translation h = {h:.6e} +- {:.1e} m ({}), verdict {}",
                    rep.screw
                        .translation_along_axis_uncertainty_m
                        .unwrap_or(0.0),
                    rep.uncertainty.source.name(),
                    v.name()
                ),
                _ => "a pure translation (infinite pitch)".into(),
            };
            self.push(
                Code::NonzeroPitch,
                here,
                format!(
                    "{from} -> {to}: expected zero screw pitch (--pitch-tol {}), found {h}",
                    self.opts.pitch_tol
                ),
            );
        }
        let pair = BaselinePair {
            transform: BaselineTransform::new(from, to, &chain.transform),
            lever_arm_m: rep.lever_arm_m,
            screw_kind: rep.screw.kind.name().to_string(),
            zero_pitch: rep.screw.kind == ScrewKind::ZeroPitch,
            adapted_metric_exists: rep.adapted_metric.exists,
            declared,
        };
        Some((pair, at))
    }
}

/// Group the files into robots: each checked directory's `audit.toml`
/// robots (their files loaded together), then every other file on its own.
/// The manifests themselves are not calibration files.
fn robots(opts: &CheckOptions, files: &mut Vec<Found>) -> Result<Vec<Robot>> {
    files.retain(|f| f.path.file_name().is_none_or(|n| n != manifest::MANIFEST));
    let mut out = Vec::new();
    let mut grouped: Vec<PathBuf> = Vec::new();
    for dir in opts.paths.iter().filter(|p| p.is_dir()) {
        for r in manifest::read(dir)? {
            for f in &r.files {
                grouped.extend(f.path.canonicalize().ok());
                if !files.iter().any(|x| same_file(&x.path, &f.path)) {
                    files.push(f.clone());
                }
            }
            out.push(Robot {
                name: Some(r.name),
                files: r.files,
                renames: r.renames,
                pairs: r.pairs,
            });
        }
    }
    for f in files.iter() {
        let canon = f.path.canonicalize().ok();
        if !canon.is_some_and(|c| grouped.contains(&c)) {
            out.push(Robot {
                files: vec![f.clone()],
                ..Robot::default()
            });
        }
    }
    Ok(out)
}

/// The directory a baseline file's keys are relative to.
fn refused(path: &Path, why: String) -> Error {
    Error::usage(format!("--write-baseline: refused, nothing written: {why}")).in_file(path)
}

/// Refuse a `--write-baseline` target that is a checked input, exists and is
/// not a regular file holding a baseline, is a symlink or lies behind a
/// symlinked directory ([`unsafe_target`]); the existing baseline when there
/// is one. Runs before anything is written.
fn write_target(path: &Path, files: &[Found], given: &[PathBuf]) -> Result<Option<Baseline>> {
    let link = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let dir = dir_of(path);
            if !std::fs::metadata(&dir).is_ok_and(|m| m.is_dir()) {
                return Err(refused(
                    path,
                    format!(
                        "expected an existing directory {}, found none",
                        dir.display()
                    ),
                ));
            }
            return match unsafe_target(path) {
                Some(why) => Err(refused(path, why)),
                None => Ok(None),
            };
        }
        Err(e) => return Err(Error::io(path, &e)),
    };
    let meta = std::fs::metadata(path).map_err(|e| {
        refused(
            path,
            format!("a symlink that leads nowhere ({e}): expected a regular file"),
        )
    })?;
    if !meta.is_file() {
        let what = if meta.is_dir() {
            "a directory"
        } else {
            "not a regular file (a device, FIFO or socket)"
        };
        let via = if link.file_type().is_symlink() {
            "a symlink to "
        } else {
            ""
        };
        return Err(refused(
            path,
            format!("expected a regular file, found {via}{what}"),
        ));
    }
    if files.iter().any(|f| same_file(&f.path, path)) || given.iter().any(|g| same_file(g, path)) {
        return Err(refused(
            path,
            "it is one of the checked calibration files: expected a separate baseline file".into(),
        ));
    }
    if let Some(why) = unsafe_target(path) {
        return Err(refused(path, why));
    }
    baseline::read(path).map(Some).map_err(|e| {
        refused(
            path,
            format!("it exists and is not a baseline ({})", e.message),
        )
    })
}

/// The checked files keyed for a baseline kept in `dir`.
fn keyed<'a>(states: &'a [FileState], dir: &Path) -> Result<BTreeMap<String, CheckedFile<'a>>> {
    let mut out = BTreeMap::new();
    for st in states {
        let key = baseline::key_for(&st.found.path, &st.found.root, dir)?;
        out.insert(
            key,
            CheckedFile {
                path: &st.found.path,
                record: &st.record,
                locations: &st.locations,
            },
        );
    }
    Ok(out)
}

/// Merge the checked files into `old` (or replace it with `prune`); what
/// changed.
fn merge(
    old: Option<Baseline>,
    now: &BTreeMap<String, CheckedFile>,
    prune: bool,
    path: &Path,
) -> (Baseline, BaselineChanges) {
    let old = old.unwrap_or(Baseline {
        schema_version: 1,
        files: BTreeMap::new(),
    });
    let mut ch = BaselineChanges {
        path: path.to_string_lossy().replace('\\', "/"),
        ..BaselineChanges::default()
    };
    let mut files = if prune {
        BTreeMap::new()
    } else {
        old.files.clone()
    };
    for (k, f) in now {
        match old.files.get(k) {
            None => ch.added.push(k.clone()),
            Some(r) if r != f.record => ch.updated.push(k.clone()),
            Some(_) => ch.unchanged += 1,
        }
        files.insert(k.clone(), f.record.clone());
    }
    if prune {
        ch.removed = old
            .files
            .keys()
            .filter(|k| !now.contains_key(*k))
            .cloned()
            .collect();
    }
    (
        Baseline {
            schema_version: 1,
            files,
        },
        ch,
    )
}

fn write_baseline(path: &Path, b: &Baseline) -> Result<()> {
    // Never write an empty or partial baseline: a serialisation error is an
    // error, not "".
    let mut text = serde_json::to_string_pretty(b).map_err(|e| {
        Error::new(Code::Io, format!("cannot serialise the baseline: {e}")).in_file(path)
    })?;
    text.push('\n');
    write_atomic(path, text.as_bytes())
}

/// Run the check; writes the baseline when asked (after refusing a target
/// that is an input or not a regular baseline file, before reading anything).
///
/// ```
/// use extrinsic_audit::{check, CheckOptions, Code};
/// use std::path::Path;
///
/// # fn main() -> extrinsic_audit::Result<()> {
/// let root = Path::new(env!("CARGO_MANIFEST_DIR"));
/// // The shipped calibrations against their baseline: every rig file and the
/// // URDF read, nothing drifted.
/// let dir = root.join("calibrations");
/// let mut opts = CheckOptions::default();
/// opts.paths = vec![dir.clone()];
/// opts.baseline = Some(dir.join("baseline.json"));
/// let report = check(&opts)?;
/// let is_calibration = |p: &Path| p.extension().is_some_and(|x| x == "toml" || x == "urdf");
/// let files = std::fs::read_dir(&dir).unwrap().filter(|e| is_calibration(&e.as_ref().unwrap().path()));
/// assert_eq!(report.files_checked, files.count());
/// assert_eq!((report.problems, report.exit_code()), (0, 0));
///
/// // ANYmal C's LiDAR sits 0.3908 m from its base (pytransform3d): a
/// // 0.3 m limit on the lever arm is a problem, exit 1.
/// let mut opts = CheckOptions::default();
/// opts.paths = vec![root.join("tests/fixtures/urdf/anymal_c_lidar.urdf")];
/// opts.pairs = vec![("base".into(), "lidar".into())];
/// opts.max_lever_arm = Some(0.3);
/// let report = check(&opts)?;
/// assert_eq!(report.exit_code(), 1);
/// assert!(report.findings.iter().any(|d| d.code == Code::LeverArm && d.message.contains("0.390790 m")));
/// # Ok(())
/// # }
/// ```
pub fn check(opts: &CheckOptions) -> Result<CheckReport> {
    check_with(opts, &NoProgress)
}

/// [`check`], reporting one step per file read to `progress` (a large
/// directory takes seconds).
pub fn check_with(opts: &CheckOptions, progress: &dyn Progress) -> Result<CheckReport> {
    if !opts.load.renames.is_empty() {
        return Err(Error::usage(
            "check: expected renames in each directory's audit.toml (per robot), found renames in the load options",
        ));
    }
    let mut walked = walk(&opts.paths, &opts.exclude)?;
    walked.files.retain(|f| {
        !opts
            .baseline
            .as_deref()
            .is_some_and(|b| same_file(&f.path, b))
            && !baseline::is_baseline_file(&f.path)
    });
    let given: Vec<PathBuf> = opts
        .paths
        .iter()
        .filter(|p| !baseline::is_baseline_file(p))
        .cloned()
        .collect();
    let old = match &opts.write_baseline {
        Some(p) => write_target(p, &walked.files, &given)?,
        None => None,
    };
    if let Some(b) = opts.baseline.as_deref().filter(|b| !b.exists()) {
        return Err(Error::usage(format!(
            "--baseline {}: no such file; write one first with `audit check PATHS --write-baseline {}` and commit it",
            b.display(),
            b.display()
        ))
        .in_file(b));
    }
    let base = opts.baseline.as_deref().map(baseline::read).transpose()?;
    if walked.files.is_empty() {
        // Only baselines or manifests given (a commit that changes only the
        // baseline): nothing to check, nothing wrong.
        let only_skipped = opts.paths.iter().all(|p| {
            p.is_file()
                && (baseline::is_baseline_file(p)
                    || p.file_name().is_some_and(|n| n == manifest::MANIFEST))
        });
        if !only_skipped || opts.write_baseline.is_some() {
            return Err(Error::usage(
                "no calibration files found under the given paths",
            ));
        }
    }
    let robots = robots(opts, &mut walked.files)?;
    let mut ck = Checker {
        opts,
        findings: std::mem::take(&mut walked.findings),
        pairs_found: vec![false; opts.pairs.len()],
        progress,
    };
    let total: usize = robots.iter().map(|r| r.files.len()).sum();
    progress.start(total as u64, "files checked");
    let mut states = Vec::new();
    for r in &robots {
        let s = ck.check_robot(r);
        if s.is_err() {
            progress.finish();
        }
        states.extend(s?);
    }
    progress.finish();
    for (i, found) in ck.pairs_found.clone().iter().enumerate() {
        if !found {
            let (a, b) = &opts.pairs[i];
            ck.push(
                Code::Frame,
                Location::default(),
                format!(
                    "--pair {a}:{b}: no checked file has both frames (checked: {})",
                    checked_list(&walked.files)
                ),
            );
        }
    }
    if let (Some(base), Some(path)) = (&base, &opts.baseline) {
        let dir = dir_of(path);
        ck.findings.extend(baseline::compare(
            &keyed(&states, &dir)?,
            base,
            &dir,
            opts.drift,
        ));
    }
    let mut changes = None;
    if let Some(path) = &opts.write_baseline {
        let now = keyed(&states, &dir_of(path))?;
        let (new, ch) = merge(old, &now, opts.prune, path);
        write_baseline(path, &new)?;
        changes = Some(ch);
    }
    for f in &mut ck.findings {
        f.severity = opts.severity(f);
    }
    let mut report = CheckReport::new(walked.files.len(), ck.findings);
    report.baseline_written = changes;
    Ok(report)
}
