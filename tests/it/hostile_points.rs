//! Point-file inputs found by the `points` fuzz target
//! (fuzz/regressions/points/). The bug: a normal whose squared norm overflowed
//! (a component above ~1.3e154) was divided by an infinite norm and became
//! `[±0, ±0, ±0]`, a zero normal accepted with success. Fixed in `src/points.rs`
//! with a scaled norm; coordinates beyond `MAX_COORDINATE` are refused
//! (tests/points_regressions.rs checks the messages).

use extrinsic_audit::internals::degeneracy::points::parse_points;
use std::time::{Duration, Instant};

fn regressions() -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<_> = std::fs::read_dir("fuzz/regressions/points")
        .expect("fuzz/regressions/points")
        .map(|e| {
            let p = e.unwrap().path();
            (p.display().to_string(), std::fs::read(&p).unwrap())
        })
        .collect();
    v.sort();
    assert!(v.len() >= 4);
    v
}

#[test]
fn point_regressions_do_not_panic_or_hang() {
    for (name, bytes) in regressions() {
        let t = Instant::now();
        let _ = parse_points(&bytes);
        assert!(t.elapsed() < Duration::from_secs(5), "{name}");
    }
}

#[test]
fn point_regressions_never_yield_a_zero_or_non_unit_normal() {
    for (name, bytes) in regressions() {
        if let Ok(p) = parse_points(&bytes) {
            for (q, n) in p.points.iter().zip(&p.normals) {
                assert!(q.iter().all(|x| x.is_finite()), "{name}: point {q:?}");
                let norm = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                assert!((norm - 1.0).abs() < 1e-6, "{name}: normal {n:?} accepted");
            }
        }
    }
}
