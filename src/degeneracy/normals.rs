//! Raw scans: voxel down-sampling and normals by PCA, as the synthetic
//! pipeline does, with the options a real scan needs.
//!
//! A point's neighbourhood is every point within `radius` (itself included),
//! optionally only its `k` nearest of those; with fewer than `min_neighbours`
//! it gets no normal and is dropped. The normal is the eigenvector of the
//! smallest eigenvalue of the neighbourhood covariance (offsets from the query
//! point, one pass), oriented toward the viewpoint (`n . (v - p) >= 0`). The
//! planarity gate drops points whose neighbourhood planarity
//! `(lambda_2 - lambda_3) / lambda_1` (eigenvalues descending; Demantke et
//! al. 2011: 1 on a plane, 0 on a line or an isotropic blob) is below
//! `min_planarity`. On a spinning LiDAR's ground the neighbourhoods of sparse
//! rings are lines whose smallest-eigenvalue direction is arbitrary about
//! the ring; the gate drops them. Duplicate points are merged first
//! ([`merge_duplicates`]): fifty copies of a point are one point, not fifty
//! neighbours standing in for a surface (60 points repeated 50 times give
//! the normals of the 60). The work is split over
//! threads by contiguous point ranges; the output keeps the input order, so it
//! does not depend on the thread count.

use super::cells::floor_i64;
use super::grid::Grid;
use super::scene::Cloud;
use super::sym3;
use crate::diagnostic::{Error, Result};
use crate::progress::{NoProgress, Progress};
use crate::tolerances::DUPLICATE_POINT_REL_TOL;
use foldhash::{HashMap, HashMapExt};
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use nalgebra::{Matrix3, SymmetricEigen, Vector3};
use std::hash::BuildHasher;
use std::num::NonZero;

/// How normals are estimated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalParams {
    /// Neighbourhood radius (m).
    pub radius: f64,
    /// At most this many nearest neighbours within the radius (itself
    /// included); `None`: all of them.
    pub knn: Option<usize>,
    /// Fewest neighbours (itself included) for a normal.
    pub min_neighbours: usize,
    /// Planarity gate: least `(lambda_2 - lambda_3) / lambda_1`; `None`: no gate.
    pub min_planarity: Option<f64>,
    /// Normals point toward this point (the sensor origin by default).
    pub viewpoint: [f64; 3],
}

/// What normal estimation kept and dropped.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NormalStats {
    /// Points given a normal.
    pub kept: usize,
    /// Dropped: fewer than `min_neighbours` neighbours.
    pub sparse: usize,
    /// Dropped by the planarity gate.
    pub not_planar: usize,
}

impl NormalParams {
    fn check(&self) -> Result<()> {
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Err(Error::usage(format!(
                "normal radius: expected a positive number of metres, found {}",
                self.radius
            )));
        }
        if self.min_neighbours < 3 {
            return Err(Error::usage(format!(
                "minimum neighbours: expected at least 3 (a plane needs three points), found {}",
                self.min_neighbours
            )));
        }
        if let Some(k) = self.knn {
            if k < self.min_neighbours {
                return Err(Error::usage(format!(
                    "k nearest: expected at least the minimum neighbours ({}), found {k}",
                    self.min_neighbours
                )));
            }
        }
        if let Some(s) = self.min_planarity {
            if !(s.is_finite() && (0.0..=1.0).contains(&s)) {
                return Err(Error::usage(format!(
                    "minimum planarity: expected a number from 0 to 1, found {s}"
                )));
            }
        }
        Ok(())
    }
}

/// One point's neighbourhood moments: count, sum and outer-product sum of the
/// offsets from the query point.
fn moments(
    index: &Index,
    points: &[[f64; 3]],
    (i, p): (usize, &[f64; 3]),
    prm: &NormalParams,
) -> (usize, [f64; 3], [f64; 6]) {
    let mut count = 0usize;
    let mut sum = [0.0f64; 3];
    let mut sxx = [0.0f64; 6];
    let mut add = |q: [f64; 3]| {
        let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
        count += 1;
        for k in 0..3 {
            sum[k] += d[k];
        }
        for (s, t) in sxx.iter_mut().zip(sym3::outer(d)) {
            *s += t;
        }
    };
    let r2 = prm.radius * prm.radius;
    match (prm.knn.and_then(NonZero::new), index) {
        (_, Index::Grid(g)) => g.visit_within(i, p, r2, add),
        (Some(k), Index::Tree(tree)) => {
            let found = tree
                .query(p)
                .nearest_n::<SquaredEuclidean<f64>>(k)
                .within(r2)
                .execute();
            for nb in found {
                if let Some(q) = points.get(nb.item as usize) {
                    add(*q);
                }
            }
        }
        (None, Index::Tree(tree)) => {
            tree.query(p)
                .within::<SquaredEuclidean<f64>>(r2)
                .unsorted()
                .with_points()
                .visit(|q| add([q.point[0], q.point[1], q.point[2]]));
        }
    }
    (count, sum, sxx)
}

/// How neighbourhoods are found: the k-d tree, or the grid (radius only).
enum Index {
    Tree(ImmutableKdTree<f64, 3>),
    Grid(Grid),
}

/// Why a point got no normal.
enum Drop {
    Sparse,
    NotPlanar,
}

fn normal_at(
    index: &Index,
    all: &[[f64; 3]],
    (i, p): (usize, &[f64; 3]),
    prm: &NormalParams,
) -> std::result::Result<[f64; 3], Drop> {
    normal_from(moments(index, all, (i, p), prm), p, prm)
}

/// The normal of the point `p` from its neighbourhood moments.
fn normal_from(
    (count, sum, sxx): (usize, [f64; 3], [f64; 6]),
    p: &[f64; 3],
    prm: &NormalParams,
) -> std::result::Result<[f64; 3], Drop> {
    if count < prm.min_neighbours {
        return Err(Drop::Sparse);
    }
    let nf = count as f64;
    let m = [sum[0] / nf, sum[1] / nf, sum[2] / nf];
    let cov = [
        sxx[0] / nf - m[0] * m[0],
        sxx[1] / nf - m[0] * m[1],
        sxx[2] / nf - m[0] * m[2],
        sxx[3] / nf - m[1] * m[1],
        sxx[4] / nf - m[1] * m[2],
        sxx[5] / nf - m[2] * m[2],
    ];
    if !cov.iter().all(|x| x.is_finite()) {
        return Err(Drop::Sparse);
    }
    // Eigenvalues ascending and the smallest one's eigenvector: the closed
    // form (sym3.rs), or nalgebra's iterative solver where it gives none.
    let (values, smallest) =
        sym3::eigen(&cov).map_or_else(|| iterative_eigen(&cov), |e| (e.values, e.vectors[0]));
    if let Some(gate) = prm.min_planarity {
        let l = [values[2], values[1], values[0]].map(|x| x.max(0.0));
        let planarity = if l[0] > 0.0 {
            (l[1] - l[2]) / l[0]
        } else {
            0.0
        };
        if planarity < gate {
            return Err(Drop::NotPlanar);
        }
    }
    let mut n = Vector3::from(smallest);
    let nn = n.norm();
    if !nn.is_finite() || nn <= 0.0 {
        return Err(Drop::Sparse);
    }
    n /= nn;
    if n.dot(&(Vector3::from(prm.viewpoint) - Vector3::from(*p))) < 0.0 {
        n = -n;
    }
    Ok([n.x, n.y, n.z])
}

/// Eigenvalues ascending and the smallest one's eigenvector by nalgebra's
/// QR iteration: where the closed form gives none (sym3.rs).
fn iterative_eigen(c: &sym3::Upper) -> ([f64; 3], [f64; 3]) {
    let m = Matrix3::new(c[0], c[1], c[2], c[1], c[3], c[4], c[2], c[4], c[5]);
    let eig = SymmetricEigen::new(m);
    let mut k = [0usize, 1, 2];
    k.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let v = eig.eigenvectors.column(k[0]);
    (k.map(|i| eig.eigenvalues[i]), [v[0], v[1], v[2]])
}

/// Normals of `points` (a range of `all`) against the whole tree.
/// With each kept point's index in `points`, offset by `first`.
fn estimate_range(
    tree: &Index,
    all: &[[f64; 3]],
    (first, points): (usize, &[[f64; 3]]),
    (prm, progress): (&NormalParams, &dyn Progress),
) -> (Cloud, NormalStats, Vec<usize>) {
    let normal = |i: usize, p: &[f64; 3]| normal_at(tree, all, (i, p), prm);
    collect_normals((first, points), &normal, progress)
}

/// A point's normal from its index in all the points and its coordinates.
type NormalOf<'a> = dyn Fn(usize, &[f64; 3]) -> std::result::Result<[f64; 3], Drop> + 'a;

/// Every point's normal (`normal(index in all, point)`) or why it has none,
/// in order: the kept points, what was dropped, and each kept point's index.
fn collect_normals(
    (first, points): (usize, &[[f64; 3]]),
    normal: &NormalOf,
    progress: &dyn Progress,
) -> (Cloud, NormalStats, Vec<usize>) {
    let mut out = Cloud::default();
    let mut st = NormalStats::default();
    let mut kept = Vec::new();
    for (i, p) in points.iter().enumerate() {
        if i % PROGRESS_STEP == PROGRESS_STEP - 1 {
            progress.advance(PROGRESS_STEP as u64);
        }
        match normal(first + i, p) {
            Ok(n) => {
                out.points.push(*p);
                out.normals.push(n);
                kept.push(first + i);
                st.kept += 1;
            }
            Err(Drop::Sparse) => st.sparse += 1,
            Err(Drop::NotPlanar) => st.not_planar += 1,
        }
    }
    progress.advance((points.len() % PROGRESS_STEP) as u64);
    (out, st, kept)
}

/// Points with duplicates merged, and their weights when the input had any.
pub type Merged = (Vec<[f64; 3]>, Option<Vec<f64>>);

/// `points` with duplicates merged, or `None` when there are none: the first
/// of each group of points in one cell of the duplicate grid
/// ([`DUPLICATE_POINT_REL_TOL`] of the scan's scale), in input order, with
/// the mean of the group's weights (as the voxel grid does).
pub fn merge_duplicates(points: &[[f64; 3]], weights: Option<&[f64]>) -> Option<Merged> {
    let scale = points.iter().flatten().fold(1.0f64, |m, c| m.max(c.abs()));
    let cell = DUPLICATE_POINT_REL_TOL * scale;
    let n = points.len();
    if !cell.is_finite() || n < 2 {
        return None;
    }
    // |c| / cell <= 2^40: the keys fit an i64 exactly, but span more than 32
    // bits, so the cells' packed sort does not apply; sorting the keys as
    // tuples was 40 % of a million-point raw scan's run (BENCHMARKS.md).
    let key = |i: usize| points[i].map(|c| floor_i64(c / cell));
    // first[i]: the first point (input order) of i's group.
    let first = if n <= u32::MAX as usize {
        firsts_by_hash(n, key)
    } else {
        firsts_by_map(n, key)
    }?;
    let mut sum = vec![0.0f64; if weights.is_some() { n } else { 0 }];
    let mut size = vec![0u32; sum.len()];
    if let Some(w) = weights {
        for (i, &f) in first.iter().enumerate() {
            sum[f] += w.get(i).copied().unwrap_or(1.0);
            size[f] += 1;
        }
    }
    let leads = || (0..n).filter(|&i| first[i] == i);
    let kept = leads().map(|i| points[i]).collect();
    let w = weights.map(|_| leads().map(|i| sum[i] / f64::from(size[i])).collect());
    Some((kept, w))
}

/// Each key's group leader (the first index holding the same key), or
/// `None` when every key is distinct: keys sorted by a 32-bit hash packed
/// with their index into one `u64` (a plain integer sort), each run of one
/// hash then split by its exact keys (a hash collision is two groups).
fn firsts_by_hash(n: usize, key: impl Fn(usize) -> [i64; 3]) -> Option<Vec<usize>> {
    let state = foldhash::fast::FixedState::with_seed(0x5eed);
    let hash = |k: &[i64; 3]| state.hash_one(k) as u32;
    let mut order: Vec<u64> = (0..n)
        .map(|i| (u64::from(hash(&key(i))) << 32) | i as u64)
        .collect();
    order.sort_unstable();
    let mut first: Vec<usize> = (0..n).collect();
    let mut any = false;
    for run in order.chunk_by(|a, b| a >> 32 == b >> 32) {
        if run.len() < 2 {
            continue;
        }
        // In (key, index) order, so each group's first is its leader.
        let mut sub: Vec<([i64; 3], usize)> = run
            .iter()
            .map(|&v| {
                let i = (v as u32) as usize;
                (key(i), i)
            })
            .collect();
        sub.sort_unstable();
        for g in sub.chunk_by(|a, b| a.0 == b.0) {
            for &(_, i) in &g[1..] {
                first[i] = g[0].1;
                any = true;
            }
        }
    }
    any.then_some(first)
}

/// [`firsts_by_hash`] for more points than a `u32` indexes: a hash map.
fn firsts_by_map(n: usize, key: impl Fn(usize) -> [i64; 3]) -> Option<Vec<usize>> {
    let mut leader: HashMap<[i64; 3], usize> = HashMap::with_capacity(n);
    let mut any = false;
    let first = (0..n)
        .map(|i| {
            let f = *leader.entry(key(i)).or_insert(i);
            any |= f != i;
            f
        })
        .collect();
    any.then_some(first)
}

/// Points between two progress reports of the normal estimation.
const PROGRESS_STEP: usize = 4096;

/// Normals by PCA (see the module notes), on up to `threads` threads (0: one
/// per core).
pub fn estimate_normals_with(
    points: &[[f64; 3]],
    prm: &NormalParams,
    threads: usize,
) -> Result<(Cloud, NormalStats)> {
    estimate_normals_indexed(points, prm, threads).map(|(c, s, _)| (c, s))
}

/// As [`estimate_normals_with`], with the index in `points` of every point
/// kept (ascending), to carry per-point data such as weights along.
pub fn estimate_normals_indexed(
    points: &[[f64; 3]],
    prm: &NormalParams,
    threads: usize,
) -> Result<(Cloud, NormalStats, Vec<usize>)> {
    estimate_normals_progress(points, prm, threads, &NoProgress)
}

/// `estimate_normals_indexed`, reporting the points done to `progress`.
pub fn estimate_normals_progress(
    points: &[[f64; 3]],
    prm: &NormalParams,
    threads: usize,
    progress: &dyn Progress,
) -> Result<(Cloud, NormalStats, Vec<usize>)> {
    prm.check()?;
    progress.start(points.len() as u64, "normals estimated");
    let r = normals_on_threads(points, prm, threads, progress);
    progress.finish();
    r
}

fn normals_on_threads(
    points: &[[f64; 3]],
    prm: &NormalParams,
    threads: usize,
    progress: &dyn Progress,
) -> Result<(Cloud, NormalStats, Vec<usize>)> {
    if points.is_empty() {
        return Ok((Cloud::default(), NormalStats::default(), Vec::new()));
    }
    // The radius search goes through the grid where it can (the same
    // neighbours, about half the instructions: grid.rs); k nearest, and
    // coordinates the grid cannot index exactly, through the k-d tree.
    let grid = match prm.knn {
        None => Grid::new(points, prm.radius),
        Some(_) => None,
    };
    let tree =
        match grid {
            Some(g) => Index::Grid(g),
            None => Index::Tree(ImmutableKdTree::<f64, 3>::new_from_slice(points).map_err(
                |e| Error::invalid(format!("normal estimation: cannot index the points ({e})")),
            )?),
        };
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let t = if threads == 0 { cores } else { threads };
    let t = t.clamp(1, 64).min(points.len().div_ceil(4096));
    let per = points.len().div_ceil(t.max(1));
    let parts: Vec<(Cloud, NormalStats, Vec<usize>)> = if let (true, Index::Grid(g)) =
        (t <= 1, &tree)
    {
        // One thread: each pair of neighbours found once (grid.rs), the same
        // moments bit for bit as a query per point.
        let m = g.moments_within(prm.radius * prm.radius);
        let normal = |i: usize, p: &[f64; 3]| normal_from(m.of(g, i), p, prm);
        vec![collect_normals((0, points), &normal, progress)]
    } else if t <= 1 {
        vec![estimate_range(&tree, points, (0, points), (prm, progress))]
    } else {
        let tree = &tree;
        std::thread::scope(|s| {
            let chunks: Vec<(usize, &[[f64; 3]])> = points
                .chunks(per)
                .enumerate()
                .map(|(k, c)| (k * per, c))
                .collect();
            let handles: Vec<_> = chunks[1..]
                .iter()
                .map(|c| {
                    let c = *c;
                    std::thread::Builder::new()
                        .spawn_scoped(s, move || estimate_range(tree, points, c, (prm, progress)))
                })
                .collect();
            let mut out = vec![estimate_range(tree, points, chunks[0], (prm, progress))];
            for (h, c) in handles.into_iter().zip(&chunks[1..]) {
                out.push(match h {
                    Ok(h) => h
                        .join()
                        .unwrap_or_else(|_| estimate_range(tree, points, *c, (prm, progress))),
                    Err(_) => estimate_range(tree, points, *c, (prm, progress)),
                });
            }
            out
        })
    };
    let mut cloud = Cloud::default();
    let mut st = NormalStats::default();
    let mut kept = Vec::new();
    for (c, s, k) in parts {
        cloud.points.extend(c.points);
        cloud.normals.extend(c.normals);
        kept.extend(k);
        st.kept += s.kept;
        st.sparse += s.sparse;
        st.not_planar += s.not_planar;
    }
    Ok((cloud, st, kept))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hashed_sort_and_the_map_find_the_same_groups() {
        // Keys with repeats at scattered positions, a key repeated many
        // times, and distinct keys whose 32-bit hashes may collide: both
        // ways give every index its group's first index.
        let mut keys: Vec<[i64; 3]> = (0..5000).map(|i| [i % 977, -(i % 13), 1 << 40]).collect();
        keys.extend((0..300).map(|_| [5, 5, 5]));
        keys.extend((0..2000).map(|i| [i, i * 7, -i]));
        let key = |i: usize| keys[i];
        let a = firsts_by_hash(keys.len(), key).expect("groups");
        let b = firsts_by_map(keys.len(), key).expect("groups");
        assert_eq!(a, b);
        for (i, &f) in a.iter().enumerate() {
            assert!(f <= i && keys[f] == keys[i]);
            assert_eq!(keys[..f].iter().position(|k| *k == keys[i]), None);
        }
        let distinct: Vec<[i64; 3]> = (0..1000).map(|i| [i, 0, 0]).collect();
        assert_eq!(firsts_by_hash(1000, |i| distinct[i]), None);
        assert_eq!(firsts_by_map(1000, |i| distinct[i]), None);
    }

    /// One thread (each neighbour pair once, grid.rs) and several (a query
    /// per point) give the same normals bit for bit.
    #[test]
    fn one_thread_and_several_agree_bit_for_bit() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        // A wall, a floor, a noisy blob and lone points: 12,300, three chunks.
        let mut pts = Vec::new();
        for _ in 0..5000 {
            pts.push([3.0 * rnd(), 2.0 + 0.01 * rnd(), 2.0 * rnd()]);
            pts.push([3.0 * rnd(), 2.0 * rnd(), 0.01 * rnd()]);
        }
        for _ in 0..2000 {
            pts.push([5.0 + rnd(), rnd(), rnd()]);
        }
        // Lone points: too few neighbours.
        for k in 0..300 {
            pts.push([-1.0 - 0.5 * f64::from(k), rnd(), rnd()]);
        }
        let prm = NormalParams {
            radius: 0.2,
            knn: None,
            min_neighbours: 5,
            min_planarity: None,
            viewpoint: [1.0, 1.0, 1.0],
        };
        let bits = |c: &Cloud| -> Vec<u64> {
            c.points
                .iter()
                .chain(&c.normals)
                .flatten()
                .map(|x| x.to_bits())
                .collect()
        };
        let (one, s1, k1) = estimate_normals_indexed(&pts, &prm, 1).unwrap();
        let (three, s3, k3) = estimate_normals_indexed(&pts, &prm, 3).unwrap();
        assert!(s1.kept > 10_000 && s1.sparse > 0, "{s1:?}");
        assert_eq!((s1, &k1), (s3, &k3));
        assert_eq!(bits(&one), bits(&three));
    }

    #[test]
    fn duplicates_merge_within_the_cell_and_keep_the_first_in_order() {
        // Far from the origin: scale 4e6 m, cell 4e6 * 2^-40 (3.6 um).
        let cell = DUPLICATE_POINT_REL_TOL * 4.0e6;
        let c = |k: f64| (1.0e12 + k) * cell; // a cell boundary near 3.6e6 m
        let base = [c(0.5), 4.0e6, 10.0];
        let pts = [
            [1.0, 2.0, 3.0],
            base,
            [c(0.5) + 0.25 * cell, 4.0e6, 10.0], // same cell: merged
            [1.0, 2.0, 3.0],                     // exact copy: merged
            [c(2.5), 4.0e6, 10.0],               // two cells on (7 um): kept
        ];
        let w = [1.0, 2.0, 4.0, 3.0, 5.0];
        let (kept, weights) = merge_duplicates(&pts, Some(&w)).expect("duplicates");
        assert_eq!(kept, [pts[0], pts[1], pts[4]]);
        assert_eq!(weights, Some(vec![2.0, 3.0, 5.0]));
        // No duplicate: nothing copied.
        assert_eq!(merge_duplicates(&[pts[0], pts[1], pts[4]], None), None);
        // Near the origin the cell is 2^-40 m: a picometre apart stays two.
        assert_eq!(merge_duplicates(&[[0.0; 3], [1e-12, 0.0, 0.0]], None), None);
    }
}
