//! The commands over calibration files: `check` (the CI gate), `diff` and
//! `survey`, each giving its report's JSON as the CLI writes it. GIL
//! released throughout.

use crate::diag::{json, pitch_tol, tuples, DiagTuple, IntoPy, LoadArgs};
use clap::ValueEnum;
use extrinsic_audit::SurveyOptions;
use extrinsic_audit::{
    CheckOptions, Code, DiffOptions, DriftTolerances, Error, LoadOptions, SortColumn,
};
use pyo3::prelude::*;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// `check`'s keyword arguments (every key passed by the Python layer).
#[derive(Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct CheckArgs {
    pub baseline: Option<PathBuf>,
    pub write_baseline: Option<PathBuf>,
    pub prune: bool,
    pub exclude: Vec<String>,
    pub pairs: Vec<(String, String)>,
    pub max_lever_arm: Option<f64>,
    pub require_zero_pitch: bool,
    pub max_translation_drift: Option<f64>,
    pub max_rotation_drift: Option<f64>,
    pub pitch_tol: Option<String>,
    pub joints: BTreeMap<String, f64>,
    pub allow: Vec<String>,
    pub deny: Vec<String>,
    pub deny_warnings: bool,
}

fn codes(names: &[String], what: &str) -> extrinsic_audit::Result<Vec<Code>> {
    names
        .iter()
        .map(|n| {
            Code::from_name(n).ok_or_else(|| {
                Error::usage(format!("{what}: expected a diagnostic code, found `{n}`"))
            })
        })
        .collect()
}

impl CheckArgs {
    fn options(&self, paths: Vec<PathBuf>) -> extrinsic_audit::Result<CheckOptions> {
        let d = DriftTolerances::default();
        let drift = DriftTolerances {
            translation_m: self.max_translation_drift.unwrap_or(d.translation_m),
            rotation_deg: self.max_rotation_drift.unwrap_or(d.rotation_deg),
        };
        let mut load = LoadOptions::default();
        load.joints = self.joints.clone();
        let pitch = pitch_tol(self.pitch_tol.as_deref())?;
        let (allow, deny) = (codes(&self.allow, "allow")?, codes(&self.deny, "deny")?);
        Ok(CheckOptions::new(paths)
            .baseline(
                self.baseline.clone(),
                self.write_baseline.clone(),
                self.prune,
            )
            .walk(self.exclude.clone(), self.pairs.clone())
            .gate(self.max_lever_arm, self.require_zero_pitch, drift, pitch)
            .policy(allow, deny, self.deny_warnings)
            .load(load))
    }
}

/// `audit check PATHS...`: the report's JSON and its exit code (0 clean, 1
/// findings).
#[pyfunction]
pub fn check(py: Python<'_>, paths: Vec<PathBuf>, args: CheckArgs) -> PyResult<(String, i32)> {
    let opts = args.options(paths).py()?;
    py.detach(|| {
        let report = extrinsic_audit::check(&opts)?;
        Ok((json(&report, &[])?, report.exit_code()))
    })
    .py()
}

/// `diff`'s keyword arguments.
#[derive(Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct DiffArgs {
    pub frm: Option<String>,
    pub to: Option<String>,
    pub key_old: Option<String>,
    pub key_new: Option<String>,
    pub invert_old: bool,
    pub invert_new: bool,
    pub ells: Option<Vec<f64>>,
    pub pitch_tol: Option<String>,
    pub tolerance: Option<(f64, f64)>,
}

/// `audit diff OLD NEW`: the report's JSON (as the CLI's, without the
/// warnings), the warnings, and whether a change exceeded the tolerance.
#[pyfunction]
pub fn diff(
    py: Python<'_>,
    old: PathBuf,
    new: PathBuf,
    args: DiffArgs,
    load: LoadArgs,
) -> PyResult<(String, Vec<DiagTuple>, bool)> {
    let mut opts = DiffOptions::new(old, new);
    opts.from = args.frm;
    opts.to = args.to;
    opts.load = load.options().py()?;
    opts.old_read.key = args.key_old;
    opts.old_read.invert = args.invert_old;
    opts.new_read.key = args.key_new;
    opts.new_read.invert = args.invert_new;
    if let Some(ells) = args.ells {
        opts.rig.ells = ells;
    }
    opts.rig.pitch_tol = pitch_tol(args.pitch_tol.as_deref()).py()?;
    if let Some((mm, deg)) = args.tolerance {
        opts.tolerance.translation_mm = mm;
        opts.tolerance.rotation_deg = deg;
    }
    py.detach(|| {
        let (report, warnings) = extrinsic_audit::diff(&opts)?;
        let exceeded = !report.exceeded.is_empty();
        Ok((json(&report, &[])?, tuples(&warnings), exceeded))
    })
    .py()
}

/// `survey`'s keyword arguments.
#[derive(Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct SurveyArgs {
    pub all: bool,
    pub sort: Option<String>,
    pub pair: Option<(String, String)>,
    pub pitch_tol: Option<String>,
}

/// `audit survey PATHS...`: the report's JSON (warnings in it) and the
/// warnings.
#[pyfunction]
pub fn survey(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    args: SurveyArgs,
    load: LoadArgs,
) -> PyResult<(String, Vec<DiagTuple>)> {
    let mut opts = SurveyOptions::default();
    opts.paths = paths;
    opts.all = args.all;
    opts.sort = args
        .sort
        .as_deref()
        .map(|s| {
            SortColumn::from_str(s, true)
                .map_err(|_| Error::usage(format!("sort: expected a survey column, found `{s}`")))
        })
        .transpose()
        .py()?;
    opts.pair = args.pair;
    opts.pitch_tol = pitch_tol(args.pitch_tol.as_deref()).py()?;
    opts.load = load.options().py()?;
    py.detach(|| {
        let (report, warnings) = extrinsic_audit::survey(&opts)?;
        Ok((json(&report, &warnings)?, tuples(&warnings)))
    })
    .py()
}
