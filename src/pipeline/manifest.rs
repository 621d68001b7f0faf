//! `audit.toml`: which files of a checked directory are one robot.
//!
//! A directory of calibrations usually holds many robots that reuse frame
//! names (`imu`, `lidar`), so files are grouped only where a manifest says so:
//!
//! ```toml
//! [[robot]]
//! name = "anymal-d"
//! files = ["anymal-d.urdf", "fast_lio.yaml"]          # relative to audit.toml
//! renames = [{ file = "fast_lio.yaml", old = "imu", new = "imu_link" }]
//! pairs = ["base:lidar"]                               # FROM:TO, checked and baselined
//! ```
//!
//! A fleet (one file per vehicle) sets its gate once, at the top:
//! `fleet_tolerance = [5.0, 0.5]` (mm, deg), what `check --fleet-tolerance
//! 5,0.5` does; the flag, when given, wins. Two checked directories whose
//! manifests set different tolerances are an error.
//!
//! Each robot's files are loaded into one frame graph, as `audit a b` loads
//! several files: the same edge given different values in two files, a cycle
//! or a frame with two parents is a finding naming both file:line. A file
//! not listed is its own robot. `audit.toml` itself is not a calibration file.
//! A listed file that does not exist, a file listed twice, an unknown key, a
//! rename that matches no frame, or a malformed pair is an error (exit 2).

use super::walk::Found;
use crate::diagnostic::{Error, Result};
use crate::formats::Rename;
use crate::tolerances::MAX_MANIFEST_FILE_SIZE;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The manifest's file name.
pub const MANIFEST: &str = "audit.toml";

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Manifest {
    #[serde(default)]
    robot: Vec<RobotSpec>,
    /// `fleet_tolerance = [MM, DEG]`: `check --fleet-tolerance` for this
    /// directory when the flag is not given.
    fleet_tolerance: Option<Vec<f64>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RobotSpec {
    name: String,
    files: Vec<String>,
    #[serde(default)]
    renames: Vec<RenameSpec>,
    #[serde(default)]
    pairs: Vec<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RenameSpec {
    file: Option<String>,
    old: String,
    new: String,
}

/// A robot of a manifest, its files resolved.
#[derive(Debug, Clone)]
pub struct ManifestRobot {
    /// Its name.
    pub name: String,
    /// Its files (manifest directory joined), in the listed order.
    pub files: Vec<Found>,
    /// Renames, each restricted to its file's full path when it names one.
    pub renames: Vec<Rename>,
    /// Frame pairs to check.
    pub pairs: Vec<(String, String)>,
}

/// `FROM:TO`, two non-empty frame names (a manifest's `pairs`, `check --pair`).
pub fn parse_pair(s: &str) -> Option<(String, String)> {
    match s.split_once(':') {
        Some((a, b)) if !a.is_empty() && !b.is_empty() => Some((a.into(), b.into())),
        _ => None,
    }
}

/// The robots of `dir/audit.toml` (none when there is no manifest) and its
/// `fleet_tolerance` as `[mm, deg]` (two finite numbers, not negative).
pub fn read(dir: &Path) -> Result<(Vec<ManifestRobot>, Option<[f64; 2]>)> {
    let path = dir.join(MANIFEST);
    if !path.is_file() {
        return Ok((Vec::new(), None));
    }
    let text = crate::input::read_text(&path, MAX_MANIFEST_FILE_SIZE, "the audit.toml size cap")?;
    let m: Manifest = toml::from_str(&text).map_err(|e| {
        let line = e
            .span()
            .map(|s| text[..s.start.min(text.len())].lines().count().max(1));
        let err = Error::parse(format!("audit.toml: {}", e.message())).in_file(&path);
        match line {
            Some(l) => err.at_line(l, None),
            None => err,
        }
    })?;
    let fleet = match m.fleet_tolerance.as_deref() {
        None => None,
        Some(&[mm, deg]) if [mm, deg].iter().all(|x| x.is_finite() && *x >= 0.0) => Some([mm, deg]),
        Some(v) => {
            return Err(Error::usage(format!(
                "audit.toml: fleet_tolerance: expected [MM, DEG], two numbers not negative, found {v:?}"
            ))
            .in_file(&path))
        }
    };
    let mut out = Vec::new();
    let mut seen: Vec<PathBuf> = Vec::new();
    for r in m.robot {
        let bad = |what: String| {
            Error::usage(format!("audit.toml: robot {:?}: {what}", r.name)).in_file(&path)
        };
        let mut files = Vec::new();
        for f in &r.files {
            let p = dir.join(f);
            let canon = p
                .canonicalize()
                .map_err(|e| bad(format!("expected the file {f:?}, found none ({e})")))?;
            if seen.contains(&canon) {
                return Err(bad(format!("file {f:?} is listed twice")));
            }
            seen.push(canon);
            files.push(Found {
                path: p,
                root: dir.to_path_buf(),
            });
        }
        let renames = r
            .renames
            .iter()
            .map(|x| Rename {
                file: x
                    .file
                    .as_ref()
                    .map(|f| dir.join(f).to_string_lossy().into_owned()),
                old: x.old.clone(),
                new: x.new.clone(),
            })
            .collect();
        let pairs = r
            .pairs
            .iter()
            .map(|s| {
                parse_pair(s).ok_or_else(|| bad(format!("expected a pair FROM:TO, found {s:?}")))
            })
            .collect::<Result<Vec<_>>>()?;
        out.push(ManifestRobot {
            name: r.name.clone(),
            files,
            renames,
            pairs,
        });
    }
    Ok((out, fleet))
}
