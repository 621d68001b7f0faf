//! Fixed-radius neighbour search on a uniform grid, for normal estimation.
//!
//! Every query of the normal estimation has the same radius `r`, so a grid of
//! cubic cells of side `c >= r` finds a point's neighbours in the 27 cells
//! around its own: `|q_x - p_x| <= r <= c` puts `q`'s cell index within one
//! of `p`'s on every axis. This is what a k-d tree radius query returns (the
//! same set: squared distance `<= r^2`, computed in the same x, y, z order),
//! for about half the instructions on a LiDAR scan (the tree's backtracking
//! is what a fixed radius does not need).
//!
//! `c = r (1 + CELL_MARGIN)`: a cell index is `floor(x / c)` in floating
//! point, off by at most a few units in the last place of `x / c`; the margin
//! keeps a neighbour at distance exactly `r` within one cell as long as
//! `|x| / c < MAX_CELL_INDEX`. Beyond that (or with a non-finite coordinate)
//! [`Grid::new`] returns `None` and the caller keeps the k-d tree.
//!
//! Points are visited in a fixed order (neighbour cells in x, y, z order,
//! points within a cell in input order), so the result does not depend on
//! threads.

use super::cells::{floor_i64, order_by_key};

/// Relative widening of a cell over the search radius (see the module notes).
const CELL_MARGIN: f64 = 1e-3;

/// Largest `|x| / c` the grid accepts: `2^40` cells, where the rounding of
/// `x / c` (about `2^40 * 2^-52 = 2^-12` of a cell) stays far inside the
/// margin (`1e-3` of a cell), and the index fits an `i64` exactly.
const MAX_CELL_INDEX: f64 = (1u64 << 40) as f64;

/// Points sorted by cell, and each cell's neighbour cells.
pub(crate) struct Grid {
    /// The points, sorted by cell (stable: input order within a cell).
    sorted: Vec<[f64; 3]>,
    /// For each input point, its cell.
    cell_of: Vec<u32>,
    /// For each input point, its place in `sorted`.
    at: Vec<u32>,
    /// Cell `k` holds `sorted[cell_start[k]..cell_start[k + 1]]`.
    cell_start: Vec<u32>,
    /// Cell `k`'s occupied neighbour cells (itself included) as at most
    /// nine runs of `sorted`, one per `(dx, dy)` in x, y order:
    /// `runs[runs_start[k]..runs_start[k + 1]]`. The cells `(x + dx, y + dy,
    /// z - 1..=z + 1)` that are occupied are consecutive in the (x, y, z)
    /// order of `sorted`, so each column of three is one contiguous run.
    runs: Vec<(u32, u32)>,
    runs_start: Vec<u32>,
}

impl Grid {
    /// The grid of `points` for radius `radius`; `None` when a coordinate is
    /// not finite or too far from the origin for exact cells, or there are
    /// more points than a `u32` indexes (the caller keeps the k-d tree then).
    pub(crate) fn new(points: &[[f64; 3]], radius: f64) -> Option<Grid> {
        if points.is_empty()
            || points.len() >= u32::MAX as usize
            || radius.is_nan()
            || radius <= 0.0
        {
            return None;
        }
        let cell = radius * (1.0 + CELL_MARGIN);
        if !cell.is_finite() {
            return None;
        }
        let mut keys: Vec<[i64; 3]> = Vec::with_capacity(points.len());
        for p in points {
            let mut key = [0i64; 3];
            for k in 0..3 {
                let c = p[k] / cell;
                if c.is_nan() || c.abs() >= MAX_CELL_INDEX {
                    return None;
                }
                key[k] = floor_i64(c);
            }
            keys.push(key);
        }
        // (key, index) order keeps input order within a cell.
        let order = order_by_key(&keys);
        let mut sorted = Vec::with_capacity(points.len());
        let mut cell_of = vec![0u32; points.len()];
        let mut at = vec![0u32; points.len()];
        // Cell `k` holds `sorted[start[k]..start[k + 1]]`; its key `cells[k]`.
        let start: Vec<u32> = order.starts.iter().map(|&j| j as u32).collect();
        let mut cells: Vec<[i64; 3]> = Vec::with_capacity(start.len() - 1);
        for (k, run) in order.runs().enumerate() {
            cells.push(keys[run[0]]);
            for &i in run {
                cell_of[i] = k as u32;
                at[i] = sorted.len() as u32;
                sorted.push(points[i]);
            }
        }
        drop(keys);
        let (runs, runs_start) = neighbour_runs(&cells, &start);
        Some(Grid {
            sorted,
            cell_of,
            at,
            cell_start: start,
            runs,
            runs_start,
        })
    }

    /// Calls `f` with every point within `radius` of `points[i]` (squared
    /// distance `<= r2`, itself included), `points` being the slice the grid
    /// was built from.
    #[inline]
    pub(crate) fn visit_within(
        &self,
        i: usize,
        p: &[f64; 3],
        r2: f64,
        mut f: impl FnMut([f64; 3]),
    ) {
        let c = self.cell_of[i] as usize;
        let runs = &self.runs[self.runs_start[c] as usize..self.runs_start[c + 1] as usize];
        // Candidates a block at a time: the distance test writes the block's
        // hits without a branch (about a third of a LiDAR neighbourhood's
        // candidates are hits, in no pattern a branch predictor learns),
        // then `f` gets them in order.
        let mut hit = [0u8; BLOCK];
        for &(a, b) in runs {
            for block in self.sorted[a as usize..b as usize].chunks(BLOCK) {
                let mut n = 0;
                for (j, q) in block.iter().enumerate() {
                    let dx = q[0] - p[0];
                    let dy = q[1] - p[1];
                    let dz = q[2] - p[2];
                    hit[n] = j as u8;
                    n += usize::from(dx * dx + dy * dy + dz * dz <= r2);
                }
                for &j in &hit[..n] {
                    f(block[j as usize]);
                }
            }
        }
    }

    /// Every point's neighbourhood moments ([`Moments`]): each pair of
    /// neighbours found once, from the one first in `sorted`, and added to
    /// both. A query per point visits its neighbours in `sorted` order (the
    /// runs are in that order); here the pairs of a point come in the same
    /// order (those with points before it while they are visited, then its
    /// own in the order of its runs), and the terms are the same numbers
    /// (`a - b` is exactly `-(b - a)`, the products of two negated offsets
    /// are the products of the offsets), so the sums are the same bit for
    /// bit, for about half the distance tests.
    pub(crate) fn moments_within(&self, r2: f64) -> Moments {
        let n = self.sorted.len();
        let mut count = vec![0u32; n];
        let mut acc = vec![[0.0f64; 9]; n];
        let mut hit = [0u8; BLOCK];
        for c in 0..self.cell_start.len() - 1 {
            let runs = &self.runs[self.runs_start[c] as usize..self.runs_start[c + 1] as usize];
            for a in self.cell_start[c] as usize..self.cell_start[c + 1] as usize {
                let p = self.sorted[a];
                // The terms of the points before `a` are in; itself adds
                // one to the count and zeros (no change) to the sums.
                let mut own = acc[a];
                let mut own_count = count[a] + 1;
                for &(lo, hi) in runs {
                    let lo = (lo as usize).max(a + 1);
                    let hi = hi as usize;
                    if lo >= hi {
                        continue;
                    }
                    // The run's points with their moments and counts, a
                    // block at a time (`a < lo`: `own` is not among them).
                    let blocks = self.sorted[lo..hi]
                        .chunks(BLOCK)
                        .zip(acc[lo..hi].chunks_mut(BLOCK))
                        .zip(count[lo..hi].chunks_mut(BLOCK));
                    for ((block, accs), counts) in blocks {
                        let mut m = 0;
                        for (j, q) in block.iter().enumerate() {
                            let dx = q[0] - p[0];
                            let dy = q[1] - p[1];
                            let dz = q[2] - p[2];
                            // m <= j < BLOCK: the mask only spares a check.
                            hit[m & (BLOCK - 1)] = j as u8;
                            m += usize::from(dx * dx + dy * dy + dz * dz <= r2);
                        }
                        for &j in &hit[..m] {
                            let j = j as usize;
                            let q = block[j];
                            let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
                            let t = crate::degeneracy::sym3::outer(d);
                            let other = &mut accs[j];
                            for k in 0..3 {
                                own[k] += d[k];
                                other[k] -= d[k];
                            }
                            for k in 0..6 {
                                own[3 + k] += t[k];
                                other[3 + k] += t[k];
                            }
                            counts[j] += 1;
                            own_count += 1;
                        }
                    }
                }
                acc[a] = own;
                count[a] = own_count;
            }
        }
        Moments { count, acc }
    }
}

/// Every point's neighbourhood moments, by place in the grid's `sorted`:
/// count, then the sum of the offsets from the point (x, y, z) and of their
/// outer products (xx, xy, xz, yy, yz, zz), as `normals.rs` accumulates them.
pub(crate) struct Moments {
    count: Vec<u32>,
    acc: Vec<[f64; 9]>,
}

impl Moments {
    /// The moments of input point `i` of the grid `g` they were made from.
    pub(crate) fn of(&self, g: &Grid, i: usize) -> (usize, [f64; 3], [f64; 6]) {
        let s = g.at[i] as usize;
        let a = &self.acc[s];
        (
            self.count[s] as usize,
            [a[0], a[1], a[2]],
            [a[3], a[4], a[5], a[6], a[7], a[8]],
        )
    }
}

/// Each cell's occupied neighbour cells as runs of the sorted points (see
/// [`Grid::runs`]), from the cells' keys in (x, y, z) order and where each
/// starts. Translating every key by one `(dx, dy, -1)` keeps their order, so
/// one cursor per `(dx, dy)` walks the keys once (a merge, no hash map):
/// the first key at or after `(x + dx, y + dy, z - 1)` is where that
/// column's run starts, the keys up to `(x + dx, y + dy, z + 1)` are in it.
fn neighbour_runs(cells: &[[i64; 3]], start: &[u32]) -> (Vec<(u32, u32)>, Vec<u32>) {
    // Keys packed into one u64 when they fit (a scan's do: about 20 bits):
    // one comparison each instead of three. Each axis is offset so that its
    // smallest key is 1: a neighbour's -1 and +1 stay inside the axis's
    // field, so translating the packed value translates every field alone
    // and the packed order stays the keys' order.
    let mut lo = cells.first().copied().unwrap_or_default();
    let mut hi = lo;
    for k in cells {
        for a in 0..3 {
            lo[a] = lo[a].min(k[a]);
            hi[a] = hi[a].max(k[a]);
        }
    }
    // Bits for 0..=span + 2 (keys are within 2^40 of 0: no overflow).
    let w: [u32; 3] = std::array::from_fn(|a| 64 - ((hi[a] - lo[a] + 2) as u64).leading_zeros());
    if w.iter().sum::<u32>() > 63 {
        return merge_runs(cells, start, |k, [dx, dy, dz]| {
            [k[0] + dx, k[1] + dy, k[2] + dz]
        });
    }
    let (sy, sx) = (w[2], w[1] + w[2]);
    let packed: Vec<u64> = cells
        .iter()
        .map(|k| {
            let f = |a: usize| (k[a] - lo[a] + 1) as u64;
            (f(0) << sx) | (f(1) << sy) | f(2)
        })
        .collect();
    merge_runs(&packed, start, |v, [dx, dy, dz]| {
        v.wrapping_add_signed((dx << sx) + (dy << sy) + dz)
    })
}

/// [`neighbour_runs`] over keys of any ordered kind, `at(k, d)` the key
/// of the cell at offset `d` from `k`'s (see there).
fn merge_runs<K: Ord + Copy>(
    cells: &[K],
    start: &[u32],
    at: impl Fn(&K, [i64; 3]) -> K,
) -> (Vec<(u32, u32)>, Vec<u32>) {
    let mut cursor = [0usize; 9];
    let mut runs = Vec::with_capacity(cells.len() * 9);
    let mut runs_start = Vec::with_capacity(cells.len() + 1);
    for key in cells {
        runs_start.push(runs.len() as u32);
        let mut m = 0;
        for dx in -1..=1 {
            for dy in -1..=1 {
                let lo = at(key, [dx, dy, -1]);
                let hi = at(key, [dx, dy, 1]);
                let c = &mut cursor[m];
                while *c < cells.len() && cells[*c] < lo {
                    *c += 1;
                }
                let mut end = *c;
                while end < cells.len() && cells[end] <= hi {
                    end += 1;
                }
                if end > *c {
                    runs.push((start[*c], start[end]));
                }
                m += 1;
            }
        }
    }
    runs_start.push(runs.len() as u32);
    (runs, runs_start)
}

/// Candidates tested between two calls of the visitor (fits a `u8` index;
/// a power of two: an index masked by `BLOCK - 1` is itself).
const BLOCK: usize = 64;

#[cfg(test)]
mod tests {
    use super::*;
    use kiddo::{ImmutableKdTree, SquaredEuclidean};

    /// A deterministic cloud: a jittered plane, a line and a blob, some points
    /// on cell boundaries and at exactly the radius from another.
    fn cloud() -> Vec<[f64; 3]> {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut v = Vec::new();
        for _ in 0..3000 {
            v.push([4.0 * rnd() - 2.0, 4.0 * rnd() - 2.0, 0.01 * rnd()]);
        }
        for k in 0..200 {
            v.push([0.3 * k as f64, 1.0, 0.5]); // spaced exactly by the radius
        }
        for _ in 0..500 {
            v.push([rnd() - 3.0, rnd(), rnd()]);
        }
        v
    }

    fn tree_set(tree: &ImmutableKdTree<f64, 3>, p: &[f64; 3], r2: f64) -> Vec<u64> {
        let mut v: Vec<u64> = Vec::new();
        tree.query(p)
            .within::<SquaredEuclidean<f64>>(r2)
            .unsorted()
            .with_points()
            .visit(|q| v.push(bits(&[q.point[0], q.point[1], q.point[2]])));
        v.sort_unstable();
        v
    }

    fn bits(q: &[f64; 3]) -> u64 {
        q[0].to_bits() ^ q[1].to_bits().rotate_left(21) ^ q[2].to_bits().rotate_left(42)
    }

    #[test]
    fn the_grid_finds_what_the_tree_finds() {
        for offset in [0.0, 1e6] {
            let pts: Vec<[f64; 3]> = cloud()
                .iter()
                .map(|p| [p[0] + offset, p[1] - offset, p[2]])
                .collect();
            let tree = ImmutableKdTree::<f64, 3>::new_from_slice(&pts).unwrap();
            for r in [0.3, 0.05, 1.0] {
                let g = Grid::new(&pts, r).unwrap();
                let r2 = r * r;
                for (i, p) in pts.iter().enumerate().step_by(7) {
                    let mut got = Vec::new();
                    g.visit_within(i, p, r2, |q| got.push(bits(&q)));
                    got.sort_unstable();
                    assert_eq!(
                        got,
                        tree_set(&tree, p, r2),
                        "point {i}, r {r}, offset {offset}"
                    );
                }
            }
        }
    }

    /// A lattice spaced by half the radius puts points on cell faces and
    /// corners and at exactly `r` from each other; points a hair inside and
    /// outside `r` test the margin.
    #[test]
    fn lattice_points_at_the_radius_are_found() {
        for (r, offset) in [(0.3, 0.0), (0.3, -1e6), (0.25, 3e5), (1.0, 0.0)] {
            let h = r / 2.0;
            let mut pts = Vec::new();
            for i in -4..=4 {
                for j in -4..=4 {
                    for k in -3..=3 {
                        pts.push([offset + i as f64 * h, j as f64 * h, k as f64 * h]);
                    }
                }
            }
            // Points a hair inside and outside `r` of the lattice's centre.
            for s in [1.0 - 1e-12, 1.0, 1.0 + 1e-12] {
                let d = r * s / 3f64.sqrt();
                pts.push([offset + d, d, d]);
                pts.push([offset - r * s, 0.0, 0.0]);
            }
            let tree = ImmutableKdTree::<f64, 3>::new_from_slice(&pts).unwrap();
            let g = Grid::new(&pts, r).unwrap();
            let r2 = r * r;
            for (i, p) in pts.iter().enumerate() {
                let mut got = Vec::new();
                g.visit_within(i, p, r2, |q| got.push(bits(&q)));
                got.sort_unstable();
                assert_eq!(got, tree_set(&tree, p, r2), "point {i}, r {r}");
            }
        }
    }

    /// Count, offset sum and outer-product sum of one query, as normals.rs
    /// accumulates them.
    fn query_moments(g: &Grid, i: usize, p: &[f64; 3], r2: f64) -> (usize, [f64; 3], [f64; 6]) {
        let (mut n, mut sum, mut sxx) = (0usize, [0.0f64; 3], [0.0f64; 6]);
        g.visit_within(i, p, r2, |q| {
            let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            n += 1;
            for k in 0..3 {
                sum[k] += d[k];
            }
            for (s, t) in sxx.iter_mut().zip(crate::degeneracy::sym3::outer(d)) {
                *s += t;
            }
        });
        (n, sum, sxx)
    }

    #[test]
    fn pairwise_moments_are_the_queries_bit_for_bit() {
        let bits_of =
            |(n, s, x): (usize, [f64; 3], [f64; 6])| (n, s.map(f64::to_bits), x.map(f64::to_bits));
        for offset in [0.0, 1e6] {
            let pts: Vec<[f64; 3]> = cloud()
                .iter()
                .map(|p| [p[0] + offset, p[1] - offset, p[2]])
                .collect();
            for r in [0.3, 0.05, 1.0] {
                let g = Grid::new(&pts, r).unwrap();
                let r2 = r * r;
                let m = g.moments_within(r2);
                for (i, p) in pts.iter().enumerate() {
                    assert_eq!(
                        bits_of(m.of(&g, i)),
                        bits_of(query_moments(&g, i, p, r2)),
                        "point {i}, r {r}, offset {offset}"
                    );
                }
            }
        }
    }

    /// Clusters at the corners of a cube 2e8 m across: keys past 63 bits
    /// in all, so the neighbour runs merge the keys unpacked.
    #[test]
    fn keys_too_wide_to_pack_find_the_same_neighbours() {
        let base = cloud();
        let mut pts = Vec::new();
        for corner in 0..8 {
            let at = |b: usize| if corner >> b & 1 == 1 { 1e8 } else { -1e8 };
            let c = [at(0), at(1), at(2)];
            pts.extend(
                base[..400]
                    .iter()
                    .map(|p| [c[0] + p[0], c[1] + p[1], c[2] + p[2]]),
            );
        }
        let tree = ImmutableKdTree::<f64, 3>::new_from_slice(&pts).unwrap();
        let g = Grid::new(&pts, 0.3).unwrap();
        for (i, p) in pts.iter().enumerate().step_by(5) {
            let mut got = Vec::new();
            g.visit_within(i, p, 0.09, |q| got.push(bits(&q)));
            got.sort_unstable();
            assert_eq!(got, tree_set(&tree, p, 0.09), "point {i}");
        }
    }

    #[test]
    fn far_or_non_finite_points_keep_the_tree() {
        assert!(Grid::new(&[[0.0; 3], [f64::NAN, 0.0, 0.0]], 0.3).is_none());
        assert!(Grid::new(&[[0.0; 3], [f64::INFINITY, 0.0, 0.0]], 0.3).is_none());
        assert!(Grid::new(&[[0.0; 3], [1e12, 0.0, 0.0]], 0.3).is_none());
        assert!(Grid::new(&[], 0.3).is_none());
        assert!(Grid::new(&[[1e9, 0.0, 0.0]], 0.3).is_some());
    }
}
