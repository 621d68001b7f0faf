//! The detector commands through the binary: `tunnel` (the paper's example),
//! `degeneracy` on point files (README "JSON"), `simulate` on a shipped rig,
//! `calibrate-threshold` on a reduced sweep.

use crate::common::schema;

use assert_cmd::Command;
use serde_json::Value;

fn json(args: &[&str]) -> Value {
    let out = Command::cargo_bin("audit")
        .unwrap()
        .env("NO_COLOR", "1")
        .args(args)
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("json")
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn bools(v: &Value) -> Vec<bool> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_bool().unwrap())
        .collect()
}

#[test]
fn tunnel_reproduces_the_paper() {
    let j = json(&["tunnel", "--format", "json"]);
    assert_eq!(j["radius_m"], 2.85);
    assert_eq!(j["on_axis"]["nullity"], 2);
    assert_eq!(j["shifted"]["nullity"], 2);
    let on = f64s(&j["on_axis"]["rotational_twists"][0]);
    let off = f64s(&j["shifted"]["rotational_twists"][0]);
    let want_on = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    let want_off = [0.0, 0.0, 1.0, 0.0, 1.0, 0.0];
    for k in 0..6 {
        assert!((on[k] - want_on[k]).abs() < 1e-12, "{on:?}");
        assert!((off[k] - want_off[k]).abs() < 1e-12, "{off:?}");
    }
    assert!((j["rotational_tuple_angle_deg"].as_f64().unwrap() - 45.0).abs() < 1e-9);
    assert_eq!(j["on_axis"]["contains_pure_rotation"], true);
    assert_eq!(j["shifted"]["contains_pure_rotation"], false);
    assert!(j["eigenvalue_max_abs_diff"].as_f64().unwrap() < 1e-12);
}

#[test]
fn degeneracy_on_points_follows_the_schema_and_the_footprint_moves() {
    let f = "tests/fixtures/detector/tunnel_small.csv";
    let a = json(&["degeneracy", f, "--format", "json"]);
    let errs = schema::check(&a, &schema::degeneracy_spec(), "$");
    assert!(errs.is_empty(), "{errs:?}");
    assert_eq!(a["schema_version"], 1);
    assert_eq!(
        bools(&a["footprint"]),
        [false, false, true, false, false, true]
    );
    assert_eq!(a["degenerate_subspace"].as_array().unwrap().len(), 2);
    let b = json(&["degeneracy", f, "--shift", "1,0,0", "--format", "json"]);
    assert_eq!(
        bools(&b["footprint"]),
        [false, false, true, false, true, true]
    );
    assert_eq!(f64s(&b["frame"]["translation_m"]), [1.0, 0.0, 0.0]);
    // Point-displacement eigenvalues are the same in both frames; I6's are not.
    let fam = |j: &Value, name: &str| {
        f64s(
            &j["families"]
                .as_array()
                .unwrap()
                .iter()
                .find(|x| x["family"] == name)
                .unwrap()["eigenvalues"],
        )
    };
    let (pa, pb) = (fam(&a, "point_displacement"), fam(&b, "point_displacement"));
    for k in 0..6 {
        assert!((pa[k] - pb[k]).abs() < 1e-10, "{pa:?} vs {pb:?}");
        assert!((-1e-12..=1.0 + 1e-12).contains(&pa[k]));
    }
    let (ua, ub) = (fam(&a, "unnormalized"), fam(&b, "unnormalized"));
    assert!(ua
        .iter()
        .zip(&ub)
        .any(|(x, y)| (x - y).abs() > 1e-3 * x.abs().max(1.0)));
    // The same points in binary PLY give the same answer.
    let c = json(&[
        "degeneracy",
        "tests/fixtures/detector/tunnel_small_le.ply",
        "--format",
        "json",
    ]);
    assert_eq!(c["points"], a["points"]);
    let pc = fam(&c, "point_displacement");
    for k in 0..6 {
        assert!((pa[k] - pc[k]).abs() < 1e-12);
    }
}

#[test]
fn degeneracy_refuses_collinear_points() {
    let out = Command::cargo_bin("audit")
        .unwrap()
        .args(["degeneracy", "tests/fixtures/detector/collinear.csv"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("collinear"), "{err}");
}

#[test]
fn simulate_on_a_shipped_rig() {
    let j = json(&[
        "simulate",
        "calibrations/m3dgr-mid360-d435i-imu.toml",
        "--scene",
        "corridor",
        "--format",
        "json",
    ]);
    let fam = |name: &str| {
        j["families"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["family"] == name)
            .unwrap_or_else(|| panic!("{name}"))
            .clone()
    };
    let pd = fam("point_displacement");
    assert_eq!(
        pd["degenerate_count"]["from"], 1,
        "a corridor has one degenerate direction"
    );
    assert_eq!(pd["degenerate_count"]["to"], 1);
    assert!(
        pd["correction_difference"]["translation_m"]
            .as_f64()
            .unwrap()
            < 1e-12
    );
    assert!(pd["subspace_angle_deg"].as_f64().unwrap() < 1e-9);
    let ea = f64s(&pd["eigenvalues"]["from"]);
    let eb = f64s(&pd["eigenvalues"]["to"]);
    for k in 0..6 {
        assert!((ea[k] - eb[k]).abs() < 1e-10);
    }
    // The footprint changes even under the equivariant metric.
    assert_eq!(pd["footprint_changes"], true);
    // I6 with the rig's 0.46 m lever arm: the applied correction differs.
    let i6 = fam("unnormalized");
    assert!(
        i6["correction_difference"]["translation_m"]
            .as_f64()
            .unwrap()
            > 1e-4
    );
    assert!(i6["max_eigenvalue_rel_change"].as_f64().unwrap() > 1e-3);
}

#[test]
fn calibrate_threshold_reduced_sweep() {
    let j = json(&[
        "calibrate-threshold",
        "--seeds",
        "1",
        "--noise",
        "0",
        "--voxel",
        "0.1",
        "--format",
        "json",
    ]);
    let pd = j["families"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["family"] == "point_displacement")
        .unwrap();
    let i = &pd["intersection"];
    assert_eq!(i["empty"], false);
    let (lo, hi) = (i["lo"].as_f64().unwrap(), i["hi"].as_f64().unwrap());
    assert!(
        lo < 1e-2 && 1e-2 < hi,
        "tau = 1e-2 reproduces the counts: ({lo}, {hi}]"
    );
    assert!(hi <= 1.0, "point-displacement eigenvalues are at most 1");
}
