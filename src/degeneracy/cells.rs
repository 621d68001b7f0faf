//! Integer cell keys of points and their order: what the voxel grid
//! (scene.rs), the duplicate grid and the neighbour grid (grid.rs) share.
//!
//! The order is (key x, key y, key z, input index) ascending, so runs of one
//! cell come out in input order and the result is deterministic. When every
//! key range fits 32 bits and there are fewer than 2^32 points (always, for
//! a LiDAR scan: 2^32 cells of 1 mm is 4,300 km), the four numbers are packed
//! into one `u128` whose order is theirs, and sorted as plain integers:
//! about a third of the instructions of sorting the tuples. When the key
//! spans and the index fit 64 bits together (a scan's voxel and neighbour
//! cells: about 40 bits), the packing is a `u64`, sorted by an LSD radix sort
//! on the key's bits alone: the values start in index order and an LSD radix
//! sort is stable, so equal keys stay in index order without sorting the
//! index bits (a scan's voxel keys: 23 bits, two passes instead of five).
//! Consecutive points with one key (a spinning LiDAR's neighbouring returns)
//! are sorted as one value, their indices expanded afterwards.

/// `x.floor() as i64`, without the libm call `floor` is on x86-64 without
/// SSE4.1 (this was 4 % of a run's instructions). Same results for every
/// `f64`: NaN gives 0, values beyond the `i64` range saturate.
#[inline]
pub(crate) fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// The indices of some keys in (key, index) order (see the module notes)
/// and where each run of one key starts in it.
pub(crate) struct KeyRuns {
    /// Indices of the keys, in (key, index) order.
    pub(crate) order: Vec<usize>,
    /// Run `k` (one key) is `order[starts[k]..starts[k + 1]]`; the last
    /// entry is the number of keys.
    pub(crate) starts: Vec<usize>,
}

impl KeyRuns {
    /// The runs: each a slice of indices holding one key.
    pub(crate) fn runs(&self) -> impl Iterator<Item = &[usize]> + '_ {
        self.starts.windows(2).map(|w| &self.order[w[0]..w[1]])
    }
}

/// The indices of `keys` in (key, index) order and their runs of one key
/// (see the module notes).
pub(crate) fn order_by_key(keys: &[[i64; 3]]) -> KeyRuns {
    let n = keys.len();
    let mut lo = [i64::MAX; 3];
    let mut hi = [i64::MIN; 3];
    for k in keys {
        for a in 0..3 {
            lo[a] = lo[a].min(k[a]);
            hi[a] = hi[a].max(k[a]);
        }
    }
    if n == 0 {
        return KeyRuns {
            order: Vec::new(),
            starts: vec![0],
        };
    }
    let span = |a: usize| (hi[a] as i128 - lo[a] as i128) as u128;
    // Bits for 0..=v.
    let width = |v: u128| 128 - v.leading_zeros();
    let (bx, by, bz) = (width(span(0)), width(span(1)), width(span(2)));
    let o = |k: &[i64; 3], a: usize| (k[a] as i128 - lo[a] as i128) as u128;
    // Stretches of consecutive equal keys (a spinning LiDAR's neighbouring
    // returns share a voxel: about five per stretch on the bench scans) are
    // sorted as one value: their indices are consecutive, so expanding the
    // sorted stretches gives the (key, index) order.
    // A plain loop: `extend` of a filter pushed one at a time, with a
    // capacity check each (31 instructions a key).
    let mut firsts: Vec<usize> = Vec::with_capacity(n + 1);
    firsts.push(0);
    for (i, w) in keys.windows(2).enumerate() {
        if w[1] != w[0] {
            firsts.push(i + 1);
        }
    }
    let bi = width((firsts.len() - 1) as u128);
    if bx + by + bz + bi <= 64 {
        // A scan's voxel or neighbour cells (e.g. 200 m x 4 m x 3 m at
        // 0.1 m, 130k points: at most 39 bits): one u64 per stretch,
        // radix-sorted on the key's bits alone (the stretch numbers are
        // already in order).
        let mut packed: Vec<u64> = firsts
            .iter()
            .enumerate()
            .map(|(r, &i)| {
                let k = &keys[i];
                let cell = (o(k, 0) << (by + bz)) | (o(k, 1) << bz) | o(k, 2);
                ((cell << bi) | r as u128) as u64
            })
            .collect();
        radix_sort(&mut packed, bi, bx + by + bz);
        firsts.push(n);
        let mask = (1u64 << bi) - 1;
        let mut order = Vec::with_capacity(n);
        let mut starts = Vec::with_capacity(packed.len() + 1);
        for (j, &v) in packed.iter().enumerate() {
            if j == 0 || v >> bi != packed[j - 1] >> bi {
                starts.push(order.len());
            }
            let r = (v & mask) as usize;
            order.extend(firsts[r]..firsts[r + 1]);
        }
        starts.push(n);
        return KeyRuns { order, starts };
    }
    drop(firsts);
    let fits = n <= u32::MAX as usize && (0..3).all(|a| span(a) <= u32::MAX as u128);
    let order: Vec<usize> = if fits {
        let mut packed: Vec<u128> = keys
            .iter()
            .enumerate()
            .map(|(i, k)| (o(k, 0) << 96) | (o(k, 1) << 64) | (o(k, 2) << 32) | i as u128)
            .collect();
        packed.sort_unstable();
        packed.iter().map(|&v| (v as u32) as usize).collect()
    } else {
        let mut keyed: Vec<([i64; 3], usize)> =
            keys.iter().enumerate().map(|(i, k)| (*k, i)).collect();
        keyed.sort_unstable();
        keyed.into_iter().map(|(_, i)| i).collect()
    };
    let starts = run_starts(n, |j| keys[order[j]] == keys[order[j - 1]]);
    KeyRuns { order, starts }
}

/// Where runs start among `n` sorted values (and `n`), `same(j)` telling
/// whether value `j` has the key of value `j - 1`.
fn run_starts(n: usize, same: impl Fn(usize) -> bool) -> Vec<usize> {
    let mut starts = Vec::with_capacity(n / 4 + 2);
    starts.push(0);
    starts.extend((1..n).filter(|&j| !same(j)));
    starts.push(n);
    starts
}

/// Sorts `v` by its bits `low..low + bits` (the bits above are zero),
/// stably: least significant digit first, passes of at most `MAX_DIGIT`
/// bits (as few as the bits need), a pass skipped when every value has the
/// same digit there; below `RADIX_MIN` values, the standard library's sort
/// of the whole values (the same order when `v` starts sorted by its bits
/// below `low`, as the packed keys do).
fn radix_sort(v: &mut Vec<u64>, low: u32, bits: u32) {
    const RADIX_MIN: usize = 512;
    // 2^12 counters (32 KiB) stay in the first-level cache; a scan's 22 to
    // 24 bits of voxel key are two passes.
    const MAX_DIGIT: u32 = 12;
    if v.len() < RADIX_MIN {
        v.sort_unstable();
        return;
    }
    let passes = bits.div_ceil(MAX_DIGIT).max(1);
    let digit = bits.div_ceil(passes).max(1);
    let mask = (1u64 << digit) - 1;
    let mut other = vec![0u64; v.len()];
    let mut count = vec![0usize; 1 << digit];
    let mut shift = low;
    while shift < low + bits {
        count.fill(0);
        for &x in v.iter() {
            count[((x >> shift) & mask) as usize] += 1;
        }
        if count.contains(&v.len()) {
            shift += digit;
            continue;
        }
        let mut at = 0;
        for c in count.iter_mut() {
            let k = *c;
            *c = at;
            at += k;
        }
        for &x in v.iter() {
            let d = ((x >> shift) & mask) as usize;
            other[count[d]] = x;
            count[d] += 1;
        }
        std::mem::swap(v, &mut other);
        shift += digit;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_i64_is_floor_as_i64_everywhere() {
        let mut xs = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.5,
            -2.5,
            1e-300,
            -1e-300,
            4503599627370495.5,
            -4503599627370495.5,
            9007199254740993.0,
            9.2e18,
            -9.2e18,
            9.3e18,
            -9.3e18,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            i64::MAX as f64,
            i64::MIN as f64,
        ];
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..10_000 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            xs.push(f64::from_bits(s));
            xs.push((s >> 11) as f64 / 1024.0 - 4e12);
        }
        for x in xs {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x:e}");
        }
    }

    #[test]
    fn packed_and_tuple_orders_agree() {
        let keys: Vec<[i64; 3]> = (0..500)
            .map(|i: i64| [(i * 7919) % 13 - 6, (i * 104729) % 5, -(i % 3)])
            .collect();
        let mut want: Vec<([i64; 3], usize)> =
            keys.iter().enumerate().map(|(i, k)| (*k, i)).collect();
        want.sort_unstable();
        let want: Vec<usize> = want.into_iter().map(|(_, i)| i).collect();
        assert_eq!(order_by_key(&keys).order, want);
        // A range past 32 bits takes the tuple sort, with the same order.
        let mut wide = keys.clone();
        wide.push([i64::MIN, 0, i64::MAX]);
        wide.push([i64::MAX, 0, i64::MIN]);
        let mut want: Vec<([i64; 3], usize)> =
            wide.iter().enumerate().map(|(i, k)| (*k, i)).collect();
        want.sort_unstable();
        let want: Vec<usize> = want.into_iter().map(|(_, i)| i).collect();
        assert_eq!(order_by_key(&wide).order, want);
        assert!(order_by_key(&[]).order.is_empty());
    }

    /// The three packings (u64 radix-sorted, u128, tuples) give the tuple
    /// order: many keys (past the radix threshold) with repeats, spans that
    /// need 64 bits or more in total.
    #[test]
    fn radix_packing_gives_the_tuple_order() {
        let tuple_order = |keys: &[[i64; 3]]| {
            let mut w: Vec<([i64; 3], usize)> =
                keys.iter().enumerate().map(|(i, k)| (*k, i)).collect();
            w.sort_unstable();
            w.into_iter().map(|(_, i)| i).collect::<Vec<usize>>()
        };
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = |m: i64| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % m as u64) as i64
        };
        // 39 bits (radix), a span of 2^20 on x (48 bits: radix), 2^31 on
        // every axis (u128), and the small case (std sort).
        for (span, n) in [(2000, 20_000), (1 << 20, 5000), (1 << 31, 3000), (7, 100)] {
            let mut keys: Vec<[i64; 3]> = (0..n)
                .map(|_| [rnd(span) - span / 2, rnd(40) - 20, -rnd(30)])
                .collect();
            // Stretches of one key, of 1 to 12 points, as a ring's returns.
            let mut i = 0;
            while i < keys.len() {
                let len = 1 + rnd(12) as usize;
                let k = keys[i];
                for x in keys.iter_mut().skip(i).take(len) {
                    *x = k;
                }
                i += len;
            }
            keys.extend_from_within(..n / 3);
            let got = order_by_key(&keys);
            assert_eq!(got.order, tuple_order(&keys), "span {span}");
            // Every run holds one key, and consecutive runs differ.
            for run in got.runs() {
                assert!(!run.is_empty() && run.iter().all(|&i| keys[i] == keys[run[0]]));
            }
            let firsts: Vec<[i64; 3]> = got.runs().map(|r| keys[r[0]]).collect();
            assert!(firsts.windows(2).all(|w| w[0] < w[1]), "span {span}");
            assert_eq!(got.starts.last(), Some(&keys.len()));
        }
        let mut v: Vec<u64> = (0..5000u64).map(|i| (i * 2_654_435_761) % 65_536).collect();
        let mut want = v.clone();
        want.sort_unstable();
        radix_sort(&mut v, 0, 16);
        assert_eq!(v, want);
    }
}
