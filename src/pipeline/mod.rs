//! The pipeline the commands call: files -> frame graph (with renames and
//! joint values) -> chain -> rig report; the survey over rig files; the check
//! of calibration files against a baseline. The CLI parses arguments, calls
//! these and picks a renderer; nothing here prints.

mod check;
mod cleanup;
pub mod detector;
mod diff;
pub mod files;
mod fleet;
pub mod manifest;
mod mistakes;
mod output;
mod parallel;
pub mod run;
mod spread;
mod survey;
pub mod walk;

pub use check::{check, check_with, CheckOptions, Robot};
pub use diff::{diff, DiffOptions, SideRead};
pub use files::{expand_paths, same_file, write_atomic};
pub use output::check_output_target;
pub use spread::{check_spread_plot_target, spread, write_spread_plot, SpreadOptions};
pub use survey::{check_plot_target, survey, write_survey_plot, SortColumn, SurveyOptions};

use crate::diagnostic::{Code, Error, Result, Warning};
use crate::formats::{self, LoadOptions};
use crate::frames::{Chain, FrameGraph};
use crate::geometry::{PitchTol, UserSigma};
use crate::report::rig::{kappa_check, rig_report, Judgement};
use crate::report::RigReport;
use std::path::{Path, PathBuf};

/// `--rename [FILE:]OLD=NEW`: a frame renamed as it is loaded.
#[derive(Debug, Clone, PartialEq)]
pub struct Rename {
    /// Only in files whose path ends with this (`None`: every file).
    pub file: Option<String>,
    /// The name in the file.
    pub old: String,
    /// The name to use.
    pub new: String,
}

/// Files loaded into one frame graph.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The graph (its warnings included).
    pub graph: FrameGraph,
    /// The frame pair the first rig file declares, if any.
    pub rig_pair: Option<(String, String)>,
}

/// Apply the renames that concern `path` to what it yielded; returns how many
/// frame names changed per rename.
pub(crate) fn apply_renames(
    renames: &[Rename],
    path: &Path,
    loaded: &mut formats::Loaded,
) -> Vec<usize> {
    let p = path.to_string_lossy();
    renames
        .iter()
        .map(|r| {
            if r.file.as_deref().is_some_and(|f| !p.ends_with(f)) {
                return 0;
            }
            let mut n = 0;
            for e in loaded.edges.iter_mut().chain(&mut loaded.redundant) {
                for name in [&mut e.parent, &mut e.child] {
                    if *name == r.old {
                        *name = r.new.clone();
                        n += 1;
                    }
                }
            }
            for f in &mut loaded.frames {
                if f.name == r.old {
                    f.name = r.new.clone();
                    n += 1;
                }
            }
            if let Some(meta) = &mut loaded.rig {
                for name in [&mut meta.from, &mut meta.to] {
                    if *name == r.old {
                        *name = r.new.clone();
                    }
                }
            }
            n
        })
        .collect()
}

/// Load `files` into one frame graph, renaming frames as asked. A rename that
/// matches no frame is an error (a typo, not a no-op).
pub fn load(files: &[PathBuf], opts: &LoadOptions, renames: &[Rename]) -> Result<Loaded> {
    let mut graph = FrameGraph::new();
    let mut rig_pair: Option<(String, String)> = None;
    let mut renamed = vec![0usize; renames.len()];
    for f in files {
        let mut loaded = formats::load_file(f, opts)?;
        for (total, n) in renamed
            .iter_mut()
            .zip(apply_renames(renames, f, &mut loaded))
        {
            *total += n;
        }
        if let Some(meta) = &loaded.rig {
            if rig_pair.is_none() && !meta.from.is_empty() && !meta.to.is_empty() {
                rig_pair = Some((meta.from.clone(), meta.to.clone()));
            }
        }
        graph.add(loaded)?;
    }
    if let Some(i) = renamed.iter().position(|&n| n == 0) {
        let r = &renames[i];
        let file = r
            .file
            .as_deref()
            .map(|f| format!("{f}:"))
            .unwrap_or_default();
        return Err(Error::usage(format!(
            "--rename {file}{}={}: expected a frame `{}` in {}, found none",
            r.old,
            r.new,
            r.old,
            r.file.as_deref().unwrap_or("the files")
        )));
    }
    Ok(Loaded { graph, rig_pair })
}

fn abbreviate(v: &[String], n: usize) -> String {
    if v.len() <= n {
        v.join(", ")
    } else {
        format!("{}, ... ({} in all)", v[..n].join(", "), v.len())
    }
}

impl Loaded {
    /// The frame pair to report: given, declared by a rig file, or the only
    /// edge there is.
    pub fn frame_pair(&self, from: Option<&str>, to: Option<&str>) -> Result<(String, String)> {
        match (from, to) {
            (Some(f), Some(t)) => Ok((f.to_string(), t.to_string())),
            (None, None) => {
                if let Some(p) = &self.rig_pair {
                    return Ok(p.clone());
                }
                let edges = self.graph.edges();
                if edges.len() == 1 {
                    return Ok((edges[0].parent.clone(), edges[0].child.clone()));
                }
                Err(Error::usage(format!(
                    "these files yield {} edges: name the frames with --from FRAME --to FRAME (frames: {}; `--frames` lists them)",
                    edges.len(),
                    abbreviate(&self.graph.frames(), 12)
                )))
            }
            _ => Err(Error::usage(
                "give both --from and --to, or neither (when the files yield one edge)",
            )),
        }
    }

    /// A `--joint` that names no movable joint is a typo, not a no-op: the
    /// error suggests the closest names.
    pub fn check_joint_names<'a>(&self, names: impl IntoIterator<Item = &'a str>) -> Result<()> {
        let known = self.graph.joint_names();
        for name in names {
            if known.iter().any(|k| k == name) {
                continue;
            }
            let close: Vec<String> = known
                .iter()
                .filter(|k| strsim::normalized_levenshtein(k, name) > 0.5)
                .take(3)
                .map(|c| format!("`{c}`"))
                .collect();
            let hint = if !close.is_empty() {
                format!("did you mean {}?", close.join(", "))
            } else if known.is_empty() {
                "movable joints in these files: none".to_string()
            } else {
                format!("movable joints in these files: {}", abbreviate(&known, 12))
            };
            return Err(Error::usage(format!(
                "--joint {name}=...: expected the name of a movable joint, found no joint `{name}`; {hint}"
            )));
        }
        Ok(())
    }
}

/// `--strict`: warnings (already printed) stop the command, an error naming
/// their codes.
pub fn deny_warnings(strict: bool, warnings: &[Warning]) -> Result<()> {
    if !strict || warnings.is_empty() {
        return Ok(());
    }
    let mut codes: Vec<&str> = warnings.iter().map(|w| w.code.name()).collect();
    codes.sort_unstable();
    codes.dedup();
    Err(Error::new(
        Code::WarningsDenied,
        format!(
            "--strict: expected no warnings, found {} ({})",
            warnings.len(),
            codes.join(", ")
        ),
    ))
}

/// What the rig report is asked for besides the chain.
#[derive(Debug, Clone)]
pub struct RigOptions {
    /// Characteristic lengths (m) of the certificate bands.
    pub ells: Vec<f64>,
    /// `--pitch-tol`: `auto` or a tolerance on `|h|` (m).
    pub pitch_tol: PitchTol,
    /// `--sigma-t`/`--sigma-r`: the user's uncertainty per edge.
    pub sigma: Option<UserSigma>,
    /// `--kappa K --lambda L`: the band check.
    pub kappa_lambda: Option<(f64, f64)>,
}

/// The rig report of a composed chain.
pub fn report(chain: &Chain, opts: &RigOptions) -> Result<RigReport> {
    let how = Judgement {
        pitch_tol: opts.pitch_tol,
        user: opts.sigma,
    };
    let mut rep = rig_report(chain, &opts.ells, &how)?;
    if let Some((kappa, lambda)) = opts.kappa_lambda {
        rep.kappa_check = Some(kappa_check(&rep, kappa, lambda)?);
    }
    Ok(rep)
}

/// `T_from_to` composed from `files` (frames given, or the files' one edge).
pub fn transform_between(
    files: &[PathBuf],
    from: Option<&str>,
    to: Option<&str>,
    opts: &LoadOptions,
) -> Result<crate::geometry::Transform> {
    let loaded = load(files, opts, &[])?;
    let (from, to) = match (from, to) {
        (None, None) if loaded.graph.edges().len() != 1 => {
            return Err(Error::usage(format!(
                "expected --from and --to (frames: {})",
                loaded.graph.frames().join(", ")
            )))
        }
        _ => loaded.frame_pair(from, to)?,
    };
    Ok(loaded.graph.transform(&from, &to)?.transform)
}
