#![no_main]
//! Point files (CSV, PLY ascii/binary, PCD ascii/binary) through the public
//! in-memory reader. On success every point and normal is finite, normals unit.
//! The same bytes as a raw scan (`parse_xyz`: normals not required; LAS and
//! LAZ read): on success every point is finite.
use extrinsic_audit::internals::degeneracy::points::{parse_points, parse_xyz};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(p) = parse_xyz(data) {
        assert_eq!(
            p.points.len(),
            p.normals.len(),
            "points and normals differ in count"
        );
        assert!(
            p.points.iter().flatten().all(|x| x.is_finite()),
            "non-finite point"
        );
    }
    if let Ok(p) = parse_points(data) {
        assert_eq!(
            p.points.len(),
            p.normals.len(),
            "points and normals differ in count"
        );
        if let Some(w) = &p.weights {
            assert_eq!(
                w.len(),
                p.points.len(),
                "weights and points differ in count"
            );
            assert!(
                w.iter().all(|x| x.is_finite() && *x >= 0.0),
                "bad weight accepted"
            );
        }
        for (q, n) in p.points.iter().zip(&p.normals) {
            assert!(q.iter().all(|x| x.is_finite()), "non-finite point {q:?}");
            let norm = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((norm - 1.0).abs() < 1e-6, "normal {n:?} not unit");
        }
    }
});
