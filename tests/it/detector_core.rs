//! Detector core: assembly, congruence, generalized eigenproblem, invariances,
//! remapping projector.

use extrinsic_audit::internals::degeneracy::scene::SceneRng;
use extrinsic_audit::internals::degeneracy::*;
use extrinsic_audit::internals::geometry::se3::skew;
use extrinsic_audit::internals::tolerances::DEFAULT_TAU;
use extrinsic_audit::Transform;
use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

/// Random points in a box of half-size `extent` with random unit normals and
/// optional random weights.
fn random_data(seed: u64, n: usize, extent: f64) -> (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<f64>) {
    let mut rng = SceneRng::new(seed);
    let mut p = Vec::with_capacity(n);
    let mut nn = Vec::with_capacity(n);
    let mut w = Vec::with_capacity(n);
    for _ in 0..n {
        p.push([
            extent * (2.0 * rng.uniform() - 1.0),
            extent * (2.0 * rng.uniform() - 1.0),
            extent * (2.0 * rng.uniform() - 1.0),
        ]);
        let u = rng.unit_vector();
        nn.push([u.x, u.y, u.z]);
        w.push(0.1 + rng.uniform());
    }
    (p, nn, w)
}

fn random_transform(rng: &mut SceneRng, lever: f64) -> Transform {
    let r = rng.rotation();
    let d = rng.unit_vector() * lever;
    let mut warnings = Vec::new();
    let rows = [
        [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
        [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
        [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
    ];
    Transform::from_matrix3(rows, [d.x, d.y, d.z], &mut warnings).unwrap()
}

fn direct(
    points: &[[f64; 3]],
    normals: &[[f64; 3]],
    w: Option<&[f64]>,
) -> (Matrix6<f64>, Matrix6<f64>) {
    let mut h = Matrix6::zeros();
    let mut m = Matrix6::zeros();
    for i in 0..points.len() {
        let p = Vector3::from(points[i]);
        let n = Vector3::from(normals[i]);
        let wi = w.map_or(1.0, |w| w[i]);
        let mut j = nalgebra::Matrix3x6::zeros();
        j.fixed_view_mut::<3, 3>(0, 0).copy_from(&(-skew(&p)));
        j.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&Matrix3::identity());
        let a = j.transpose() * n;
        h += a * a.transpose() * wi;
        m += j.transpose() * j * wi;
    }
    (h, m)
}

#[test]
fn moments_match_direct_per_point_sum() {
    for (seed, n) in [(1u64, 1usize), (2, 7), (3, 8), (4, 1001)] {
        let (p, nn, w) = random_data(seed, n, 3.0);
        let (h0, m0) = direct(&p, &nn, None);
        let a = Assembly::from_points(&p, &nn, None).unwrap();
        assert!(rel_diff(&a.h, &h0) < 1e-13, "H seed {seed}");
        assert!(
            rel_diff(&a.m, &m0) < 1e-13,
            "M seed {seed}: {}",
            rel_diff(&a.m, &m0)
        );
        let (h1, m1) = direct(&p, &nn, Some(&w));
        let b = Assembly::from_points(&p, &nn, Some(&w)).unwrap();
        assert!(rel_diff(&b.h, &h1) < 1e-13);
        assert!(rel_diff(&b.m, &m1) < 1e-13);
        // Streaming one point at a time agrees with the batch kernel.
        let mut acc = Accumulator::new();
        for i in 0..n {
            acc.push_weighted(&p[i], &nn[i], w[i]);
        }
        let c = acc.finish();
        assert!(rel_diff(&c.h, &b.h) < 1e-13);
        assert!(rel_diff(&c.m, &b.m) < 1e-13);
        assert_eq!(c.count, n);
    }
}

#[test]
fn mismatched_lengths_are_errors() {
    let (p, nn, _) = random_data(5, 10, 1.0);
    assert!(Assembly::from_points(&p, &nn[..9], None).is_err());
    assert!(Assembly::from_points(&p, &nn, Some(&[1.0; 3])).is_err());
}

#[test]
fn congruence_equals_reassembly_to_1e12() {
    let mut rng = SceneRng::new(42);
    let mut worst_h: f64 = 0.0;
    let mut worst_m: f64 = 0.0;
    for seed in 0..20u64 {
        let (p, nn, w) = random_data(100 + seed, 500, 5.0);
        let asm = Assembly::from_points(&p, &nn, Some(&w)).unwrap();
        for lever in [0.0, 0.05, 0.5, 3.0, 20.0] {
            let t = random_transform(&mut rng, lever);
            let (p2, n2) = reexpress(&p, &nn, &t);
            let re = Assembly::from_points(&p2, &n2, Some(&w)).unwrap();
            let cong = asm.congruence(&t.adjoint());
            worst_h = worst_h.max(rel_diff(&cong.h, &re.h));
            worst_m = worst_m.max(rel_diff(&cong.m, &re.m));
        }
    }
    assert!(worst_h < 1e-12, "H: {worst_h:e}");
    assert!(worst_m < 1e-12, "M: {worst_m:e}");
}

#[test]
fn congruence_check_catches_wrong_transforms() {
    let mut rng = SceneRng::new(7);
    let (p, nn, _) = random_data(8, 400, 4.0);
    let asm = Assembly::from_points(&p, &nn, None).unwrap();
    let t = random_transform(&mut rng, 0.8);
    let a = t.adjoint();
    let r = *t.rotation();
    let d = *t.translation();
    // Correct: passes.
    let (p2, n2) = reexpress(&p, &nn, &t);
    let good = Assembly::from_points(&p2, &n2, None).unwrap();
    assert!(rel_diff(&asm.congruence(&a).h, &good.h) < 1e-12);
    // 1. Missing R^T: points and normals rotated by R instead of R^T.
    let pw: Vec<[f64; 3]> = p
        .iter()
        .map(|x| (r * (Vector3::from(*x) - d)).into())
        .collect();
    let nw: Vec<[f64; 3]> = nn.iter().map(|x| (r * Vector3::from(*x)).into()).collect();
    let bad = Assembly::from_points(&pw, &nw, None).unwrap();
    assert!(rel_diff(&asm.congruence(&a).h, &bad.h) > 1e-3);
    // 2. A swapped with A^-1.
    let ainv = t.adjoint_inverse();
    assert!(rel_diff(&asm.congruence(&ainv).h, &good.h) > 1e-3);
    assert!(rel_diff(&asm.congruence(&ainv).m, &good.m) > 1e-3);
    // 3. Normals left unrotated.
    let bad3 = Assembly::from_points(&p2, &nn, None).unwrap();
    assert!(rel_diff(&asm.congruence(&a).h, &bad3.h) > 1e-3);
    // (M does not depend on normals: only the H check can see this one.)
    assert!(rel_diff(&asm.congruence(&a).m, &bad3.m) < 1e-12);
}

#[test]
fn generalized_eigen_solves_the_pencil() {
    let (p, nn, w) = random_data(11, 300, 2.0);
    let asm = Assembly::from_points(&p, &nn, Some(&w)).unwrap();
    let e = generalized_eigen(&asm.h, &asm.m, "point-displacement").unwrap();
    for k in 0..5 {
        assert!(e.values[k] <= e.values[k + 1]);
    }
    let v = e.vectors;
    let vtmv = v.transpose() * asm.m * v;
    assert!((vtmv - Matrix6::identity()).amax() < 1e-12, "{vtmv}");
    let lam = Matrix6::from_diagonal(&Vector6::from(e.values));
    let resid = asm.h * v - asm.m * v * lam;
    assert!(resid.amax() < 1e-10 * asm.h.amax());
}

#[test]
fn point_displacement_eigenvalues_in_unit_interval() {
    for seed in 0..30u64 {
        let (p, nn, w) = random_data(200 + seed, 50 + 10 * seed as usize, 1.0 + seed as f64);
        let asm = Assembly::from_points(&p, &nn, Some(&w)).unwrap();
        let an = analyse(&asm, &MetricRule::PointDisplacement, DEFAULT_TAU).unwrap();
        for l in an.eig.values {
            assert!((-1e-12..=1.0 + 1e-12).contains(&l), "seed {seed}: {l}");
        }
    }
}

#[test]
fn point_displacement_invariant_to_frame_unit_and_scale() {
    let mut rng = SceneRng::new(99);
    for seed in 0..10u64 {
        let (p, nn, w) = random_data(300 + seed, 400, 3.0);
        let asm = Assembly::from_points(&p, &nn, Some(&w)).unwrap();
        let base = analyse(&asm, &MetricRule::PointDisplacement, DEFAULT_TAU).unwrap();
        let check = |q: &[[f64; 3]], n: &[[f64; 3]], what: &str| {
            let a = Assembly::from_points(q, n, Some(&w)).unwrap();
            let an = analyse(&a, &MetricRule::PointDisplacement, DEFAULT_TAU).unwrap();
            for k in 0..6 {
                let d = (an.eig.values[k] - base.eig.values[k]).abs();
                assert!(d < 1e-10, "{what} seed {seed} k {k}: {d:e}");
            }
        };
        // Frame.
        let t = random_transform(&mut rng, 2.0);
        let (p2, n2) = reexpress(&p, &nn, &t);
        check(&p2, &n2, "frame");
        // Unit: metres -> millimetres.
        let pmm: Vec<[f64; 3]> = p
            .iter()
            .map(|x| [x[0] * 1e3, x[1] * 1e3, x[2] * 1e3])
            .collect();
        check(&pmm, &nn, "unit");
        // Scene scale 0.1 and 7.
        for s in [0.1, 7.0] {
            let ps: Vec<[f64; 3]> = p.iter().map(|x| [x[0] * s, x[1] * s, x[2] * s]).collect();
            check(&ps, &nn, "scale");
        }
        // The congruence path too.
        let an = analyse(
            &asm.congruence(&t.adjoint()),
            &MetricRule::PointDisplacement,
            DEFAULT_TAU,
        )
        .unwrap();
        let tc = check_transport(&base, &an, &t.adjoint());
        assert!(tc.eigenvalue_diff < 1e-10);
    }
}

#[test]
fn unnormalized_eigenvalues_change_under_translation() {
    let (p, nn, _) = random_data(400, 400, 3.0);
    let asm = Assembly::from_points(&p, &nn, None).unwrap();
    let base = analyse(&asm, &MetricRule::Unnormalized, DEFAULT_TAU).unwrap();
    let t = Transform::from_translation([0.5, 0.0, 0.0]).unwrap();
    let (p2, n2) = reexpress(&p, &nn, &t);
    let moved = Assembly::from_points(&p2, &n2, None).unwrap();
    let an = analyse(&moved, &MetricRule::Unnormalized, DEFAULT_TAU).unwrap();
    let diff = (0..6)
        .map(|k| (an.eig.values[k] - base.eig.values[k]).abs() / base.eig.values[k])
        .fold(0.0, f64::max);
    assert!(diff > 1e-3, "I6 eigenvalues moved only {diff:e}");
    // A pure rotation leaves them unchanged (Proposition 1).
    let mut rng = SceneRng::new(1);
    let r = random_transform(&mut rng, 0.0);
    let rot = analyse(
        &asm.congruence(&r.adjoint()),
        &MetricRule::Unnormalized,
        DEFAULT_TAU,
    )
    .unwrap();
    for k in 0..6 {
        assert!((rot.eig.values[k] - base.eig.values[k]).abs() < 1e-10 * base.eig.values[5]);
    }
}

#[test]
fn correction_difference_vanishes_only_for_point_displacement() {
    // A corridor-like set (planes x = +-1.5, y = -1, 1.5 along z) with one exact
    // null direction, plus a weak extra direction through a handful of points.
    let mut p = Vec::new();
    let mut n = Vec::new();
    for i in 0..60 {
        let z = -6.0 + 0.2 * i as f64;
        for j in 0..15 {
            let s = -1.0 + 2.5 * j as f64 / 14.0;
            p.push([-1.5, s, z]);
            n.push([1.0, 0.0, 0.0]);
            p.push([1.5, s, z]);
            n.push([-1.0, 0.0, 0.0]);
            let u = -1.5 + 3.0 * j as f64 / 14.0;
            p.push([u, -1.0, z]);
            n.push([0.0, 1.0, 0.0]);
            p.push([u, 1.5, z]);
            n.push([0.0, -1.0, 0.0]);
        }
    }
    let asm = Assembly::from_points(&p, &n, None).unwrap();
    let t = Transform::from_rpy([0.1, -0.2, 0.3], [0.3, -0.2, 0.4]).unwrap();
    let a = t.adjoint();
    let ainv = t.adjoint_inverse();
    let (p2, n2) = reexpress(&p, &n, &t);
    let asm2 = Assembly::from_points(&p2, &n2, None).unwrap();
    let xi = Vector6::new(0.01, -0.02, 0.015, 0.05, 0.03, -0.04);
    let pd1 = analyse(&asm, &MetricRule::PointDisplacement, DEFAULT_TAU).unwrap();
    let pd2 = analyse(&asm2, &MetricRule::PointDisplacement, DEFAULT_TAU).unwrap();
    assert_eq!(pd1.degenerate_count, 1);
    assert_eq!(pd2.degenerate_count, 1);
    let dpd = correction_difference(&pd1, &pd2, &a, &ainv, &xi);
    assert!(dpd.norm() < 1e-12, "PD Delta {:e}", dpd.norm());
    let i1 = analyse(&asm, &MetricRule::Unnormalized, DEFAULT_TAU).unwrap();
    let i2 = analyse(&asm2, &MetricRule::Unnormalized, DEFAULT_TAU).unwrap();
    assert_eq!(i1.degenerate_count, i2.degenerate_count);
    let di6 = correction_difference(&i1, &i2, &a, &ainv, &xi);
    assert!(di6.norm() > 1e-4, "I6 Delta {:e}", di6.norm());
    // Using a Euclidean projector for PD, or reversing the congruence, breaks it.
    let bad = correction_difference(&pd1, &pd2, &ainv, &a, &xi);
    assert!(bad.norm() > 1e-6);
    // Subspace transport: PD subspaces agree after v = A v'.
    let tc = check_transport(&pd1, &pd2, &a);
    assert!(tc.count_equal);
    assert!(tc.subspace_angle.unwrap() < 1e-9);
}

#[test]
fn collinear_points_give_a_clear_error() {
    let p: Vec<[f64; 3]> = (0..50)
        .map(|i| {
            let s = i as f64 * 0.1;
            [1.0 + s, 2.0 + 2.0 * s, -0.5 * s]
        })
        .collect();
    let n: Vec<[f64; 3]> = (0..50).map(|_| [0.0, 0.0, 1.0]).collect();
    let asm = Assembly::from_points(&p, &n, None).unwrap();
    let err = analyse(&asm, &MetricRule::PointDisplacement, DEFAULT_TAU).unwrap_err();
    assert!(
        err.message.contains("points are collinear"),
        "{}",
        err.message
    );
    // A single point and no point at all: the same error, not a panic.
    let one = Assembly::from_points(&p[..1], &n[..1], None).unwrap();
    assert!(analyse(&one, &MetricRule::PointDisplacement, DEFAULT_TAU).is_err());
    let none = Assembly::from_points(&[], &[], None).unwrap();
    assert!(analyse(&none, &MetricRule::PointDisplacement, DEFAULT_TAU).is_err());
    assert!(analyse(&none, &MetricRule::BlockScaling, DEFAULT_TAU).is_err());
    assert!(analyse(&none, &MetricRule::Jacobi, DEFAULT_TAU).is_err());
    // Coplanar points are fine.
    let q: Vec<[f64; 3]> = (0..50)
        .map(|i| [(i % 7) as f64, (i / 7) as f64, 0.0])
        .collect();
    let nq: Vec<[f64; 3]> = (0..50).map(|_| [0.0, 0.0, 1.0]).collect();
    let asm = Assembly::from_points(&q, &nq, None).unwrap();
    let an = analyse(&asm, &MetricRule::PointDisplacement, DEFAULT_TAU).unwrap();
    assert_eq!(an.degenerate_count, 3); // a plane: 2 translations + 1 rotation
}

#[test]
fn paper_sweep_has_861_changes_and_pd_never_flips() {
    let changes = paper_frame_changes(1);
    assert_eq!(changes.len(), 861);
    // Orthogonal control matrices are orthogonal; adjoints have det 1.
    for c in &changes {
        match c.arm {
            Arm::OrthogonalControl => {
                assert!((c.a.transpose() * c.a - Matrix6::identity()).amax() < 1e-12)
            }
            _ => assert!((c.a.determinant() - 1.0).abs() < 1e-6),
        }
    }
    let (p, nn, _) = random_data(500, 300, 3.0);
    let asm = Assembly::from_points(&p, &nn, None).unwrap();
    let rows = frame_sweep(&asm, &changes, &MetricRule::paper_configs(), &[0.2; 8]).unwrap();
    assert!(frame_sweep(&asm, &changes, &MetricRule::paper_configs(), &[0.2; 7]).is_err());
    assert_eq!(rows.len(), 8);
    let pd = rows.last().unwrap();
    assert_eq!(pd.rule, MetricRule::PointDisplacement);
    assert_eq!(pd.decision_changes, 0);
    assert_eq!(pd.count_changes, 0);
    assert!(
        pd.max_eigenvalue_change < 1e-8,
        "{:e}",
        pd.max_eigenvalue_change
    );
    assert_eq!(pd.evaluations, 861);
    let i6 = &rows[0];
    assert!(i6.max_eigenvalue_change > 1e-2);
}

#[test]
fn twist_screw_reads_axis_pitch_and_point() {
    // Rotation about the z axis through (-1, 0, 0): t = c x omega = (0, 1, 0).
    let s = TwistScrew::from_twist(&Vector6::new(0.0, 0.0, 1.0, 0.0, 1.0, 0.0));
    assert_eq!(s.kind, "zero_pitch");
    assert!((s.axis_point.unwrap() - Vector3::new(-1.0, 0.0, 0.0)).norm() < 1e-15);
    let s = TwistScrew::from_twist(&Vector6::new(0.0, 0.0, 2.0, 0.0, 0.0, 1.0));
    assert_eq!(s.kind, "general");
    assert!((s.pitch.unwrap() - 0.5).abs() < 1e-15);
    let s = TwistScrew::from_twist(&Vector6::new(0.0, 0.0, 0.0, 0.0, 0.0, -3.0));
    assert_eq!(s.kind, "pure_translation");
    assert_eq!(s.direction.unwrap(), Vector3::new(0.0, 0.0, -1.0));
}

#[test]
fn sweep_on_a_tunnel_behaves_as_the_paper_says() {
    use extrinsic_audit::internals::degeneracy::scene::{synthesize, Preprocess, SceneKind};
    use extrinsic_audit::internals::degeneracy::threshold::default_threshold;
    let cloud = synthesize(SceneKind::Tunnel, &Preprocess::pipeline(0.1, 0.01, 3)).unwrap();
    let asm = Assembly::from_points(&cloud.points, &cloud.normals, None).unwrap();
    let rules = MetricRule::paper_configs();
    let taus: Vec<f64> = rules
        .iter()
        .map(|r| default_threshold(r, DEFAULT_TAU))
        .collect();
    let rows = frame_sweep(&asm, &paper_frame_changes(7), &rules, &taus).unwrap();
    let (rot, orth) = (1, 4); // Arm::ALL order
                              // I6: pure rotation and the orthogonal control leave the spectrum unchanged
                              // (Proposition 1; the control isolates the non-orthogonality of Ad(T)).
    let i6 = &rows[0];
    assert!(i6.max_eigenvalue_change_by_arm[rot] < 1e-9);
    assert!(i6.max_eigenvalue_change_by_arm[orth] < 1e-9);
    assert_eq!(
        i6.decision_changes_by_arm[rot] + i6.decision_changes_by_arm[orth],
        0
    );
    // ... but translations move it.
    assert!(i6.max_eigenvalue_change_by_arm[2] > 0.1);
    // Isotropic fixed metrics are rotation-invariant too.
    for row in &rows[1..6] {
        assert!(
            row.max_eigenvalue_change_by_arm[rot] < 1e-9,
            "{}",
            row.rule.label()
        );
    }
    // Jacobi responds to a pure rotation (diag(H) is axis-defined).
    assert!(rows[6].max_eigenvalue_change_by_arm[rot] > 1e-3);
    // Point displacement: unchanged in every arm, even the orthogonal control.
    let pd = &rows[7];
    assert_eq!(pd.decision_changes, 0);
    assert_eq!(pd.count_changes, 0);
    assert!(
        pd.max_eigenvalue_change < 1e-6,
        "{:e}",
        pd.max_eigenvalue_change
    );
}
