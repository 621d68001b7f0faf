//! The survey over rig files: each TOML rig file loaded, its declared pair
//! composed and analysed at `l = 1`.

use super::expand_paths;
use crate::diagnostic::{Error, Result, Warning};
use crate::formats::{self, LoadOptions};
use crate::frames::FrameGraph;
use crate::geometry::{PitchTol, ScrewKind, UserSigma};
use crate::report::rig::{rig_report, Judgement};
use crate::report::survey::{RowMarks, SurveyRigJson};
use crate::report::SurveyReport;
use std::path::{Path, PathBuf};

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

/// What to survey and how.
#[derive(Debug, Clone)]
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
}

/// A `.toml` file other than a check manifest (`audit.toml`).
fn is_rig_file(p: &Path) -> bool {
    p.extension().is_some_and(|e| e == "toml")
        && p.file_name()
            .is_some_and(|n| n != super::manifest::MANIFEST)
}

/// Load and analyse one rig file; its warnings go to `warnings`.
fn survey_rig(
    path: &Path,
    how: &Judgement,
    warnings: &mut Vec<Warning>,
) -> Result<(SurveyRigJson, RowMarks, bool)> {
    let loaded = formats::load_file(path, &LoadOptions::default())?;
    let meta = loaded.rig.clone().ok_or_else(|| {
        Error::parse("expected a TOML rig file with a [rig] table (see docs/rig-format.md)")
            .in_file(path)
    })?;
    let mut graph = FrameGraph::new();
    graph.add(loaded)?;
    warnings.extend(graph.warnings().iter().cloned());
    let chain = graph
        .transform(&meta.from, &meta.to)
        .map_err(|e| e.in_file(path))?;
    let rep = rig_report(&chain, &[1.0], how).map_err(|e| e.in_file(path))?;
    let json = SurveyRigJson {
        id: meta.id.clone(),
        sensor: meta.sensor.clone(),
        platform: meta.platform.clone(),
        dataset: meta.dataset.clone(),
        from: meta.from.clone(),
        to: meta.to.clone(),
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
        placeholder: meta.placeholder,
        duplicate_of: meta.duplicate_of.clone(),
    };
    Ok((json, marks, meta.in_statistics()))
}

fn sort_rows(rows: &mut [(SurveyRigJson, RowMarks, bool)], col: Option<SortColumn>) {
    rows.sort_by(|a, b| a.0.id.cmp(&b.0.id));
    let Some(col) = col else { return };
    rows.sort_by(|a, b| {
        let (a, b) = (&a.0, &b.0);
        match col {
            SortColumn::Id => a.id.cmp(&b.id),
            SortColumn::Sensor => a.sensor.cmp(&b.sensor),
            SortColumn::Platform => a.platform.cmp(&b.platform),
            SortColumn::Dataset => a.dataset.cmp(&b.dataset),
            SortColumn::LeverArm => a.lever_arm_m.total_cmp(&b.lever_arm_m),
            SortColumn::Angle => a.angle_deg.total_cmp(&b.angle_deg),
            SortColumn::ScrewTranslation => {
                let k = |x: &SurveyRigJson| x.screw_translation_m.map(f64::abs).unwrap_or(-1.0);
                k(a).total_cmp(&k(b))
            }
            SortColumn::SigmaMax => a.sigma_max.total_cmp(&b.sigma_max),
        }
    });
}

/// Survey every rig under the paths; returns the report and the warnings the
/// files raised.
pub fn survey(opts: &SurveyOptions) -> Result<(SurveyReport, Vec<Warning>)> {
    let files = expand_paths(&opts.paths, is_rig_file)?;
    if files.is_empty() {
        return Err(Error::usage(format!(
            "no rig files (*.toml) found under {}",
            opts.paths
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    let how = Judgement {
        pitch_tol: opts.pitch_tol,
        user: opts.sigma,
    };
    let mut warnings = Vec::new();
    let mut rows = Vec::new();
    for f in &files {
        let row = survey_rig(f, &how, &mut warnings)?;
        if row.2 || opts.all {
            rows.push(row);
        }
    }
    sort_rows(&mut rows, opts.sort);
    let counted: Vec<bool> = rows.iter().map(|r| r.2).collect();
    let report = SurveyReport::new(rows.into_iter().map(|(j, m, _)| (j, m)).collect(), &counted);
    Ok((report, warnings))
}
