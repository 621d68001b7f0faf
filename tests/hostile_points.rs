//! Point-file crash inputs found by the `points` fuzz target
//! (fuzz/regressions/points/). `src/points.rs` belongs to another change in
//! flight, so the bug is recorded here, not fixed:
//!
//! A normal whose squared norm overflows (a component above ~1.3e154) is
//! divided by an infinite norm and becomes `[±0, ±0, ±0]`: a zero normal
//! accepted with success (the reader refuses zero normals it reads as zero).
//! Fix: scaled norm in the normal check (divide by the largest |component|
//! first, as `se3::Transform::from_quaternion` does).
//!
//! The non-ignored test guards what holds today (no panic, no hang); the
//! ignored one is the acceptance test for the fix: un-ignore it with the fix.

use extrinsic_audit::points::parse_points;
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
#[ignore = "open: src/points.rs normal check overflows (see module docs); un-ignore with the fix"]
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
