//! `audit simulate` on a transform given directly (the file-loading glue is
//! another module's; see `load_transform`).

use crate::common::run_cli;
use extrinsic_audit::internals::degeneracy::scene::SceneKind;
use extrinsic_audit::internals::pipeline::detector::{simulate, SimulateParams};
use extrinsic_audit::Family;
use extrinsic_audit::Transform;

fn args(scene: &str) -> SimulateParams {
    SimulateParams {
        scene: SceneKind::parse(scene).unwrap(),
        noise: 0.01,
        seed: 1,
        voxel: 0.1,
        exact_normals: false,
        tau: 1e-2,
        ells: vec![0.25, 1.0, 2.85, 10.0],
        update: nalgebra::Vector6::new(0.01, -0.02, 0.015, 0.05, 0.03, -0.04),
    }
}

const CLI: [&str; 6] = [
    "--shift",
    "0.3,-0.2,0.4",
    "--rotate-rpy",
    "0.1,-0.2,0.3",
    "--noise",
    "0.01",
];

fn cli(scene: &str, extra: &[&str]) -> (i32, String, String) {
    let mut a = vec!["simulate", "--scene", scene, "--seed", "1"];
    a.extend(CLI);
    a.extend(extra);
    run_cli(&a)
}

#[test]
fn simulate_tunnel_point_displacement_is_frame_independent() {
    let a = args("tunnel");
    let t = Transform::from_rpy([0.1, -0.2, 0.3], [0.3, -0.2, 0.4]).unwrap();
    let s = simulate(&a, &t).unwrap();
    assert_eq!(s.families.len(), 8);
    let pd = s.families.last().unwrap();
    assert_eq!(pd.family, Family::PointDisplacement);
    assert_eq!([pd.degenerate_count.from, pd.degenerate_count.to], [2, 2]);
    assert!(!pd.decision_changes);
    assert!(
        pd.max_eigenvalue_rel_change < 1e-9,
        "{:e}",
        pd.max_eigenvalue_rel_change
    );
    assert!(pd.subspace_angle_deg.unwrap() < 1e-6);
    assert!(
        pd.correction_difference.translation_m < 1e-12
            && pd.correction_difference.rotation_rad < 1e-12,
        "{:e}",
        pd.correction_difference.translation_m
    );
    // The footprint changes even under the equivariant metric.
    assert_ne!(pd.footprint.from, pd.footprint.to);
    // I6: eigenvalues move, the correction differs.
    let i6 = &s.families[0];
    assert_eq!(i6.family, Family::Unnormalized);
    assert!(i6.max_eigenvalue_rel_change > 1e-3);
    assert!(
        i6.correction_difference.translation_m > 1e-6,
        "{:e}",
        i6.correction_difference.translation_m
    );
}

#[test]
fn simulate_command_output() {
    for scene in ["tunnel", "corridor", "corner"] {
        let (code, s, _) = cli(scene, &[]);
        assert_eq!(code, 0);
        println!("{s}");
        assert!(s.contains("point displacement"));
    }
    let (code, out, _) = cli("corridor", &["--format", "json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let pd = &v["families"][7];
    assert_eq!(pd["family"], "point_displacement");
    assert_eq!(pd["degenerate_count"]["from"], 1);
    assert_eq!(pd["degenerate_count"]["to"], 1);
    assert_eq!(pd["decision_changes"], false);
    assert!(
        pd["correction_difference"]["translation_m"]
            .as_f64()
            .unwrap()
            < 1e-12
    );
    assert_eq!(cli("moon", &[]).0, 2);
    assert_eq!(run_cli(&["simulate", "--scene", "tunnel"]).0, 2);
    assert_eq!(cli("tunnel", &["--update", "1,2,3"]).0, 2);
}

#[test]
fn simulate_zero_pitch_rig_adds_the_adapted_metric() {
    // Rotation about z through (0.5, 0, 0): zero pitch.
    let r = Transform::from_rpy([0.0, 0.0, 0.7], [0.0, 0.0, 0.0]).unwrap();
    let c = Transform::from_translation([0.5, 0.0, 0.0]).unwrap();
    let t = c.compose(&r).compose(&c.inverse());
    let mut a = args("corner");
    a.exact_normals = true;
    let s = simulate(&a, &t).unwrap();
    let ad = s
        .families
        .iter()
        .find(|r| r.family == Family::AdaptedConstant)
        .unwrap();
    assert!(
        ad.max_eigenvalue_rel_change < 1e-9,
        "{:e}",
        ad.max_eigenvalue_rel_change
    );
    assert_eq!(s.families.len(), 9);
}
