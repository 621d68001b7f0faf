//! Metric families as rules `M(D)` for `H v = lambda M v`, the adapted constant
//! metric of one rig, per-rig verdicts (the README's detector table; paper,
//! Section IV), and [`analyze`], the one allocation-free entry point that
//! computes everything the report says about a single transform.
//!
//! Conventions are those of [`crate::geometry::se3`]. In short: `T = (R, d)`,
//! `A = Ad(T) = [[R, 0], [[d]x R, R]]`, `H' = A^T H A`; a metric rule is
//! *equivariant* if `M(T . D) = A^T M(D) A` for every `T`, and a fixed metric `M`
//! is *invariant on a rig* if `A^T M A = M` for that rig's `T`.
//!
//! Definitions of the reported numbers:
//! - invariance residual `||A^T M0 A - M0||_F / ||M0||_F`;
//! - off-diagonal block norm: Frobenius norm of the lower-left 3x3 block of `M0`
//!   (the translation-rotation coupling; the upper-right block is its transpose);
//! - `rel_diff_identity = ||M0 - I6||_F / ||I6||_F`.
//!
//! The residual is computed directly, as a check rather than by a formula; its
//! rounding floor grows like `eps (1 + ||c||)^2 (1 + ||d||)^2`, about 1e-15 for
//! real rigs and meaningless for translations of 1e6 m and more.
//!
//! With `c` the screw-axis point, `M0 = Ad(P)^-T Ad(P)^-1 =
//! [[I + ||c||^2 I - c c^T, [c]x], [-[c]x, I]]`, so the off-diagonal norm is
//! `sqrt(2) ||c||` and `rel_diff_identity = ||c|| sqrt((||c||^2 + 2) / 3)`.

pub use super::family::Family;
use crate::diagnostic::{Error, Result};
use crate::geometry::certificate::{self, AdjointSummary, Certificates};
use crate::geometry::se3::{Screw, ScrewKind, Transform};
use crate::tolerances::{LENGTH_ZERO_TOL, SIGNED_PERMUTATION_TOL};
use nalgebra::{Matrix3, Matrix6, Vector3};

/// Block scaling: the paper gives no formula for `l` from `H`. This crate uses the
/// `l` that equalises the traces of the two scaled diagonal blocks of
/// `diag(l^2 I, I)^(-1/2) H diag(l^2 I, I)^(-1/2)`, i.e. `tr(H_rr) / l^2 =
/// tr(H_tt)`, so `l^2 = tr(H_rr) / tr(H_tt)` (metres: `H_rr` carries m^2). Changing
/// the rule means changing this one function.
///
/// Returns a non-finite value when `tr(H_tt) = 0` (no translational information)
/// or `tr(H_rr) = 0` with it (both blocks empty); callers must check.
pub fn block_scaling_ell(h: &Matrix6<f64>) -> f64 {
    let rr = h[(0, 0)] + h[(1, 1)] + h[(2, 2)];
    let tt = h[(3, 3)] + h[(4, 4)] + h[(5, 5)];
    (rr / tt).sqrt()
}

/// `M0 = Ad(P)^-T Ad(P)^-1` with `P` the pure translation to the screw-axis point,
/// when `T` has a rotation and zero pitch (`|h| <= pitch_tol`); `None` otherwise.
/// The identity transform gets `I6` (every metric is invariant under it).
pub fn adapted_metric_matrix(t: &Transform, pitch_tol: f64) -> Option<Matrix6<f64>> {
    adapted_metric_matrix_for_screw(&t.screw(pitch_tol))
}

/// [`adapted_metric_matrix`] from an already computed screw.
pub fn adapted_metric_matrix_for_screw(s: &Screw) -> Option<Matrix6<f64>> {
    match s.kind {
        ScrewKind::Identity => Some(Matrix6::identity()),
        ScrewKind::ZeroPitch => {
            let c: Vector3<f64> = s.axis_point?;
            // Ad(P)^-1 = Ad(P^-1), P^-1 = (I, -c).
            let a = Transform::from_parts_unchecked(Matrix3::identity(), -c).adjoint();
            Some(a.transpose() * a)
        }
        ScrewKind::PureTranslation | ScrewKind::General => None,
    }
}

/// `||A^T M A - M||_F / ||M||_F`: zero iff the fixed metric `M` is invariant
/// under the frame change `A`.
pub fn invariance_residual(a: &Matrix6<f64>, m: &Matrix6<f64>) -> f64 {
    let moved = a.transpose() * m * a;
    (moved - m).norm() / m.norm()
}

/// Why an adapted constant metric exists or not, in words.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AdaptedReason {
    /// `T` is the identity: `M0 = I6`.
    Identity,
    /// A rotation about an axis in space: `M0` is centred on that axis.
    ZeroPitch,
    /// No rotation: nothing to centre a metric on.
    PureTranslation,
    /// `h != 0`: `Ad(T)` is defective.
    NonzeroPitch,
    /// `h` within its uncertainty of zero, but the uncertainty is too wide to
    /// call it zero (`--pitch-tol auto`).
    UndecidablePitch,
}

impl AdaptedReason {
    /// A stable machine name.
    pub fn name(self) -> &'static str {
        match self {
            AdaptedReason::Identity => "identity",
            AdaptedReason::ZeroPitch => "zero_pitch",
            AdaptedReason::PureTranslation => "pure_translation",
            AdaptedReason::NonzeroPitch => "nonzero_pitch",
            AdaptedReason::UndecidablePitch => "undecidable_pitch",
        }
    }
    /// The sentence the report prints (JSON `adapted_metric.reason`).
    pub fn text(self) -> &'static str {
        match self {
            AdaptedReason::Identity => {
                "identity transform: nothing changes, so M0 = I6 (every metric is invariant)"
            }
            AdaptedReason::ZeroPitch => {
                "zero pitch: the extrinsic is a pure rotation about an axis in space, so \
                 M0 = Ad(P)^-T Ad(P)^-1 (P: translation to that axis) satisfies \
                 Ad(T)^T M0 Ad(T) = M0"
            }
            AdaptedReason::PureTranslation => {
                "pure translation: there is no rotation axis to centre a metric on; \
                 Ad(T) = I + nilpotent, its powers grow, so no constant metric is invariant"
            }
            AdaptedReason::NonzeroPitch => {
                "nonzero screw translation h along the rotation axis: Ad(T) is defective \
                 (its powers grow), so no constant metric is invariant"
            }
            AdaptedReason::UndecidablePitch => {
                "screw translation h undecidable at this precision: h is within its \
                 uncertainty of zero, but that uncertainty is too wide to build M0 on"
            }
        }
    }
}

impl std::fmt::Display for AdaptedReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.text())
    }
}

/// The adapted constant metric of one rig (JSON `adapted_metric`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptedMetric {
    /// A constant metric `M0` with `A^T M0 A = M0` exists for this rig (identity
    /// or zero-pitch screw); then `matrix` and the three numbers are `Some`.
    pub exists: bool,
    /// Why it exists or not (the report prints its text).
    pub reason: AdaptedReason,
    /// `M0`, when it exists.
    pub matrix: Option<Matrix6<f64>>,
    /// `||A^T M0 A - M0||_F / ||M0||_F`.
    pub invariance_residual: Option<f64>,
    /// Frobenius norm of the off-diagonal 3x3 block of `M0`.
    pub offdiag_norm: Option<f64>,
    /// `||M0 - I6||_F / ||I6||_F`.
    pub rel_diff_identity: Option<f64>,
    /// The raw screw translation `h = e . d` (m) the verdict was taken on
    /// (`None` without a rotation). Published numbers have finite digits: print
    /// it beside the verdict.
    pub translation_along_axis: Option<f64>,
    /// The zero-pitch tolerance on `|h|` (m) used.
    pub pitch_tol: f64,
}

/// The adapted metric of `t` with zero-pitch tolerance `pitch_tol` (m on `|h|`).
pub fn adapted_metric(t: &Transform, pitch_tol: f64) -> AdaptedMetric {
    adapted_metric_for_screw(t, &t.screw(pitch_tol), pitch_tol)
}

/// [`adapted_metric`] from an already computed screw of `t`.
pub fn adapted_metric_for_screw(t: &Transform, s: &Screw, pitch_tol: f64) -> AdaptedMetric {
    let reason = match s.kind {
        ScrewKind::Identity => AdaptedReason::Identity,
        ScrewKind::ZeroPitch => AdaptedReason::ZeroPitch,
        ScrewKind::PureTranslation => AdaptedReason::PureTranslation,
        ScrewKind::General => AdaptedReason::NonzeroPitch,
    };
    let matrix = adapted_metric_matrix_for_screw(s);
    let (invariance_residual, offdiag_norm, rel_diff_identity) = match &matrix {
        Some(m0) => {
            let a = t.adjoint();
            let offdiag = m0.fixed_view::<3, 3>(3, 0).norm();
            let rel = (m0 - Matrix6::identity()).norm() / 6f64.sqrt();
            (Some(invariance_residual(&a, m0)), Some(offdiag), Some(rel))
        }
        None => (None, None, None),
    };
    AdaptedMetric {
        exists: matrix.is_some(),
        reason,
        matrix,
        invariance_residual,
        offdiag_norm,
        rel_diff_identity,
        translation_along_axis: s.translation_along_axis,
        pitch_tol,
    }
}

/// `R` has exactly one entry `+-1` in each row and column, zeros elsewhere
/// (within `tol` per entry). For an orthonormal `R` the entry test suffices.
pub fn is_signed_permutation(r: &Matrix3<f64>, tol: f64) -> bool {
    let mut ones_in_col = [0u8; 3];
    for i in 0..3 {
        let mut ones_in_row = 0u8;
        for j in 0..3 {
            let x = r[(i, j)].abs();
            if (x - 1.0).abs() <= tol {
                ones_in_row += 1;
                ones_in_col[j] += 1;
            } else if x > tol {
                return false;
            }
        }
        if ones_in_row != 1 {
            return false;
        }
    }
    ones_in_col == [1, 1, 1]
}

/// Why a family is or is not frame-invariant on a rig, in words.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum VerdictReason {
    /// Isotropic fixed metric (`I6`, `diag(l^2 I, I)`), `d = 0`.
    IsotropicPureRotation,
    /// Isotropic fixed metric, `d != 0`.
    IsotropicLeverArm,
    /// Block scaling, `d = 0`.
    BlockScalingPureRotation,
    /// Block scaling, `d != 0`.
    BlockScalingLeverArm,
    /// Jacobi, `d = 0` and `R` a signed permutation.
    JacobiSignedPermutation,
    /// Jacobi, `d = 0` but `R` mixes axes.
    JacobiMixesAxes,
    /// Jacobi, `d != 0`.
    JacobiLeverArm,
    /// Adapted constant metric, identity transform.
    AdaptedIdentity,
    /// Adapted constant metric, zero pitch: built for this rig.
    AdaptedZeroPitch,
    /// Adapted constant metric, pure translation: none exists.
    AdaptedPureTranslation,
    /// Adapted constant metric, `h != 0`: none exists.
    AdaptedNonzeroPitch,
    /// Adapted constant metric, `h` undecidable at this precision.
    AdaptedUndecidablePitch,
    /// Point displacement: equivariant, invariant on every rig.
    PointDisplacementEquivariant,
}

impl VerdictReason {
    /// The sentence the report prints (JSON `detectors[i].reason`).
    pub fn text(self) -> &'static str {
        match self {
            VerdictReason::IsotropicPureRotation => {
                "no lever arm (d = 0): Ad(T) = diag(R, R) is orthogonal and leaves this \
                 metric unchanged, so the eigenvalues do not move"
            }
            VerdictReason::IsotropicLeverArm => {
                "nonzero lever arm: Ad(T) is not orthogonal, Ad(T)^T M Ad(T) != M, so the \
                 eigenvalues move with the frame (bounded by the certificate band)"
            }
            VerdictReason::BlockScalingPureRotation => {
                "no lever arm (d = 0): the traces of the rotation and translation blocks \
                 of H, hence l, are unchanged and Ad(T) is orthogonal"
            }
            VerdictReason::BlockScalingLeverArm => {
                "nonzero lever arm: H changes by a non-orthogonal congruence, the scale l \
                 recomputed from H changes with it, and not by the congruence an \
                 invariant rule needs"
            }
            VerdictReason::JacobiSignedPermutation => {
                "no lever arm and R only permutes and flips axes: diag(H) follows the \
                 same permutation, so the eigenvalues do not move"
            }
            VerdictReason::JacobiMixesAxes => {
                "no lever arm, but R mixes axes: diag(A^T H A) != A^T diag(H) A, so the \
                 per-axis scaling changes with the frame"
            }
            VerdictReason::JacobiLeverArm => {
                "nonzero lever arm: Ad(T) mixes rotation and translation coordinates, \
                 diag(A^T H A) != A^T diag(H) A, so the eigenvalues move with the frame"
            }
            VerdictReason::AdaptedIdentity => {
                "identity transform: there is no frame change to be invariant to"
            }
            VerdictReason::AdaptedZeroPitch => {
                "zero pitch: M0 is built for this rig and satisfies Ad(T)^T M0 Ad(T) = M0, \
                 but it is a fixed matrix for this one extrinsic, not an equivariant rule"
            }
            VerdictReason::AdaptedPureTranslation => {
                "pure translation: no adapted constant metric exists for this rig"
            }
            VerdictReason::AdaptedNonzeroPitch => {
                "nonzero screw translation h along the rotation axis: no adapted constant \
                 metric exists for this rig (Ad(T) is defective)"
            }
            VerdictReason::AdaptedUndecidablePitch => {
                "screw translation h undecidable at this precision: whether an adapted \
                 constant metric exists depends on digits the file does not give"
            }
            VerdictReason::PointDisplacementEquivariant => {
                "equivariant rule: M = sum J_i^T J_i transforms by the same congruence as \
                 H, so the eigenvalues are the same in every body frame"
            }
        }
    }
}

impl std::fmt::Display for VerdictReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.text())
    }
}

/// One family's verdict on one rig (JSON `detectors[i]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FamilyVerdict {
    /// The detector family judged.
    pub family: Family,
    /// `M(T . D) = Ad(T)^T M(D) Ad(T)` for every `T`: only point displacement.
    pub equivariant_rule: bool,
    /// The family's eigenvalues are unchanged by this rig's frame change.
    pub invariant_on_rig: bool,
    /// Why (the report prints its text).
    pub reason: VerdictReason,
}

/// The verdict of each family (in [`Family::ALL`] order) for the rig `t` with
/// screw `s` (from `t.screw(pitch_tol)`).
///
/// `d = 0` means `||d|| <= LENGTH_ZERO_TOL`; a signed permutation is tested with
/// `SIGNED_PERMUTATION_TOL`.
pub fn family_verdicts(t: &Transform, s: &Screw) -> [FamilyVerdict; Family::ALL.len()] {
    let no_lever = t.lever_arm() <= LENGTH_ZERO_TOL;
    Family::ALL.map(|family| {
        let (invariant, reason) = match family {
            Family::Unnormalized | Family::CharacteristicLength => {
                if no_lever {
                    (true, VerdictReason::IsotropicPureRotation)
                } else {
                    (false, VerdictReason::IsotropicLeverArm)
                }
            }
            Family::BlockScaling => {
                if no_lever {
                    (true, VerdictReason::BlockScalingPureRotation)
                } else {
                    (false, VerdictReason::BlockScalingLeverArm)
                }
            }
            Family::Jacobi => {
                if !no_lever {
                    (false, VerdictReason::JacobiLeverArm)
                } else if is_signed_permutation(t.rotation(), SIGNED_PERMUTATION_TOL) {
                    (true, VerdictReason::JacobiSignedPermutation)
                } else {
                    (false, VerdictReason::JacobiMixesAxes)
                }
            }
            Family::AdaptedConstant => match s.kind {
                ScrewKind::Identity => (true, VerdictReason::AdaptedIdentity),
                ScrewKind::ZeroPitch => (true, VerdictReason::AdaptedZeroPitch),
                ScrewKind::PureTranslation => (false, VerdictReason::AdaptedPureTranslation),
                ScrewKind::General => (false, VerdictReason::AdaptedNonzeroPitch),
            },
            Family::PointDisplacement => (true, VerdictReason::PointDisplacementEquivariant),
        };
        FamilyVerdict {
            family,
            equivariant_rule: family.is_equivariant_rule(),
            invariant_on_rig: invariant,
            reason,
        }
    })
}

/// Everything the report says about one transform. Plain `Copy` data, built
/// without touching the heap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigAnalysis {
    /// The transform analysed.
    pub transform: Transform,
    /// `||d||` (m).
    pub lever_arm_m: f64,
    /// `phi` in `[0, pi]` (rad).
    pub angle_rad: f64,
    /// Unit rotation axis (`None` below `ANGLE_ZERO_TOL`); the screw's axis.
    pub axis: Option<Vector3<f64>>,
    /// Chasles decomposition (kind, `h`, pitch, axis point).
    pub screw: Screw,
    /// Zero-pitch tolerance on `|h|` (m) used for `screw.kind`.
    pub pitch_tol: f64,
    /// Singular values of `Ad(T)` (closed form), orthogonality and
    /// `||A^T A - I||_F / ||I||_F`.
    pub adjoint: AdjointSummary,
    /// One band per characteristic length, in the order given.
    pub certificate: Certificates,
    /// The adapted constant metric `M0` of this rig, or why there is none.
    pub adapted_metric: AdaptedMetric,
    /// In [`Family::ALL`] order.
    pub detectors: [FamilyVerdict; Family::ALL.len()],
}

/// Analyse one transform: lever arm, angle and axis, screw, closed-form adjoint
/// singular values, certificate bands for each `l` in `ells` (at most
/// [`MAX_ELLS`](crate::tolerances::MAX_ELLS)), adapted metric and detector verdicts.
///
/// Allocation-free on success. Errors (which build a message): a non-finite
/// transform, more than `MAX_ELLS` lengths or one that is not finite and `> 0`,
/// a `pitch_tol` that is not finite and `>= 0`.
///
/// ```
/// use extrinsic_audit::{analyze, Family, ScrewKind, Transform};
///
/// # fn main() -> extrinsic_audit::Result<()> {
/// // A quarter turn about z, the origin moved 0.1 m along x: h = e . d = 0.
/// let t = Transform::from_rpy([0.0, 0.0, std::f64::consts::FRAC_PI_2], [0.1, 0.0, 0.0])?;
/// let rig = analyze(&t, &[1.0], 1e-9)?;
/// assert_eq!(rig.screw.kind, ScrewKind::ZeroPitch);
/// assert!((rig.lever_arm_m - 0.1).abs() < 1e-15);
/// // The axis point c solves (I - R) c = d in the plane: c = (0.05, 0.05, 0).
/// let c = rig.screw.axis_point.unwrap();
/// assert!((c - nalgebra::Vector3::new(0.05, 0.05, 0.0)).norm() < 1e-12);
/// // The band at l = 1: s = (sqrt(delta^2 + 4) -+ delta) / 2, delta = |d| / l.
/// let (dl, band) = (0.1f64, rig.certificate.as_slice()[0].band);
/// let s = |sign: f64| ((dl * dl + 4.0).sqrt() + sign * dl) / 2.0;
/// assert!((band[0] - s(-1.0).powi(2)).abs() < 1e-12 && (band[1] - s(1.0).powi(2)).abs() < 1e-12);
/// // Zero pitch: an adapted constant metric exists.
/// assert!(rig.adapted_metric.exists);
/// let pd = rig.detectors.iter().find(|v| v.family == Family::PointDisplacement).unwrap();
/// assert!(pd.invariant_on_rig);
/// # Ok(())
/// # }
/// ```
pub fn analyze(t: &Transform, ells: &[f64], pitch_tol: f64) -> Result<RigAnalysis> {
    if !(pitch_tol.is_finite() && pitch_tol >= 0.0) {
        return Err(Error::usage(format!(
            "zero-pitch tolerance: expected a finite length >= 0 m, found {pitch_tol}"
        )));
    }
    if !(t.rotation().iter().all(|x| x.is_finite())
        && t.translation().iter().all(|x| x.is_finite()))
    {
        return Err(Error::invalid(
            "transform: expected finite numbers, found NaN or infinity",
        ));
    }
    let lever = t.lever_arm();
    let certificate = certificate::certificates(lever, ells)?;
    let screw = t.screw(pitch_tol);
    Ok(RigAnalysis {
        transform: *t,
        lever_arm_m: lever,
        angle_rad: screw.angle,
        axis: screw.axis,
        screw,
        pitch_tol,
        adjoint: certificate::adjoint_summary(t),
        certificate,
        adapted_metric: adapted_metric_for_screw(t, &screw, pitch_tol),
        detectors: family_verdicts(t, &screw),
    })
}
