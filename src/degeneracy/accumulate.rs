//! Assembly of `H` and `M` in one streaming pass: the accumulator of 31 running
//! sums, its kernels (a scalar reference and an AVX2 + FMA kernel chosen at run
//! time), and re-expression of points in another body frame.
//!
//! # Layout and summation order
//!
//! Points enter a structure-of-arrays chunk of [`CHUNK`] points (x, y, z, nx,
//! ny, nz, w: 14 KiB, held in L1). A full chunk is folded into the current
//! block's sums by the kernel; the caller ends a block every [`BLOCK`] records
//! and the block's sums are added to the total in order. Everything about the
//! summation order is thus fixed by the record sequence alone: how a file is
//! read (buffer sizes, chunk boundaries inside a record) and how many threads
//! assemble the blocks do not change a single bit of the result.
//!
//! The AVX2 kernel keeps one 4-lane register per running sum and splits the 30
//! sums over four passes across the (L1-resident) chunk so that each pass's
//! accumulators and inputs fit in the 16 vector registers: no spills, no
//! shuffles, one fused multiply-add per product. It agrees with the scalar
//! reference to rounding (tested to 1e-12 relative to the largest entry).
//!
//! # Reference points (exact anywhere)
//!
//! Each block sums its points about its own first point `o_b` (`q = p - o_b`),
//! so the products stay of the size of the data's extent whatever the
//! coordinates (map or UTM frames at 1e6 m lose no digit). A closed block is
//! moved to the total's reference `o` (the first block's) exactly: with
//! `delta = o_b - o`, `a' = B a` for `B = [[I, [delta]x], [0, I]]`, so
//! `H' = B H B^T`, and `s' = s + W delta`,
//! `S' = S + s delta^T + delta s^T + W delta delta^T`. [`Accumulator::finish`]
//! moves the sums to the centroid the same way and keeps that pair
//! ([`Assembly::hc`], [`Assembly::mc`]); the pair about the frame's origin is
//! the centred pair moved once more, by the centroid itself. The subtraction
//! is three operations per point in the copy into the chunk, so the kernels
//! are unchanged.

#![allow(clippy::needless_range_loop)] // index loops mirror the maths and the lane layout

use crate::diagnostic::{Error, Result};
use crate::geometry::se3::{skew, Transform};
use crate::tolerances::ASSEMBLY_PARALLEL_MIN_POINTS;
use nalgebra::{Matrix3, Matrix6, Vector3};

/// 21 products of `a`, weight sum, `sum w p` (3), `sum w p p^T` (6).
pub(crate) const NSUM: usize = 31;
/// Points per structure-of-arrays chunk (a multiple of the 4 lanes).
pub(crate) const CHUNK: usize = 256;
/// Records per block: the unit of deterministic combination (and of the work
/// split between threads).
pub const BLOCK: usize = 1 << 16;

/// Running sums of one block or of the total.
pub(crate) type Sums = [f64; NSUM];

/// A closed block's sums about its reference point (its first point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Block {
    pub(crate) sums: Sums,
    pub(crate) origin: [f64; 3],
}

/// Move sums about reference `o` to reference `o - delta` (points `q + delta`),
/// exactly in exact arithmetic (see the module notes).
pub(crate) fn shift_sums(s: &Sums, delta: &[f64; 3]) -> Sums {
    let h = h_of(s);
    let mut b = Matrix6::identity();
    b.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&skew(&Vector3::from(*delta)));
    let h2 = b * h * b.transpose();
    let mut out = [0.0; NSUM];
    let mut idx = 0;
    for i in 0..6 {
        for j in i..6 {
            out[idx] = h2[(i, j)];
            idx += 1;
        }
    }
    let w = s[21];
    out[21] = w;
    let sp = [s[22], s[23], s[24]];
    for k in 0..3 {
        out[22 + k] = sp[k] + w * delta[k];
    }
    let mut idx = 25;
    for i in 0..3 {
        for j in i..3 {
            out[idx] = s[idx] + sp[i] * delta[j] + delta[i] * sp[j] + w * delta[i] * delta[j];
            idx += 1;
        }
    }
    out
}

/// `H` from the 21 product sums.
fn h_of(s: &Sums) -> Matrix6<f64> {
    let mut h = Matrix6::zeros();
    let mut idx = 0;
    for i in 0..6 {
        for j in i..6 {
            h[(i, j)] = s[idx];
            h[(j, i)] = s[idx];
            idx += 1;
        }
    }
    h
}

/// `M = [[tr(S) I - S, [s]x], [-[s]x, W I]]` from the moment sums.
fn m_of(s: &Sums) -> Matrix6<f64> {
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
    m
}

/// Index of the product `a_i a_j` (`i <= j`) in the sums.
const fn hidx(i: usize, j: usize) -> usize {
    // Rows of the upper triangle: row i starts at 6i - i(i-1)/2.
    6 * i - i * (i.saturating_sub(1)) / 2 + (j - i)
}

/// Which assembly kernel runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kernel {
    /// One point at a time, plain multiply and add: the reference.
    Scalar,
    /// Four lanes, fused multiply-add, four register-resident passes per chunk.
    Avx2Fma,
}

impl Kernel {
    /// The fastest kernel this CPU runs.
    pub fn detect() -> Kernel {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
            {
                return Kernel::Avx2Fma;
            }
        }
        Kernel::Scalar
    }

    /// Every kernel this CPU runs (the reference first).
    pub fn available() -> Vec<Kernel> {
        let mut v = vec![Kernel::Scalar];
        if Kernel::detect() == Kernel::Avx2Fma {
            v.push(Kernel::Avx2Fma);
        }
        v
    }
}

/// Structure-of-arrays chunk: columns x, y, z, nx, ny, nz, w.
#[derive(Debug, Clone, PartialEq)]
struct Chunk {
    cols: [[f64; CHUNK]; 7],
    len: usize,
    /// The open block's reference point, subtracted from every point copied in.
    origin: [f64; 3],
    /// Some weight differs from 1 (otherwise the cheaper unweighted pass runs;
    /// with unit weights both give the same bits).
    weighted: bool,
}

impl Chunk {
    fn new() -> Self {
        Chunk {
            cols: [[0.0; CHUNK]; 7],
            len: 0,
            origin: [0.0; 3],
            weighted: false,
        }
    }

    #[inline(always)]
    fn push(&mut self, p: &[f64; 3], n: &[f64; 3], w: f64) {
        let i = self.len;
        if i < CHUNK {
            let o = self.origin;
            self.cols[0][i] = p[0] - o[0];
            self.cols[1][i] = p[1] - o[1];
            self.cols[2][i] = p[2] - o[2];
            self.cols[3][i] = n[0];
            self.cols[4][i] = n[1];
            self.cols[5][i] = n[2];
            self.cols[6][i] = w;
            self.weighted |= w != 1.0;
            self.len = i + 1;
        }
    }

    /// Copy as many points as fit (all lengths equal); returns how many.
    fn fill(&mut self, p: &[[f64; 3]], n: &[[f64; 3]], w: Option<&[f64]>) -> usize {
        let start = self.len.min(CHUNK);
        let k = (CHUNK - start).min(p.len()).min(n.len());
        let [c0, c1, c2, c3, c4, c5, c6] = &mut self.cols;
        let range = start..start + k;
        let o = self.origin;
        for (j, (pi, ni)) in p[..k].iter().zip(n).enumerate() {
            // Fetch the next chunk's points while this one is copied, so that
            // memory keeps streaming while the kernel folds this chunk.
            if j % 2 == 0 {
                prefetch(p, j + CHUNK);
                prefetch(n, j + CHUNK);
            }
            let i = start + j;
            c0[i] = pi[0] - o[0];
            c1[i] = pi[1] - o[1];
            c2[i] = pi[2] - o[2];
            c3[i] = ni[0];
            c4[i] = ni[1];
            c5[i] = ni[2];
        }
        match w {
            Some(w) => {
                let w = &w[..k.min(w.len())];
                c6[start..start + w.len()].copy_from_slice(w);
                self.weighted |= w.iter().any(|&x| x != 1.0);
            }
            None => c6[range].fill(1.0),
        }
        self.len = start + k;
        k
    }

    fn is_full(&self) -> bool {
        self.len == CHUNK
    }

    /// Fold the chunk into `out` and empty it.
    fn flush(&mut self, kernel: Kernel, out: &mut Sums) {
        if self.len > 0 {
            fold_chunk(kernel, &mut self.cols, self.len, self.weighted, out);
        }
        self.len = 0;
        self.weighted = false;
    }
}

/// Ask for the cache line holding `s[i]` (nothing past the end).
#[inline(always)]
fn prefetch<T>(s: &[T], i: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(x) = s.get(i) {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: a prefetch never faults, and the address is inside `s`.
        #[allow(unused_unsafe)]
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>((x as *const T).cast::<i8>())
        };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (s, i);
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

/// The reference: one point at a time.
#[inline(always)]
fn push_one(out: &mut Sums, p: &[f64; 3], n: &[f64; 3], w: f64) {
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

fn fold_scalar(cols: &[[f64; CHUNK]; 7], len: usize, out: &mut Sums) {
    for i in 0..len.min(CHUNK) {
        let p = [cols[0][i], cols[1][i], cols[2][i]];
        let n = [cols[3][i], cols[4][i], cols[5][i]];
        push_one(out, &p, &n, cols[6][i]);
    }
}

/// Fold `len` points of a chunk into `out` with the chosen kernel. The lanes
/// past `len` up to the next multiple of 4 are zeroed first: a zero point with
/// a zero normal and weight adds exactly nothing.
fn fold_chunk(
    kernel: Kernel,
    cols: &mut [[f64; CHUNK]; 7],
    len: usize,
    weighted: bool,
    out: &mut Sums,
) {
    match kernel {
        Kernel::Scalar => fold_scalar(cols, len, out),
        Kernel::Avx2Fma => {
            let groups = len.min(CHUNK).div_ceil(4);
            for col in cols.iter_mut() {
                col[len.min(CHUNK)..groups * 4].fill(0.0);
            }
            #[cfg(target_arch = "x86_64")]
            {
                if Kernel::detect() == Kernel::Avx2Fma {
                    // SAFETY: the CPU supports AVX2 and FMA (checked just above).
                    unsafe {
                        if weighted {
                            avx2::fold::<true>(cols, groups, out)
                        } else {
                            avx2::fold::<false>(cols, groups, out);
                            out[21] += len as f64;
                        }
                    }
                    return;
                }
            }
            let _ = weighted;
            fold_scalar(cols, len, out)
        }
    }
}

/// The AVX2 + FMA kernel: four passes over an L1-resident chunk, each with at
/// most 9 accumulators (one 4-lane register per running sum) so that sums,
/// inputs and temporaries fit in the 16 vector registers.
#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::{hidx, Sums, CHUNK};
    use std::arch::x86_64::*;

    type Cols = [[f64; CHUNK]; 7];

    /// Lanes summed as `(l0 + l1) + (l2 + l3)`.
    #[inline(always)]
    fn hsum(v: __m256d) -> f64 {
        // SAFETY: __m256d and [f64; 4] have the same size and any bits are valid.
        let a: [f64; 4] = unsafe { std::mem::transmute::<__m256d, [f64; 4]>(v) };
        (a[0] + a[1]) + (a[2] + a[3])
    }

    /// Column `k` at point `o` (4 lanes). The caller keeps `o + 4 <= CHUNK`.
    macro_rules! ld {
        ($c:expr, $k:expr, $o:expr) => {
            _mm256_loadu_pd($c[$k].as_ptr().add($o))
        };
    }

    /// `a * b - c * d`, the components of `p x n`.
    macro_rules! cross {
        ($a:expr, $b:expr, $c:expr, $d:expr) => {
            _mm256_fmsub_pd($a, $b, _mm256_mul_pd($c, $d))
        };
    }

    /// Weighted left factor `w * v` (or `v` when unweighted).
    macro_rules! wt {
        ($w:expr, $v:expr, $weighted:expr) => {
            if $weighted {
                _mm256_mul_pd($w, $v)
            } else {
                $v
            }
        };
    }

    /// Sums for `groups` groups of 4 points (`4 * groups <= CHUNK`).
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn fold<const W: bool>(c: &Cols, groups: usize, out: &mut Sums) {
        let groups = groups.min(CHUNK / 4);
        // SAFETY (all passes): every load reads c[k][4g..4g + 4] with 4g + 4 <= CHUNK.
        unsafe {
            pass_cc::<W>(c, groups, out);
            pass_c01n::<W>(c, groups, out);
            pass_c2n_nn::<W>(c, groups, out);
            pass_moments::<W>(c, groups, out);
        }
    }

    /// `sum w c_i c_j`, `i <= j < 3`, with `c = p x n`.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn pass_cc<const W: bool>(c: &Cols, groups: usize, out: &mut Sums) {
        let z = _mm256_setzero_pd();
        let [mut s00, mut s01, mut s02, mut s11, mut s12, mut s22] = [z; 6];
        for g in 0..groups {
            let o = 4 * g;
            let (x, y, zz) = unsafe { (ld!(c, 0, o), ld!(c, 1, o), ld!(c, 2, o)) };
            let (nx, ny, nz) = unsafe { (ld!(c, 3, o), ld!(c, 4, o), ld!(c, 5, o)) };
            let c0 = cross!(y, nz, zz, ny);
            let c1 = cross!(zz, nx, x, nz);
            let c2 = cross!(x, ny, y, nx);
            let w = if W { unsafe { ld!(c, 6, o) } } else { z };
            let (w0, w1, w2) = (wt!(w, c0, W), wt!(w, c1, W), wt!(w, c2, W));
            s00 = _mm256_fmadd_pd(w0, c0, s00);
            s01 = _mm256_fmadd_pd(w0, c1, s01);
            s02 = _mm256_fmadd_pd(w0, c2, s02);
            s11 = _mm256_fmadd_pd(w1, c1, s11);
            s12 = _mm256_fmadd_pd(w1, c2, s12);
            s22 = _mm256_fmadd_pd(w2, c2, s22);
        }
        out[hidx(0, 0)] += hsum(s00);
        out[hidx(0, 1)] += hsum(s01);
        out[hidx(0, 2)] += hsum(s02);
        out[hidx(1, 1)] += hsum(s11);
        out[hidx(1, 2)] += hsum(s12);
        out[hidx(2, 2)] += hsum(s22);
    }

    /// `sum w c_i n_j` for `i` in 0, 1.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn pass_c01n<const W: bool>(c: &Cols, groups: usize, out: &mut Sums) {
        let z = _mm256_setzero_pd();
        let [mut s03, mut s04, mut s05, mut s13, mut s14, mut s15] = [z; 6];
        for g in 0..groups {
            let o = 4 * g;
            let (x, y, zz) = unsafe { (ld!(c, 0, o), ld!(c, 1, o), ld!(c, 2, o)) };
            let (nx, ny, nz) = unsafe { (ld!(c, 3, o), ld!(c, 4, o), ld!(c, 5, o)) };
            let c0 = cross!(y, nz, zz, ny);
            let c1 = cross!(zz, nx, x, nz);
            let w = if W { unsafe { ld!(c, 6, o) } } else { z };
            let (w0, w1) = (wt!(w, c0, W), wt!(w, c1, W));
            s03 = _mm256_fmadd_pd(w0, nx, s03);
            s04 = _mm256_fmadd_pd(w0, ny, s04);
            s05 = _mm256_fmadd_pd(w0, nz, s05);
            s13 = _mm256_fmadd_pd(w1, nx, s13);
            s14 = _mm256_fmadd_pd(w1, ny, s14);
            s15 = _mm256_fmadd_pd(w1, nz, s15);
        }
        out[hidx(0, 3)] += hsum(s03);
        out[hidx(0, 4)] += hsum(s04);
        out[hidx(0, 5)] += hsum(s05);
        out[hidx(1, 3)] += hsum(s13);
        out[hidx(1, 4)] += hsum(s14);
        out[hidx(1, 5)] += hsum(s15);
    }

    /// `sum w c_2 n_j` and `sum w n_i n_j`.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn pass_c2n_nn<const W: bool>(c: &Cols, groups: usize, out: &mut Sums) {
        let z = _mm256_setzero_pd();
        let [mut s23, mut s24, mut s25, mut s33, mut s34, mut s35, mut s44, mut s45, mut s55] =
            [z; 9];
        for g in 0..groups {
            let o = 4 * g;
            let (x, y) = unsafe { (ld!(c, 0, o), ld!(c, 1, o)) };
            let (nx, ny, nz) = unsafe { (ld!(c, 3, o), ld!(c, 4, o), ld!(c, 5, o)) };
            let c2 = cross!(x, ny, y, nx);
            let w = if W { unsafe { ld!(c, 6, o) } } else { z };
            let (w2, wx, wy, wz) = (wt!(w, c2, W), wt!(w, nx, W), wt!(w, ny, W), wt!(w, nz, W));
            s23 = _mm256_fmadd_pd(w2, nx, s23);
            s24 = _mm256_fmadd_pd(w2, ny, s24);
            s25 = _mm256_fmadd_pd(w2, nz, s25);
            s33 = _mm256_fmadd_pd(wx, nx, s33);
            s34 = _mm256_fmadd_pd(wx, ny, s34);
            s35 = _mm256_fmadd_pd(wx, nz, s35);
            s44 = _mm256_fmadd_pd(wy, ny, s44);
            s45 = _mm256_fmadd_pd(wy, nz, s45);
            s55 = _mm256_fmadd_pd(wz, nz, s55);
        }
        out[hidx(2, 3)] += hsum(s23);
        out[hidx(2, 4)] += hsum(s24);
        out[hidx(2, 5)] += hsum(s25);
        out[hidx(3, 3)] += hsum(s33);
        out[hidx(3, 4)] += hsum(s34);
        out[hidx(3, 5)] += hsum(s35);
        out[hidx(4, 4)] += hsum(s44);
        out[hidx(4, 5)] += hsum(s45);
        out[hidx(5, 5)] += hsum(s55);
    }

    /// `sum w` (weighted only; the caller adds the count otherwise),
    /// `sum w p` and `sum w p p^T`.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn pass_moments<const W: bool>(c: &Cols, groups: usize, out: &mut Sums) {
        let z = _mm256_setzero_pd();
        let [mut sw, mut sx, mut sy, mut sz] = [z; 4];
        let [mut sxx, mut sxy, mut sxz, mut syy, mut syz, mut szz] = [z; 6];
        for g in 0..groups {
            let o = 4 * g;
            let (x, y, zz) = unsafe { (ld!(c, 0, o), ld!(c, 1, o), ld!(c, 2, o)) };
            let w = if W { unsafe { ld!(c, 6, o) } } else { z };
            let (wx, wy, wz) = (wt!(w, x, W), wt!(w, y, W), wt!(w, zz, W));
            if W {
                sw = _mm256_add_pd(sw, w);
            }
            sx = _mm256_add_pd(sx, wx);
            sy = _mm256_add_pd(sy, wy);
            sz = _mm256_add_pd(sz, wz);
            sxx = _mm256_fmadd_pd(wx, x, sxx);
            sxy = _mm256_fmadd_pd(wx, y, sxy);
            sxz = _mm256_fmadd_pd(wx, zz, sxz);
            syy = _mm256_fmadd_pd(wy, y, syy);
            syz = _mm256_fmadd_pd(wy, zz, syz);
            szz = _mm256_fmadd_pd(wz, zz, szz);
        }
        if W {
            out[21] += hsum(sw);
        }
        for (k, s) in [sx, sy, sz, sxx, sxy, sxz, syy, syz, szz]
            .into_iter()
            .enumerate()
        {
            out[22 + k] += hsum(s);
        }
    }
}

/// Streaming accumulator of `H` and `M`: 31 running sums, no per-point storage
/// beyond one chunk of 256 points.
#[derive(Debug, Clone, PartialEq)]
pub struct Accumulator {
    /// Sums of the completed blocks, added in order, about `origin`.
    total: Sums,
    /// Reference point of `total` (the first block's; `None` before one).
    origin: Option<[f64; 3]>,
    /// The open block has a reference point (its first point).
    started: bool,
    /// Sums of the current block (flushed chunks only).
    block: Sums,
    chunk: Box<Chunk>,
    /// Points added to the current block through [`Accumulator::add`].
    in_block: usize,
    count: usize,
    kernel: Kernel,
    /// Most threads [`Accumulator::add`] uses (0: as many as the machine has).
    threads: usize,
}

impl Default for Accumulator {
    fn default() -> Self {
        Self::new()
    }
}

impl Accumulator {
    /// With the fastest kernel this CPU runs.
    pub fn new() -> Self {
        Self::with_kernel(Kernel::detect())
    }

    /// With a chosen kernel (a kernel the CPU lacks falls back to the scalar one).
    pub fn with_kernel(kernel: Kernel) -> Self {
        Accumulator {
            total: [0.0; NSUM],
            origin: None,
            started: false,
            block: [0.0; NSUM],
            chunk: Box::new(Chunk::new()),
            in_block: 0,
            count: 0,
            kernel,
            threads: 0,
        }
    }

    /// At most `threads` threads in [`Accumulator::add`] (0: one per core). The
    /// result does not depend on it.
    pub fn threads(mut self, threads: usize) -> Self {
        self.threads = threads;
        self
    }

    /// The kernel this accumulator runs.
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// Add one point with its unit normal and weight (the readers'
    /// record-by-record path; whole batches go through `push_slices`).
    #[inline(always)]
    pub(crate) fn push_point(&mut self, p: &[f64; 3], n: &[f64; 3], w: f64) {
        self.start_block(p);
        self.chunk.push(p, n, w);
        self.count += 1;
        if self.chunk.is_full() {
            self.chunk.flush(self.kernel, &mut self.block);
        }
    }

    /// Add one point with its unit normal (weight 1).
    pub fn push(&mut self, p: &[f64; 3], n: &[f64; 3]) {
        self.push_point(p, n, 1.0);
    }

    /// Add one point with its unit normal and weight.
    pub fn push_weighted(&mut self, p: &[f64; 3], n: &[f64; 3], w: f64) {
        self.push_point(p, n, w);
    }

    /// Close the current block: its sums are added to the total. Readers call
    /// this every [`BLOCK`] records, [`Accumulator::add`] every [`BLOCK`] points.
    pub fn end_block(&mut self) {
        let b = self.take_block();
        self.add_block(&b);
    }

    /// The first point of a block is its reference point.
    #[inline(always)]
    fn start_block(&mut self, p: &[f64; 3]) {
        if !self.started {
            self.chunk.origin = *p;
            self.started = true;
        }
    }

    /// Close the current block and return its sums (not added to the total).
    pub(crate) fn take_block(&mut self) -> Block {
        self.chunk.flush(self.kernel, &mut self.block);
        self.in_block = 0;
        self.started = false;
        Block {
            sums: std::mem::replace(&mut self.block, [0.0; NSUM]),
            origin: self.chunk.origin,
        }
    }

    /// Add a closed block's sums to the total (after any block of this one),
    /// moved to the total's reference point.
    pub(crate) fn add_block(&mut self, b: &Block) {
        // An empty block adds nothing and must not set the reference point.
        if b.sums.iter().all(|&x| x == 0.0) {
            return;
        }
        let o = *self.origin.get_or_insert(b.origin);
        let delta = [b.origin[0] - o[0], b.origin[1] - o[1], b.origin[2] - o[2]];
        let s = if delta == [0.0; 3] {
            b.sums
        } else {
            shift_sums(&b.sums, &delta)
        };
        for k in 0..NSUM {
            self.total[k] += s[k];
        }
    }

    /// Count points whose sums arrive through `add_block`.
    pub(crate) fn add_count(&mut self, n: usize) {
        self.count += n;
    }

    /// Add a batch. `weights`, when given, has one entry per point. Mismatched
    /// lengths are an error. Large batches are split by block over threads.
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
        if let Some(w) = weights {
            if w.len() != points.len() {
                return Err(Error::invalid(format!(
                    "expected one weight per point, found {} points and {} weights",
                    points.len(),
                    w.len()
                )));
            }
        }
        let batch = Batch {
            points,
            normals,
            weights,
        };
        // Finish the open block point by point, then whole blocks (in parallel
        // when it pays), then the remainder opens a new block.
        let head = (BLOCK - self.in_block).min(points.len());
        self.add_serial(&batch.slice(0, head));
        let whole = (points.len() - head) / BLOCK;
        let body = batch.slice(head, head + whole * BLOCK);
        let threads = worker_count(self.threads, whole, points.len());
        if threads > 1 {
            for b in assemble_blocks_parallel(&body, self.kernel, threads) {
                self.add_block(&b);
            }
            self.count += body.points.len();
        } else {
            self.add_serial(&body);
        }
        self.add_serial(&batch.slice(head + whole * BLOCK, points.len()));
        Ok(())
    }

    /// Into the open block, a chunk at a time, closing a block every
    /// [`BLOCK`] points.
    fn add_serial(&mut self, b: &Batch) {
        let len = b.points.len();
        let mut i = 0;
        while i < len {
            let k = (BLOCK - self.in_block).min(len - i);
            self.push_batch(&b.slice(i, i + k));
            self.in_block += k;
            i += k;
            if self.in_block >= BLOCK {
                self.end_block();
            }
        }
    }

    /// Points into the open block (no block is closed): the bulk path of the
    /// streaming readers.
    pub(crate) fn push_slices(&mut self, p: &[[f64; 3]], n: &[[f64; 3]], w: Option<&[f64]>) {
        let m = p.len().min(n.len()).min(w.map_or(usize::MAX, <[f64]>::len));
        self.push_batch(&Batch {
            points: &p[..m],
            normals: &n[..m],
            weights: w.map(|w| &w[..m]),
        });
    }

    /// Into the open block, a chunk at a time (no block is closed).
    fn push_batch(&mut self, b: &Batch) {
        if let Some(p) = b.points.first() {
            self.start_block(p);
        }
        let mut i = 0;
        while i < b.points.len() {
            let k = self
                .chunk
                .fill(&b.points[i..], &b.normals[i..], b.weights.map(|w| &w[i..]));
            i += k;
            self.count += k;
            if self.chunk.is_full() {
                self.chunk.flush(self.kernel, &mut self.block);
            }
            if k == 0 {
                break;
            }
        }
    }

    /// Combine two partial accumulations (`other` after `self`).
    pub fn merge(&mut self, other: &Accumulator) {
        self.end_block();
        self.add_block(&other.sums());
        self.count += other.count;
    }

    /// Points added so far.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Total sums about their reference point, the open block and chunk
    /// included (`self` unchanged).
    fn sums(&self) -> Block {
        let mut me = self.clone();
        if me.started {
            let b = me.take_block();
            me.add_block(&b);
        }
        Block {
            sums: me.total,
            origin: me.origin.unwrap_or([0.0; 3]),
        }
    }

    /// Form `H` and `M` from the running sums: about the centroid first, then
    /// moved to the frame's origin (see the module notes).
    pub fn finish(&self) -> Assembly {
        let Block { sums: s, origin: o } = self.sums();
        let w = s[21];
        // Centroid offset from the reference; none without weight.
        let mean = if w > 0.0 {
            [s[22] / w, s[23] / w, s[24] / w]
        } else {
            [0.0; 3]
        };
        let mut sc = shift_sums(&s, &[-mean[0], -mean[1], -mean[2]]);
        // About the centroid the first moment is zero by definition.
        sc[22..25].fill(0.0);
        let center = [o[0] + mean[0], o[1] + mean[1], o[2] + mean[2]];
        let raw = shift_sums(&sc, &center);
        Assembly {
            h: h_of(&raw),
            m: m_of(&raw),
            hc: h_of(&sc),
            mc: m_of(&sc),
            center,
            count: self.count,
            weight_sum: w,
        }
    }
}

/// A batch of points, normals and optional weights of equal lengths.
struct Batch<'a> {
    points: &'a [[f64; 3]],
    normals: &'a [[f64; 3]],
    weights: Option<&'a [f64]>,
}

impl<'a> Batch<'a> {
    fn slice(&self, a: usize, b: usize) -> Batch<'a> {
        Batch {
            points: &self.points[a..b],
            normals: &self.normals[a..b],
            weights: self.weights.map(|w| &w[a..b]),
        }
    }
}

/// Threads worth using for `blocks` whole blocks of a batch of `points`
/// (`requested` 0: one per core).
pub(crate) fn worker_count(requested: usize, blocks: usize, points: usize) -> usize {
    if points < ASSEMBLY_PARALLEL_MIN_POINTS || blocks < 2 {
        return 1;
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let t = if requested == 0 { cores } else { requested };
    t.min(blocks).max(1)
}

/// The sums of each block of `body` (a whole number of blocks), in order: the
/// blocks are split into `threads` contiguous runs, one per scoped thread.
fn assemble_blocks_parallel(body: &Batch, kernel: Kernel, threads: usize) -> Vec<Block> {
    let blocks = body.points.len() / BLOCK;
    let per = blocks.div_ceil(threads.max(1));
    let runs: Vec<Batch> = (0..blocks)
        .step_by(per.max(1))
        .map(|b0| body.slice(b0 * BLOCK, ((b0 + per).min(blocks)) * BLOCK))
        .collect();
    let run_blocks = |run: &Batch| -> Vec<Block> {
        let mut acc = Accumulator::with_kernel(kernel).threads(1);
        (0..run.points.len() / BLOCK)
            .map(|b| {
                acc.push_batch(&run.slice(b * BLOCK, (b + 1) * BLOCK));
                acc.take_block()
            })
            .collect()
    };
    let Some((first, others)) = runs.split_first() else {
        return Vec::new();
    };
    let rb = &run_blocks;
    std::thread::scope(|s| {
        // A run whose thread cannot start (or that panics, a bug) is done here.
        let handles: Vec<_> = others
            .iter()
            .map(|r| {
                std::thread::Builder::new()
                    .spawn_scoped(s, move || rb(r))
                    .map_err(|_| r)
            })
            .collect();
        let mut all = rb(first);
        for (h, r) in handles.into_iter().zip(others) {
            match h {
                Ok(h) => all.extend(h.join().unwrap_or_else(|_| rb(r))),
                Err(r) => all.extend(rb(r)),
            }
        }
        all
    })
}

/// `H` and `M` of one point set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Assembly {
    /// Information matrix `sum w a a^T`.
    pub h: Matrix6<f64>,
    /// Point-displacement metric `sum w J^T J`.
    pub m: Matrix6<f64>,
    /// `H` about the centroid (axes of the frame): `H = B hc B^T` with
    /// `B = [[I, [center]x], [0, I]]`. Its generalized eigenvalues with
    /// [`Assembly::mc`] are those of `(H, M)`, free of the offset's rounding.
    pub hc: Matrix6<f64>,
    /// `M` about the centroid: `[[tr(S) I - S, 0], [0, W I]]`.
    pub mc: Matrix6<f64>,
    /// Weighted centroid of the points in the frame (m; the origin when the
    /// weights sum to zero).
    pub center: [f64; 3],
    /// Points assembled.
    pub count: usize,
    /// `sum w` (the point count with unit weights).
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
    /// `M' = A^T M A` with `A = Ad(T)`. The centred pair turns with `R` only
    /// and the centroid becomes `R^T (c - d)` (`R`, `d` read from `A`). For an
    /// `A` that is not an adjoint (the sweep's orthogonal control) there is no
    /// centroid: the centred pair is the transformed pair about the origin.
    pub fn congruence(&self, a: &Matrix6<f64>) -> Assembly {
        let h = a.transpose() * self.h * a;
        let m = a.transpose() * self.m * a;
        let r: Matrix3<f64> = a.fixed_view::<3, 3>(0, 0).into_owned();
        let adjoint = a.fixed_view::<3, 3>(0, 3).iter().all(|&x| x == 0.0)
            && a.fixed_view::<3, 3>(3, 3).into_owned() == r
            && (r.transpose() * r - Matrix3::identity()).amax() < 1e-12;
        if !adjoint {
            return Assembly {
                h,
                m,
                hc: h,
                mc: m,
                center: [0.0; 3],
                count: self.count,
                weight_sum: self.weight_sum,
            };
        }
        let dx: Matrix3<f64> = a.fixed_view::<3, 3>(3, 0) * r.transpose();
        let d = Vector3::new(dx[(2, 1)], dx[(0, 2)], dx[(1, 0)]);
        let mut q = Matrix6::zeros();
        q.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
        q.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
        let c = r.transpose() * (Vector3::from(self.center) - d);
        Assembly {
            h,
            m,
            hc: q.transpose() * self.hc * q,
            mc: q.transpose() * self.mc * q,
            center: [c.x, c.y, c.z],
            count: self.count,
            weight_sum: self.weight_sum,
        }
    }

    /// `Ad` of the centroid frame `(I, center)`: a twist about the centroid
    /// `xi_c` is `xi = A xi_c` in this frame.
    pub fn center_adjoint(&self) -> Matrix6<f64> {
        let mut a = Matrix6::identity();
        a.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&skew(&Vector3::from(self.center)));
        a
    }

    /// RMS distance of the points from their centroid (m):
    /// `sqrt(tr(S_c) / W)`, the length that makes a rotation and a
    /// translation comparable on this cloud (0 without weight).
    pub fn rms_radius(&self) -> f64 {
        let w = self.mc[(3, 3)];
        let tr = self.mc[(0, 0)] + self.mc[(1, 1)] + self.mc[(2, 2)];
        if w > 0.0 && tr > 0.0 {
            (0.5 * tr / w).sqrt()
        } else {
            0.0
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
