//! Transport of a report between body frames (`v = A v'`), subspace angles and the difference of the remapping corrections.

#![allow(clippy::needless_range_loop)] // index loops mirror the maths and the lane layout

use super::analysis::Analysis;
use super::subspace::orthonormal_basis;
use nalgebra::{DMatrix, Matrix6, Vector6};

// ---------------------------------------------------------------------------
// Transport between frames and downstream remapping
// ---------------------------------------------------------------------------

/// Transport twists expressed in frame 2 to frame 1: `v = A v'`.
pub fn transport(vs: &[Vector6<f64>], a: &Matrix6<f64>) -> Vec<Vector6<f64>> {
    vs.iter().map(|v| a * v).collect()
}

/// Largest principal angle (rad, Euclidean coordinates) between the spans of
/// two sets of twists; `None` when the dimensions differ or both are empty.
pub fn subspace_angle(a: &[Vector6<f64>], b: &[Vector6<f64>]) -> Option<f64> {
    let qa = orthonormal_basis(a);
    let qb = orthonormal_basis(b);
    if qa.ncols() != qb.ncols() || qa.ncols() == 0 {
        return None;
    }
    let pa = &qa * qa.transpose();
    let resid = (DMatrix::identity(6, 6) - pa) * &qb;
    let s = resid.svd(false, false).singular_values.max();
    let c = (qa.transpose() * &qb)
        .svd(false, false)
        .singular_values
        .min();
    Some(s.atan2(c.max(0.0)))
}

/// Agreement of a report in frame 1 with a report in frame 2 transported to
/// frame 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TransportCheck {
    /// `max_k |lambda_k - lambda'_k| / max(|lambda_k|, 1)` (`lambda` in frame 1,
    /// `lambda'` in frame 2): relative for large eigenvalues, absolute near zero.
    pub eigenvalue_diff: f64,
    /// Both frames declare the same number of degenerate directions.
    pub count_equal: bool,
    /// Largest principal angle between the degenerate subspaces (rad), when
    /// both have the same non-zero dimension.
    pub subspace_angle: Option<f64>,
}

/// Compare `an1` (frame 1) with `an2` (frame 2, where `xi = A xi'`).
pub fn check_transport(an1: &Analysis, an2: &Analysis, a: &Matrix6<f64>) -> TransportCheck {
    let eigenvalue_diff = an1
        .eig
        .values
        .iter()
        .zip(an2.eig.values.iter())
        .map(|(x, y)| (x - y).abs() / x.abs().max(1.0))
        .fold(0.0, f64::max);
    let v2 = transport(&an2.degenerate_vectors(), a);
    TransportCheck {
        eigenvalue_diff,
        count_equal: an1.degenerate_count == an2.degenerate_count,
        subspace_angle: subspace_angle(&an1.degenerate_vectors(), &v2),
    }
}

/// Difference between the two frames' corrections of one update `xi` (given in
/// frame 1): `Delta = (P1 - A P2 A^-1) xi`.
pub fn correction_difference(
    an1: &Analysis,
    an2: &Analysis,
    a: &Matrix6<f64>,
    a_inv: &Matrix6<f64>,
    xi: &Vector6<f64>,
) -> Vector6<f64> {
    an1.projector() * xi - a * (an2.projector() * (a_inv * xi))
}
