//! `audit check`: every file parses; rotations are orthonormal, quaternions
//! unit, units plausible (the readers' warnings for these are findings); the
//! frames each rig declares, and every `--pair`, exist and connect; optional
//! lever-arm and zero-pitch rules; against a baseline, drift and verdicts
//! (`crate::baseline`).
//!
//! A file that exists but does not parse is a finding; an unreadable file or
//! baseline is an error (exit 2).

use super::{expand_paths, write_atomic};
use crate::baseline::{self, Baseline, BaselineFile, BaselinePair, BaselineTransform, Tolerances};
use crate::diagnostic::{Code, Diagnostic, Error, Location, Result, Severity, Warning};
use crate::formats::{self, is_calibration_file, LoadOptions};
use crate::frames::FrameGraph;
use crate::geometry::ScrewKind;
use crate::report::rig::rig_report;
use crate::report::CheckReport;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What `audit check` is asked to check.
#[derive(Debug, Clone)]
pub struct CheckOptions {
    /// Calibration files or directories of them.
    pub paths: Vec<PathBuf>,
    /// Compare against this baseline.
    pub baseline: Option<PathBuf>,
    /// Write the current state as a baseline.
    pub write_baseline: Option<PathBuf>,
    /// Also check these frame pairs wherever both frames exist.
    pub pairs: Vec<(String, String)>,
    /// A finding when a checked pair's lever arm exceeds this (m).
    pub max_lever_arm: Option<f64>,
    /// A finding when a checked pair does not have zero screw pitch.
    pub require_zero_pitch: bool,
    /// Drift tolerances against the baseline.
    pub drift: Tolerances,
    /// Zero-pitch tolerance on `|h|` (m).
    pub pitch_tol: f64,
    /// How files are read (joint values, size cap).
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

fn key_of(p: &Path) -> String {
    p.to_string_lossy().replace('\\', "/")
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
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

struct Checker<'a> {
    opts: &'a CheckOptions,
    findings: Vec<Diagnostic>,
}

impl Checker<'_> {
    /// A reader's error as a finding on `file`.
    fn error(&mut self, file: &str, e: &Error) {
        self.findings
            .push(e.clone().with_severity(Severity::Error).in_file(file));
    }

    fn warning(&mut self, file: &str, w: &Warning) {
        let mut d = w.clone();
        // The finding names the checked file; the line is the warning's own.
        d.location = Location {
            file: Some(PathBuf::from(file)),
            line: w.location.line,
            column: None,
        };
        self.findings.push(d);
    }

    fn push(&mut self, code: Code, file: &str, line: Option<usize>, message: String) {
        let mut d = Diagnostic::new(code, message);
        if !file.is_empty() {
            d.location = Location {
                file: Some(PathBuf::from(file)),
                line,
                column: None,
            };
        }
        self.findings.push(d);
    }

    /// Check one file; returns its baseline record when it loaded.
    fn check_file(
        &mut self,
        path: &Path,
        pairs_found: &mut [bool],
    ) -> Result<Option<BaselineFile>> {
        let file = key_of(path);
        let loaded = match formats::load_file(path, &self.opts.load) {
            Ok(l) => l,
            Err(e) if e.code == Code::Io => return Err(e),
            Err(e) => {
                self.error(&file, &e);
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
            self.error(&file, &e);
            return Ok(None);
        }
        for w in graph.warnings().to_vec() {
            self.warning(&file, &w);
        }
        let frames = graph.frames();
        let mut record = BaselineFile {
            edges: graph
                .edges()
                .iter()
                .map(BaselineTransform::of_edge)
                .collect(),
            pairs: Vec::new(),
        };
        let mut pairs: Vec<(String, String, bool)> = rig_pair.into_iter().collect();
        for (i, (a, b)) in self.opts.pairs.iter().enumerate() {
            if frames.contains(a) && frames.contains(b) {
                pairs_found[i] = true;
                pairs.push((a.clone(), b.clone(), false));
            }
        }
        for (from, to, declared) in pairs {
            if let Some(p) = self.check_pair(&graph, &file, &from, &to, declared) {
                record.pairs.push(p);
            }
        }
        Ok(Some(record))
    }

    /// The rules on one frame pair; its baseline record when it composes.
    fn check_pair(
        &mut self,
        graph: &FrameGraph,
        file: &str,
        from: &str,
        to: &str,
        declared: bool,
    ) -> Option<BaselinePair> {
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
        let rep = match rig_report(&chain, &[1.0], self.opts.pitch_tol) {
            Ok(r) => r,
            Err(e) => {
                self.error(file, &e);
                return None;
            }
        };
        let line = chain
            .steps
            .last()
            .and_then(|s| s.edge.provenance.location.line);
        if let Some(max) = self.opts.max_lever_arm.filter(|m| rep.lever_arm_m > *m) {
            self.push(
                Code::LeverArm,
                file,
                line,
                format!(
                    "{from} -> {to}: lever arm {:.6} m exceeds --max-lever-arm {max} m",
                    rep.lever_arm_m
                ),
            );
        }
        let zero_pitch = matches!(rep.screw.kind, ScrewKind::ZeroPitch | ScrewKind::Identity);
        if self.opts.require_zero_pitch && !zero_pitch {
            let h = rep
                .screw
                .translation_along_axis_m
                .map(|h| format!("screw translation h = {h:.6e} m"))
                .unwrap_or_else(|| "a pure translation (infinite pitch)".into());
            self.push(
                Code::NonzeroPitch,
                file,
                line,
                format!(
                    "{from} -> {to}: expected zero screw pitch (|h| <= {:e} m), found {h}",
                    self.opts.pitch_tol
                ),
            );
        }
        Some(BaselinePair {
            transform: BaselineTransform::new(from, to, &chain.transform),
            lever_arm_m: rep.lever_arm_m,
            screw_kind: rep.screw.kind.name().to_string(),
            zero_pitch: rep.screw.kind == ScrewKind::ZeroPitch,
            adapted_metric_exists: rep.adapted_metric.exists,
        })
    }
}

/// Run the check; writes the baseline when asked.
pub fn check(opts: &CheckOptions) -> Result<CheckReport> {
    let base = opts.baseline.as_deref().map(baseline::read).transpose()?;
    let mut files = expand_paths(&opts.paths, is_calibration_file)?;
    files.retain(|f| {
        ![&opts.baseline, &opts.write_baseline]
            .iter()
            .any(|b| b.as_deref().is_some_and(|b| same_file(f, b)))
            && !baseline::is_baseline_file(f)
    });
    if files.is_empty() {
        return Err(Error::usage(
            "no calibration files found under the given paths",
        ));
    }
    let mut ck = Checker {
        opts,
        findings: Vec::new(),
    };
    let mut pairs_found = vec![false; opts.pairs.len()];
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
            let (a, b) = &opts.pairs[i];
            ck.push(
                Code::Frame,
                "",
                None,
                format!(
                    "--pair {a}:{b}: no checked file has both frames (checked: {})",
                    checked_list(&files)
                ),
            );
        }
    }
    if let Some(base) = &base {
        ck.findings
            .extend(baseline::compare(&current, base, opts.drift));
    }
    if let Some(path) = &opts.write_baseline {
        // Never write an empty or partial baseline: a serialisation error is
        // an error, not "".
        let mut text = serde_json::to_string_pretty(&current).map_err(|e| {
            Error::new(Code::Io, format!("cannot serialise the baseline: {e}")).in_file(path)
        })?;
        text.push('\n');
        write_atomic(path, text.as_bytes())?;
    }
    for f in &mut ck.findings {
        f.severity = opts.severity(f);
    }
    Ok(CheckReport::new(files.len(), ck.findings))
}
