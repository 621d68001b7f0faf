//! The generalized eigenproblem `H v = lambda M v` for 6x6 symmetric matrices: Cholesky with a unit-free pivot test, then a symmetric eigen-solve.

#![allow(clippy::needless_range_loop)] // index loops mirror the maths and the lane layout

use crate::diagnostic::{Error, Result};
use crate::tolerances::CHOLESKY_REL_TOL;
use nalgebra::{Matrix6, SymmetricEigen};

/// `max |X - Y| / max(|Y|)`: the relative difference used by the congruence
/// checks.
pub fn rel_diff(x: &Matrix6<f64>, y: &Matrix6<f64>) -> f64 {
    let scale = y.amax().max(f64::MIN_POSITIVE);
    (x - y).amax() / scale
}

// ---------------------------------------------------------------------------
// Generalized eigenproblem
// ---------------------------------------------------------------------------

/// Lower Cholesky factor `L` (`M = L L^T`) with the relative pivot test of
/// [`CHOLESKY_REL_TOL`]; `Err(k)` names the first failing pivot.
pub fn cholesky6(m: &Matrix6<f64>) -> std::result::Result<Matrix6<f64>, usize> {
    let mut l = Matrix6::zeros();
    for j in 0..6 {
        let mut d = m[(j, j)];
        for k in 0..j {
            d -= l[(j, k)] * l[(j, k)];
        }
        let mjj = m[(j, j)];
        if !d.is_finite() || d <= CHOLESKY_REL_TOL * mjj.abs() || mjj.is_nan() || mjj <= 0.0 {
            return Err(j);
        }
        let ljj = d.sqrt();
        l[(j, j)] = ljj;
        for i in j + 1..6 {
            let mut s = m[(i, j)];
            for k in 0..j {
                s -= l[(i, k)] * l[(j, k)];
            }
            l[(i, j)] = s / ljj;
        }
    }
    Ok(l)
}

/// Solve `L X = B` (forward substitution, `L` lower triangular).
fn forward(l: &Matrix6<f64>, b: &Matrix6<f64>) -> Matrix6<f64> {
    let mut x = Matrix6::zeros();
    for c in 0..6 {
        for i in 0..6 {
            let mut s = b[(i, c)];
            for k in 0..i {
                s -= l[(i, k)] * x[(k, c)];
            }
            x[(i, c)] = s / l[(i, i)];
        }
    }
    x
}

/// Solve `L^T X = B` (back substitution).
fn backward_t(l: &Matrix6<f64>, b: &Matrix6<f64>) -> Matrix6<f64> {
    let mut x = Matrix6::zeros();
    for c in 0..6 {
        for i in (0..6).rev() {
            let mut s = b[(i, c)];
            for k in i + 1..6 {
                s -= l[(k, i)] * x[(k, c)];
            }
            x[(i, c)] = s / l[(i, i)];
        }
    }
    x
}

/// Generalized eigenvalues (ascending) and `M`-orthonormal eigenvectors
/// (columns, `V^T M V = I`, `H V = M V diag(values)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GenEigen {
    /// The six generalized eigenvalues `lambda`, ascending (dimensionless
    /// when `H` and `M` carry the same units).
    pub values: [f64; 6],
    /// Eigenvector `k` is column `k`, a twist `[omega; t]` paired with
    /// `values[k]`.
    pub vectors: Matrix6<f64>,
}

/// Why a metric could not be factored.
fn singular_metric_error(what: &str, pivot: usize) -> Error {
    let axis = AXIS_NAMES[pivot];
    Error::invalid(format!(
        "the {what} metric is singular or not positive definite (Cholesky pivot {pivot}, axis {axis}, below {CHOLESKY_REL_TOL:e} of its diagonal)"
    ))
}

/// Axis names, rotation first.
pub const AXIS_NAMES: [&str; 6] = ["rot-x", "rot-y", "rot-z", "trans-x", "trans-y", "trans-z"];

/// `H v = lambda M v` through the Cholesky factor of `M`: `C = L^-1 H L^-T`,
/// symmetric eigen of `C`, `v = L^-T y`. `Err(pivot)` when `M` is not positive
/// definite (see `CHOLESKY_REL_TOL`).
pub fn generalized_eigen_raw(
    h: &Matrix6<f64>,
    m: &Matrix6<f64>,
) -> std::result::Result<GenEigen, usize> {
    let l = cholesky6(m)?;
    let x = forward(&l, h); // L^-1 H
    let mut c = forward(&l, &x.transpose()); // L^-1 H^T L^-T = L^-1 H L^-T
                                             // Symmetrize rounding.
    for i in 0..6 {
        for j in i + 1..6 {
            let v = 0.5 * (c[(i, j)] + c[(j, i)]);
            c[(i, j)] = v;
            c[(j, i)] = v;
        }
    }
    let eig = SymmetricEigen::new(c);
    let mut order = [0usize, 1, 2, 3, 4, 5];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let mut y = Matrix6::zeros();
    let mut values = [0.0; 6];
    for (k, &o) in order.iter().enumerate() {
        values[k] = eig.eigenvalues[o];
        y.set_column(k, &eig.eigenvectors.column(o));
    }
    let vectors = backward_t(&l, &y);
    Ok(GenEigen { values, vectors })
}

/// [`generalized_eigen_raw`] with a named error. `what` names the metric in the
/// message (the point-displacement family's name, or `point-displacement`,
/// gets the collinear-points explanation).
pub fn generalized_eigen(h: &Matrix6<f64>, m: &Matrix6<f64>, what: &str) -> Result<GenEigen> {
    if !h.iter().all(|x| x.is_finite()) || !m.iter().all(|x| x.is_finite()) {
        return Err(Error::invalid(
            "information matrix or metric has non-finite entries (check the input points and normals)",
        ));
    }
    generalized_eigen_raw(h, m).map_err(|pivot| {
        let pd = crate::analysis::family::Family::PointDisplacement.label();
        if what == "point-displacement" || what == pd {
            Error::invalid(format!(
                "points are collinear (or fewer than two distinct points): the point-displacement metric is singular (Cholesky pivot {pivot}, axis {}, below {CHOLESKY_REL_TOL:e} of its diagonal)",
                AXIS_NAMES[pivot]
            ))
        } else {
            singular_metric_error(what, pivot)
        }
    })
}
