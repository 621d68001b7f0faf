//! Detector on real-world coordinates and real scans (issue 16): exact
//! assembly anywhere (centroid reference), relative footprint and screw
//! classification, raw scans with estimated normals.

use extrinsic_audit::degeneracy::scene::{synthesize, Preprocess, SceneKind};
use extrinsic_audit::degeneracy::*;
use extrinsic_audit::tolerances::DEFAULT_TAU;

/// A noisy corridor with PCA normals (a real-looking cloud of a few thousand
/// points), offset by `shift`.
fn corridor(shift: [f64; 3]) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let c = synthesize(SceneKind::Corridor, &Preprocess::pipeline(0.1, 0.01, 3)).unwrap();
    let p = c
        .points
        .iter()
        .map(|p| [p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]])
        .collect();
    (p, c.normals)
}

fn pd_values(p: &[[f64; 3]], n: &[[f64; 3]]) -> [f64; 6] {
    let asm = Assembly::from_points(p, n, None).unwrap();
    analyse(&asm, &MetricRule::PointDisplacement, DEFAULT_TAU)
        .unwrap()
        .eig
        .values
}

#[test]
fn a_cloud_shifted_by_1e6_m_keeps_its_point_displacement_eigenvalues() {
    let (p0, n) = corridor([0.0; 3]);
    let base = pd_values(&p0, &n);
    for shift in [[1e6, 0.0, 0.0], [1e6, -1e6, 1e6], [3e5, 4.5e6, 12.0]] {
        let (p, _) = corridor(shift);
        let v = pd_values(&p, &n);
        for k in 0..6 {
            let rel = (v[k] - base[k]).abs() / base[k].abs().max(base[5] * 1e-6);
            assert!(
                rel < 1e-9,
                "shift {shift:?}, eigenvalue {k}: {} vs {}",
                v[k],
                base[k]
            );
        }
    }
}

#[test]
fn the_centroid_pair_transports_to_the_per_point_sums() {
    // H = B hc B^T, with the centroid the weighted mean of the points.
    let (p, n) = corridor([12.0, -7.0, 3.0]);
    let asm = Assembly::from_points(&p, &n, None).unwrap();
    let w = p.len() as f64;
    let c: Vec<f64> = (0..3)
        .map(|k| p.iter().map(|q| q[k]).sum::<f64>() / w)
        .collect();
    for k in 0..3 {
        assert!(
            (asm.center[k] - c[k]).abs() < 1e-12 * 20.0,
            "{:?} vs {c:?}",
            asm.center
        );
    }
    // The centroid frame is T = (I, c): hc = A^T H A with A = Ad(T).
    let a = asm.center_adjoint();
    let hc = a.transpose() * asm.h * a;
    let mc = a.transpose() * asm.m * a;
    assert!(rel_diff(&asm.hc, &hc) < 1e-12, "{}", rel_diff(&asm.hc, &hc));
    assert!(rel_diff(&asm.mc, &mc) < 1e-12, "{}", rel_diff(&asm.mc, &mc));
    // About the centroid the translation-rotation coupling of M vanishes.
    assert!(asm.mc.fixed_view::<3, 3>(0, 3).amax() == 0.0);
}

#[test]
fn collinearity_is_refused_at_any_offset_and_scale_and_only_then() {
    let line = |o: f64, s: f64| -> Vec<[f64; 3]> {
        (0..200)
            .map(|i| [o + s * i as f64, o + 2.0 * s * i as f64, o])
            .collect()
    };
    let normals = vec![[0.0, 0.0, 1.0]; 200];
    for (o, s) in [(0.0, 1.0), (1e6, 1.0), (1e8, 1e-3), (-4e6, 1e3)] {
        let asm = Assembly::from_points(&line(o, s), &normals, None).unwrap();
        let e = analyse(&asm, &MetricRule::PointDisplacement, DEFAULT_TAU).unwrap_err();
        assert!(e.message.contains("collinear"), "{}", e.message);
    }
    // A plane at 1e6 m is not collinear (main refused it as collinear).
    let plane: Vec<[f64; 3]> = (0..400)
        .map(|i| {
            [
                1e6 + (i % 20) as f64 * 0.1,
                1e6 + (i / 20) as f64 * 0.1,
                1e6,
            ]
        })
        .collect();
    let asm = Assembly::from_points(&plane, &vec![[0.0, 0.0, 1.0]; 400], None).unwrap();
    let an = analyse(&asm, &MetricRule::PointDisplacement, DEFAULT_TAU).unwrap();
    assert_eq!(an.degenerate_count, 3);
}

#[test]
fn units_do_not_change_the_point_displacement_eigenvalues() {
    let (p, n) = corridor([5.0, 5.0, 0.0]);
    let base = pd_values(&p, &n);
    let mm: Vec<[f64; 3]> = p
        .iter()
        .map(|q| [q[0] * 1e3, q[1] * 1e3, q[2] * 1e3])
        .collect();
    let v = pd_values(&mm, &n);
    for k in 0..6 {
        assert!(
            (v[k] - base[k]).abs() <= 1e-9 * base[5],
            "{k}: {} vs {}",
            v[k],
            base[k]
        );
    }
}

#[test]
fn kernels_and_threads_agree_with_reference_points() {
    // Several blocks with distinct reference points: serial, parallel and
    // scalar agree to rounding.
    let (p, n) = corridor([2e5, 1e5, 0.0]);
    let mut big_p = Vec::new();
    let mut big_n = Vec::new();
    while big_p.len() < 3 * BLOCK + 17 {
        big_p.extend_from_slice(&p);
        big_n.extend_from_slice(&n);
    }
    let mut a1 = Accumulator::with_kernel(Kernel::Scalar).threads(1);
    a1.add(&big_p, &big_n, None).unwrap();
    let mut a2 = Accumulator::new().threads(4);
    a2.add(&big_p, &big_n, None).unwrap();
    let (x, y) = (a1.finish(), a2.finish());
    assert!(rel_diff(&x.hc, &y.hc) < 1e-12);
    assert!(rel_diff(&x.mc, &y.mc) < 1e-12);
}
