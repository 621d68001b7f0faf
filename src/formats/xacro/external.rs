//! The explicit fallback (`--xacro external`): run the `xacro` program found
//! on the search path and read its output as URDF. Line numbers then refer to
//! xacro's printed output, not to the source files.

use super::advice;
use crate::diagnostic::{Error, Result};
use crate::formats::{urdf, LoadOptions, Loaded};
use std::path::Path;

fn find_on_path(prog: &str, search: Option<&std::ffi::OsStr>) -> Option<std::path::PathBuf> {
    let path = match search {
        Some(s) => s.to_os_string(),
        None => std::env::var_os("PATH")?,
    };
    std::env::split_paths(&path)
        .map(|d| d.join(prog))
        .find(|p| p.is_file())
}

/// Expand `path` with the external `xacro` program, passing `--arg`s as
/// `name:=value`.
pub fn parse(path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    let Some(xacro) = find_on_path("xacro", opts.xacro_search_path.as_deref()) else {
        return Err(Error::parse(format!(
            "--xacro external: the `xacro` program is not on PATH ({})",
            advice(path)
        )));
    };
    let out = std::process::Command::new(&xacro)
        .arg(path)
        .args(opts.xacro_args.iter().map(|(k, v)| format!("{k}:={v}")))
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
