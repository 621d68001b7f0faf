//! The degeneracy detector: information matrix `H` and point-displacement metric
//! `M` in one streaming pass, the generalized eigenproblem `H v = lambda M v` for
//! every metric family, the degenerate subspace reported as screws, the per-axis
//! footprint, transport of a report between body frames and the remapping
//! projector (paper, sections III-V).
//!
//! # Conventions (DESIGN.md)
//!
//! - Twist `xi = [omega; t]`, rotation first; right (body) perturbation.
//! - `J_i = [-[p_i]x, I3]`, `a_i = J_i^T n_i = [p_i x n_i; n_i]`.
//! - `H = sum_i w_i a_i a_i^T`, `M = sum_i w_i J_i^T J_i`.
//! - `A = Ad(T) = [[R, 0], [[d]x R, R]]`, `xi = A xi'`; re-expression into the
//!   frame `T = (R, d)`: `p~ = R^T (p - d)`, `n~ = R^T n`; then `H' = A^T H A`,
//!   `M' = A^T M A`.
//!
//! # `M` from moments
//!
//! `J = [-[p]x, I3]`, so `J^T` stacks `-[p]x^T = [p]x` over `I3` and
//! `J^T J = [[-[p]x [p]x, [p]x], [-[p]x, I3]]`, with `-[p]x [p]x = |p|^2 I - p p^T`.
//! Summing with weights, with `W = sum w`, `s = sum w p`, `S = sum w p p^T`:
//! `M = [[tr(S) I - S, [s]x], [-[s]x, W I]]` (tested against the per-point sum).

#![allow(clippy::needless_range_loop)] // index loops mirror the maths and the lane layout

use crate::error::{Error, Result};
use crate::metric::{block_scaling_ell, Family};
use crate::se3::{skew, Transform};
use nalgebra::{DMatrix, Matrix3, Matrix6, SymmetricEigen, Vector3, Vector6};

/// Default degeneracy threshold on generalized eigenvalues (`lambda < tau`).
pub const DEFAULT_TAU: f64 = 1e-2;

/// Relative pivot tolerance of the Cholesky factorisation of a metric: pivot `k`
/// (the Schur complement `d_k` before the square root) must exceed
/// `CHOLESKY_REL_TOL * M_kk`. The ratio `d_k / M_kk` is invariant to the length
/// unit (a diagonal rescaling), so the test does not depend on metres versus
/// millimetres. For exactly collinear points the ratio is rounding (`~1e-16`).
pub const CHOLESKY_REL_TOL: f64 = 1e-10;

/// A projector diagonal entry above this flags the axis in the footprint.
pub const FOOTPRINT_TOL: f64 = 1e-6;

/// In the canonical basis of a degenerate subspace, a direction whose rotational
/// part has singular value at or below this (for a unit coordinate vector) is a
/// pure translation.
pub const PURE_TRANSLATION_TOL: f64 = 1e-6;

/// `|pitch|` (m/rad) at or below which a degenerate twist is a pure rotation
/// about an axis (zero pitch).
pub const TWIST_PITCH_TOL: f64 = 1e-9;

/// Jacobi metric: a diagonal entry of `H` below `JACOBI_FLOOR * max_k H_kk` is
/// raised to that floor (a zero diagonal entry means that row of `H` is zero, the
/// axis is exactly unobserved, and its generalized eigenvalue is 0 whatever the
/// floor).
pub const JACOBI_FLOOR: f64 = 1e-12;

// ---------------------------------------------------------------------------
// Assembly
// ---------------------------------------------------------------------------

/// Number of lanes processed together by the assembly kernel.
const LANES: usize = 8;
/// 21 products of `a`, weight sum, `sum w p` (3), `sum w p p^T` (6).
const NSUM: usize = 31;

/// Streaming accumulator of `H` and `M`: 31 running sums, no per-point storage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accumulator {
    sums: [f64; NSUM],
    count: usize,
}

impl Default for Accumulator {
    fn default() -> Self {
        Self::new()
    }
}

#[inline(always)]
fn a_vector(p: &[f64; 3], n: &[f64; 3]) -> [f64; 6] {
    [
        p[1] * n[2] - p[2] * n[1],
        p[2] * n[0] - p[0] * n[2],
        p[0] * n[1] - p[1] * n[0],
        n[0],
        n[1],
        n[2],
    ]
}

/// The chunked kernel: `LANES` points at a time into lane-wise partial sums so
/// that the compiler can vectorise across points.
#[inline(always)]
fn kernel<const WEIGHTED: bool>(
    points: &[[f64; 3]],
    normals: &[[f64; 3]],
    weights: &[f64],
    out: &mut [f64; NSUM],
) {
    let mut acc = [[0.0f64; LANES]; NSUM];
    let n_chunks = points.len() / LANES;
    for c in 0..n_chunks {
        let base = c * LANES;
        let pc = &points[base..base + LANES];
        let nc = &normals[base..base + LANES];
        let mut a = [[0.0f64; LANES]; 6];
        let mut p = [[0.0f64; LANES]; 3];
        let mut w = [1.0f64; LANES];
        for l in 0..LANES {
            let av = a_vector(&pc[l], &nc[l]);
            for k in 0..6 {
                a[k][l] = av[k];
            }
            for k in 0..3 {
                p[k][l] = pc[l][k];
            }
            if WEIGHTED {
                w[l] = weights[base + l];
            }
        }
        let mut wa = a;
        let mut wp = p;
        if WEIGHTED {
            for k in 0..6 {
                for l in 0..LANES {
                    wa[k][l] *= w[l];
                }
            }
            for k in 0..3 {
                for l in 0..LANES {
                    wp[k][l] *= w[l];
                }
            }
        }
        let mut idx = 0;
        for i in 0..6 {
            for j in i..6 {
                for l in 0..LANES {
                    acc[idx][l] += wa[i][l] * a[j][l];
                }
                idx += 1;
            }
        }
        for l in 0..LANES {
            acc[21][l] += w[l];
        }
        for k in 0..3 {
            for l in 0..LANES {
                acc[22 + k][l] += wp[k][l];
            }
        }
        let mut idx = 25;
        for i in 0..3 {
            for j in i..3 {
                for l in 0..LANES {
                    acc[idx][l] += wp[i][l] * p[j][l];
                }
                idx += 1;
            }
        }
    }
    for k in 0..NSUM {
        out[k] += acc[k].iter().sum::<f64>();
    }
    // Tail, one point at a time.
    for i in n_chunks * LANES..points.len() {
        let w = if WEIGHTED { weights[i] } else { 1.0 };
        push_one(out, &points[i], &normals[i], w);
    }
}

#[inline(always)]
fn push_one(out: &mut [f64; NSUM], p: &[f64; 3], n: &[f64; 3], w: f64) {
    let a = a_vector(p, n);
    let mut idx = 0;
    for i in 0..6 {
        let wai = w * a[i];
        for j in i..6 {
            out[idx] += wai * a[j];
            idx += 1;
        }
    }
    out[21] += w;
    for k in 0..3 {
        out[22 + k] += w * p[k];
    }
    let mut idx = 25;
    for i in 0..3 {
        for j in i..3 {
            out[idx] += w * p[i] * p[j];
            idx += 1;
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn kernel_avx2<const WEIGHTED: bool>(
    points: &[[f64; 3]],
    normals: &[[f64; 3]],
    weights: &[f64],
    out: &mut [f64; NSUM],
) {
    kernel::<WEIGHTED>(points, normals, weights, out)
}

fn run_kernel<const WEIGHTED: bool>(
    points: &[[f64; 3]],
    normals: &[[f64; 3]],
    weights: &[f64],
    out: &mut [f64; NSUM],
) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the CPU supports AVX2 and FMA (checked just above).
            unsafe { kernel_avx2::<WEIGHTED>(points, normals, weights, out) };
            return;
        }
    }
    kernel::<WEIGHTED>(points, normals, weights, out)
}

impl Accumulator {
    pub fn new() -> Self {
        Accumulator {
            sums: [0.0; NSUM],
            count: 0,
        }
    }

    /// Add one point with its unit normal (weight 1).
    pub fn push(&mut self, p: &[f64; 3], n: &[f64; 3]) {
        push_one(&mut self.sums, p, n, 1.0);
        self.count += 1;
    }

    /// Add one point with its unit normal and weight.
    pub fn push_weighted(&mut self, p: &[f64; 3], n: &[f64; 3], w: f64) {
        push_one(&mut self.sums, p, n, w);
        self.count += 1;
    }

    /// Add a batch (the fast path). `weights`, when given, has one entry per point.
    /// Mismatched lengths are an error.
    pub fn add(
        &mut self,
        points: &[[f64; 3]],
        normals: &[[f64; 3]],
        weights: Option<&[f64]>,
    ) -> Result<()> {
        if points.len() != normals.len() {
            return Err(Error::invalid(format!(
                "expected one normal per point, found {} points and {} normals",
                points.len(),
                normals.len()
            )));
        }
        match weights {
            Some(w) => {
                if w.len() != points.len() {
                    return Err(Error::invalid(format!(
                        "expected one weight per point, found {} points and {} weights",
                        points.len(),
                        w.len()
                    )));
                }
                run_kernel::<true>(points, normals, w, &mut self.sums);
            }
            None => run_kernel::<false>(points, normals, &[], &mut self.sums),
        }
        self.count += points.len();
        Ok(())
    }

    /// Combine two partial accumulations.
    pub fn merge(&mut self, other: &Accumulator) {
        for k in 0..NSUM {
            self.sums[k] += other.sums[k];
        }
        self.count += other.count;
    }

    pub fn count(&self) -> usize {
        self.count
    }

    /// Form `H` and `M` from the running sums.
    pub fn finish(&self) -> Assembly {
        let s = &self.sums;
        let mut h = Matrix6::zeros();
        let mut idx = 0;
        for i in 0..6 {
            for j in i..6 {
                h[(i, j)] = s[idx];
                h[(j, i)] = s[idx];
                idx += 1;
            }
        }
        let w = s[21];
        let sp = Vector3::new(s[22], s[23], s[24]);
        let spp = Matrix3::new(
            s[25], s[26], s[27], s[26], s[28], s[29], s[27], s[29], s[30],
        );
        let mut m = Matrix6::zeros();
        let rr = Matrix3::identity() * spp.trace() - spp;
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&rr);
        let k = skew(&sp);
        m.fixed_view_mut::<3, 3>(0, 3).copy_from(&k);
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-k));
        m.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(Matrix3::identity() * w));
        Assembly {
            h,
            m,
            count: self.count,
            weight_sum: w,
        }
    }
}

/// `H` and `M` of one point set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Assembly {
    /// Information matrix `sum w a a^T`.
    pub h: Matrix6<f64>,
    /// Point-displacement metric `sum w J^T J`.
    pub m: Matrix6<f64>,
    pub count: usize,
    pub weight_sum: f64,
}

impl Assembly {
    /// Assemble from points and unit normals (and optional weights) in one pass.
    pub fn from_points(
        points: &[[f64; 3]],
        normals: &[[f64; 3]],
        weights: Option<&[f64]>,
    ) -> Result<Assembly> {
        let mut acc = Accumulator::new();
        acc.add(points, normals, weights)?;
        Ok(acc.finish())
    }

    /// The same data described about another body frame: `H' = A^T H A`,
    /// `M' = A^T M A` with `A = Ad(T)`.
    pub fn congruence(&self, a: &Matrix6<f64>) -> Assembly {
        Assembly {
            h: a.transpose() * self.h * a,
            m: a.transpose() * self.m * a,
            count: self.count,
            weight_sum: self.weight_sum,
        }
    }
}

/// Re-express points and normals in the frame whose pose in the current one is
/// `T = (R, d)`: `p~ = R^T (p - d)`, `n~ = R^T n`.
pub fn reexpress(
    points: &[[f64; 3]],
    normals: &[[f64; 3]],
    t: &Transform,
) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let rt = t.rotation().transpose();
    let d = t.translation();
    let ps = points
        .iter()
        .map(|p| {
            let q = rt * (Vector3::from(*p) - d);
            [q.x, q.y, q.z]
        })
        .collect();
    let ns = normals
        .iter()
        .map(|n| {
            let q = rt * Vector3::from(*n);
            [q.x, q.y, q.z]
        })
        .collect();
    (ps, ns)
}

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
    pub values: [f64; 6],
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
/// definite (see [`CHOLESKY_REL_TOL`]).
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
/// message ("point-displacement" gets the collinear-points explanation).
pub fn generalized_eigen(h: &Matrix6<f64>, m: &Matrix6<f64>, what: &str) -> Result<GenEigen> {
    if !h.iter().all(|x| x.is_finite()) || !m.iter().all(|x| x.is_finite()) {
        return Err(Error::invalid(
            "information matrix or metric has non-finite entries (check the input points and normals)",
        ));
    }
    generalized_eigen_raw(h, m).map_err(|pivot| {
        if what == "point-displacement" {
            Error::invalid(format!(
                "points are collinear (or fewer than two distinct points): the point-displacement metric is singular (Cholesky pivot {pivot}, axis {}, below {CHOLESKY_REL_TOL:e} of its diagonal)",
                AXIS_NAMES[pivot]
            ))
        } else {
            singular_metric_error(what, pivot)
        }
    })
}

// ---------------------------------------------------------------------------
// Metric rules
// ---------------------------------------------------------------------------

/// One metric configuration: a family and its parameter.
#[derive(Debug, Clone, PartialEq)]
pub enum MetricRule {
    /// `I6`.
    Unnormalized,
    /// `diag(l^2 I3, I3)` with the given `l` (m).
    CharacteristicLength(f64),
    /// `diag(l^2 I3, I3)`, `l^2 = tr(H_rr) / tr(H_tt)` ([`block_scaling_ell`]).
    BlockScaling,
    /// `diag(H)` (floored, see [`JACOBI_FLOOR`]).
    Jacobi,
    /// A constant metric adapted to one rig (`metric::adapted_metric_matrix`).
    AdaptedConstant(Box<Matrix6<f64>>),
    /// `M = sum w J^T J`.
    PointDisplacement,
}

/// Default characteristic lengths (m).
pub const DEFAULT_ELLS: [f64; 4] = [0.25, 1.0, 2.85, 10.0];

impl MetricRule {
    pub fn family(&self) -> Family {
        match self {
            MetricRule::Unnormalized => Family::Unnormalized,
            MetricRule::CharacteristicLength(_) => Family::CharacteristicLength,
            MetricRule::BlockScaling => Family::BlockScaling,
            MetricRule::Jacobi => Family::Jacobi,
            MetricRule::AdaptedConstant(_) => Family::AdaptedConstant,
            MetricRule::PointDisplacement => Family::PointDisplacement,
        }
    }

    /// Short label for tables, e.g. `I6`, `l=2.85`, `point displacement`.
    pub fn label(&self) -> String {
        match self {
            MetricRule::Unnormalized => "I6".into(),
            MetricRule::CharacteristicLength(l) => format!("l={l}"),
            MetricRule::BlockScaling => "block scaling".into(),
            MetricRule::Jacobi => "Jacobi".into(),
            MetricRule::AdaptedConstant(_) => "adapted constant".into(),
            MetricRule::PointDisplacement => "point displacement".into(),
        }
    }

    /// Whether the rule is equivariant (only point displacement).
    pub fn equivariant(&self) -> bool {
        matches!(self, MetricRule::PointDisplacement)
    }

    /// `l` used (fixed, or from `H` for block scaling).
    pub fn ell(&self, asm: &Assembly) -> Option<f64> {
        match self {
            MetricRule::CharacteristicLength(l) => Some(*l),
            MetricRule::BlockScaling => Some(block_scaling_ell(&asm.h)),
            _ => None,
        }
    }

    /// The metric this rule assigns to the data.
    pub fn metric(&self, asm: &Assembly) -> Result<Matrix6<f64>> {
        let diag_ell = |l: f64| {
            let l2 = l * l;
            Matrix6::from_diagonal(&Vector6::new(l2, l2, l2, 1.0, 1.0, 1.0))
        };
        match self {
            MetricRule::Unnormalized => Ok(Matrix6::identity()),
            MetricRule::CharacteristicLength(l) => {
                if !(l.is_finite() && *l > 0.0) {
                    return Err(Error::usage(format!(
                        "characteristic length: expected a positive number of metres, found {l}"
                    )));
                }
                Ok(diag_ell(*l))
            }
            MetricRule::BlockScaling => {
                let l = block_scaling_ell(&asm.h);
                if !(l.is_finite() && l > 0.0) {
                    return Err(Error::invalid(format!(
                        "block scaling: l^2 = tr(H_rr)/tr(H_tt) is not a positive finite number (l = {l}); the data constrain no rotation or no translation at all"
                    )));
                }
                Ok(diag_ell(l))
            }
            MetricRule::Jacobi => {
                let mx = (0..6).map(|k| asm.h[(k, k)]).fold(0.0f64, f64::max);
                if mx.is_nan() || mx <= 0.0 {
                    return Err(Error::invalid(
                        "Jacobi metric: H has no positive diagonal entry",
                    ));
                }
                let floor = JACOBI_FLOOR * mx;
                Ok(Matrix6::from_diagonal(&Vector6::from_fn(|k, _| {
                    asm.h[(k, k)].max(floor)
                })))
            }
            MetricRule::AdaptedConstant(m0) => Ok(**m0),
            MetricRule::PointDisplacement => Ok(asm.m),
        }
    }

    /// The paper's eight configurations: I6, l = 0.25, 1, 2.85, 10, block
    /// scaling, Jacobi, point displacement.
    pub fn paper_configs() -> Vec<MetricRule> {
        let mut v = vec![MetricRule::Unnormalized];
        v.extend(
            DEFAULT_ELLS
                .iter()
                .map(|&l| MetricRule::CharacteristicLength(l)),
        );
        v.push(MetricRule::BlockScaling);
        v.push(MetricRule::Jacobi);
        v.push(MetricRule::PointDisplacement);
        v
    }

    /// The families reported by default (`ells` for the characteristic length;
    /// `adapted`, when given, adds the adapted constant metric of a rig).
    pub fn default_set(ells: &[f64], adapted: Option<Matrix6<f64>>) -> Vec<MetricRule> {
        let mut v = vec![MetricRule::Unnormalized];
        v.extend(ells.iter().map(|&l| MetricRule::CharacteristicLength(l)));
        v.push(MetricRule::BlockScaling);
        v.push(MetricRule::Jacobi);
        if let Some(m0) = adapted {
            v.push(MetricRule::AdaptedConstant(Box::new(m0)));
        }
        v.push(MetricRule::PointDisplacement);
        v
    }

    fn what(&self) -> &'static str {
        match self {
            MetricRule::PointDisplacement => "point-displacement",
            MetricRule::Unnormalized => "unnormalized (I6)",
            MetricRule::CharacteristicLength(_) => "characteristic-length",
            MetricRule::BlockScaling => "block-scaling",
            MetricRule::Jacobi => "Jacobi",
            MetricRule::AdaptedConstant(_) => "adapted constant",
        }
    }
}

// ---------------------------------------------------------------------------
// Analysis / report
// ---------------------------------------------------------------------------

/// One family's answer on one data set.
#[derive(Debug, Clone, PartialEq)]
pub struct Analysis {
    pub rule: MetricRule,
    pub metric: Matrix6<f64>,
    pub eig: GenEigen,
    pub tau: f64,
    /// Number of eigenvalues `< tau` (they are the first ones).
    pub degenerate_count: usize,
}

/// Solve one family on one assembly.
pub fn analyse(asm: &Assembly, rule: &MetricRule, tau: f64) -> Result<Analysis> {
    let metric = rule.metric(asm)?;
    let eig = generalized_eigen(&asm.h, &metric, rule.what())?;
    let degenerate_count = eig.values.iter().filter(|&&l| l < tau).count();
    Ok(Analysis {
        rule: rule.clone(),
        metric,
        eig,
        tau,
        degenerate_count,
    })
}

impl Analysis {
    /// Whether anything is declared degenerate.
    pub fn degenerate(&self) -> bool {
        self.degenerate_count > 0
    }

    /// The `M`-orthonormal eigenvectors of the degenerate eigenvalues.
    pub fn degenerate_vectors(&self) -> Vec<Vector6<f64>> {
        (0..self.degenerate_count)
            .map(|k| self.eig.vectors.column(k).into_owned())
            .collect()
    }

    /// Remapping projector `P = sum over non-degenerate k of v_k v_k^T M`.
    pub fn projector(&self) -> Matrix6<f64> {
        let mut p = Matrix6::zeros();
        for k in self.degenerate_count..6 {
            let v = self.eig.vectors.column(k);
            p += v * v.transpose();
        }
        p * self.metric
    }

    /// Per-axis footprint (frame-dependent): axis `k` flagged when the `k`-th
    /// diagonal entry of the Euclidean projector onto the degenerate subspace
    /// exceeds [`FOOTPRINT_TOL`].
    pub fn footprint(&self) -> [bool; 6] {
        footprint(&self.degenerate_vectors())
    }

    /// The degenerate subspace as screws (canonical basis, see
    /// [`canonical_basis`]) with each basis twist's Rayleigh quotient
    /// `v^T H v / v^T M v` under this analysis' metric.
    pub fn subspace_screws(&self, h: &Matrix6<f64>) -> Vec<(f64, TwistScrew)> {
        canonical_basis(&self.degenerate_vectors())
            .into_iter()
            .map(|v| {
                let q = (v.transpose() * h * v)[(0, 0)] / (v.transpose() * self.metric * v)[(0, 0)];
                (q, TwistScrew::from_twist(&v))
            })
            .collect()
    }
}

/// Orthonormal (Euclidean) basis of the span of `vs`, by SVD; rank by
/// singular value above `1e-12` of the largest.
fn orthonormal_basis(vs: &[Vector6<f64>]) -> DMatrix<f64> {
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

/// Per-axis footprint of the span of `vs` (see [`Analysis::footprint`]).
pub fn footprint(vs: &[Vector6<f64>]) -> [bool; 6] {
    let q = orthonormal_basis(vs);
    let mut f = [false; 6];
    for (k, fk) in f.iter_mut().enumerate() {
        let d: f64 = (0..q.ncols()).map(|j| q[(k, j)] * q[(k, j)]).sum();
        *fk = d > FOOTPRINT_TOL;
    }
    f
}

/// A canonical basis of the span of `vs`: first the rotational twists, then the
/// pure translations.
///
/// Pure translations are the directions of the span with no rotational part
/// (singular value of the rotational block at or below
/// [`PURE_TRANSLATION_TOL`]); each rotational twist has the pure-translation
/// directions removed from its translational part (for the tunnel that leaves
/// the zero-pitch rotation about the axis), is scaled to `|omega| = 1` and signed
/// so that its largest rotational component is positive. Pure translations are
/// unit and signed the same way. The span is frame-covariant (`v = A v'`); this
/// representative is a coordinate choice.
pub fn canonical_basis(vs: &[Vector6<f64>]) -> Vec<Vector6<f64>> {
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
    let mut trans: Vec<Vector3<f64>> = Vec::new();
    for j in 0..k {
        let x = &q * v_full.column(j);
        let xi = Vector6::from_fn(|i, _| x[i]);
        if sv[j] <= PURE_TRANSLATION_TOL {
            let t = Vector3::new(xi[3], xi[4], xi[5]);
            let n = t.norm();
            if n > 0.0 {
                trans.push(t / n);
            }
        } else {
            rot.push(xi);
        }
    }
    // Orthonormalise the translation directions (Gram-Schmidt).
    let mut tdirs: Vec<Vector3<f64>> = Vec::new();
    for t in trans {
        let mut u = t;
        for e in &tdirs {
            u -= *e * e.dot(&u);
        }
        let n = u.norm();
        if n > 1e-12 {
            tdirs.push(u / n);
        }
    }
    let mut out = Vec::new();
    for xi in rot {
        let om = Vector3::new(xi[0], xi[1], xi[2]);
        let mut t = Vector3::new(xi[3], xi[4], xi[5]);
        for e in &tdirs {
            t -= *e * e.dot(&t);
        }
        let n = om.norm();
        let mut v = Vector6::new(om.x, om.y, om.z, t.x, t.y, t.z) / n;
        if largest_component(&Vector3::new(v[0], v[1], v[2])) < 0.0 {
            v = -v;
        }
        out.push(v);
    }
    for e in tdirs {
        let mut e = e;
        if largest_component(&e) < 0.0 {
            e = -e;
        }
        out.push(Vector6::new(0.0, 0.0, 0.0, e.x, e.y, e.z));
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
    /// `max_k |lambda_k - lambda'_k| / max(|lambda_k|, 1e-300)`... relative to
    /// `max(1, |lambda_k|)` so zeros compare absolutely.
    pub eigenvalue_diff: f64,
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

// ---------------------------------------------------------------------------
// The paper's per-pair frame sweep
// ---------------------------------------------------------------------------

/// Arm of the per-pair frame sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Arm {
    Identity,
    PureRotation,
    PureTranslation,
    General,
    /// `A` a random orthogonal 6x6 matrix, not an adjoint.
    OrthogonalControl,
}

impl Arm {
    pub fn name(self) -> &'static str {
        match self {
            Arm::Identity => "identity",
            Arm::PureRotation => "pure rotation",
            Arm::PureTranslation => "pure translation",
            Arm::General => "general",
            Arm::OrthogonalControl => "orthogonal control",
        }
    }
}

/// One frame change of the sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameChange {
    pub arm: Arm,
    /// `||d||` (m); 0 for identity and pure rotation.
    pub magnitude: f64,
    /// `Ad(T)` or the orthogonal control matrix.
    pub a: Matrix6<f64>,
}

/// The fourteen lever arms (m) of the sweep, 0 to 20 m (the paper gives the
/// range and the count, not the values; these include the tabulated 0.1, 0.5,
/// 1 and 20 m).
pub const SWEEP_MAGNITUDES: [f64; 14] = [
    0.0, 0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0, 5.0, 10.0, 15.0, 20.0,
];

/// The paper's 861 frame changes: identity, 20 pure rotations, and 3 arms (pure
/// translation, general, orthogonal control) x 14 magnitudes x 20 draws;
/// seeded (PCG64, see `scene::SceneRng`).
pub fn paper_frame_changes(seed: u64) -> Vec<FrameChange> {
    let mut rng = crate::scene::SceneRng::new(seed);
    let mut out = Vec::with_capacity(861);
    out.push(FrameChange {
        arm: Arm::Identity,
        magnitude: 0.0,
        a: Matrix6::identity(),
    });
    for _ in 0..20 {
        let r = rng.rotation();
        let t = Transform::from_parts_unchecked(r, Vector3::zeros());
        out.push(FrameChange {
            arm: Arm::PureRotation,
            magnitude: 0.0,
            a: t.adjoint(),
        });
    }
    for arm in [Arm::PureTranslation, Arm::General, Arm::OrthogonalControl] {
        for &mag in &SWEEP_MAGNITUDES {
            for _ in 0..20 {
                let a = match arm {
                    Arm::PureTranslation => {
                        let d = rng.unit_vector() * mag;
                        Transform::from_parts_unchecked(Matrix3::identity(), d).adjoint()
                    }
                    Arm::General => {
                        let d = rng.unit_vector() * mag;
                        Transform::from_parts_unchecked(rng.rotation(), d).adjoint()
                    }
                    _ => rng.orthogonal6(),
                };
                out.push(FrameChange {
                    arm,
                    magnitude: mag,
                    a,
                });
            }
        }
    }
    out
}

/// Outcome of the sweep for one metric configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepRow {
    pub rule: MetricRule,
    pub tau: f64,
    /// Frame changes whose binary decision (any `lambda < tau`) differs from the
    /// reference frame's.
    pub decision_changes: usize,
    /// Frame changes whose degenerate count differs.
    pub count_changes: usize,
    /// Decision changes per arm, in [`Arm::ALL`] order.
    pub decision_changes_by_arm: [usize; 5],
    /// Largest relative eigenvalue change per arm, in [`Arm::ALL`] order (each
    /// eigenvalue relative to itself, floored at 1e-12 of the largest).
    pub max_eigenvalue_change_by_arm: [f64; 5],
    /// Largest relative eigenvalue change over the whole sweep.
    pub max_eigenvalue_change: f64,
    pub evaluations: usize,
}

impl Arm {
    pub const ALL: [Arm; 5] = [
        Arm::Identity,
        Arm::PureRotation,
        Arm::PureTranslation,
        Arm::General,
        Arm::OrthogonalControl,
    ];
    fn index(self) -> usize {
        match self {
            Arm::Identity => 0,
            Arm::PureRotation => 1,
            Arm::PureTranslation => 2,
            Arm::General => 3,
            Arm::OrthogonalControl => 4,
        }
    }
}

/// Apply every frame change to one assembly (`H' = A^T H A`, `M' = A^T M A`;
/// each rule then assigns its metric to the new data) and count decision
/// changes per rule, each rule with its own threshold (`taus[k]` for
/// `rules[k]`). Constant metrics stay the same matrix in every frame.
pub fn frame_sweep(
    asm: &Assembly,
    changes: &[FrameChange],
    rules: &[MetricRule],
    taus: &[f64],
) -> Result<Vec<SweepRow>> {
    if taus.len() != rules.len() {
        return Err(Error::usage(format!(
            "frame sweep: expected one threshold per rule, found {} rules and {} thresholds",
            rules.len(),
            taus.len()
        )));
    }
    let refs: Vec<Analysis> = rules
        .iter()
        .zip(taus)
        .map(|(r, &t)| analyse(asm, r, t))
        .collect::<Result<_>>()?;
    let mut rows: Vec<SweepRow> = rules
        .iter()
        .zip(taus)
        .map(|(r, &t)| SweepRow {
            rule: r.clone(),
            tau: t,
            decision_changes: 0,
            count_changes: 0,
            decision_changes_by_arm: [0; 5],
            max_eigenvalue_change_by_arm: [0.0; 5],
            max_eigenvalue_change: 0.0,
            evaluations: 0,
        })
        .collect();
    for ch in changes {
        let moved = asm.congruence(&ch.a);
        let arm = ch.arm.index();
        for (k, rule) in rules.iter().enumerate() {
            let an = analyse(&moved, rule, taus[k])?;
            let row = &mut rows[k];
            row.evaluations += 1;
            if an.degenerate() != refs[k].degenerate() {
                row.decision_changes += 1;
                row.decision_changes_by_arm[arm] += 1;
            }
            if an.degenerate_count != refs[k].degenerate_count {
                row.count_changes += 1;
            }
            // Relative to each eigenvalue, floored at 1e-12 of the largest so
            // that exact zeros compare absolutely.
            let floor = 1e-12 * refs[k].eig.values[5].abs();
            let d = an
                .eig
                .values
                .iter()
                .zip(refs[k].eig.values.iter())
                .map(|(x, y)| (x - y).abs() / y.abs().max(floor).max(f64::MIN_POSITIVE))
                .fold(0.0, f64::max);
            row.max_eigenvalue_change = row.max_eigenvalue_change.max(d);
            row.max_eigenvalue_change_by_arm[arm] = row.max_eigenvalue_change_by_arm[arm].max(d);
        }
    }
    Ok(rows)
}
