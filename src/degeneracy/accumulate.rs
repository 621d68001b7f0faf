//! Assembly of `H` and `M` in one streaming pass: the lane kernel (with an AVX2 + FMA dispatch), the accumulator of 31 running sums, and re-expression of points in another body frame.

#![allow(clippy::needless_range_loop)] // index loops mirror the maths and the lane layout

use crate::diagnostic::{Error, Result};
use crate::geometry::se3::{skew, Transform};
use nalgebra::{Matrix3, Matrix6, Vector3};

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
