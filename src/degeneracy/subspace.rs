//! The degenerate subspace: orthonormal and canonical bases, the per-axis footprint, and a twist read as a screw.

#![allow(clippy::needless_range_loop)] // index loops mirror the maths and the lane layout

use crate::tolerances::{FOOTPRINT_SCORE_TOL, PURE_TRANSLATION_TOL, TWIST_PITCH_TOL};
use nalgebra::{DMatrix, Vector3, Vector6};

/// Orthonormal (Euclidean) basis of the span of `vs`, by SVD; rank by
/// singular value above `1e-12` of the largest.
pub(crate) fn orthonormal_basis(vs: &[Vector6<f64>]) -> DMatrix<f64> {
    if vs.is_empty() {
        return DMatrix::zeros(6, 0);
    }
    let m = DMatrix::from_fn(6, vs.len(), |i, j| vs[j][i]);
    let svd = m.svd(true, false);
    let smax = svd.singular_values.max();
    let Some(u) = svd.u else {
        return DMatrix::zeros(6, 0);
    };
    let cols: Vec<usize> = (0..svd.singular_values.len())
        .filter(|&k| svd.singular_values[k] > 1e-12 * smax)
        .collect();
    DMatrix::from_fn(6, cols.len(), |i, j| u[(i, cols[j])])
}

/// Per-axis footprint of the span of `vs` (see [`Analysis::footprint`](crate::degeneracy::Analysis::footprint)):
/// an axis whose score ([`footprint_scores`]) is at least
/// `FOOTPRINT_SCORE_TOL`, as `audit degeneracy` flags it.
pub fn footprint(vs: &[Vector6<f64>]) -> [bool; 6] {
    footprint_scores(vs).map(|d| d >= FOOTPRINT_SCORE_TOL)
}

/// Per-axis footprint scores of the span of `vs`: the diagonal of the
/// Euclidean projector onto it, each in `[0, 1]`, summing to its dimension
/// (1 for an axis inside the span, 0 for one orthogonal to it).
pub fn footprint_scores(vs: &[Vector6<f64>]) -> [f64; 6] {
    let q = orthonormal_basis(vs);
    // fold from +0.0: an empty sum of f64 is -0.0, printed "-0.000".
    std::array::from_fn(|k| (0..q.ncols()).fold(0.0, |s, j| s + q[(k, j)] * q[(k, j)]))
}

/// A canonical basis of the span of `vs`: first the rotational twists, then the
/// pure translations.
///
/// Pure translations are the directions of the span with no rotational part
/// (singular value of the rotational block at or below
/// `PURE_TRANSLATION_TOL`); each rotational twist has the pure-translation
/// directions removed from its translational part (for the tunnel that leaves
/// the zero-pitch rotation about the axis), is scaled to `|omega| = 1` and signed
/// so that its largest rotational component is positive. Pure translations are
/// unit and signed the same way. The span is frame-covariant (`v = A v'`); this
/// representative is a coordinate choice.
pub fn canonical_basis(vs: &[Vector6<f64>]) -> Vec<Vector6<f64>> {
    canonical_basis_scored(vs, PURE_TRANSLATION_TOL)
        .into_iter()
        .map(|(v, _)| v)
        .collect()
}

/// [`canonical_basis`] with the pure-translation tolerance `tol` on the
/// rotational singular values, each twist paired with its singular value
/// (the norm of the rotational part of the unit direction it came from: its
/// rotation fraction, in the units the caller scaled `vs` to).
pub fn canonical_basis_scored(vs: &[Vector6<f64>], tol: f64) -> Vec<(Vector6<f64>, f64)> {
    let q = orthonormal_basis(vs);
    let k = q.ncols();
    if k == 0 {
        return Vec::new();
    }
    let w = q.rows(0, 3).into_owned();
    // SVD of the 3 x k rotational block; right singular vectors (k x k).
    let svd = w.clone().svd(false, true);
    let Some(vt) = svd.v_t else {
        return Vec::new();
    };
    let nsv = svd.singular_values.len();
    let mut sv = vec![0.0; k];
    sv[..nsv].copy_from_slice(&svd.singular_values.as_slice()[..nsv]);
    // Complete V when k > 3 (thin SVD): use full k x k basis via QR of V^T rows.
    let v_full: DMatrix<f64> = if vt.nrows() == k {
        vt.transpose()
    } else {
        // Null space of w (k > 3): extend.
        let svd2 = (w.transpose() * &w).symmetric_eigen();
        let mut idx: Vec<usize> = (0..k).collect();
        idx.sort_by(|&a, &b| svd2.eigenvalues[b].total_cmp(&svd2.eigenvalues[a]));
        for (j, &i) in idx.iter().enumerate() {
            sv[j] = svd2.eigenvalues[i].max(0.0).sqrt();
        }
        DMatrix::from_fn(k, k, |r, c| svd2.eigenvectors[(r, idx[c])])
    };
    let mut rot = Vec::new();
    let mut trans: Vec<(Vector3<f64>, f64)> = Vec::new();
    for j in 0..k {
        let x = &q * v_full.column(j);
        let xi = Vector6::from_fn(|i, _| x[i]);
        if sv[j] <= tol {
            let t = Vector3::new(xi[3], xi[4], xi[5]);
            let n = t.norm();
            if n > 0.0 {
                trans.push((t / n, sv[j]));
            }
        } else {
            rot.push((xi, sv[j]));
        }
    }
    // Orthonormalise the translation directions (Gram-Schmidt).
    let mut tdirs: Vec<(Vector3<f64>, f64)> = Vec::new();
    for (t, s) in trans {
        let mut u = t;
        for (e, _) in &tdirs {
            u -= *e * e.dot(&u);
        }
        let n = u.norm();
        if n > 1e-12 {
            tdirs.push((u / n, s));
        }
    }
    let mut out = Vec::new();
    for (xi, s) in rot {
        let om = Vector3::new(xi[0], xi[1], xi[2]);
        let mut t = Vector3::new(xi[3], xi[4], xi[5]);
        for (e, _) in &tdirs {
            t -= *e * e.dot(&t);
        }
        let n = om.norm();
        let mut v = Vector6::new(om.x, om.y, om.z, t.x, t.y, t.z) / n;
        if largest_component(&Vector3::new(v[0], v[1], v[2])) < 0.0 {
            v = -v;
        }
        out.push((v, s));
    }
    for (e, s) in tdirs {
        let mut e = e;
        if largest_component(&e) < 0.0 {
            e = -e;
        }
        out.push((Vector6::new(0.0, 0.0, 0.0, e.x, e.y, e.z), s));
    }
    out
}

fn largest_component(v: &Vector3<f64>) -> f64 {
    let mut best = v[0];
    for k in 1..3 {
        if v[k].abs() > best.abs() + 1e-12 {
            best = v[k];
        }
    }
    best
}

/// A degenerate twist read as a screw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwistScrew {
    /// The twist `[omega; t]`.
    pub twist: Vector6<f64>,
    /// `pure_translation`, `zero_pitch` (rotation about an axis in space) or
    /// `general` (a screw with pitch); names as `se3::ScrewKind::name`.
    pub kind: &'static str,
    /// Unit rotation axis (none for a pure translation).
    pub axis: Option<Vector3<f64>>,
    /// `omega . t / |omega|^2` (m/rad).
    pub pitch: Option<f64>,
    /// Point of the axis closest to the origin, `omega x t / |omega|^2` (m).
    pub axis_point: Option<Vector3<f64>>,
    /// Unit direction of a pure translation.
    pub direction: Option<Vector3<f64>>,
}

impl TwistScrew {
    /// Reads the twist `xi = [omega; t]` as a screw: a pure translation when
    /// `|omega| <= PURE_TRANSLATION_TOL |xi|` (direction `t / |t|`, none for the
    /// zero twist), otherwise a rotation about the axis through
    /// `omega x t / |omega|^2` with pitch `omega . t / |omega|^2`, zero pitch
    /// within `TWIST_PITCH_TOL` (m/rad).
    pub fn from_twist(xi: &Vector6<f64>) -> TwistScrew {
        let om = Vector3::new(xi[0], xi[1], xi[2]);
        let t = Vector3::new(xi[3], xi[4], xi[5]);
        let n2 = om.norm_squared();
        let scale = xi.norm();
        if om.norm() <= PURE_TRANSLATION_TOL * scale || n2 == 0.0 {
            let n = t.norm();
            return TwistScrew {
                twist: *xi,
                kind: "pure_translation",
                axis: None,
                pitch: None,
                axis_point: None,
                direction: if n > 0.0 { Some(t / n) } else { None },
            };
        }
        let pitch = om.dot(&t) / n2;
        let c = om.cross(&t) / n2;
        TwistScrew {
            twist: *xi,
            kind: if pitch.abs() <= TWIST_PITCH_TOL {
                "zero_pitch"
            } else {
                "general"
            },
            axis: Some(om / om.norm()),
            pitch: Some(pitch),
            axis_point: Some(c),
            direction: None,
        }
    }
}
