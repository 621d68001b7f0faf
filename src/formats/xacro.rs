//! xacro: a `.xacro` file is expanded by the `xacro` program when it is on PATH
//! (`xacro FILE`, its standard output parsed as URDF; line numbers then refer to
//! the expanded text), otherwise refused with the command to run.

use crate::diagnostic::{Error, Result};
use crate::formats::registry::FormatSpec;
use crate::formats::{urdf, LoadOptions, Loaded};
use std::path::Path;

/// Whether URDF text still holds xacro: the namespace, elements or
/// substitutions.
pub fn has_markers(text: &str) -> bool {
    text.contains("xmlns:xacro")
        || text.contains("<xacro:")
        || text.contains("${")
        || text.contains("$(")
}

/// The command that expands `path`, for messages.
pub fn advice(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_else(|| "robot.urdf.xacro".to_string());
    let out = name
        .strip_suffix(".xacro")
        .map(|s| {
            if s.ends_with(".urdf") {
                s.to_string()
            } else {
                format!("{s}.urdf")
            }
        })
        .unwrap_or_else(|| "robot.urdf".to_string());
    let out = if out == name {
        "expanded.urdf".to_string()
    } else {
        out
    };
    format!("expand it first: `xacro {name} > {out}` (pip install xacro), then pass {out}")
}

fn find_on_path(prog: &str, search: Option<&std::ffi::OsStr>) -> Option<std::path::PathBuf> {
    let path = match search {
        Some(s) => s.to_os_string(),
        None => std::env::var_os("PATH")?,
    };
    std::env::split_paths(&path)
        .map(|d| d.join(prog))
        .find(|p| p.is_file())
}

/// A `.xacro` file: expand with the `xacro` program if present, else refuse.
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    let _ = text;
    let Some(xacro) = find_on_path("xacro", opts.xacro_search_path.as_deref()) else {
        return Err(Error::parse(format!(
            "this is a xacro file, not URDF, and the `xacro` program is not on PATH: {}",
            advice(path)
        )));
    };
    let out = std::process::Command::new(&xacro)
        .arg(path)
        .output()
        .map_err(|e| Error::parse(format!("running {}: {e}", xacro.display())))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(Error::parse(format!(
            "xacro could not expand this file ({}): {}",
            out.status,
            err.lines().last().unwrap_or("").trim()
        )));
    }
    let expanded = String::from_utf8(out.stdout)
        .map_err(|_| Error::parse("xacro printed something that is not UTF-8"))?;
    let mut loaded = urdf::parse(&expanded, path, opts)?;
    for e in &mut loaded.edges {
        e.provenance.key = format!("{} (line in xacro's expanded output)", e.provenance.key);
    }
    Ok(loaded)
}

/// xacro macro files.
pub const SPEC: FormatSpec = FormatSpec {
    id: "xacro",
    description: "xacro macro file: expanded with the `xacro` program when it is on PATH, otherwise refused with the command to run",
    extensions: &["xacro", "urdf.xacro"],
    walk: &[".xacro"],
    sniff: |_| None,
    parse,
};
