//! The rig report (`audit FILE... --from A --to B`): the analysis of one
//! composed transform in the JSON schema `docs/schemas/rig-report.schema.json`
//! (schema_version 1, other programs read it: keep field names and types), and
//! its layout for people.

use crate::analysis::metric::{self, RigAnalysis};
use crate::analysis::Family;
use crate::diagnostic::Result;
use crate::document::numbers::{degrees, fixed, metres, ratio, short, unit, vector};
use crate::document::SCHEMA_VERSION;
use crate::document::{Block, Document, Report, Table};
use crate::frames::Chain;
use crate::geometry::certificate;
use crate::geometry::uncertainty::{self, Step, UncertaintySource};
use crate::geometry::{EdgePrecision, PitchTol, PitchVerdict, ScrewKind, Transform, UserSigma};
use crate::tolerances::{
    NEAR_HALF_TURN_RAD, PITCH_FLOAT_FLOOR_M, PITCH_K, PITCH_RESOLUTION_M, SMALL_ROTATION_DEG,
};
use serde::Serialize;

/// `sources[]`: one per edge used, in chain order.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SourceJson {
    /// The file the edge was read from, as the user named it (empty when the
    /// edge came from no file).
    pub file: String,
    /// 1-based line of the edge in that file; null when unknown.
    pub line: Option<usize>,
    /// Id of the format that read it (`urdf`, `fast-lio`, ...), as
    /// `--input-format` takes it.
    pub format: String,
}

/// `transform`: the composed `from -> to` transform, the pose of `to` in `from`
/// (`p_from = R p_to + d`), in four equivalent forms.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct TransformJson {
    /// `d` (m): the origin of `to` in `from` coordinates.
    pub translation_m: [f64; 3],
    /// `R`, row-major (`rotation_matrix[i][j] = R_ij`).
    pub rotation_matrix: [[f64; 3]; 3],
    /// `R` as a unit quaternion `[x, y, z, w]`, `w >= 0`.
    pub quaternion_xyzw: [f64; 4],
    /// `R` as URDF fixed-axis `[roll, pitch, yaw]` (rad):
    /// `R = Rz(yaw) Ry(pitch) Rx(roll)`.
    pub rpy_rad: [f64; 3],
}

/// `rotation`: angle and axis of `R`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RotationJson {
    /// Rotation angle `phi` in `[0, pi]` (rad).
    pub angle_rad: f64,
    /// The same angle in degrees, `[0, 180]`.
    pub angle_deg: f64,
    /// First-order standard uncertainty of the angle (rad).
    pub angle_uncertainty_rad: f64,
    /// Unit axis `e` (right-handed about `e` by `phi`); null when the angle is
    /// below `ANGLE_ZERO_TOL` (no rotation).
    pub axis: Option<[f64; 3]>,
}

/// `screw`: the Chasles decomposition (conventions in [`crate::Transform::screw`]).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ScrewJson {
    /// `identity`, `pure_translation`, `zero_pitch` or `general`.
    pub kind: ScrewKind,
    /// Screw translation `h = e . d` (m), the same for `T` and `T^-1`; null
    /// without a rotation.
    pub translation_along_axis_m: Option<f64>,
    /// Pitch `h / phi` (m/rad); null without a rotation.
    pub pitch_m_per_rad: Option<f64>,
    /// The point of the screw axis closest to the origin of `from` (m, in
    /// `from` coordinates); null without a rotation.
    pub axis_point_m: Option<[f64; 3]>,
    /// First-order standard uncertainty of `h` (m); null without a rotation.
    pub translation_along_axis_uncertainty_m: Option<f64>,
    /// First-order standard uncertainty of the pitch (m/rad); null without a
    /// rotation.
    pub pitch_uncertainty_m_per_rad: Option<f64>,
    /// `zero`, `nonzero` or `undecidable` (conventions in
    /// [`crate::PitchVerdict`]); null without a rotation.
    pub pitch_verdict: Option<PitchVerdict>,
    /// For `undecidable`: the standard uncertainty of `h` (m) below which the
    /// verdict would be decided; null otherwise.
    pub deciding_uncertainty_m: Option<f64>,
}

/// `uncertainty`: where the standard uncertainties come from and how the
/// pitch verdict was taken.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct UncertaintyJson {
    /// `none`, `rounding` (of the numbers as written), `user` (`--sigma-t`,
    /// `--sigma-r`) or `both`.
    pub source: UncertaintySource,
    /// `--pitch-tol`: `"auto"` or the tolerance on `|h|` (m) as a string.
    pub pitch_tol: String,
    /// `k`: `h` is zero within `k` standard uncertainties (`auto`).
    pub k: f64,
    /// Widest `k * sigma_h` (m) at which a zero verdict is given (`auto`).
    pub resolution_m: f64,
    /// Edges of the chain whose format recorded no rounding (their numbers
    /// count as exact).
    pub edges_without_rounding: usize,
}

/// `adjoint`: the singular values of `Ad(T)`, in closed form from `||d||`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct AdjointJson {
    /// Six, descending: `s_max, s_max, 1, 1, s_min, s_min` with
    /// `s_max = ||d||/2 + sqrt(1 + ||d||^2/4)` (`||d||` in metres) and
    /// `s_min = 1/s_max`.
    pub singular_values: [f64; 6],
    /// First-order standard uncertainty of each singular value.
    pub singular_values_uncertainty: [f64; 6],
    /// `Ad(T)` is orthogonal: `||d||` within `LENGTH_ZERO_TOL`.
    pub orthogonal: bool,
    /// `||A^T A - I||_F / ||I||_F` (dimensionless, 0 when orthogonal).
    pub ata_minus_i_rel: f64,
}

/// `certificate[i]`: the certificate band at one characteristic length.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct CertificateJson {
    /// Characteristic length `l` (m).
    pub ell_m: f64,
    /// Effective lever arm `||d|| / l` (dimensionless).
    pub delta_eff: f64,
    /// `[s_min^2, s_max^2]` at `delta_eff`: the factors by which the frame
    /// change can multiply an eigenvalue.
    pub band: [f64; 2],
    /// First-order standard uncertainty of each band edge.
    pub band_uncertainty: [f64; 2],
}

/// `adapted_metric`: the constant metric `M0` with `A^T M0 A = M0` for this
/// rig, when one exists.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct AdaptedMetricJson {
    /// `M0` exists (identity or zero-pitch screw); then the other fields are
    /// numbers, otherwise null.
    pub exists: bool,
    /// Why it exists or not, in words.
    pub reason: String,
    /// `M0`, row-major 6x6 in twist order `[omega; t]`; null when none.
    pub matrix: Option<[[f64; 6]; 6]>,
    /// `||A^T M0 A - M0||_F / ||M0||_F`, computed as a check (rounding, about 1e-15 for real rigs).
    pub invariance_residual: Option<f64>,
    /// Frobenius norm of the lower-left 3x3 block of `M0` (the
    /// rotation-translation coupling).
    pub offdiag_norm: Option<f64>,
    /// `||M0 - I6||_F / ||I6||_F`: how far `M0` is from the unnormalized metric.
    pub rel_diff_identity: Option<f64>,
}

/// `detectors[i]`: one detector family's verdict on this rig.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct DetectorJson {
    /// The family's JSON name (`unnormalized`, `characteristic_length`, ...).
    pub family: Family,
    /// The family's metric rule is equivariant (`M(T . D) = A^T M(D) A` for
    /// every `T`): only `point_displacement`.
    pub equivariant_rule: bool,
    /// The family's eigenvalues are the same in both frames of this rig.
    pub invariant_on_rig: bool,
    /// Why, in words.
    pub reason: String,
}

/// `--kappa K --lambda L`: does the band certify that L cannot cross K?
/// Present only when asked for.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct KappaCheckJson {
    /// The detector's threshold `K` (`--kappa`).
    pub kappa: f64,
    /// The eigenvalue `L` to test (`--lambda`), in the same units as `K`.
    pub lambda: f64,
    /// `L / K`.
    pub ratio: f64,
    /// Per characteristic length, same order as `certificate`.
    pub certified: Vec<bool>,
}

/// The rig report (`audit FILE... --from A --to B --format json`).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RigReport {
    /// Version of this JSON layout (1).
    pub schema_version: u32,
    /// The frame the transform is expressed in (`--from`).
    pub from: String,
    /// The frame whose pose it is (`--to`).
    pub to: String,
    /// One entry per edge composed, in chain order from `from` to `to`.
    pub sources: Vec<SourceJson>,
    /// The composed transform: pose of `to` in `from`.
    pub transform: TransformJson,
    /// Lever arm `||d||` (m).
    pub lever_arm_m: f64,
    /// First-order standard uncertainty of the lever arm (m).
    pub lever_arm_uncertainty_m: f64,
    /// Where the uncertainties come from and how the pitch was judged.
    pub uncertainty: UncertaintyJson,
    /// Rotation angle and axis.
    pub rotation: RotationJson,
    /// Screw decomposition.
    pub screw: ScrewJson,
    /// Singular values of `Ad(T)`.
    pub adjoint: AdjointJson,
    /// One band per characteristic length, in the order given (`--ell`).
    pub certificate: Vec<CertificateJson>,
    /// The adapted constant metric, or why there is none.
    pub adapted_metric: AdaptedMetricJson,
    /// One verdict per detector family, in the family table's order.
    pub detectors: Vec<DetectorJson>,
    /// Only with `--kappa` and `--lambda` (absent from the JSON otherwise).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub kappa_check: Option<KappaCheckJson>,
    /// The chain's edges for the text renderings (the JSON has `sources`).
    #[serde(skip)]
    pub(crate) chain: Vec<ChainRow>,
    /// The whole frame tree, the chain marked, for the 3D scene (every edge
    /// of the graph); `None`: the scene has the one `from -> to` transform.
    #[serde(skip)]
    pub tree: Option<super::frames::FramesReport>,
    /// What the user's own detector does on this rig (`--detector NAME`, or
    /// the odometry an input reveals): set it to
    /// [`OdometryDetector::advise`](crate::OdometryDetector::advise) of the
    /// chain's transform; `None` (absent from the JSON) otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub detector: Option<crate::analysis::detectors::DetectorAdvice>,
}

/// One edge of the chain as the report's table shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainRow {
    /// `parent -> child`, in the direction walked.
    pub edge: String,
    /// Walked child -> parent.
    pub inverted: bool,
    /// `file:line:col`.
    pub place: String,
    /// Format id.
    pub format: &'static str,
    /// The key or element the numbers came from.
    pub key: String,
}

fn arr3(v: &nalgebra::Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// The four forms of `t` the report prints.
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

/// `sources[]` of a chain: one entry per edge, in chain order.
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

fn chain_rows(chain: &Chain) -> Vec<ChainRow> {
    chain
        .steps
        .iter()
        .map(|step| {
            let e = &step.edge;
            let (a, b) = if step.inverted {
                (e.child.as_str(), e.parent.as_str())
            } else {
                (e.parent.as_str(), e.child.as_str())
            };
            ChainRow {
                edge: format!("{a} -> {b}"),
                inverted: step.inverted,
                place: e.provenance.location.to_string(),
                format: e.provenance.format,
                key: e.provenance.key.clone(),
            }
        })
        .collect()
}

/// How the pitch is judged and what calibration uncertainty the user adds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Judgement {
    /// `--pitch-tol`: `auto` (three-way) or a length (m).
    pub pitch_tol: PitchTol,
    /// `--sigma-t`/`--sigma-r`: for every edge whose file gives none.
    pub user: Option<UserSigma>,
}

impl Default for Judgement {
    fn default() -> Self {
        Judgement {
            pitch_tol: PitchTol::Auto,
            user: None,
        }
    }
}

/// The edges' precisions, the user's uncertainty filled in where the file
/// gave none.
fn precisions(chain: &Chain, how: &Judgement) -> Vec<EdgePrecision> {
    chain
        .steps
        .iter()
        .map(|s| {
            let mut p = s.edge.precision.full();
            if p.user.is_none() {
                p.user = how.user;
            }
            p
        })
        .collect()
}

/// What the rig report and [`rig_verdicts`] both start from: the edges'
/// precisions, the chain's uncertainty ([`uncertainty::propagate`]), the
/// pitch decision it gives, and the analysis at the decision's tolerance.
struct Judged {
    prec: Vec<EdgePrecision>,
    unc: uncertainty::ChainUncertainty,
    decision: Option<uncertainty::PitchDecision>,
    an: RigAnalysis,
}

fn judge(chain: &Chain, ells: &[f64], how: &Judgement) -> Result<Judged> {
    let prec = precisions(chain, how);
    let steps: Vec<Step> = chain
        .steps
        .iter()
        .zip(&prec)
        .map(|(s, p)| Step {
            transform: s.edge.transform,
            inverted: s.inverted,
            covariance: p.covariance(),
        })
        .collect();
    let nominal = chain.transform.screw(PITCH_FLOAT_FLOOR_M);
    let unc = uncertainty::propagate(&steps, nominal.axis.as_ref())?;
    let decision = Some(match nominal.translation_along_axis {
        Some(h) => uncertainty::pitch_decision(h, unc.h_m.unwrap_or(0.0), how.pitch_tol),
        None => uncertainty::no_axis_decision(nominal.kind, how.pitch_tol),
    });
    let tol = decision.map_or(PITCH_FLOAT_FLOOR_M, |d| d.screw_tol);
    let an = metric::analyze(&chain.transform, ells, tol)?;
    Ok(Judged {
        prec,
        unc,
        decision,
        an,
    })
}

/// What `audit check` judges a frame pair by: the fields of the rig report
/// at `ells = [1.0]` its rules and its baseline record read, the same
/// numbers and the same errors, without the rest of the report (its
/// sources, chain rows, texts and band uncertainties were half the cost of
/// checking a rig file's pair, issue 29).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigVerdicts {
    /// `lever_arm_m`.
    pub lever_arm_m: f64,
    /// `screw.kind`.
    pub kind: ScrewKind,
    /// `screw.translation_along_axis_m`.
    pub translation_along_axis_m: Option<f64>,
    /// `screw.translation_along_axis_uncertainty_m`.
    pub translation_along_axis_uncertainty_m: Option<f64>,
    /// `screw.pitch_verdict`.
    pub pitch_verdict: Option<PitchVerdict>,
    /// `uncertainty.source`.
    pub source: UncertaintySource,
    /// `adapted_metric.exists`.
    pub adapted_metric_exists: bool,
}

/// [`rig_report`]`(chain, &[1.0], how)` cut to [`RigVerdicts`].
pub fn rig_verdicts(chain: &Chain, how: &Judgement) -> Result<RigVerdicts> {
    let Judged {
        prec,
        unc,
        decision,
        an,
    } = judge(chain, &[1.0], how)?;
    Ok(RigVerdicts {
        lever_arm_m: an.lever_arm_m,
        kind: an.screw.kind,
        translation_along_axis_m: an.screw.translation_along_axis,
        translation_along_axis_uncertainty_m: unc.h_m,
        pitch_verdict: decision.map(|d| d.verdict),
        source: UncertaintySource::of(&prec),
        adapted_metric_exists: an.adapted_metric.exists,
    })
}

/// Build the rig report from a composed chain: the uncertainty of the chain
/// ([`uncertainty::propagate`]) decides the pitch verdict, whose tolerance
/// the analysis ([`metric::analyze`]) then uses.
pub fn rig_report(chain: &Chain, ells: &[f64], how: &Judgement) -> Result<RigReport> {
    let Judged {
        prec,
        unc,
        decision,
        an,
    } = judge(chain, ells, how)?;
    let mut rep = report_from_analysis(&an, chain);
    rep.lever_arm_uncertainty_m = unc.lever_arm_m;
    rep.rotation.angle_uncertainty_rad = unc.angle_rad;
    rep.screw.translation_along_axis_uncertainty_m = unc.h_m;
    rep.screw.pitch_uncertainty_m_per_rad = unc.pitch_m_per_rad;
    rep.screw.pitch_verdict = decision.map(|d| d.verdict);
    rep.screw.deciding_uncertainty_m = decision.and_then(|d| d.deciding_sigma_m);
    let lever = an.lever_arm_m;
    let du = |f: &dyn Fn(f64) -> f64, x: f64| uncertainty::derivative(f, x).abs() * unc.lever_arm_m;
    let smax_u = du(&certificate::sigma_max, lever);
    let smin_u = du(&certificate::sigma_min, lever);
    rep.adjoint.singular_values_uncertainty = [smax_u, smax_u, 0.0, 0.0, smin_u, smin_u];
    for c in &mut rep.certificate {
        let ell = c.ell_m;
        c.band_uncertainty = [
            du(&|l| certificate::band(l / ell)[0], lever),
            du(&|l| certificate::band(l / ell)[1], lever),
        ];
    }
    rep.uncertainty = UncertaintyJson {
        source: UncertaintySource::of(&prec),
        pitch_tol: how.pitch_tol.to_string(),
        k: PITCH_K,
        resolution_m: PITCH_RESOLUTION_M,
        edges_without_rounding: prec.iter().filter(|p| p.rounding.is_none()).count(),
    };
    if decision.map(|d| d.verdict) == Some(PitchVerdict::Undecidable) {
        mark_undecidable(&mut rep);
    }
    Ok(rep)
}

/// An undecidable pitch: no adapted metric is offered, and the adapted-metric
/// family says why.
fn mark_undecidable(rep: &mut RigReport) {
    rep.adapted_metric.reason = metric::AdaptedReason::UndecidablePitch.text().to_string();
    for d in &mut rep.detectors {
        if d.family == Family::AdaptedConstant {
            d.invariant_on_rig = false;
            d.reason = metric::VerdictReason::AdaptedUndecidablePitch
                .text()
                .to_string();
        }
    }
}

/// Arrange an analysis of `chain.transform` (from [`metric::analyze`]) as the
/// rig report; the uncertainties are zero and `kappa_check` is empty.
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
        lever_arm_uncertainty_m: 0.0,
        uncertainty: UncertaintyJson {
            source: UncertaintySource::None,
            pitch_tol: an.pitch_tol.to_string(),
            k: PITCH_K,
            resolution_m: PITCH_RESOLUTION_M,
            edges_without_rounding: 0,
        },
        rotation: RotationJson {
            angle_rad: an.angle_rad,
            angle_deg: an.angle_rad.to_degrees(),
            angle_uncertainty_rad: 0.0,
            axis: an.axis.map(|e| arr3(&e)),
        },
        screw: ScrewJson {
            kind: s.kind,
            translation_along_axis_m: s.translation_along_axis,
            pitch_m_per_rad: s.pitch,
            axis_point_m: s.axis_point.map(|c| arr3(&c)),
            translation_along_axis_uncertainty_m: None,
            pitch_uncertainty_m_per_rad: None,
            pitch_verdict: None,
            deciding_uncertainty_m: None,
        },
        adjoint: AdjointJson {
            singular_values: an.adjoint.singular_values,
            singular_values_uncertainty: [0.0; 6],
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
                band_uncertainty: [0.0; 2],
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
                family: d.family,
                equivariant_rule: d.equivariant_rule,
                invariant_on_rig: d.invariant_on_rig,
                reason: d.reason.text().to_string(),
            })
            .collect(),
        kappa_check: None,
        chain: chain_rows(chain),
        tree: None,
        detector: None,
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

/// Whether `angle` (rad) is within [`NEAR_HALF_TURN_RAD`] of a half-turn: the
/// sign of the axis, and of `h`, then follows the rounding of the numbers.
pub fn near_half_turn(angle_rad: f64) -> bool {
    (std::f64::consts::PI - angle_rad).abs() < NEAR_HALF_TURN_RAD
}

/// Whether a rotation (deg) is small enough that its screw axis is set by
/// calibration noise ([`SMALL_ROTATION_DEG`]).
pub fn small_rotation(angle_deg: f64) -> bool {
    angle_deg > 0.0 && angle_deg < SMALL_ROTATION_DEG
}

impl RigReport {
    /// The one-line verdict that opens the report.
    pub fn verdict_line(&self) -> String {
        let invariant: Vec<Family> = self
            .detectors
            .iter()
            .filter(|d| d.invariant_on_rig)
            .map(|d| d.family)
            .collect();
        let lever = format!("lever arm {} m", fixed(self.lever_arm_m, 3));
        let screw = match self.screw.kind {
            ScrewKind::Identity => "identity transform".to_string(),
            ScrewKind::PureTranslation => "no rotation (pure translation)".to_string(),
            ScrewKind::ZeroPitch | ScrewKind::General => {
                let deg = self.rotation.angle_deg;
                let caveat = if deg < SMALL_ROTATION_DEG {
                    format!(
                        " (rotation only {} deg: the screw axis is set by calibration noise)",
                        fixed(deg, 3)
                    )
                } else if near_half_turn(self.rotation.angle_rad) {
                    " (half-turn: the sign of h follows the rounding)".to_string()
                } else {
                    String::new()
                };
                format!("{}{caveat}", self.h_with_verdict())
            }
        };
        let undecidable = self.screw.pitch_verdict == Some(PitchVerdict::Undecidable);
        let tail = if undecidable && invariant == [Family::PointDisplacement] {
            "whether a constant metric is frame-invariant on this rig is undecidable at this precision; the point-displacement metric is".to_string()
        } else if invariant.len() == self.detectors.len() && !invariant.is_empty() {
            "every detector family is frame-invariant on this rig".to_string()
        } else if invariant == [Family::PointDisplacement] {
            if self.adapted_metric.exists {
                "only the point-displacement metric is frame-invariant on this rig".to_string()
            } else {
                "no constant metric is frame-invariant on this rig; only the point-displacement metric is".to_string()
            }
        } else if invariant.is_empty() {
            "no detector family is frame-invariant on this rig".to_string()
        } else {
            format!(
                "frame-invariant on this rig: {}",
                invariant
                    .iter()
                    .map(|f| f.label())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        format!("{lever}, {screw}: {tail}. {}", self.advice())
    }

    /// `h = -6.0e-7 +- 5e-5 m (rounding), pitch zero`: `h`, its standard
    /// uncertainty and source, and the verdict.
    pub fn h_with_verdict(&self) -> String {
        let sc = &self.screw;
        let h = short(sc.translation_along_axis_m.unwrap_or(0.0));
        let u = match (
            sc.translation_along_axis_uncertainty_m,
            self.uncertainty.source,
        ) {
            (Some(u), src) if src != UncertaintySource::None => {
                format!(" +- {} m ({})", short(u), src.name())
            }
            _ if self.uncertainty.edges_without_rounding == 0 => {
                " m (exact as written)".to_string()
            }
            _ => " m (no rounding recorded by the format)".to_string(),
        };
        let verdict = match (sc.pitch_verdict, sc.deciding_uncertainty_m) {
            (Some(PitchVerdict::Undecidable), Some(need)) => format!(
                "pitch undecidable at this precision (decided with sigma_h below {} m)",
                short(need)
            ),
            (Some(v), _) => format!("pitch {}", v.name()),
            (None, _) => String::new(),
        };
        format!("h = {h}{u}, {verdict}")
    }

    /// The closing "what to do" sentence, in this rig's numbers: which metric
    /// to use, what the pitch verdict allows (the adapted metric M0 or not,
    /// with `h`), and how far an eigenvalue threshold tuned in `to` moves in
    /// `from` (the certificate band at `l = 1 m`, else at the first length
    /// given, with the lever arm); with the user's detector
    /// ([`RigReport::detector`]), that detector's concrete step instead of
    /// the generic band clause.
    pub fn advice(&self) -> String {
        let pd = "the point-displacement metric (frame-invariant on every rig)";
        if self.screw.kind == ScrewKind::Identity {
            return "Every metric is frame-invariant here: use any.".into();
        }
        let m0 = self.m0_clause();
        match &self.detector {
            Some(a) => format!("To do ({}): {}; {m0}.", a.detector.label, a.step),
            None if self.screw.pitch_verdict == Some(PitchVerdict::Zero)
                && self.screw.kind != ScrewKind::PureTranslation =>
            {
                format!("To do: use {pd} or {m0}; {}.", self.band_clause())
            }
            None => format!("To do: use {pd}: {m0}, and {}.", self.band_clause()),
        }
    }

    /// What the pitch verdict allows of the adapted metric M0, with `h`.
    fn m0_clause(&self) -> String {
        let sc = &self.screw;
        let h = short(sc.translation_along_axis_m.unwrap_or(0.0));
        match (sc.kind, sc.pitch_verdict) {
            (ScrewKind::PureTranslation, _) => format!(
                "no constant metric is invariant under a pure translation of {} m",
                fixed(self.lever_arm_m, 3)
            ),
            (_, Some(PitchVerdict::Zero)) => format!(
                "the adapted metric M0 printed below (h = {h} m: invariant on this rig at its written precision, residual {})",
                self.adapted_metric
                    .invariance_residual
                    .map(short)
                    .unwrap_or_else(|| "-".into())
            ),
            (_, Some(PitchVerdict::Undecidable)) => format!(
                "M0 can be used once h (now {h} m) is known to {} m (standard uncertainty)",
                short(sc.deciding_uncertainty_m.unwrap_or(0.0))
            ),
            _ => format!("h = {h} m rules out an adapted metric M0"),
        }
    }

    /// How an eigenvalue threshold tuned in `to` acts in `from`: the
    /// certificate band at `l = 1 m` (else the first length), or unchanged
    /// at zero lever arm.
    fn band_clause(&self) -> String {
        let (from, to) = (&self.from, &self.to);
        let Some(c) = self
            .certificate
            .iter()
            .find(|c| c.ell_m == 1.0)
            .or(self.certificate.first())
        else {
            return format!("thresholds tuned in {to} need re-tuning in {from}");
        };
        if self.lever_arm_m == 0.0 {
            return format!(
                "an eigenvalue threshold tuned in {to} carries to {from} unchanged (zero lever arm)"
            );
        }
        format!(
            "an eigenvalue threshold tuned in {to} acts in {from} as {} to {} times itself (lever arm {} m, l = {} m)",
            ratio(c.band[0]),
            ratio(c.band[1]),
            fixed(self.lever_arm_m, 3),
            short(c.ell_m)
        )
    }

    fn transform_section(&self, doc: &mut Document) {
        doc.section(format!("Transform {} -> {}", self.from, self.to));
        let tf = &self.transform;
        let (angle_deg, axis) = (self.rotation.angle_deg, self.rotation.axis);
        let mut rows = vec![vec![
            "translation (m)".into(),
            vector(&tf.translation_m, metres),
        ]];
        for (i, r) in tf.rotation_matrix.iter().enumerate() {
            rows.push(vec![
                format!("rotation matrix row {}", i + 1),
                vector(r, unit),
            ]);
        }
        rows.push(vec![
            "quaternion [x, y, z, w]".into(),
            vector(&tf.quaternion_xyzw, unit),
        ]);
        rows.push(vec![
            "URDF rpy (rad)".into(),
            format!(
                "{}  = {} deg",
                vector(&tf.rpy_rad, unit),
                vector(&tf.rpy_rad.map(f64::to_degrees), degrees)
            ),
        ]);
        rows.push(vec![
            "axis-angle".into(),
            match axis {
                Some(e) => format!("{} deg about {}", degrees(angle_deg), vector(&e, unit)),
                None => format!("{} deg (no axis)", degrees(angle_deg)),
            },
        ]);
        let (a, b) = (&self.from, &self.to);
        doc.push(Block::Note {
            text: format!("pose of {b} in {a}: p_{a} = R p_{b} + d"),
            markdown: Some(format!("Pose of `{b}` in `{a}`: `p_{a} = R p_{b} + d`.")),
        });
        doc.table(Table::new(&["quantity", "value"], rows));
    }

    fn chain_section(&self, doc: &mut Document) {
        doc.section("Chain of edges");
        if self.chain.is_empty() {
            doc.text("(from and to are the same frame)");
            return;
        }
        let rows = self
            .chain
            .iter()
            .enumerate()
            .map(|(i, c)| {
                vec![
                    format!("{}", i + 1),
                    format!("{}{}", c.edge, if c.inverted { " (inverted)" } else { "" }),
                    c.place.clone(),
                    c.format.to_string(),
                    c.key.clone(),
                ]
            })
            .collect();
        doc.table(Table::new(
            &["#", "edge", "file:line", "format", "from"],
            rows,
        ));
    }

    fn rig_section(&self, doc: &mut Document) {
        doc.section("Rig");
        let sc = &self.screw;
        let mut rows = vec![
            vec![
                "lever arm ||d||".into(),
                format!(
                    "{} +- {} m",
                    metres(self.lever_arm_m),
                    short(self.lever_arm_uncertainty_m)
                ),
            ],
            vec![
                "rotation angle".into(),
                format!(
                    "{} deg ({} +- {} rad)",
                    degrees(self.rotation.angle_deg),
                    unit(self.rotation.angle_rad),
                    short(self.rotation.angle_uncertainty_rad)
                ),
            ],
            vec!["screw kind".into(), sc.kind.label().into()],
        ];
        if sc.translation_along_axis_m.is_some() {
            rows.push(vec![
                "screw translation h = e.d".into(),
                // The label names h: the value alone (one line at 80 columns).
                self.h_with_verdict().trim_start_matches("h = ").to_string(),
            ]);
        }
        if sc.kind == ScrewKind::PureTranslation {
            // No axis, no h: the pitch is infinite, and its verdict definite.
            rows.push(vec![
                "screw pitch h/phi".into(),
                "infinite (no rotation), pitch nonzero".into(),
            ]);
        }
        if let Some(p) = sc.pitch_m_per_rad {
            let u = sc
                .pitch_uncertainty_m_per_rad
                .map(|u| format!(" +- {}", short(u)))
                .unwrap_or_default();
            rows.push(vec![
                "screw pitch h/phi".into(),
                format!("{}{u} m/rad", metres(p)),
            ]);
        }
        if let Some(c) = sc.axis_point_m {
            rows.push(vec![
                "screw axis point (closest to origin)".into(),
                format!("{} m", vector(&c, metres)),
            ]);
        }
        let sv = self.adjoint.singular_values;
        rows.push(vec![
            "Ad(T) singular values".into(),
            format!(
                "{} +- {} (x2), 1 (x2), {} (x2)",
                ratio(sv[0]),
                short(self.adjoint.singular_values_uncertainty[0]),
                ratio(sv[5])
            ),
        ]);
        rows.push(vec![
            "Ad(T) orthogonal".into(),
            if self.adjoint.orthogonal {
                "yes (d = 0)".into()
            } else {
                "no (d != 0)".into()
            },
        ]);
        rows.push(vec![
            "||A^T A - I||_F / ||I||_F".into(),
            ratio(self.adjoint.ata_minus_i_rel),
        ]);
        doc.table(Table::new(&["quantity", "value"], rows));
    }

    fn certificate_section(&self, doc: &mut Document) {
        doc.section("Certificate bands");
        let rows = self
            .certificate
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let mut r = vec![
                    short(c.ell_m),
                    ratio(c.delta_eff),
                    ratio(c.band[0]),
                    ratio(c.band[1]),
                ];
                if let Some(k) = &self.kappa_check {
                    r.push(if k.certified[i] { "yes" } else { "no" }.into());
                }
                r
            })
            .collect();
        let mut header = vec!["ell (m)", "delta_eff", "band lower", "band upper"];
        if self.kappa_check.is_some() {
            header.push("lambda/kappa outside: certified");
        }
        doc.table(Table::new(&header, rows));
        doc.text("If lambda/kappa lies outside the band, no frame change with this lever arm can move eigenvalue lambda across threshold kappa.");
        if let Some(k) = &self.kappa_check {
            doc.text(format!(
                "lambda/kappa = {} / {} = {}",
                short(k.lambda),
                short(k.kappa),
                ratio(k.ratio)
            ));
        }
    }

    fn adapted_section(&self, doc: &mut Document) {
        doc.section("Adapted constant metric");
        let am = &self.adapted_metric;
        if !am.exists {
            doc.text(format!("none: {}", am.reason));
            return;
        }
        doc.text(format!("exists: {}", am.reason));
        if let Some(m) = &am.matrix {
            let rows = m
                .iter()
                .map(|r| r.iter().map(|x| ratio(*x)).collect())
                .collect();
            doc.table(Table::new(&["wx", "wy", "wz", "tx", "ty", "tz"], rows));
        }
        let opt = |x: Option<f64>| x.map(short).unwrap_or_else(|| "-".into());
        doc.text(format!(
            "invariance residual {} (at the values as written), off-diagonal block norm {}, ||M0 - I||_F/||I||_F {}",
            opt(am.invariance_residual),
            opt(am.offdiag_norm),
            opt(am.rel_diff_identity)
        ));
    }

    fn families_section(&self, doc: &mut Document) {
        doc.section("Detector families");
        let yes_no = |b: bool| if b { "yes" } else { "no" }.to_string();
        let rows = self
            .detectors
            .iter()
            .map(|d| {
                vec![
                    d.family.label().to_string(),
                    yes_no(d.equivariant_rule),
                    yes_no(d.invariant_on_rig),
                    d.reason.clone(),
                ]
            })
            .collect();
        // The reasons are sentences: wrap them.
        doc.table(
            Table::new(
                &["family", "equivariant rule", "invariant on this rig", "why"],
                rows,
            )
            .bounded(&[(0, 22), (3, 60)]),
        );
    }
}

impl Report for RigReport {
    fn document(&self) -> Document {
        let mut doc = Document::new();
        let good = self.detectors.iter().filter(|d| d.invariant_on_rig).count() > 1;
        doc.push(Block::Headline {
            text: self.verdict_line(),
            good,
        });
        self.transform_section(&mut doc);
        self.chain_section(&mut doc);
        self.rig_section(&mut doc);
        self.certificate_section(&mut doc);
        self.adapted_section(&mut doc);
        self.families_section(&mut doc);
        if let Some(a) = &self.detector {
            doc.section(format!("Your detector: {}", a.detector.label));
            // Its step is the headline's "To do".
            doc.text(format!("{}.\nSource: {}.", a.statement, a.detector.source));
        }
        doc.table(self.data_table());
        doc.push(Block::Scene(self.scene()));
        doc
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::{load_file, LoadOptions};
    use crate::frames::FrameGraph;

    /// `rig_verdicts` is `rig_report` at `ells = [1.0]` cut to its fields:
    /// over every shipped rig file, with and without a user's sigma and a
    /// fixed pitch tolerance, each field equal to the report's (bit for bit).
    #[test]
    fn verdicts_are_the_reports_fields() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("calibrations");
        let mut rigs = 0;
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "toml") {
                continue;
            }
            let mut loaded = load_file(&path, &LoadOptions::default()).unwrap();
            let meta = loaded.rig.take().unwrap();
            let mut graph = FrameGraph::new();
            graph.add(loaded).unwrap();
            let chain = graph.transform(&meta.from, &meta.to).unwrap();
            let hows = [
                Judgement::default(),
                Judgement {
                    pitch_tol: PitchTol::Fixed(1e-3),
                    user: Some(UserSigma {
                        sigma_t_m: 0.01,
                        sigma_r_rad: 0.002,
                    }),
                },
            ];
            for how in &hows {
                let v = rig_verdicts(&chain, how).unwrap();
                let r = rig_report(&chain, &[1.0], how).unwrap();
                let name = path.display();
                assert_eq!(v.lever_arm_m.to_bits(), r.lever_arm_m.to_bits(), "{name}");
                assert_eq!(v.kind, r.screw.kind, "{name}");
                assert_eq!(
                    v.translation_along_axis_m.map(f64::to_bits),
                    r.screw.translation_along_axis_m.map(f64::to_bits),
                    "{name}"
                );
                assert_eq!(
                    v.translation_along_axis_uncertainty_m.map(f64::to_bits),
                    r.screw
                        .translation_along_axis_uncertainty_m
                        .map(f64::to_bits),
                    "{name}"
                );
                assert_eq!(v.pitch_verdict, r.screw.pitch_verdict, "{name}");
                assert_eq!(v.source, r.uncertainty.source, "{name}");
                assert_eq!(v.adapted_metric_exists, r.adapted_metric.exists, "{name}");
            }
            rigs += 1;
        }
        assert!(rigs >= 20, "expected the shipped rig files, found {rigs}");
    }
}
