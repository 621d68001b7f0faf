//! Metric families as rules `M(D)` for `H v = lambda M v`, the adapted constant
//! metric of one rig, and per-rig verdicts (DESIGN.md, "Detector families").

use crate::se3::{ScrewKind, Transform};
use nalgebra::{Matrix6, Vector3};

/// The detector families, by the metric rule each implies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Family {
    /// `I6`.
    Unnormalized,
    /// `diag(l^2 I3, I3)` for a fixed `l`.
    CharacteristicLength,
    /// Same family, `l` from `H` (see [`block_scaling_ell`]).
    BlockScaling,
    /// `diag(H)`.
    Jacobi,
    /// `M0 = Ad(P)^-T Ad(P)^-1`, built for one zero-pitch rig.
    AdaptedConstant,
    /// `M = sum_i J_i^T J_i`.
    PointDisplacement,
}

impl Family {
    pub const ALL: [Family; 6] = [
        Family::Unnormalized,
        Family::CharacteristicLength,
        Family::BlockScaling,
        Family::Jacobi,
        Family::AdaptedConstant,
        Family::PointDisplacement,
    ];
    /// The JSON name (DESIGN.md schema).
    pub fn name(self) -> &'static str {
        match self {
            Family::Unnormalized => "unnormalized",
            Family::CharacteristicLength => "characteristic_length",
            Family::BlockScaling => "block_scaling",
            Family::Jacobi => "jacobi",
            Family::AdaptedConstant => "adapted_constant",
            Family::PointDisplacement => "point_displacement",
        }
    }
}

/// Block scaling: the `l` that equalises the traces of the scaled blocks,
/// `l^2 tr(H_rr)`... i.e. `l^2 = tr(H_rr) / tr(H_tt)` (DESIGN.md). Changing the
/// rule means changing this one function.
pub fn block_scaling_ell(h: &Matrix6<f64>) -> f64 {
    let rr = h[(0, 0)] + h[(1, 1)] + h[(2, 2)];
    let tt = h[(3, 3)] + h[(4, 4)] + h[(5, 5)];
    (rr / tt).sqrt()
}

/// `M0 = Ad(P)^-T Ad(P)^-1` with `P` the pure translation to the screw-axis point,
/// when `T` has a rotation and zero pitch (`|h| <= pitch_tol`); `None` otherwise.
/// The identity transform gets `I6` (every metric is invariant under it).
pub fn adapted_metric_matrix(t: &Transform, pitch_tol: f64) -> Option<Matrix6<f64>> {
    let s = t.screw(pitch_tol);
    match s.kind {
        ScrewKind::Identity => Some(Matrix6::identity()),
        ScrewKind::ZeroPitch => {
            let c: Vector3<f64> = s.axis_point?;
            let p_inv = Transform::from_translation([-c.x, -c.y, -c.z]).ok()?;
            let a = p_inv.adjoint(); // Ad(P)^-1 = Ad(P^-1)
            Some(a.transpose() * a)
        }
        ScrewKind::PureTranslation | ScrewKind::General => None,
    }
}
