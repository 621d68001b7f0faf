//! `audit simulate` on a transform given directly (the file-loading glue is
//! another module's; see `load_transform`).

use extrinsic_audit::cli::degeneracy::OutputFormat;
use extrinsic_audit::cli::simulate::{run, simulate, SimulateArgs};
use extrinsic_audit::degeneracy::MetricRule;
use extrinsic_audit::geometry::se3::Transform;

fn args(scene: &str) -> SimulateArgs {
    SimulateArgs {
        files: vec![],
        from: None,
        to: None,
        shift: Some("0.3,-0.2,0.4".into()),
        rotate_rpy: Some("0.1,-0.2,0.3".into()),
        scene: scene.into(),
        noise: 0.01,
        seed: 1,
        voxel: 0.1,
        exact_normals: false,
        tau: 1e-2,
        ell: "0.25,1,2.85,10".into(),
        update: "0.01,-0.02,0.015,0.05,0.03,-0.04".into(),
        format: OutputFormat::Table,
    }
}

#[test]
fn simulate_tunnel_point_displacement_is_frame_independent() {
    let a = args("tunnel");
    let t = Transform::from_rpy([0.1, -0.2, 0.3], [0.3, -0.2, 0.4]).unwrap();
    let s = simulate(&a, &t).unwrap();
    assert_eq!(s.rows.len(), 8);
    let pd = s.rows.last().unwrap();
    assert_eq!(pd.rule, MetricRule::PointDisplacement);
    assert_eq!(pd.counts, [2, 2]);
    assert!(!pd.decision_changes);
    assert!(
        pd.max_eigenvalue_rel_change < 1e-9,
        "{:e}",
        pd.max_eigenvalue_rel_change
    );
    assert!(pd.subspace_angle_deg.unwrap() < 1e-6);
    assert!(
        pd.delta_trans_m < 1e-12 && pd.delta_rot_rad < 1e-12,
        "{:e}",
        pd.delta_trans_m
    );
    // The footprint changes even under the equivariant metric.
    assert_ne!(pd.footprints[0], pd.footprints[1]);
    // I6: eigenvalues move, the correction differs.
    let i6 = &s.rows[0];
    assert_eq!(i6.rule, MetricRule::Unnormalized);
    assert!(i6.max_eigenvalue_rel_change > 1e-3);
    assert!(i6.delta_trans_m > 1e-6, "{:e}", i6.delta_trans_m);
}

#[test]
fn simulate_command_output() {
    for scene in ["tunnel", "corridor", "corner"] {
        let mut out = Vec::new();
        assert_eq!(run(&args(scene), &mut out).unwrap(), 0);
        let s = String::from_utf8(out).unwrap();
        println!("{s}");
        assert!(s.contains("point displacement"));
    }
    let mut a = args("corridor");
    a.format = OutputFormat::Json;
    let mut out = Vec::new();
    run(&a, &mut out).unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
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
    let mut a = args("moon");
    assert!(run(&a, &mut Vec::new()).is_err());
    a = args("tunnel");
    a.shift = None;
    a.rotate_rpy = None;
    assert!(run(&a, &mut Vec::new()).is_err());
    a = args("tunnel");
    a.update = "1,2,3".into();
    assert!(run(&a, &mut Vec::new()).is_err());
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
        .rows
        .iter()
        .find(|r| matches!(r.rule, MetricRule::AdaptedConstant(_)))
        .unwrap();
    assert!(
        ad.max_eigenvalue_rel_change < 1e-9,
        "{:e}",
        ad.max_eigenvalue_rel_change
    );
    assert_eq!(s.rows.len(), 9);
}
