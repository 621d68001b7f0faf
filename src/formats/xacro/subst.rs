//! `$(...)` substitution arguments and package lookup.
//!
//! `$(arg x)` (from `--arg x=VALUE`, else the `xacro:arg` default),
//! `$(find pkg)`, `$(env X)`, `$(optenv X default words)`, `$(dirname)` (the
//! directory of the file being read), `$(cwd)`. `$(eval ...)`, `$(anon ...)`
//! and any other command are refused by name.
//!
//! `$(find pkg)` is the package's directory, searched in this order:
//! `--package-path DIR` (a package directory, or a directory holding packages),
//! `ROS_PACKAGE_PATH` (same crawl), `AMENT_PREFIX_PATH` (`PREFIX/share/pkg`),
//! then upwards from the input file: each ancestor directory that is the
//! package, or holds it a few levels down (a source checkout keeps its
//! packages side by side). A package is a directory with a `package.xml`
//! whose `<name>` is `pkg`.

use crate::tolerances::{
    DEFAULT_MAX_FILE_SIZE, XACRO_PACKAGE_SEARCH_DEPTH, XACRO_PACKAGE_SEARCH_UP,
};
use std::path::{Path, PathBuf};

/// The `<name>` of the package in `dir`, if `dir/package.xml` is a regular
/// file of UTF-8 text (at most the default file-size cap).
fn package_name(dir: &Path) -> Option<String> {
    let p = dir.join("package.xml");
    let bytes = crate::input::read_file(&p, DEFAULT_MAX_FILE_SIZE).ok()?;
    let text = String::from_utf8(bytes).ok()?;
    let start = text.find("<name>")? + "<name>".len();
    let end = start + text[start..].find("</name>")?;
    Some(text[start..end].trim().to_string())
}

/// `pkg` in `dir` or below it, at most `depth` levels down (a package's own
/// subdirectories are not searched).
fn crawl(dir: &Path, pkg: &str, depth: usize) -> Option<PathBuf> {
    if let Some(name) = package_name(dir) {
        return (name == pkg).then(|| dir.to_path_buf());
    }
    if depth == 0 {
        return None;
    }
    let mut subdirs: Vec<PathBuf> = std::fs::read_dir(dir)
        .ok()?
        .filter_map(|e| e.ok())
        .filter(|e| e.file_type().map(|t| t.is_dir()).unwrap_or(false))
        .filter(|e| !e.file_name().to_string_lossy().starts_with('.'))
        .map(|e| e.path())
        .collect();
    subdirs.sort();
    // The directory named like the package first (the common layout).
    if let Some(i) = subdirs
        .iter()
        .position(|d| d.file_name().is_some_and(|n| n == pkg))
    {
        let d = subdirs.remove(i);
        subdirs.insert(0, d);
    }
    subdirs.iter().find_map(|d| crawl(d, pkg, depth - 1))
}

/// Where `$(find pkg)` points (absolute, as ROS gives it: the text is joined
/// to paths in other files), or the places searched (for the error).
pub fn find_package(pkg: &str, package_paths: &[PathBuf], input: &Path) -> Result<PathBuf, String> {
    let env = Env {
        ros_package_path: std::env::var_os("ROS_PACKAGE_PATH"),
        ament_prefix_path: std::env::var_os("AMENT_PREFIX_PATH"),
    };
    search(pkg, package_paths, &env, input).map(|p| std::fs::canonicalize(&p).unwrap_or(p))
}

/// The environment variables the search reads (a parameter, for the tests).
struct Env {
    ros_package_path: Option<std::ffi::OsString>,
    ament_prefix_path: Option<std::ffi::OsString>,
}

fn search(
    pkg: &str,
    package_paths: &[PathBuf],
    env: &Env,
    input: &Path,
) -> Result<PathBuf, String> {
    let mut searched = Vec::new();
    for d in package_paths {
        if let Some(p) = crawl(d, pkg, XACRO_PACKAGE_SEARCH_DEPTH) {
            return Ok(p);
        }
        searched.push(format!("--package-path {}", d.display()));
    }
    if let Some(rpp) = &env.ros_package_path {
        for d in std::env::split_paths(rpp) {
            if let Some(p) = crawl(&d, pkg, XACRO_PACKAGE_SEARCH_DEPTH) {
                return Ok(p);
            }
        }
        searched.push("ROS_PACKAGE_PATH".into());
    }
    if let Some(app) = &env.ament_prefix_path {
        for d in std::env::split_paths(app) {
            let share = d.join("share").join(pkg);
            if share.is_dir() {
                return Ok(share);
            }
        }
        searched.push("AMENT_PREFIX_PATH (PREFIX/share/<pkg>)".into());
    }
    let start = input.parent().and_then(|d| {
        let d = if d.as_os_str().is_empty() {
            Path::new(".")
        } else {
            d
        };
        std::fs::canonicalize(d).ok()
    });
    if let Some(start) = start {
        for dir in start.ancestors().take(XACRO_PACKAGE_SEARCH_UP + 1) {
            if let Some(p) = crawl(dir, pkg, XACRO_PACKAGE_SEARCH_DEPTH) {
                return Ok(p);
            }
        }
        searched.push(format!(
            "the input's directory, {XACRO_PACKAGE_SEARCH_UP} levels up and {XACRO_PACKAGE_SEARCH_DEPTH} down"
        ));
    }
    Err(format!(
        "$(find {pkg}): no package.xml with <name>{pkg}</name> found (searched {}); pass --package-path DIR",
        searched.join(", ")
    ))
}

/// One parsed `$(command args...)`.
pub enum Subst<'a> {
    /// `$(arg NAME)`.
    Arg(&'a str),
    /// `$(find PKG)`.
    Find(&'a str),
    /// `$(env NAME)`.
    Env(&'a str),
    /// `$(optenv NAME DEFAULT...)`.
    OptEnv(&'a str, String),
    /// `$(dirname)`: the directory of the file being expanded.
    Dirname,
    /// `$(cwd)`: the current directory.
    Cwd,
}

/// Parse the inside of `$(...)`.
pub fn parse(inner: &str) -> Result<Subst<'_>, String> {
    let words: Vec<&str> = inner.split(' ').filter(|w| !w.is_empty()).collect();
    let one = |what: &str| -> Result<&str, String> {
        match words.as_slice() {
            [_, x] => Ok(*x),
            _ => Err(format!(
                "$({inner}): $({what} ...) takes exactly one argument"
            )),
        }
    };
    match words.first().copied() {
        Some("arg") => one("arg").map(Subst::Arg),
        Some("find") => one("find").map(Subst::Find),
        Some("env") => one("env").map(Subst::Env),
        Some("optenv") => match words.get(1) {
            Some(name) => Ok(Subst::OptEnv(name, words[2..].join(" "))),
            None => Err(format!("$({inner}): $(optenv VAR [default]) needs a variable name")),
        },
        Some("dirname") if words.len() == 1 => Ok(Subst::Dirname),
        Some("cwd") if words.len() == 1 => Ok(Subst::Cwd),
        Some("eval") => Err(format!(
            "$({inner}): $(eval ...) is not supported by this expander; write the value out or use ${{...}}"
        )),
        Some(cmd) => Err(format!(
            "$({inner}): unknown substitution command '{cmd}': expected one of arg, find, env, optenv, dirname, cwd"
        )),
        None => Err("$(): empty substitution".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn package(dir: &Path, name: &str) -> PathBuf {
        std::fs::create_dir_all(dir).expect("mkdir");
        std::fs::write(
            dir.join("package.xml"),
            format!("<package format=\"3\">\n  <name> {name} </name>\n</package>\n"),
        )
        .expect("write");
        dir.to_path_buf()
    }

    /// The search order: --package-path, ROS_PACKAGE_PATH, AMENT_PREFIX_PATH,
    /// then upwards from the input; the <name> decides, not the directory name.
    #[test]
    fn find_searches_in_order() {
        let t = tempfile::tempdir().expect("tempdir");
        let root = t.path();
        let ws = root.join("ws/src/repo");
        let by_name = package(&ws.join("some_dir"), "robot_description");
        let input = package(&ws.join("robot_bringup"), "robot_bringup").join("urdf/r.xacro");
        std::fs::create_dir_all(input.parent().expect("dir")).expect("mkdir");
        let none = Env {
            ros_package_path: None,
            ament_prefix_path: None,
        };
        // Upwards from the input: the sibling directory, found by its <name>.
        assert_eq!(
            search("robot_description", &[], &none, &input),
            Ok(by_name.clone())
        );
        // A ROS_PACKAGE_PATH entry wins over the upward search.
        let other = package(&root.join("other/robot_description"), "robot_description");
        let rpp = Env {
            ros_package_path: Some(root.join("other").into_os_string()),
            ament_prefix_path: None,
        };
        assert_eq!(
            search("robot_description", &[], &rpp, &input),
            Ok(other.clone())
        );
        // AMENT_PREFIX_PATH: PREFIX/share/<pkg>.
        let share = root.join("install/share/robot_description");
        std::fs::create_dir_all(&share).expect("mkdir");
        let ament = Env {
            ros_package_path: None,
            ament_prefix_path: Some(root.join("install").into_os_string()),
        };
        assert_eq!(search("robot_description", &[], &ament, &input), Ok(share));
        // --package-path first of all.
        assert_eq!(
            search("robot_description", std::slice::from_ref(&ws), &rpp, &input),
            Ok(by_name)
        );
        // Not found: the message names what was searched.
        let e = search("missing_pkg", &[ws], &rpp, &input).expect_err("missing");
        assert!(
            e.contains("$(find missing_pkg)") && e.contains("ROS_PACKAGE_PATH"),
            "{e}"
        );
        assert!(e.contains("--package-path"), "{e}");
    }
}
