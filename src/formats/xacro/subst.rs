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
    XACRO_PACKAGE_SEARCH_DEPTH, XACRO_PACKAGE_SEARCH_MAX_DIRS, XACRO_PACKAGE_SEARCH_UP,
    XACRO_PACKAGE_XML_BYTES,
};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The `<name>` of the package in `dir`, if `dir/package.xml` is a regular
/// file whose first [`XACRO_PACKAGE_XML_BYTES`] hold it (a manifest of
/// gigabytes is never read whole; the name is near its top).
fn package_name(dir: &Path) -> Option<String> {
    let head = crate::input::read_head(&dir.join("package.xml"), XACRO_PACKAGE_XML_BYTES as usize)?;
    let text = String::from_utf8_lossy(&head);
    let start = text.find("<name>")? + "<name>".len();
    let end = start + text[start..].find("</name>")?;
    Some(text[start..end].trim().to_string())
}

/// Every package on the search path, by name, in search order, each with
/// where it was found (for the messages). Built once per expansion, at the
/// first `$(find)`, visiting at most [`XACRO_PACKAGE_SEARCH_MAX_DIRS`]
/// directories.
#[derive(Debug, Default)]
pub struct PackageIndex {
    packages: BTreeMap<String, Vec<(PathBuf, String)>>,
    searched: Vec<String>,
    visited: usize,
    /// The directory count ran out before the search ended.
    truncated: bool,
}

/// Where `$(find pkg)` points and the other copies found.
#[derive(Debug, PartialEq)]
pub struct FoundPackage {
    /// The directory used (absolute, as ROS gives it: the text is joined to
    /// paths in other files).
    pub dir: PathBuf,
    /// Where it was found (`--package-path DIR`, ...).
    pub from: String,
    /// Other directories holding a package of the same name, and where.
    pub others: Vec<(PathBuf, String)>,
}

impl PackageIndex {
    /// The index of `package_paths`, the environment's ROS paths and the
    /// input's surroundings.
    pub fn build(package_paths: &[PathBuf], input: &Path) -> PackageIndex {
        let env = Env {
            ros_package_path: std::env::var_os("ROS_PACKAGE_PATH"),
            ament_prefix_path: std::env::var_os("AMENT_PREFIX_PATH"),
        };
        Self::build_with(package_paths, &env, input)
    }

    fn build_with(package_paths: &[PathBuf], env: &Env, input: &Path) -> PackageIndex {
        let mut ix = PackageIndex::default();
        for d in package_paths {
            ix.crawl(
                d,
                XACRO_PACKAGE_SEARCH_DEPTH,
                &format!("--package-path {}", d.display()),
            );
        }
        if let Some(rpp) = &env.ros_package_path {
            for d in std::env::split_paths(rpp) {
                ix.crawl(&d, XACRO_PACKAGE_SEARCH_DEPTH, "ROS_PACKAGE_PATH");
            }
            ix.searched.push("ROS_PACKAGE_PATH".into());
        }
        if let Some(app) = &env.ament_prefix_path {
            for d in std::env::split_paths(app) {
                ix.share(&d.join("share"));
            }
            ix.searched
                .push("AMENT_PREFIX_PATH (PREFIX/share/<pkg>)".into());
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
                ix.crawl(
                    dir,
                    XACRO_PACKAGE_SEARCH_DEPTH,
                    "the input's directory or above",
                );
            }
            ix.searched.push(format!(
                "the input's directory, {XACRO_PACKAGE_SEARCH_UP} levels up and {XACRO_PACKAGE_SEARCH_DEPTH} down"
            ));
        }
        ix
    }

    /// Count one directory visited; false once the cap is reached.
    fn visit(&mut self) -> bool {
        self.visited += 1;
        if self.visited > XACRO_PACKAGE_SEARCH_MAX_DIRS {
            self.truncated = true;
        }
        !self.truncated
    }

    fn add(&mut self, name: String, dir: &Path, from: &str) {
        let dir = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
        let list = self.packages.entry(name).or_default();
        if !list.iter().any(|(d, _)| *d == dir) {
            list.push((dir, from.to_string()));
        }
    }

    /// `PREFIX/share/<pkg>` directories (an install space).
    fn share(&mut self, share: &Path) {
        let Ok(rd) = std::fs::read_dir(share) else {
            return;
        };
        let mut dirs: Vec<PathBuf> = rd
            .filter_map(|e| e.ok())
            .map(|e| e.path())
            .filter(|p| p.is_dir())
            .collect();
        dirs.sort();
        for d in dirs {
            if !self.visit() {
                return;
            }
            if let Some(name) = d.file_name().map(|n| n.to_string_lossy().to_string()) {
                self.add(name, &d, "AMENT_PREFIX_PATH");
            }
        }
    }

    /// The packages in `dir` or below it, at most `depth` levels down (a
    /// package's own subdirectories are not searched).
    fn crawl(&mut self, dir: &Path, depth: usize, from: &str) {
        if !self.visit() {
            return;
        }
        if let Some(name) = package_name(dir) {
            self.add(name, dir, from);
            return;
        }
        if depth == 0 {
            return;
        }
        let Ok(rd) = std::fs::read_dir(dir) else {
            return;
        };
        let mut subdirs: Vec<PathBuf> = rd
            .filter_map(|e| e.ok())
            .filter(|e| e.file_type().map(|t| t.is_dir()).unwrap_or(false))
            .filter(|e| !e.file_name().to_string_lossy().starts_with('.'))
            .map(|e| e.path())
            .collect();
        subdirs.sort();
        for d in subdirs {
            self.crawl(&d, depth - 1, from);
        }
    }

    /// `$(find pkg)`: the first package of that name in search order, or
    /// the places searched (for the error).
    pub fn find(&self, pkg: &str, package_paths: &[PathBuf]) -> Result<FoundPackage, String> {
        if let Some([(dir, from), rest @ ..]) = self.packages.get(pkg).map(Vec::as_slice) {
            return Ok(FoundPackage {
                dir: dir.clone(),
                from: from.clone(),
                others: rest.to_vec(),
            });
        }
        let shown: Vec<String> = package_paths
            .iter()
            .take(3)
            .map(|d| format!("--package-path {}", d.display()))
            .collect();
        let more = match package_paths.len() {
            n if n > 3 => format!(" and {} more --package-path", n - 3),
            _ => String::new(),
        };
        let places = shown
            .into_iter()
            .chain(self.searched.iter().cloned())
            .collect::<Vec<_>>()
            .join(", ");
        let cut = if self.truncated {
            format!("; the search stopped after {XACRO_PACKAGE_SEARCH_MAX_DIRS} directories")
        } else {
            String::new()
        };
        Err(format!(
            "$(find {pkg}): no package.xml with <name>{pkg}</name> found (searched {places}{more}{cut}); pass --package-path DIR"
        ))
    }
}

/// The environment variables the search reads (a parameter, for the tests).
struct Env {
    ros_package_path: Option<std::ffi::OsString>,
    ament_prefix_path: Option<std::ffi::OsString>,
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

    fn search(pkg: &str, paths: &[PathBuf], env: &Env, input: &Path) -> Result<PathBuf, String> {
        PackageIndex::build_with(paths, env, input)
            .find(pkg, paths)
            .map(|f| f.dir)
    }

    fn canon(p: PathBuf) -> PathBuf {
        std::fs::canonicalize(&p).unwrap_or(p)
    }

    /// The search order: --package-path, ROS_PACKAGE_PATH, AMENT_PREFIX_PATH,
    /// then upwards from the input; the <name> decides, not the directory name.
    #[test]
    fn find_searches_in_order() {
        let t = tempfile::tempdir().expect("tempdir");
        let root = t.path();
        let ws = root.join("ws/src/repo");
        let by_name = canon(package(&ws.join("some_dir"), "robot_description"));
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
        let other = canon(package(
            &root.join("other/robot_description"),
            "robot_description",
        ));
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
        assert_eq!(
            search("robot_description", &[], &ament, &input),
            Ok(canon(share))
        );
        // --package-path first of all; the other copies are named.
        let ix = PackageIndex::build_with(std::slice::from_ref(&ws), &rpp, &input);
        let f = ix
            .find("robot_description", std::slice::from_ref(&ws))
            .expect("found");
        assert_eq!(f.dir, by_name);
        assert!(f.from.starts_with("--package-path"), "{}", f.from);
        assert_eq!(f.others, vec![(other, "ROS_PACKAGE_PATH".to_string())]);
        // Not found: the message names what was searched, at most three
        // package paths.
        let many: Vec<PathBuf> = (0..60).map(|i| root.join(format!("p{i}"))).collect();
        let e = search("missing_pkg", &many, &rpp, &input).expect_err("missing");
        assert!(
            e.contains("$(find missing_pkg)") && e.contains("ROS_PACKAGE_PATH"),
            "{e}"
        );
        assert!(
            e.contains("--package-path") && e.contains("and 57 more"),
            "{e}"
        );
        assert!(e.len() < 600, "{e}");
    }
}
