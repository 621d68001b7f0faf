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

use super::files::write_atomic_with;
use super::files::{dir_of, same_file, unsafe_target};
use super::load::apply_renames;
use super::manifest;
use super::walk::{file_id, walk, FileId, Found};
use crate::analysis::detectors::OdometryDetector;
use crate::analysis::mistakes::MistakeTol;
use crate::baseline::{
    self, BaselineFile, BaselinePair, BaselineTransform, CheckedFile, DriftTolerances, Locations,
    Store, WriteLock,
};
use crate::diagnostic::{Code, Diagnostic, Error, Location, Result, Severity, Warning};
use crate::formats::{self, LoadOptions, Rename};
use crate::frames::{FrameGraph, ValuesAt};
use crate::geometry::{PitchTol, PitchVerdict, ScrewKind};
use crate::input::ReadWhole;
use crate::progress::{NoProgress, Progress};
use crate::report::check::BaselineChanges;
use crate::report::rig::{rig_verdicts, Judgement};
use crate::report::CheckReport;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

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
    /// `--fleet-tolerance`: one calibration per vehicle; a `fleet-deviation`
    /// finding for each checked pair further than this from the mean of the
    /// same pair over all checked files (`None`: no fleet comparison).
    pub fleet: Option<DriftTolerances>,
}

impl CheckOptions {
    /// Check `paths` (files or directories) with the command's defaults;
    /// the methods below set the rest group by group, as `audit check`'s
    /// flags and the Python package's `check` both do.
    ///
    /// ```
    /// use extrinsic_audit::{check, CheckOptions, DriftTolerances, PitchTol};
    ///
    /// # fn main() -> extrinsic_audit::Result<()> {
    /// let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/urdf/anymal_c_lidar.urdf");
    /// // ANYmal C's LiDAR sits 0.3908 m from its base (pytransform3d): a
    /// // 0.3 m limit is a problem (exit 1), a 0.4 m one is not.
    /// let gate = |max| {
    ///     CheckOptions::new(vec![urdf.into()])
    ///         .walk(Vec::new(), vec![("base".into(), "lidar".into())])
    ///         .gate(Some(max), false, DriftTolerances::default(), PitchTol::Auto)
    /// };
    /// assert_eq!(check(&gate(0.3))?.exit_code(), 1);
    /// assert_eq!(check(&gate(0.4))?.exit_code(), 0);
    /// # Ok(())
    /// # }
    /// ```
    pub fn new(paths: Vec<PathBuf>) -> Self {
        CheckOptions {
            paths,
            ..CheckOptions::default()
        }
    }

    /// Compare against `baseline`; write the current state to `write`
    /// (with `prune`, dropping the entries of files not checked).
    pub fn baseline(
        mut self,
        baseline: Option<PathBuf>,
        write: Option<PathBuf>,
        prune: bool,
    ) -> Self {
        self.baseline = baseline;
        self.write_baseline = write;
        self.prune = prune;
        self
    }

    /// What the walk skips (`exclude` globs) and the frame pairs checked
    /// wherever both frames exist (`pairs`).
    pub fn walk(mut self, exclude: Vec<String>, pairs: Vec<(String, String)>) -> Self {
        self.exclude = exclude;
        self.pairs = pairs;
        self
    }

    /// The gate on each checked pair: its lever arm at most `max_lever_arm`
    /// (m), zero screw pitch if `require_zero_pitch` (judged with
    /// `pitch_tol`), and the drift against the baseline within `drift`.
    pub fn gate(
        mut self,
        max_lever_arm: Option<f64>,
        require_zero_pitch: bool,
        drift: DriftTolerances,
        pitch_tol: PitchTol,
    ) -> Self {
        self.max_lever_arm = max_lever_arm;
        self.require_zero_pitch = require_zero_pitch;
        self.drift = drift;
        self.pitch_tol = pitch_tol;
        self
    }

    /// The severity policy: codes accepted (`allow`), refused (`deny`),
    /// and every warning a problem (`deny_warnings`).
    pub fn policy(mut self, allow: Vec<Code>, deny: Vec<Code>, deny_warnings: bool) -> Self {
        self.allow = allow;
        self.deny = deny;
        self.deny_warnings = deny_warnings;
        self
    }

    /// How the files are read (joint values, the size cap, xacro).
    pub fn load(mut self, load: LoadOptions) -> Self {
        self.load = load;
        self
    }

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

/// One checked file's state: its record and where its values are written,
/// with its keys in the baselines compared and written.
struct FileState {
    found: Found,
    record: BaselineFile,
    locations: Locations,
    base_key: Option<String>,
    write_key: Option<String>,
}

/// What one robot's check yields: its findings, which `--pair`s it has,
/// its files' states, how many files it read.
struct Outcome {
    findings: Vec<Diagnostic>,
    notes: Vec<String>,
    pairs_found: Vec<bool>,
    states: Vec<FileState>,
    files: usize,
}

/// The check of one robot, on a worker thread.
struct Checker<'a> {
    opts: &'a CheckOptions,
    findings: Vec<Diagnostic>,
    /// Files read and left to the files that include them.
    notes: Vec<String>,
    pairs_found: Vec<bool>,
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

    /// A detector's own configuration (DCReg's icp.yaml, X-ICP's) sets
    /// thresholds and no extrinsic: its values are checked as the detector
    /// reads them (an error is a finding at its line), a note says what it
    /// is, and it is not read as a calibration. `true` when `path` is one.
    fn detector_config(&mut self, path: &Path) -> Result<Option<Option<ReadWhole>>> {
        match OdometryDetector::sniff_config(path) {
            Ok(super::odometry_config::Sniffed::Config(cfg)) => {
                let label = OdometryDetector::find(cfg.detector).map_or(cfg.detector, |d| d.label);
                self.findings.push(
                    Diagnostic::new(
                        Code::Ignored,
                        format!(
                            "{label} configuration: detector thresholds, no sensor extrinsic; its values read as {label} reads them, nothing else to check"
                        ),
                    )
                    .at(&Location::file(path)),
                );
                Ok(None)
            }
            Ok(super::odometry_config::Sniffed::Other(read)) => Ok(Some(read)),
            Err(e) if e.code == Code::Io => Err(e),
            Err(e) => {
                self.error(path, &e);
                Ok(None)
            }
        }
    }

    /// Load one file of a robot into its graph; its state when it loaded.
    fn load_into(
        &mut self,
        robot: &Robot,
        f: &Found,
        acc: &mut RobotGraph,
    ) -> Result<Option<FileState>> {
        let index = acc.states;
        if let Some(kind) = formats::xacro::include_only(&f.path, &self.opts.load) {
            // An include: noted, not an error; its (empty) record still
            // meets the baseline, so a robot file turned into one is caught.
            self.notes.push(format!(
                "{}: {}: an include, not a robot of its own; checked where a robot file includes it",
                f.path.display(),
                kind.reason()
            ));
            return Ok(Some(FileState {
                found: f.clone(),
                record: BaselineFile {
                    edges: Vec::new(),
                    pairs: Vec::new(),
                },
                locations: Locations::new(),
                base_key: None,
                write_key: None,
            }));
        }
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
        // `None`: a detector's configuration (reported); the file as read
        // when it was read (a YAML file is then not read twice).
        let Some(read) = self.detector_config(&f.path)? else {
            return Ok(None);
        };
        let loaded = match read {
            Some(read) => formats::load_opened(&f.path, read, &self.opts.load),
            None => formats::load_file(&f.path, &self.opts.load),
        };
        let mut loaded = match loaded {
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
                (loc_of(&e.provenance.location), e.provenance.values),
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
        let tol = MistakeTol {
            translation_mm: self.opts.drift.translation_m * 1e3,
            rotation_deg: self.opts.drift.rotation_deg,
        };
        for e in loaded.edges {
            match super::mistakes::second_source(&acc.graph, &e, &tol) {
                Some(Some(finding)) => {
                    self.findings.push(finding);
                    continue;
                }
                Some(None) => continue,
                None => {}
            }
            if let Err(err) = acc.graph.add_edge(e) {
                self.error(&f.path, &err);
            }
        }
        Ok(Some(FileState {
            found: f.clone(),
            record,
            locations,
            base_key: None,
            write_key: None,
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
                .as_deref()
                .map_or_else(|| first_path.clone(), |f| f.to_path_buf());
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
    ) -> Option<(BaselinePair, (Location, ValuesAt))> {
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
        let rep = match rig_verdicts(
            &chain,
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
        here.file = Some(file.into());
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
        let zero_pitch =
            rep.kind == ScrewKind::Identity || rep.pitch_verdict == Some(PitchVerdict::Zero);
        if self.opts.require_zero_pitch && !zero_pitch {
            let h = match (rep.translation_along_axis_m, rep.pitch_verdict) {
                (Some(h), Some(v)) => format!(
                    "screw translation h = {h:.6e} +- {:.1e} m ({}), verdict {}",
                    rep.translation_along_axis_uncertainty_m.unwrap_or(0.0),
                    rep.source.name(),
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
            screw_kind: rep.kind.name().to_string(),
            zero_pitch: rep.kind == ScrewKind::ZeroPitch,
            adapted_metric_exists: rep.adapted_metric_exists,
            declared,
        };
        // One edge: the pair's numbers are that edge's.
        let values = match chain.steps.as_slice() {
            [one] => one.edge.provenance.values,
            _ => ValuesAt::default(),
        };
        Some((pair, (at, values)))
    }
}

/// One unit of work: a manifest's robot, or a walked file on its own (by
/// its index in the walk, so that a fleet's files are not copied).
enum Job {
    Robot(Robot),
    File(usize),
}

impl Job {
    /// The walk's index of the job's one file (`None`: a robot).
    fn walk_index(&self) -> Option<usize> {
        match self {
            Job::File(i) => Some(*i),
            Job::Robot(_) => None,
        }
    }
}

/// Group the files into jobs: each checked directory's `audit.toml` robots
/// (their files loaded together), then every other file on its own. The
/// manifests themselves are not calibration files.
/// Also the manifests' `fleet_tolerance` (m, deg), one value or an error.
fn jobs(
    opts: &CheckOptions,
    files: &mut Vec<Found>,
) -> Result<(Vec<Job>, Option<DriftTolerances>)> {
    files.retain(|f| f.path.file_name().is_none_or(|n| n != manifest::MANIFEST));
    let mut out = Vec::new();
    let mut grouped: HashSet<FileId> = HashSet::new();
    let mut walked: Option<HashSet<FileId>> = None;
    let mut fleet: Option<([f64; 2], &Path)> = None;
    for dir in opts.paths.iter().filter(|p| p.is_dir()) {
        let (robots, tol) = manifest::read(dir)?;
        match (tol, fleet) {
            (Some(t), Some((f, at))) if t != f => {
                return Err(Error::usage(format!(
                    "audit.toml: fleet_tolerance {t:?} here, {f:?} in {}: expected one fleet tolerance (or give --fleet-tolerance)",
                    at.join(manifest::MANIFEST).display()
                ))
                .in_file(dir.join(manifest::MANIFEST)))
            }
            (Some(t), None) => fleet = Some((t, dir)),
            _ => {}
        }
        for r in robots {
            let have = walked
                .get_or_insert_with(|| files.iter().filter_map(|f| file_id(&f.path)).collect());
            for f in &r.files {
                let id = file_id(&f.path);
                if let Some(id) = &id {
                    grouped.insert(*id);
                }
                if !id.is_some_and(|id| have.contains(&id)) {
                    files.push(f.clone());
                }
            }
            out.push(Job::Robot(Robot {
                name: Some(r.name),
                files: r.files,
                renames: r.renames,
                pairs: r.pairs,
            }));
        }
    }
    for (i, f) in files.iter().enumerate() {
        if grouped.is_empty() || !file_id(&f.path).is_some_and(|id| grouped.contains(&id)) {
            out.push(Job::File(i));
        }
    }
    let fleet = fleet.map(|([mm, deg], _)| DriftTolerances {
        translation_m: mm * 1e-3,
        rotation_deg: deg,
    });
    Ok((out, fleet))
}

/// The directory a baseline file's keys are relative to.
fn refused(path: &Path, why: String) -> Error {
    Error::usage(format!("--write-baseline: refused, nothing written: {why}")).in_file(path)
}

/// Refuse a `--write-baseline` target that is a checked input, exists and is
/// not a regular file holding a baseline, is a symlink or lies behind a
/// symlinked directory ([`unsafe_target`]); then take the write lock and read
/// the existing baseline when there is one. Runs before anything is written;
/// the lock is held until the new baseline is in place.
fn write_target(
    path: &Path,
    files: &[Found],
    given: &[PathBuf],
) -> Result<(WriteLock, Option<Store>)> {
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
    let lock = baseline::lock_for_write(&dir, path)?;
    let link = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return match unsafe_target(path) {
                Some(why) => Err(refused(path, why)),
                None => Ok((lock, None)),
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
    let id = file_id(path);
    if files.iter().any(|f| id.is_some() && file_id(&f.path) == id)
        || given.iter().any(|g| same_file(g, path))
    {
        return Err(refused(
            path,
            "it is one of the checked calibration files: expected a separate baseline file".into(),
        ));
    }
    if let Some(why) = unsafe_target(path) {
        return Err(refused(path, why));
    }
    let old = baseline::read_store(path).map_err(|e| {
        refused(
            path,
            format!("it exists and is not a baseline ({})", e.message),
        )
    })?;
    Ok((lock, Some(old)))
}

/// Keys of checked files in a baseline kept in one directory; the checked
/// roots' real paths found once, not per file.
struct KeyDir {
    dir: PathBuf,
    roots: Mutex<HashMap<PathBuf, PathBuf>>,
}

impl KeyDir {
    fn new(baseline: &Path) -> Result<Self> {
        let dir = dir_of(baseline);
        Ok(KeyDir {
            dir: dir.canonicalize().map_err(|e| Error::io(&dir, &e))?,
            roots: Mutex::new(HashMap::new()),
        })
    }

    fn key(&self, f: &Found) -> Result<String> {
        let known = self
            .roots
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&f.root)
            .cloned();
        let root = match known {
            Some(r) => r,
            None => {
                let r = f.root.canonicalize().map_err(|e| Error::io(&f.root, &e))?;
                let mut m = self.roots.lock().unwrap_or_else(|e| e.into_inner());
                m.insert(f.root.clone(), r.clone());
                r
            }
        };
        baseline::key_in(&f.path, &f.root, &root, &self.dir)
    }
}

/// Check one robot on a worker: its findings, the `--pair`s it has, its
/// files' states with their keys.
fn check_one(
    opts: &CheckOptions,
    robot: &Robot,
    base: Option<&KeyDir>,
    write: Option<&KeyDir>,
) -> Result<Outcome> {
    let mut ck = Checker {
        opts,
        findings: Vec::new(),
        notes: Vec::new(),
        pairs_found: vec![false; opts.pairs.len()],
    };
    let mut states = ck.check_robot(robot)?;
    for st in &mut states {
        st.base_key = base.map(|k| k.key(&st.found)).transpose()?;
        st.write_key = write.map(|k| k.key(&st.found)).transpose()?;
    }
    Ok(Outcome {
        findings: ck.findings,
        notes: ck.notes,
        pairs_found: ck.pairs_found,
        states,
        files: robot.files.len(),
    })
}

/// What the run gathers as results arrive, in order: the findings, the
/// baseline's comparison, the records of the baseline to write.
struct Gathered<'a> {
    opts: &'a CheckOptions,
    findings: Vec<Diagnostic>,
    /// Files read and left to the files that include them, in order.
    notes: Vec<String>,
    pairs_found: Vec<bool>,
    /// The baseline compared against, and which of its entries were checked.
    base: Option<(&'a Store, Vec<bool>)>,
    /// Baseline findings by key (sorted by key at the end, as a baseline is).
    compared: Vec<(String, Diagnostic)>,
    /// With `--fleet-tolerance`: every checked pair, in the walk's order.
    fleet: super::fleet::Fleet,
    /// The checked files' records for `--write-baseline`.
    written: Store,
}

impl Gathered<'_> {
    /// `walk`: the walk's index of the outcome's one file (`None`: a robot).
    fn take(&mut self, out: Outcome, walk: Option<usize>) {
        self.findings.extend(out.findings);
        self.notes.extend(out.notes);
        for (f, now) in self.pairs_found.iter_mut().zip(out.pairs_found) {
            *f |= now;
        }
        for st in out.states {
            if self.opts.fleet.is_some() {
                for p in &st.record.pairs {
                    let at = st
                        .locations
                        .get(&(p.transform.parent.clone(), p.transform.child.clone()))
                        .map(|(at, values)| values.locate(at, true));
                    self.fleet.add(walk, &st.found.path, at.as_ref(), p);
                }
            }
            if let (Some((base, seen)), Some(key)) = (&mut self.base, &st.base_key) {
                let now = CheckedFile {
                    path: &st.found.path,
                    record: &st.record,
                    locations: &st.locations,
                };
                let found = match base.find(key) {
                    Some(i) => {
                        seen[i] = true;
                        if base.holds(i, &st.record) {
                            Vec::new()
                        } else {
                            baseline::compare_file(&now, &base.record(i), self.opts.drift)
                        }
                    }
                    None => vec![baseline::new_file(now.path)],
                };
                self.compared
                    .extend(found.into_iter().map(|d| (key.clone(), d)));
            }
            if let Some(key) = &st.write_key {
                self.written.insert(key, &st.record);
            }
        }
    }

    /// The baseline's findings in key order, then its entries whose files
    /// are gone.
    fn baseline_findings(&mut self, dir: &Path) -> Vec<Diagnostic> {
        let mut compared = std::mem::take(&mut self.compared);
        compared.sort_by(|a, b| a.0.cmp(&b.0));
        let mut out: Vec<Diagnostic> = compared.into_iter().map(|(_, d)| d).collect();
        if let Some((base, seen)) = &self.base {
            for i in (0..base.len()).filter(|&i| !seen[i]) {
                out.extend(baseline::removed_file(base.key(i), dir));
            }
        }
        out
    }
}

/// Merge the checked files (`now`, sorted) into `old` (or replace it with
/// `prune`), write the result to `path`, and say what changed.
fn merge_and_write(
    old: Option<Store>,
    mut now: Store,
    prune: bool,
    path: &Path,
) -> Result<BaselineChanges> {
    let old = old.unwrap_or_default();
    now.finish();
    let mut ch = BaselineChanges {
        path: path.to_string_lossy().replace('\\', "/"),
        ..BaselineChanges::default()
    };
    // Both sorted: one pass, the checked file's record winning; a key
    // checked twice keeps its last record (as a map insert would).
    let mut order: Vec<(bool, usize)> = Vec::with_capacity(old.len() + now.len());
    let (mut i, mut j) = (0, 0);
    while i < old.len() || j < now.len() {
        if j + 1 < now.len() && now.key(j) == now.key(j + 1) {
            j += 1;
            continue;
        }
        let take_now = j < now.len() && (i >= old.len() || now.key(j) <= old.key(i));
        if take_now {
            let key = now.key(j);
            match (i < old.len() && old.key(i) == key).then_some(i) {
                Some(o) => {
                    if old.holds(o, &now.record(j)) {
                        ch.unchanged += 1;
                    } else {
                        ch.updated.push(key.to_string());
                    }
                    i += 1;
                }
                None => ch.added.push(key.to_string()),
            }
            order.push((true, j));
            j += 1;
        } else {
            if prune {
                ch.removed.push(old.key(i).to_string());
            } else {
                order.push((false, i));
            }
            i += 1;
        }
    }
    let entries = |(fresh, k): &(bool, usize)| {
        let s = if *fresh { &now } else { &old };
        (s.key(*k), s.record(*k))
    };
    write_atomic_with(path, &mut |w| {
        baseline::stream::write_to(w, order.iter().map(entries))
    })?;
    Ok(ch)
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

/// The walked files that are calibrations: not the baseline compared
/// against, not a baseline at all.
fn calibration_files(opts: &CheckOptions) -> Result<super::walk::Walked> {
    let mut walked = walk(&opts.paths, &opts.exclude)?;
    let base = opts.baseline.as_deref().and_then(file_id);
    walked.files.retain(|f| {
        base.is_none_or(|b| file_id(&f.path) != Some(b)) && !baseline::is_baseline_file(&f.path)
    });
    Ok(walked)
}

/// [`check`], reporting one step per file read to `progress` (a large
/// directory takes seconds). The robots are checked on every core
/// (`pipeline::parallel`), their results taken in the walk's order.
pub fn check_with(opts: &CheckOptions, progress: &dyn Progress) -> Result<CheckReport> {
    if !opts.load.renames.is_empty() {
        return Err(Error::usage(
            "check: expected renames in each directory's audit.toml (per robot), found renames in the load options",
        ));
    }
    let mut walked = calibration_files(opts)?;
    let given: Vec<PathBuf> = opts
        .paths
        .iter()
        .filter(|p| !baseline::is_baseline_file(p))
        .cloned()
        .collect();
    let (lock, old) = match &opts.write_baseline {
        Some(p) => {
            let (l, old) = write_target(p, &walked.files, &given)?;
            (Some(l), old)
        }
        None => (None, None),
    };
    if let Some(b) = opts.baseline.as_deref().filter(|b| !b.exists()) {
        return Err(Error::usage(format!(
            "--baseline {}: no such file; write one first with `audit check PATHS --write-baseline {}` and commit it",
            b.display(),
            b.display()
        ))
        .in_file(b));
    }
    let base = opts
        .baseline
        .as_deref()
        .map(baseline::read_store)
        .transpose()?;
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
    let (jobs, manifest_fleet) = jobs(opts, &mut walked.files)?;
    // The flag wins over the manifests' `fleet_tolerance`.
    let with_fleet;
    let opts = match (&opts.fleet, manifest_fleet) {
        (None, Some(t)) => {
            with_fleet = CheckOptions {
                fleet: Some(t),
                ..opts.clone()
            };
            &with_fleet
        }
        _ => opts,
    };
    let base_keys = opts.baseline.as_deref().map(KeyDir::new).transpose()?;
    let write_keys = opts
        .write_baseline
        .as_deref()
        .map(KeyDir::new)
        .transpose()?;
    let mut all = Gathered {
        opts,
        findings: std::mem::take(&mut walked.findings),
        notes: Vec::new(),
        pairs_found: vec![false; opts.pairs.len()],
        base: base.as_ref().map(|b| (b, vec![false; b.len()])),
        compared: Vec::new(),
        written: Store::new(),
        fleet: super::fleet::Fleet::with_capacity(opts.fleet.map_or(0, |_| walked.files.len())),
    };
    let total: usize = jobs
        .iter()
        .map(|j| match j {
            Job::Robot(r) => r.files.len(),
            Job::File(_) => 1,
        })
        .sum();
    progress.start(total as u64, "files checked");
    let mut failed = None;
    let files = &walked.files;
    super::parallel::ordered(
        &jobs,
        |_, job: &Job| match job {
            Job::Robot(r) => check_one(opts, r, base_keys.as_ref(), write_keys.as_ref()),
            Job::File(i) => {
                let r = Robot {
                    files: vec![files[*i].clone()],
                    ..Robot::default()
                };
                check_one(opts, &r, base_keys.as_ref(), write_keys.as_ref())
            }
        },
        |k, out| match out {
            Ok(out) => {
                progress.advance(out.files as u64);
                all.take(out, jobs[k].walk_index());
                true
            }
            Err(e) => {
                failed = Some(e);
                false
            }
        },
    );
    progress.finish();
    if let Some(e) = failed {
        return Err(e);
    }
    finish(opts, all, &walked.files, old, lock)
}

/// After every robot: the `--pair`s found nowhere, the baseline's findings,
/// the baseline written (the lock released once it is in place), the
/// severity policy.
fn finish(
    opts: &CheckOptions,
    mut all: Gathered,
    files: &[Found],
    old: Option<Store>,
    lock: Option<WriteLock>,
) -> Result<CheckReport> {
    for (i, found) in all.pairs_found.clone().iter().enumerate() {
        if !found {
            let (a, b) = &opts.pairs[i];
            all.findings.push(
                Diagnostic::new(
                    Code::Frame,
                    format!(
                        "--pair {a}:{b}: no checked file has both frames (checked: {})",
                        checked_list(files)
                    ),
                )
                .at(&Location::default()),
            );
        }
    }
    if let Some(path) = &opts.baseline {
        let found = all.baseline_findings(&dir_of(path));
        all.findings.extend(found);
    }
    if let Some(tol) = &opts.fleet {
        all.findings
            .extend(super::fleet::findings(&all.fleet, tol, files));
    }
    let mut changes = None;
    if let Some(path) = &opts.write_baseline {
        let written = std::mem::take(&mut all.written);
        changes = Some(merge_and_write(old, written, opts.prune, path)?);
    }
    drop(lock);
    let mut findings = all.findings;
    for f in &mut findings {
        f.severity = opts.severity(f);
    }
    let mut report = CheckReport::new(files.len(), findings);
    report.baseline_written = changes;
    report.notes = all.notes;
    Ok(report)
}
