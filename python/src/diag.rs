//! Diagnostics across the border: an `Error` becomes the `AuditError`
//! subclass of its code (made by `extrinsic_audit._errors.make_error`, the one
//! table of code -> class), a `Warning` a tuple the Python layer hands to
//! `warnings.warn` (`_errors.warn_all`); the options every loader shares
//! read from one dict.

use extrinsic_audit::{Diagnostic, Error, Format, LoadOptions, Rename, UrdfVersion};
use pyo3::prelude::*;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A diagnostic as the Python layer takes it: (code, severity, file, line,
/// column, message, help).
pub type DiagTuple = (
    &'static str,
    &'static str,
    Option<String>,
    Option<usize>,
    Option<usize>,
    String,
    Option<String>,
);

/// One diagnostic as its tuple.
pub fn tuple(d: &Diagnostic) -> DiagTuple {
    let severity = match d.severity {
        extrinsic_audit::Severity::Error => "error",
        extrinsic_audit::Severity::Warning => "warning",
    };
    (
        d.code.name(),
        severity,
        d.location.file.as_ref().map(|p| p.display().to_string()),
        d.location.line,
        d.location.column,
        d.message.clone(),
        d.help.clone(),
    )
}

/// Warnings as tuples.
pub fn tuples(ws: &[Diagnostic]) -> Vec<DiagTuple> {
    ws.iter().map(tuple).collect()
}

/// The library's error as the Python exception of its code.
pub fn to_py(e: Error) -> PyErr {
    Python::attach(|py| {
        let made = py
            .import("extrinsic_audit._errors")
            .and_then(|m| m.getattr("make_error"))
            .and_then(|f| f.call1(tuple(&e)));
        match made {
            Ok(exc) => PyErr::from_value(exc),
            Err(err) => err,
        }
    })
}

/// `Result<T>` to `PyResult<T>`.
pub trait IntoPy<T> {
    /// The error as its `AuditError`.
    fn py(self) -> PyResult<T>;
}

impl<T> IntoPy<T> for extrinsic_audit::Result<T> {
    fn py(self) -> PyResult<T> {
        self.map_err(to_py)
    }
}

/// The keyword arguments of `load` that say how files are read (the Python
/// layer passes every key).
#[derive(Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct LoadArgs {
    /// `(file or None, old, new)`: `--rename [FILE:]OLD=NEW`.
    pub renames: Vec<(Option<String>, String, String)>,
    pub joints: BTreeMap<String, f64>,
    pub xacro_args: BTreeMap<String, String>,
    pub package_paths: Vec<PathBuf>,
    pub key: Option<String>,
    pub invert: bool,
    pub input_format: Option<String>,
    /// `--urdf-version X.Y`.
    pub urdf_version: Option<String>,
    /// `--max-file-size BYTES` (`None`: the default).
    pub max_file_size: Option<u64>,
    /// `--xacro native|external`.
    pub xacro: String,
    /// Where the external `xacro` program is looked for (a `PATH`-style
    /// list; `None`: the process's `PATH`).
    pub xacro_path: Option<std::ffi::OsString>,
    /// `--tf-static-topic` (empty: `/tf_static`).
    pub tf_static_topics: Vec<String>,
    /// `--tf-topic`.
    pub tf_topics: Vec<String>,
    /// `--description-topic` (empty: `/robot_description`).
    pub description_topics: Vec<String>,
}

impl LoadArgs {
    /// The library's options.
    pub fn options(&self) -> extrinsic_audit::Result<LoadOptions> {
        let mut o = LoadOptions::default();
        o.renames = self
            .renames
            .iter()
            .map(|(file, old, new)| Rename {
                file: file.clone(),
                old: old.clone(),
                new: new.clone(),
            })
            .collect();
        o.joints = self.joints.clone();
        o.xacro_args = self.xacro_args.clone();
        o.package_paths = self.package_paths.clone();
        o.key = self.key.clone();
        o.invert = self.invert;
        o.format = self
            .input_format
            .as_deref()
            .map(Format::from_name)
            .transpose()?;
        o.urdf_version = self
            .urdf_version
            .as_deref()
            .map(|v| UrdfVersion::parse(v).map_err(|e| Error::usage(format!("urdf_version: {e}"))))
            .transpose()?;
        if let Some(n) = self.max_file_size {
            o.max_file_size = n;
        }
        o.xacro_external = match self.xacro.as_str() {
            "native" => false,
            "external" => true,
            x => {
                return Err(Error::usage(format!(
                    "xacro: expected \"native\" or \"external\", found `{x}`"
                )))
            }
        };
        o.xacro_search_path = self.xacro_path.clone();
        if !self.tf_static_topics.is_empty() {
            o.bag.static_topics = self.tf_static_topics.clone();
        }
        o.bag.tf_topics = self.tf_topics.clone();
        if !self.description_topics.is_empty() {
            o.bag.description_topics = self.description_topics.clone();
        }
        Ok(o)
    }
}

/// `pitch_tol`: `None` or "auto", else a tolerance on `|h|` (m), as
/// `--pitch-tol` reads it.
pub fn pitch_tol(s: Option<&str>) -> extrinsic_audit::Result<extrinsic_audit::PitchTol> {
    match s {
        None => Ok(extrinsic_audit::PitchTol::Auto),
        Some(s) => s
            .parse()
            .map_err(|e| Error::usage(format!("pitch_tol: {e}"))),
    }
}

/// The JSON of a report, as the CLI writes it (`--format json`, paths under
/// the working directory relative to it), with the warnings.
pub fn json<R: extrinsic_audit::Report>(
    report: &R,
    warnings: &[Diagnostic],
) -> extrinsic_audit::Result<String> {
    let mut opts = extrinsic_audit::RenderOptions::default();
    opts.warnings = warnings.to_vec();
    opts.cwd = std::env::current_dir().ok();
    extrinsic_audit::render(report, extrinsic_audit::OutputFormat::Json, &opts)
}
