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

use super::cells::{floor_i64, sorted_by_key};
use foldhash::HashMap;

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
        let keyed = sorted_by_key(&keys);
        drop(keys);
        let mut sorted = Vec::with_capacity(points.len());
        // Cell `k` holds `sorted[start[k]..start[k + 1]]`.
        let mut start = Vec::new();
        let mut keys: Vec<[i64; 3]> = Vec::new();
        let mut cell_of = vec![0u32; points.len()];
        for (j, &(key, i)) in keyed.iter().enumerate() {
            if keys.last() != Some(&key) {
                keys.push(key);
                start.push(j as u32);
            }
            cell_of[i] = (keys.len() - 1) as u32;
            sorted.push(points[i]);
        }
        start.push(points.len() as u32);
        drop(keyed);
        let index: HashMap<[i64; 3], u32> = {
            let mut m = HashMap::with_capacity_and_hasher(keys.len(), Default::default());
            for (k, key) in keys.iter().enumerate() {
                m.insert(*key, k as u32);
            }
            m
        };
        let mut runs = Vec::new();
        let mut runs_start = Vec::with_capacity(keys.len() + 1);
        for key in &keys {
            runs_start.push(runs.len() as u32);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    let mut first: Option<u32> = None;
                    let mut last = 0u32;
                    for dz in -1..=1 {
                        let n = [key[0] + dx, key[1] + dy, key[2] + dz];
                        if let Some(&k) = index.get(&n) {
                            first.get_or_insert(k);
                            last = k;
                        }
                    }
                    if let Some(f) = first {
                        runs.push((start[f as usize], start[last as usize + 1]));
                    }
                }
            }
        }
        runs_start.push(runs.len() as u32);
        Some(Grid {
            sorted,
            cell_of,
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
}

/// Candidates tested between two calls of the visitor (fits a `u8` index).
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

    #[test]
    fn far_or_non_finite_points_keep_the_tree() {
        assert!(Grid::new(&[[0.0; 3], [f64::NAN, 0.0, 0.0]], 0.3).is_none());
        assert!(Grid::new(&[[0.0; 3], [f64::INFINITY, 0.0, 0.0]], 0.3).is_none());
        assert!(Grid::new(&[[0.0; 3], [1e12, 0.0, 0.0]], 0.3).is_none());
        assert!(Grid::new(&[], 0.3).is_none());
        assert!(Grid::new(&[[1e9, 0.0, 0.0]], 0.3).is_some());
    }
}
