//! Reports: the rig report and the survey in the JSON schema of DESIGN.md
//! (schema_version 1, other programs read it: keep field names and types), and
//! their table / markdown renderings.

use crate::analysis::metric::{self, RigAnalysis};
use crate::diagnostic::Result;
use crate::frames::Chain;
use crate::geometry::se3::Transform;
use serde::{Deserialize, Serialize};

pub const SCHEMA_VERSION: u32 = 1;

/// `sources[]`: one per edge used, in chain order.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SourceJson {
    pub file: String,
    pub line: Option<usize>,
    pub format: String,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct TransformJson {
    pub translation_m: [f64; 3],
    pub rotation_matrix: [[f64; 3]; 3],
    pub quaternion_xyzw: [f64; 4],
    pub rpy_rad: [f64; 3],
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct RotationJson {
    pub angle_rad: f64,
    pub angle_deg: f64,
    pub axis: Option<[f64; 3]>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ScrewJson {
    pub kind: String,
    pub translation_along_axis_m: Option<f64>,
    pub pitch_m_per_rad: Option<f64>,
    pub axis_point_m: Option<[f64; 3]>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct AdjointJson {
    /// Six, descending.
    pub singular_values: [f64; 6],
    pub orthogonal: bool,
    pub ata_minus_i_rel: f64,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct CertificateJson {
    pub ell_m: f64,
    pub delta_eff: f64,
    pub band: [f64; 2],
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct AdaptedMetricJson {
    pub exists: bool,
    pub reason: String,
    pub matrix: Option<[[f64; 6]; 6]>,
    pub invariance_residual: Option<f64>,
    pub offdiag_norm: Option<f64>,
    pub rel_diff_identity: Option<f64>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct DetectorJson {
    pub family: String,
    pub equivariant_rule: bool,
    pub invariant_on_rig: bool,
    pub reason: String,
}

/// `--kappa K --lambda L`: does the band certify that L cannot cross K?
/// Present only when asked for.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct KappaCheckJson {
    pub kappa: f64,
    pub lambda: f64,
    pub ratio: f64,
    /// Per characteristic length, same order as `certificate`.
    pub certified: Vec<bool>,
}

/// The rig report (`audit FILE... --from A --to B --format json`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct RigReport {
    pub schema_version: u32,
    pub from: String,
    pub to: String,
    pub sources: Vec<SourceJson>,
    pub transform: TransformJson,
    pub lever_arm_m: f64,
    pub rotation: RotationJson,
    pub screw: ScrewJson,
    pub adjoint: AdjointJson,
    pub certificate: Vec<CertificateJson>,
    pub adapted_metric: AdaptedMetricJson,
    pub detectors: Vec<DetectorJson>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub kappa_check: Option<KappaCheckJson>,
}

fn arr3(v: &nalgebra::Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

pub fn transform_json(t: &Transform) -> TransformJson {
    let r = t.rotation();
    TransformJson {
        translation_m: arr3(t.translation()),
        rotation_matrix: [
            [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
            [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
            [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
        ],
        quaternion_xyzw: t.quaternion_xyzw(),
        rpy_rad: t.rpy(),
    }
}

pub fn sources_json(chain: &Chain) -> Vec<SourceJson> {
    chain
        .steps
        .iter()
        .map(|s| SourceJson {
            file: s
                .edge
                .provenance
                .location
                .file
                .as_ref()
                .map(|p| p.display().to_string())
                .unwrap_or_default(),
            line: s.edge.provenance.location.line,
            format: s.edge.provenance.format.to_string(),
        })
        .collect()
}

/// Markdown table (GitHub flavour), cells escaped for `|`.
pub fn markdown_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let esc = |s: &str| s.replace('|', "\\|");
    let mut s = String::new();
    s.push_str(&format!(
        "| {} |\n",
        header
            .iter()
            .map(|h| esc(h))
            .collect::<Vec<_>>()
            .join(" | ")
    ));
    s.push_str(&format!(
        "|{}|\n",
        header.iter().map(|_| "---").collect::<Vec<_>>().join("|")
    ));
    for r in rows {
        s.push_str(&format!(
            "| {} |\n",
            r.iter().map(|c| esc(c)).collect::<Vec<_>>().join(" | ")
        ));
    }
    s
}

/// A terminal table through comfy-table (no colour inside tables: they are
/// copied into tickets and logs).
pub fn terminal_table(header: &[&str], rows: &[Vec<String>]) -> String {
    terminal_table_wrapped(header, rows, &[])
}

/// [`terminal_table`] with upper bounds on some columns' widths (content wraps).
pub fn terminal_table_wrapped(
    header: &[&str],
    rows: &[Vec<String>],
    bounds: &[(usize, u16)],
) -> String {
    let mut t = comfy_table::Table::new();
    t.load_preset(comfy_table::presets::UTF8_FULL_CONDENSED);
    t.set_content_arrangement(comfy_table::ContentArrangement::Dynamic);
    t.set_header(header.iter().copied());
    for r in rows {
        t.add_row(r.iter().cloned());
    }
    for &(i, w) in bounds {
        if let Some(c) = t.column_mut(i) {
            c.set_constraint(comfy_table::ColumnConstraint::UpperBoundary(
                comfy_table::Width::Fixed(w),
            ));
        }
    }
    t.to_string()
}

/// CSV with minimal quoting (RFC 4180).
pub fn csv_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let q = |s: &str| {
        if s.contains([',', '"', '\n']) {
            format!("\"{}\"", s.replace('"', "\"\""))
        } else {
            s.to_string()
        }
    };
    let mut s = header.iter().map(|h| q(h)).collect::<Vec<_>>().join(",");
    s.push('\n');
    for r in rows {
        s.push_str(&r.iter().map(|c| q(c)).collect::<Vec<_>>().join(","));
        s.push('\n');
    }
    s
}

/// Fixed decimals, with `-0.000` printed as `0.000`.
pub fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// A short number for tables: fixed for ordinary magnitudes, scientific otherwise.
pub fn short(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        fixed(x, 6)
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    } else {
        format!("{x:.3e}")
    }
}

pub fn vec_str(v: &[f64], decimals: usize) -> String {
    format!(
        "[{}]",
        v.iter()
            .map(|x| fixed(*x, decimals))
            .collect::<Vec<_>>()
            .join(", ")
    )
}

/// Build the rig report from a composed chain: the analysis is
/// [`metric::analyze`]; this only arranges it in the schema.
pub fn rig_report(chain: &Chain, ells: &[f64], pitch_tol: f64) -> Result<RigReport> {
    let an = metric::analyze(&chain.transform, ells, pitch_tol)?;
    Ok(report_from_analysis(&an, chain))
}

pub fn report_from_analysis(an: &RigAnalysis, chain: &Chain) -> RigReport {
    let s = &an.screw;
    let am = &an.adapted_metric;
    RigReport {
        schema_version: SCHEMA_VERSION,
        from: chain.from.clone(),
        to: chain.to.clone(),
        sources: sources_json(chain),
        transform: transform_json(&an.transform),
        lever_arm_m: an.lever_arm_m,
        rotation: RotationJson {
            angle_rad: an.angle_rad,
            angle_deg: an.angle_rad.to_degrees(),
            axis: an.axis.map(|e| arr3(&e)),
        },
        screw: ScrewJson {
            kind: s.kind.name().to_string(),
            translation_along_axis_m: s.translation_along_axis,
            pitch_m_per_rad: s.pitch,
            axis_point_m: s.axis_point.map(|c| arr3(&c)),
        },
        adjoint: AdjointJson {
            singular_values: an.adjoint.singular_values,
            orthogonal: an.adjoint.orthogonal,
            ata_minus_i_rel: an.adjoint.ata_minus_i_rel,
        },
        certificate: an
            .certificate
            .iter()
            .map(|c| CertificateJson {
                ell_m: c.ell_m,
                delta_eff: c.delta_eff,
                band: c.band,
            })
            .collect(),
        adapted_metric: AdaptedMetricJson {
            exists: am.exists,
            reason: am.reason.text().to_string(),
            matrix: am
                .matrix
                .map(|m| std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))),
            invariance_residual: am.invariance_residual,
            offdiag_norm: am.offdiag_norm,
            rel_diff_identity: am.rel_diff_identity,
        },
        detectors: an
            .detectors
            .iter()
            .map(|d| DetectorJson {
                family: d.family.name().to_string(),
                equivariant_rule: d.equivariant_rule,
                invariant_on_rig: d.invariant_on_rig,
                reason: d.reason.text().to_string(),
            })
            .collect(),
        kappa_check: None,
    }
}

/// Band check for `--kappa K --lambda L`: certified when `L/K` lies outside the
/// band `[s_min^2, s_max^2]` of that characteristic length
/// ([`crate::geometry::certificate::certifies_no_crossing`]).
pub fn kappa_check(rep: &RigReport, kappa: f64, lambda: f64) -> Result<KappaCheckJson> {
    let certified = rep
        .certificate
        .iter()
        .map(|c| crate::geometry::certificate::certifies_no_crossing(lambda, kappa, c.delta_eff))
        .collect::<Result<Vec<bool>>>()?;
    Ok(KappaCheckJson {
        kappa,
        lambda,
        ratio: lambda / kappa,
        certified,
    })
}

/// One survey row (DESIGN.md survey JSON).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SurveyRigJson {
    pub id: String,
    pub sensor: String,
    pub platform: String,
    pub dataset: String,
    pub from: String,
    pub to: String,
    pub lever_arm_m: f64,
    pub angle_deg: f64,
    pub screw_translation_m: Option<f64>,
    pub zero_pitch: bool,
    pub sigma_max: f64,
    pub band_l1: [f64; 2],
    pub adapted_metric_exists: bool,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SurveySummaryJson {
    pub count: usize,
    pub lever_arm_min_m: f64,
    pub lever_arm_median_m: f64,
    pub lever_arm_max_m: f64,
    pub nonzero_pitch_count: usize,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SurveyJson {
    pub schema_version: u32,
    pub rigs: Vec<SurveyRigJson>,
    pub summary: SurveySummaryJson,
}
