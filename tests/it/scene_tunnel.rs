//! Synthetic scenes and `audit tunnel`.

use crate::common::run_cli;
use extrinsic_audit::internals::degeneracy::scene::*;
use extrinsic_audit::internals::degeneracy::{analyse, Assembly, MetricRule};
use extrinsic_audit::internals::pipeline::detector::{tunnel, TunnelParams};
use extrinsic_audit::internals::tolerances::DEFAULT_TAU;

fn args() -> TunnelParams {
    TunnelParams {
        radius: TUNNEL_RADIUS,
        length: 20.0,
        ring_spacing: 0.1,
        points_per_ring: 360,
        shift: [1.0, 0.0, 0.0],
        tau: DEFAULT_TAU,
    }
}

fn rounded(v: &[f64; 6]) -> [f64; 6] {
    let mut r = [0.0; 6];
    for k in 0..6 {
        r[k] = (v[k] * 1e6).round() / 1e6 + 0.0; // +0.0 turns -0 into 0
    }
    r
}

#[test]
fn tunnel_example_exactly_as_in_the_paper() {
    let r = tunnel(&args()).unwrap();
    // Nullity 2 in both frames.
    assert_eq!(r.on_axis.nullity, 2);
    assert_eq!(r.shifted.nullity, 2);
    // Rotational degenerate twist: [0 0 1 0 0 0] on the axis, [0 0 1 0 1 0] off it.
    assert_eq!(r.on_axis.rotational_twists.len(), 1);
    assert_eq!(r.shifted.rotational_twists.len(), 1);
    assert_eq!(
        rounded(&r.on_axis.rotational_twists[0]),
        [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
    );
    assert_eq!(
        rounded(&r.shifted.rotational_twists[0]),
        [0.0, 0.0, 1.0, 0.0, 1.0, 0.0]
    );
    assert!((r.rotational_tuple_angle_deg.unwrap() - 45.0).abs() < 1e-6);
    // Subspace footprints (README, `audit tunnel`): rot-z + trans-z; rot-z + trans-y + trans-z.
    assert_eq!(
        r.on_axis.footprint,
        [false, false, true, false, false, true]
    );
    assert_eq!(r.shifted.footprint, [false, false, true, false, true, true]);
    // A pure rotation is degenerate on the axis only.
    assert!(r.on_axis.contains_pure_rotation);
    assert!(!r.shifted.contains_pure_rotation);
    // Point-displacement eigenvalues identical.
    assert!(
        r.eigenvalue_max_abs_diff < 1e-12,
        "{:e}",
        r.eigenvalue_max_abs_diff
    );
    assert!(r.on_axis.eigenvalues[0].abs() < 1e-12 && r.on_axis.eigenvalues[1].abs() < 1e-12);
    assert!(r.on_axis.eigenvalues[2] > 0.1);
    // Same physical subspace after transport, and congruence = reassembly.
    assert!(r.transported_subspace_angle_deg.unwrap() < 1e-6);
    assert!(r.congruence_rel_diff.h < 1e-12 && r.congruence_rel_diff.m < 1e-12);
}

#[test]
fn tunnel_command_prints_the_numbers() {
    let (code, s, _) = run_cli(&["tunnel"]);
    assert_eq!(code, 0);
    assert!(s.contains("rot-z + trans-z"), "{s}");
    assert!(s.contains("rot-z + trans-y + trans-z"), "{s}");
    assert!(s.contains("[0, 0, 1.000, 0, 1.000, 0]"), "{s}");
    assert!(
        s.contains("angle between the two twist tuples: 45.000 deg"),
        "{s}"
    );
    let (code, out, _) = run_cli(&["tunnel", "--format", "json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["on_axis"]["nullity"], 2);
    assert_eq!(
        v["shifted"]["footprint"],
        serde_json::json!([false, false, true, false, true, true])
    );
    let tw: Vec<f64> = v["shifted"]["rotational_twists"][0]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    for (x, y) in tw.iter().zip([0.0, 0.0, 1.0, 0.0, 1.0, 0.0]) {
        assert!((x - y).abs() < 1e-12, "{tw:?}");
    }
    // Bad input is an error, not a panic.
    assert_eq!(run_cli(&["tunnel", "--shift", "1,0"]).0, 2);
    assert_eq!(run_cli(&["tunnel", "--radius=-1"]).0, 2);
    let mut a = args();
    a.radius = -1.0;
    assert!(tunnel(&a).is_err());
}

fn pd_count(c: &Cloud) -> (usize, [f64; 6]) {
    let asm = Assembly::from_points(&c.points, &c.normals, None).unwrap();
    let an = analyse(&asm, &MetricRule::PointDisplacement, DEFAULT_TAU).unwrap();
    (an.degenerate_count, an.eig.values)
}

#[test]
fn exact_scenes_have_the_analytic_nullity() {
    for kind in SceneKind::ALL {
        let mut rng = SceneRng::new(3);
        let c = sample_scene(kind, 0.1, &mut rng).unwrap();
        let (n, ev) = pd_count(&c);
        assert_eq!(n, kind.analytic_count(), "{}: {ev:?}", kind.name());
        // Clearly separated: the smallest non-degenerate eigenvalue is far above tau.
        assert!(ev[n] > 0.03, "{}: {ev:?}", kind.name());
        for k in 0..n {
            assert!(ev[k].abs() < 1e-12, "{}: {ev:?}", kind.name());
        }
    }
}

#[test]
fn pipeline_scenes_have_the_analytic_count_at_tau() {
    for kind in SceneKind::ALL {
        let c = synthesize(kind, &Preprocess::pipeline(0.1, 0.01, 5)).unwrap();
        assert!(c.len() > 1000);
        let (n, ev) = pd_count(&c);
        assert_eq!(n, kind.analytic_count(), "{}: {ev:?}", kind.name());
    }
}

#[test]
fn scenes_are_deterministic_and_seed_dependent() {
    let a = synthesize(SceneKind::Corner, &Preprocess::pipeline(0.2, 0.02, 11)).unwrap();
    let b = synthesize(SceneKind::Corner, &Preprocess::pipeline(0.2, 0.02, 11)).unwrap();
    assert_eq!(a, b);
    let c = synthesize(SceneKind::Corner, &Preprocess::pipeline(0.2, 0.02, 12)).unwrap();
    assert_ne!(a, c);
    // The PRNG stream is fixed (PCG64): first draws for seed 0.
    let mut r = SceneRng::new(0);
    let u = r.uniform();
    assert!((0.0..1.0).contains(&u));
    let mut r2 = SceneRng::new(0);
    assert_eq!(u, r2.uniform());
}

#[test]
fn normals_are_estimated_and_oriented_toward_the_sensor() {
    let c = synthesize(SceneKind::Tunnel, &Preprocess::pipeline(0.1, 0.0, 1)).unwrap();
    let mut worst: f64 = 1.0;
    for (p, n) in c.points.iter().zip(c.normals.iter()) {
        let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
        let radial = [-p[0] / r, -p[1] / r, 0.0];
        let dot = radial[0] * n[0] + radial[1] * n[1];
        worst = worst.min(dot);
    }
    assert!(worst > 0.99, "worst cos {worst}");
    // At the coarsest voxel (0.20 m) many points have fewer than 8 neighbours
    // within 0.30 m and are dropped.
    let coarse = synthesize(SceneKind::Corridor, &Preprocess::pipeline(0.2, 0.0, 1)).unwrap();
    let fine_count = (2.0 * (3.0 + 2.5) * SCENE_LENGTH / 0.04) as usize;
    assert!(coarse.len() < fine_count);
    // Voxel downsampling: one centroid per voxel.
    let pts = vec![[0.01, 0.01, 0.01], [0.02, 0.02, 0.02], [0.5, 0.5, 0.5]];
    let v = voxel_downsample(&pts, 0.1, [0.0; 3]);
    assert_eq!(v.len(), 2);
    assert!((v[0][0] - 0.015).abs() < 1e-15);
}
