//! The survey: each file loaded, one frame pair composed and analysed at
//! `l = 1`.
//!
//! Which pair: `FILE:FROM:TO` on the command line (also `DIR:FROM:TO`, for
//! every file under it), else the pair a TOML rig file declares, else
//! `--from`/`--to`. Without a pair anywhere only TOML rig files are read (a
//! directory yields its `*.toml`); with `--from`/`--to` or a `:FROM:TO` on a
//! directory, every file a walk reads (URDF, xacro, YAML, launch, ...). A
//! walked file that cannot be read or lacks the frames is skipped with an
//! `ignored` warning (a folder holds other robots too); a file named on the
//! command line is an error.

use super::files::expand_paths;
use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::{self, LoadOptions, RigMeta};
use crate::frames::FrameGraph;
use crate::geometry::{PitchTol, ScrewKind, UserSigma};
use crate::report::rig::{rig_report, Judgement};
use crate::report::survey::{RigView, RowMarks, SurveyRigJson, SurveyRowsBuilder};
use crate::report::SurveyReport;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Survey columns to sort by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SortColumn {
    /// Rig id.
    Id,
    /// Sensor name.
    Sensor,
    /// Platform name.
    Platform,
    /// Dataset name.
    Dataset,
    /// Lever arm.
    LeverArm,
    /// Rotation angle.
    Angle,
    /// `|h|` (pure translations first).
    ScrewTranslation,
    /// Largest adjoint singular value.
    SigmaMax,
}

/// What to survey and how. `Default`: the command's defaults, no paths.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct SurveyOptions {
    /// Rig files or directories of them.
    pub paths: Vec<PathBuf>,
    /// `--pitch-tol`: `auto` or a tolerance on `|h|` (m).
    pub pitch_tol: PitchTol,
    /// `--sigma-t`/`--sigma-r` for rigs whose file gives none.
    pub sigma: Option<UserSigma>,
    /// Also list placeholder and duplicate rigs.
    pub all: bool,
    /// Sort by this column (ties by id).
    pub sort: Option<SortColumn>,
    /// `--from`/`--to`: the pair for files that are not rig files.
    pub pair: Option<(String, String)>,
    /// How the files are read (`--package-path`, `--arg` for xacro and launch
    /// files).
    pub load: LoadOptions,
}

/// One file to survey.
#[derive(Debug, Clone)]
struct Input {
    path: PathBuf,
    /// From `FILE:FROM:TO` (or `DIR:FROM:TO`), shared by a directory's
    /// files (an input is kept per file: issue 29).
    pair: Option<Arc<(String, String)>>,
    /// Found by a directory walk (skipped with a warning when unusable).
    walked: bool,
    /// The same file is surveyed more than once (several pairs of it): its
    /// rows' ids carry the pair.
    shared: bool,
}

/// Mark the inputs whose file appears more than once (the inputs sorted by
/// path as indices: no copy of every path, issue 29).
fn mark_shared(files: &mut [Input]) {
    let mut by_path: Vec<u32> = (0..files.len() as u32).collect();
    by_path.sort_unstable_by(|&a, &b| files[a as usize].path.cmp(&files[b as usize].path));
    let mut shared = Vec::new();
    for run in by_path.chunk_by(|&a, &b| files[a as usize].path == files[b as usize].path) {
        if run.len() > 1 {
            shared.extend_from_slice(run);
        }
    }
    for i in shared {
        files[i as usize].shared = true;
    }
}

/// `FILE:FROM:TO` split, when `p` is not itself an existing path.
pub(super) fn split_pair(p: &Path) -> (PathBuf, Option<(String, String)>) {
    if p.exists() {
        return (p.to_path_buf(), None);
    }
    let s = p.to_string_lossy();
    let mut it = s.rsplitn(3, ':');
    match (it.next(), it.next(), it.next()) {
        (Some(to), Some(from), Some(file))
            if !to.is_empty() && !from.is_empty() && !file.is_empty() =>
        {
            (
                PathBuf::from(file),
                Some((from.to_string(), to.to_string())),
            )
        }
        _ => (p.to_path_buf(), None),
    }
}

/// Any file a directory walk reads, but a check manifest.
pub(super) fn is_any_input(p: &Path) -> bool {
    formats::is_calibration_file(p)
        && p.file_name()
            .is_some_and(|n| n != super::manifest::MANIFEST)
}

/// The files to survey, with the pair each is given.
fn inputs(opts: &SurveyOptions) -> Result<Vec<Input>> {
    let mut v = Vec::new();
    for p in &opts.paths {
        let (path, pair) = split_pair(p);
        let pair = pair.map(Arc::new);
        if !path.is_dir() {
            v.push(Input {
                path,
                pair,
                walked: false,
                shared: false,
            });
            continue;
        }
        let any = pair.is_some() || opts.pair.is_some();
        let accept: fn(&Path) -> bool = if any { is_any_input } else { is_rig_file };
        for f in expand_paths(std::slice::from_ref(&path), accept)? {
            v.push(Input {
                path: f,
                pair: pair.clone(),
                walked: true,
                shared: false,
            });
        }
    }
    Ok(v)
}

/// A `.toml` file other than a check manifest (`audit.toml`).
fn is_rig_file(p: &Path) -> bool {
    p.extension().is_some_and(|e| e == "toml")
        && p.file_name()
            .is_some_and(|n| n != super::manifest::MANIFEST)
}

/// The pair for `input`, and the rig metadata when it is a rig file.
fn pair_of(
    input: &Input,
    meta: Option<&RigMeta>,
    global: Option<&(String, String)>,
) -> Result<(String, String)> {
    let declared = meta
        .filter(|m| !m.from.is_empty() && !m.to.is_empty())
        .map(|m| (m.from.clone(), m.to.clone()));
    input
        .pair
        .as_deref()
        .cloned()
        .or(declared)
        .or_else(|| global.cloned())
        .ok_or_else(|| {
            Error::usage(
                "expected a TOML rig file with a [rig] table (see docs/rig-format.md), or a frame pair: --from FRAME --to FRAME, or FILE:FROM:TO",
            )
            .in_file(&input.path)
        })
}

/// One survey row: the report at `l = 1`, the row's marks, and whether it
/// counts in the statistics.
type Row = (SurveyRigJson, RowMarks, bool);

/// Load and analyse one file; its warnings go to `warnings`.
fn survey_one(
    input: &Input,
    opts: &SurveyOptions,
    how: &Judgement,
    warnings: &mut Vec<Warning>,
) -> Result<Row> {
    let path = &input.path;
    let mut loaded = formats::load_file(path, &opts.load)?;
    // Moved out, not copied: the graph takes the edges, frames and warnings.
    let meta = loaded.rig.take();
    let robot = loaded.platform.take();
    let (from, to) = pair_of(input, meta.as_ref(), opts.pair.as_ref())?;
    let mut graph = FrameGraph::new();
    graph.add(loaded)?;
    warnings.extend(graph.warnings().iter().cloned());
    let chain = graph.transform(&from, &to).map_err(|e| e.in_file(path))?;
    let rep = rig_report(&chain, &[1.0], how).map_err(|e| e.in_file(path))?;
    // A file that is not a rig file is named by its path, and by its pair
    // too when the survey reads several pairs of it (issue 33: two rows of
    // one URDF had the same id).
    // Its sensor is the frame measured (`to`) and its platform the robot the
    // file names (a URDF's `<robot name>`), where it names one.
    let meta = meta.unwrap_or_else(|| RigMeta {
        id: if input.shared {
            format!("{}:{from}:{to}", path.display())
        } else {
            path.display().to_string()
        },
        sensor: to.clone(),
        platform: robot.unwrap_or_default(),
        ..RigMeta::default()
    });
    let in_statistics = meta.in_statistics();
    let RigMeta {
        id,
        sensor,
        platform,
        dataset,
        placeholder,
        duplicate_of,
        ..
    } = meta;
    let json = SurveyRigJson {
        id,
        sensor,
        platform,
        dataset,
        from,
        to,
        lever_arm_m: rep.lever_arm_m,
        angle_deg: rep.rotation.angle_deg,
        screw_translation_m: rep.screw.translation_along_axis_m,
        zero_pitch: rep.screw.kind == ScrewKind::ZeroPitch,
        screw_translation_uncertainty_m: rep.screw.translation_along_axis_uncertainty_m,
        pitch_verdict: rep.screw.pitch_verdict,
        uncertainty_source: rep.uncertainty.source,
        sigma_max: rep.adjoint.singular_values[0],
        band_l1: rep.certificate[0].band,
        adapted_metric_exists: rep.adapted_metric.exists,
    };
    let marks = RowMarks {
        placeholder,
        duplicate_of,
    };
    Ok((json, marks, in_statistics))
}

/// The order rows are printed in, as a permutation of the rows as read: by
/// `col`, ties by id, ties of both in the order read (what a stable sort by
/// id then a stable sort by `col` give; one sort of `u32` indices, the rows
/// never moved).
fn sort_order(rows: &SurveyRowsBuilder, col: Option<SortColumn>) -> Vec<u32> {
    let n = u32::try_from(rows.len()).expect("fewer than 2^32 rows");
    let mut order: Vec<u32> = (0..n).collect();
    let by_col = |a: &RigView, b: &RigView| match col {
        None | Some(SortColumn::Id) => std::cmp::Ordering::Equal,
        Some(SortColumn::Sensor) => a.sensor.cmp(b.sensor),
        Some(SortColumn::Platform) => a.platform.cmp(b.platform),
        Some(SortColumn::Dataset) => a.dataset.cmp(b.dataset),
        Some(SortColumn::LeverArm) => a.lever_arm_m.total_cmp(&b.lever_arm_m),
        Some(SortColumn::Angle) => a.angle_deg.total_cmp(&b.angle_deg),
        Some(SortColumn::ScrewTranslation) => {
            let k = |x: &RigView| x.screw_translation_m.map(f64::abs).unwrap_or(-1.0);
            k(a).total_cmp(&k(b))
        }
        Some(SortColumn::SigmaMax) => a.sigma_max.total_cmp(&b.sigma_max),
    };
    let by_id = |a: u32, b: u32| rows.id(a as usize).cmp(rows.id(b as usize));
    match col {
        None | Some(SortColumn::Id) => order.sort_by(|&a, &b| by_id(a, b)),
        Some(_) => order.sort_by(|&a, &b| {
            by_col(&rows.view(a as usize), &rows.view(b as usize)).then_with(|| by_id(a, b))
        }),
    }
    order
}

/// Survey every rig under the paths; returns the report and the warnings the
/// files raised.
///
/// ```
/// use extrinsic_audit::{survey, SurveyOptions};
///
/// # fn main() -> extrinsic_audit::Result<()> {
/// let mut opts = SurveyOptions::default();
/// opts.paths = vec![concat!(env!("CARGO_MANIFEST_DIR"), "/calibrations").into()];
/// let (report, _warnings) = survey(&opts)?;
/// // As numpy and pytransform3d compute them from the same files
/// // (tests/fixtures/survey/expected.json): 38 rigs counted (placeholders and
/// // duplicates left out), the median lever arm, 37 with a nonzero pitch.
/// assert_eq!(report.summary.count, 38);
/// assert!((report.summary.lever_arm_median_m - 0.0755011509284429).abs() < 1e-12);
/// assert_eq!(report.summary.nonzero_pitch_count, 37);
/// # Ok(())
/// # }
/// ```
pub fn survey(opts: &SurveyOptions) -> Result<(SurveyReport, Vec<Warning>)> {
    let files = inputs(opts)?;
    let names = || {
        opts.paths
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if files.is_empty() {
        return Err(Error::usage(format!(
            "no rig files (*.toml) found under {}; for URDF, xacro, YAML or launch files give the frames: --from FRAME --to FRAME, or PATH:FROM:TO",
            names()
        )));
    }
    let how = Judgement {
        pitch_tol: opts.pitch_tol,
        user: opts.sigma,
    };
    let mut files = files;
    mark_shared(&mut files);
    let mut warnings = Vec::new();
    let mut rows = SurveyRowsBuilder::with_capacity(files.len());
    let mut failed = None;
    // Every file on every core, taken in order (`pipeline::parallel`).
    super::parallel::ordered(
        &files,
        |_, f| {
            let mut w = Vec::new();
            (survey_one(f, opts, &how, &mut w), w)
        },
        |i, (row, w)| {
            let f = &files[i];
            warnings.extend(w);
            match row {
                Ok((json, marks, counted)) => {
                    if counted || opts.all {
                        rows.push(&json, &marks, counted);
                    }
                }
                // A folder holds other robots too: a walked file that cannot
                // give the pair is reported, not fatal.
                Err(e) if f.walked && (f.pair.is_some() || opts.pair.is_some()) => {
                    let loc = if e.location.is_empty() {
                        Location::file(&f.path)
                    } else {
                        e.location
                    };
                    warnings.push(
                        Warning::new(Code::Ignored, format!("not surveyed: {}", e.message))
                            .at(&loc),
                    );
                }
                Err(e) => {
                    failed = Some(e);
                    return false;
                }
            }
            true
        },
    );
    if let Some(e) = failed {
        return Err(e);
    }
    if rows.is_empty() && files.iter().all(|f| f.walked) {
        return Err(Error::usage(format!(
            "no file under {} yields the frame pair asked for (each is listed above with why)",
            names()
        )));
    }
    drop(files);
    let order = sort_order(&rows, opts.sort);
    let report = SurveyReport::new(rows.finish(order));
    Ok((report, warnings))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::uncertainty::UncertaintySource;
    use crate::geometry::PitchVerdict;

    fn rig(id: &str, sensor: &str, lever: f64, h: Option<f64>) -> SurveyRigJson {
        SurveyRigJson {
            id: id.into(),
            sensor: sensor.into(),
            platform: ["p", "q"][id.len() % 2].into(),
            dataset: String::new(),
            from: "imu".into(),
            to: "lidar".into(),
            lever_arm_m: lever,
            angle_deg: lever * 10.0,
            screw_translation_m: h,
            zero_pitch: false,
            screw_translation_uncertainty_m: None,
            pitch_verdict: Some(PitchVerdict::Nonzero),
            uncertainty_source: UncertaintySource::None,
            sigma_max: 1.0 + lever,
            band_l1: [0.5, 1.5],
            adapted_metric_exists: false,
        }
    }

    /// The permutation `sort_order` gives is the order the rows take under a
    /// stable sort by id then a stable sort by the column (how the rows were
    /// sorted before issue 29), ties included: equal ids, equal values,
    /// rows without h (sorted as -1).
    #[test]
    fn the_permutation_gives_the_order_of_two_stable_sorts() {
        let rigs = vec![
            rig("c", "os1", 0.2, Some(-0.3)),
            rig("a", "vlp", 0.1, None),
            rig("bb", "os1", 0.2, Some(0.3)),
            rig("a", "os1", 0.3, Some(0.0)),
            rig("d", "hesai", 0.1, None),
            rig("bb", "vlp", 0.2, Some(-0.3)),
            rig("e", "os1", 0.0, Some(0.1)),
        ];
        let mut rows = SurveyRowsBuilder::with_capacity(rigs.len());
        for r in &rigs {
            rows.push(r, &RowMarks::default(), true);
        }
        let cols = [
            None,
            Some(SortColumn::Id),
            Some(SortColumn::Sensor),
            Some(SortColumn::Platform),
            Some(SortColumn::Dataset),
            Some(SortColumn::LeverArm),
            Some(SortColumn::Angle),
            Some(SortColumn::ScrewTranslation),
            Some(SortColumn::SigmaMax),
        ];
        for col in cols {
            let mut want: Vec<(u32, &SurveyRigJson)> = (0..).zip(&rigs).collect();
            want.sort_by(|a, b| a.1.id.cmp(&b.1.id));
            if let Some(col) = col {
                want.sort_by(|(_, a), (_, b)| match col {
                    SortColumn::Id => a.id.cmp(&b.id),
                    SortColumn::Sensor => a.sensor.cmp(&b.sensor),
                    SortColumn::Platform => a.platform.cmp(&b.platform),
                    SortColumn::Dataset => a.dataset.cmp(&b.dataset),
                    SortColumn::LeverArm => a.lever_arm_m.partial_cmp(&b.lever_arm_m).unwrap(),
                    SortColumn::Angle => a.angle_deg.partial_cmp(&b.angle_deg).unwrap(),
                    SortColumn::ScrewTranslation => {
                        let k = |x: &SurveyRigJson| x.screw_translation_m.map_or(-1.0, f64::abs);
                        k(a).partial_cmp(&k(b)).unwrap()
                    }
                    SortColumn::SigmaMax => a.sigma_max.partial_cmp(&b.sigma_max).unwrap(),
                });
            }
            let want: Vec<u32> = want.iter().map(|w| w.0).collect();
            assert_eq!(sort_order(&rows, col), want, "{col:?}");
        }
        // Spelled out for one column: by sensor, ties by id, then as read.
        assert_eq!(
            sort_order(&rows, Some(SortColumn::Sensor)),
            [4, 3, 2, 0, 6, 1, 5]
        );
    }
}
