//! Files loaded into one frame graph: each file read (`formats::load_file`),
//! its frames renamed as `LoadOptions::renames` asks, added to the graph; the
//! frame pair to report; `--joint` names checked.

use crate::diagnostic::{Error, Result};
use crate::formats::{self, LoadOptions, Rename};
use crate::frames::FrameGraph;
use std::path::{Path, PathBuf};

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
    loaded: &mut formats::Parsed,
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

/// Load `files` into one frame graph, renaming frames as `opts.renames` asks.
/// A rename that matches no frame is an error (a typo, not a no-op).
pub fn load(files: &[PathBuf], opts: &LoadOptions) -> Result<Loaded> {
    let renames = &opts.renames[..];
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
    /// The files named (`named`) and every file an edge of the graph came
    /// from (includes among them), each once: what an output must not
    /// replace.
    pub fn files_read(&self, named: &[PathBuf]) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = named.to_vec();
        for e in self.graph.edges() {
            if let Some(f) = &e.provenance.location.file {
                if !v.iter().any(|p| **p == **f) {
                    v.push(f.to_path_buf());
                }
            }
        }
        v
    }

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
/// `T_from_to` composed from `files` (frames given, or the files' one edge).
pub fn transform_between(
    files: &[PathBuf],
    from: Option<&str>,
    to: Option<&str>,
    opts: &LoadOptions,
) -> Result<crate::geometry::Transform> {
    let loaded = load(files, opts)?;
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
