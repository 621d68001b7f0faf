//! Numerical hostility (issue 7): NaN and infinities anywhere, rotations a
//! hair off orthonormal, quaternions of norm 0 / 1e300 / 1.001, translations of
//! 1e12 m, angles of 1e6 rad, collinear and identical points. Each has one
//! defined outcome, tested through the real loaders and the binary:
//!
//! | input | outcome |
//! |---|---|
//! | NaN / inf in any number | error naming the file and place |
//! | rotation matrix 1e-7 off orthonormal | accepted quietly, projected to a rotation |
//! | rotation matrix 1e-4 off | warning `non-orthonormal-rotation`, projected |
//! | rotation matrix 0.1 off | error (how far off) |
//! | quaternion norm 0 | error |
//! | quaternion norm 1e300 | warning `non-unit-quaternion`, normalised (no overflow) |
//! | quaternion norm beyond f64 (components ~f64::MAX) | error |
//! | quaternion norm 1.001 | warning `non-unit-quaternion`, normalised |
//! | translation 1e12 m (any format) | error: beyond `MAX_TRANSLATION_M` (1e6 m) |
//! | translation 50 m in a metre field | warning `millimetres-in-metre-field` |
//! | rpy angle 1e6 rad | accepted: the rotation of the angle mod 2 pi, orthonormal |
//! | points all collinear / identical | `audit degeneracy` exits 2, "collinear" |

use crate::common::hostile;

use extrinsic_audit::internals::formats::{load_str, Parsed};
use extrinsic_audit::internals::geometry::se3::rpy_to_matrix;
use extrinsic_audit::internals::tolerances::MAX_TRANSLATION_M;
use extrinsic_audit::Code;
use extrinsic_audit::LoadOptions;
use extrinsic_audit::{QuatOrder, Transform};
use hostile::{run_audit, write_tmp};
use std::path::Path;

fn load(name: &str, text: &str) -> Result<Parsed, String> {
    load_str(text, Path::new(name), &LoadOptions::default()).map_err(|e| e.to_string())
}

fn codes(l: &Parsed) -> Vec<Code> {
    l.warnings.iter().map(|w| w.code).collect()
}

fn ortho_err(t: &Transform) -> f64 {
    let r = t.rotation();
    (r.transpose() * r - nalgebra::Matrix3::identity()).norm()
}

fn urdf(xyz: &str, rpy: &str) -> String {
    format!(
        "<robot name=\"r\"><link name=\"base\"/><link name=\"lidar\"/><joint name=\"j\" type=\"fixed\"><parent link=\"base\"/><child link=\"lidar\"/><origin xyz=\"{xyz}\" rpy=\"{rpy}\"/></joint></robot>\n"
    )
}

fn fast_lio(t: &str, r: &str) -> String {
    format!("mapping:\n  extrinsic_T: [{t}]\n  extrinsic_R: [{r}]\n")
}

fn matrix_yaml(rows: [&str; 4]) -> String {
    format!(
        "T_imu_lidar:\n  - [{}]\n  - [{}]\n  - [{}]\n  - [{}]\n",
        rows[0], rows[1], rows[2], rows[3]
    )
}

fn tf_echo(q: [&str; 4]) -> String {
    format!(
        "transforms:\n- header:\n    frame_id: base_link\n  child_frame_id: lidar\n  transform:\n    translation: {{x: 0.1, y: 0.0, z: 0.2}}\n    rotation: {{x: {}, y: {}, z: {}, w: {}}}\n",
        q[0], q[1], q[2], q[3]
    )
}

fn launch(args: &str) -> String {
    format!("<launch>\n  <node pkg=\"tf\" type=\"static_transform_publisher\" name=\"t\" args=\"{args} base_link lidar 100\" />\n</launch>\n")
}

fn rig_toml(translation: &str, rpy: &str) -> String {
    format!(
        r#"[rig]
id = "hostile"
sensor = "LiDAR"
platform = "bench"
dataset = "test"
category = "cad-or-nominal"
licence = "MIT"
direction = "pose of lidar in imu"
from = "imu"
to = "lidar"

[rig.source]
repo = "example/repo"
path = "calib.yaml"
commit = "0123456789abcdef0123456789abcdef01234567"

[[transform]]
parent = "imu"
child = "lidar"
unit = "m"
translation = {translation}
rpy = {rpy}
source_key = "k"
"#
    )
}

// ------------------------------------------------------------ NaN and inf

#[test]
fn nan_and_inf_anywhere_are_errors() {
    let cases: Vec<(&str, String)> =
        vec![
        ("nan_xyz.urdf", urdf("nan 0 0", "0 0 0")),
        ("inf_xyz.urdf", urdf("0 inf 0", "0 0 0")),
        ("neg_inf_rpy.urdf", urdf("0 0 0", "0 -inf 0")),
        ("nan_rpy.urdf", urdf("0 0 0", "NaN 0 0")),
        ("nan_t.yaml", fast_lio("0.1, .nan, 0", "1, 0, 0, 0, 1, 0, 0, 0, 1")),
        ("inf_r.yaml", fast_lio("0.1, 0, 0", "1, 0, 0, 0, .inf, 0, 0, 0, 1")),
        (
            "nan_matrix.yaml",
            matrix_yaml(["1, 0, 0, .nan", "0, 1, 0, 0", "0, 0, 1, 0", "0, 0, 0, 1"]),
        ),
        (
            "inf_matrix_rot.yaml",
            matrix_yaml(["1, 0, 0, 0", "0, .inf, 0, 0", "0, 0, 1, 0", "0, 0, 0, 1"]),
        ),
        ("nan_quat.yaml", tf_echo(["0", ".nan", "0", "1"])),
        ("inf_quat.yaml", tf_echo(["0", "0", "0", ".inf"])),
        ("nan_args.launch", launch("0.1 nan 0 0 0 0")),
        ("inf_args.launch", launch("0.1 0 0 0 0 inf")),
        ("inf_quat_args.launch", launch("0.1 0 0 0 0 0 inf")),
        ("nan_rig.toml", rig_toml("[0.1, nan, 0.0]", "[0, 0, 0]")),
        ("inf_rig.toml", rig_toml("[0.1, 0.0, 0.0]", "[0, -inf, 0]")),
        (
            "nan_ouster.json",
            "{\"lidar_to_sensor_transform\": [-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, NaN, 0, 0, 0, 1]}"
                .to_string(),
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in &cases {
        let e = load(name, text).expect_err(name);
        assert!(
            e.starts_with(name),
            "{name}: message does not name the file: {e}"
        );
        let lower = e.to_lowercase();
        assert!(
            lower.contains("finite")
                || lower.contains("nan")
                || lower.contains("inf")
                || lower.contains("json"),
            "{name}: {e}"
        );
        let p = write_tmp(&dir, name, text);
        let out = run_audit(&[p.to_str().unwrap(), "--frames"], 20);
        assert_eq!(out.code, Some(2), "{name}: {out:?}");
        assert!(out.stderr.contains(name), "{name}: {out:?}");
    }
}

#[test]
fn nan_joint_value_is_refused_by_the_cli() {
    let dir = tempfile::tempdir().unwrap();
    let text = "<robot name=\"r\"><link name=\"base\"/><link name=\"lidar\"/><joint name=\"j\" type=\"revolute\"><parent link=\"base\"/><child link=\"lidar\"/><axis xyz=\"0 0 1\"/><origin xyz=\"0.1 0 0\" rpy=\"0 0 0\"/></joint></robot>\n";
    let p = write_tmp(&dir, "rev.urdf", text);
    for v in ["nan", "inf", "-inf", "1e400"] {
        let out = run_audit(
            &[
                p.to_str().unwrap(),
                "--from",
                "base",
                "--to",
                "lidar",
                "--joint",
                &format!("j={v}"),
            ],
            20,
        );
        assert_eq!(out.code, Some(2), "{v}: {out:?}");
        assert!(out.stderr.contains("finite"), "{v}: {}", out.stderr);
    }
}

// ------------------------------------------------------- rotation matrices

/// R = Rz(0.3) with entry (0,0) off by `eps`.
fn off_rotation(eps: f64) -> String {
    let r = rpy_to_matrix(0.0, 0.0, 0.3);
    let mut v: Vec<String> = Vec::new();
    for i in 0..3 {
        for j in 0..3 {
            let x = r[(i, j)] + if i == 0 && j == 0 { eps } else { 0.0 };
            v.push(format!("{x:.17e}"));
        }
    }
    v.join(", ")
}

#[test]
fn rotation_a_hair_off_orthonormal() {
    // 1e-7 off: accepted quietly (rounding in published files), and the edge
    // holds a rotation orthonormal to rounding.
    let l = load("r7.yaml", &fast_lio("0.1, 0, 0", &off_rotation(1e-7))).unwrap();
    assert!(codes(&l).is_empty(), "{:?}", l.warnings);
    assert!(ortho_err(&l.edges[0].transform) < 1e-12);

    // 1e-4 off: projected, with a named warning.
    let l = load("r4.yaml", &fast_lio("0.1, 0, 0", &off_rotation(1e-4))).unwrap();
    assert_eq!(
        codes(&l),
        vec![Code::NonOrthonormalRotation],
        "{:?}",
        l.warnings
    );
    assert!(ortho_err(&l.edges[0].transform) < 1e-12);
    assert!(
        l.warnings[0].to_string().contains("r4.yaml"),
        "{}",
        l.warnings[0]
    );

    // 0.1 off: an error that says how far.
    let e = load("r1.yaml", &fast_lio("0.1, 0, 0", &off_rotation(0.1))).unwrap_err();
    assert!(e.starts_with("r1.yaml"), "{e}");
    assert!(e.contains("orthonormal"), "{e}");

    // The same through a 4x4 matrix YAML and the binary.
    let rows = |eps: f64| {
        let r = off_rotation(eps);
        let v: Vec<&str> = r.split(", ").collect();
        [
            format!("{}, {}, {}, 0.1", v[0], v[1], v[2]),
            format!("{}, {}, {}, 0", v[3], v[4], v[5]),
            format!("{}, {}, {}, 0", v[6], v[7], v[8]),
            "0, 0, 0, 1".to_string(),
        ]
    };
    let dir = tempfile::tempdir().unwrap();
    for (eps, code, warn) in [(1e-7, 0, false), (1e-4, 0, true), (0.1, 2, false)] {
        let r = rows(eps);
        let text = matrix_yaml([&r[0], &r[1], &r[2], &r[3]]);
        let p = write_tmp(&dir, &format!("m{eps}.yaml"), &text);
        let out = run_audit(&[p.to_str().unwrap(), "--from", "imu", "--to", "lidar"], 20);
        assert_eq!(out.code, Some(code), "{eps}: {out:?}");
        assert_eq!(
            out.stderr.contains("non-orthonormal-rotation"),
            warn,
            "{eps}: {}",
            out.stderr
        );
        assert!(!out.stdout.contains("NaN"), "{eps}");
    }
}

// ------------------------------------------------------------- quaternions

#[test]
fn quaternion_norms() {
    // 0: error.
    let e = load("q0.yaml", &tf_echo(["0", "0", "0", "0"])).unwrap_err();
    assert!(e.starts_with("q0.yaml"), "{e}");
    assert!(e.contains("norm 0"), "{e}");
    // Tiny (1e-300): error as well, not a division blow-up.
    let e = load("qtiny.yaml", &tf_echo(["0", "0", "0", "1e-300"])).unwrap_err();
    assert!(e.contains("expected a unit quaternion"), "{e}");
    // 1e300: normalised without overflow, warned.
    let l = load("q300.yaml", &tf_echo(["0", "0", "1e300", "1e300"])).unwrap();
    assert_eq!(codes(&l), vec![Code::NonUnitQuaternion]);
    let t = &l.edges[0].transform;
    assert!(ortho_err(t) < 1e-12);
    let want = rpy_to_matrix(0.0, 0.0, std::f64::consts::FRAC_PI_2);
    assert!((t.rotation() - want).norm() < 1e-12, "{t:?}");
    // 1.001: normalised, warned.
    let l = load("q1001.yaml", &tf_echo(["0", "0", "0", "1.001"])).unwrap();
    assert_eq!(codes(&l), vec![Code::NonUnitQuaternion]);
    assert!(ortho_err(&l.edges[0].transform) < 1e-12);
    // Exactly 1 within 1e-7: quiet.
    let l = load("q1.yaml", &tf_echo(["0", "0", "0", "1.0000001"])).unwrap();
    assert!(codes(&l).is_empty(), "{:?}", l.warnings);

    // The constructor directly, both orders.
    let mut w = Vec::new();
    for order in [QuatOrder::Xyzw, QuatOrder::Wxyz] {
        assert!(Transform::from_quaternion([0.0; 4], order, [0.0; 3], &mut w).is_err());
        let t = Transform::from_quaternion([1e300; 4], order, [0.0; 3], &mut w).unwrap();
        assert!(ortho_err(&t) < 1e-12);
        // A norm beyond the f64 range: an error (tests/core_edges.rs), not inf.
        assert!(Transform::from_quaternion([f64::MAX; 4], order, [0.0; 3], &mut w).is_err());
    }

    // Through the binary and the launch args (x y z qx qy qz qw).
    let dir = tempfile::tempdir().unwrap();
    let p = write_tmp(&dir, "q0.launch", &launch("0.1 0 0 0 0 0 0"));
    let out = run_audit(&[p.to_str().unwrap(), "--frames"], 20);
    assert_eq!(out.code, Some(2), "{out:?}");
    assert!(out.stderr.contains("q0.launch"), "{out:?}");
    let p = write_tmp(&dir, "q300.launch", &launch("0.1 0 0 0 0 1e300 1e300"));
    let out = run_audit(
        &[p.to_str().unwrap(), "--from", "base_link", "--to", "lidar"],
        20,
    );
    assert_eq!(out.code, Some(0), "{out:?}");
    assert!(out.stderr.contains("non-unit-quaternion"), "{}", out.stderr);
    assert!(!out.stdout.contains("NaN") && !out.stdout.contains("inf"));
}

// ------------------------------------------------------------ translations

#[test]
fn translation_of_1e12_m_is_refused_in_every_format() {
    let cases: Vec<(&str, String)> = vec![
        ("big.urdf", urdf("1e12 0 0", "0 0 0")),
        ("big_fast_lio.yaml", fast_lio("0, 1e12, 0", "1, 0, 0, 0, 1, 0, 0, 0, 1")),
        (
            "big_matrix.yaml",
            matrix_yaml(["1, 0, 0, 0", "0, 1, 0, 0", "0, 0, 1, -1e12", "0, 0, 0, 1"]),
        ),
        ("big.launch", launch("1e12 0 0 0 0 0")),
        ("big_rig.toml", rig_toml("[1e12, 0.0, 0.0]", "[0, 0, 0]")),
        (
            "big_ouster.json",
            "{\"lidar_to_sensor_transform\": [-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 1e15, 0, 0, 0, 1]}"
                .to_string(),
        ),
        ("huge.urdf", urdf("1e308 1e308 0", "0 0 0")),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in &cases {
        let e = load(name, text).expect_err(name);
        assert!(e.starts_with(name), "{name}: {e}");
        assert!(
            e.contains(&format!("expected at most {MAX_TRANSLATION_M:e} m")),
            "{name}: {e}"
        );
        let p = write_tmp(&dir, name, text);
        let out = run_audit(&[p.to_str().unwrap(), "--frames"], 20);
        assert_eq!(out.code, Some(2), "{name}: {out:?}");
        assert!(out.stderr.contains(name), "{name}: {out:?}");
    }
    // Just within the limit: loads, and the report has no NaN or inf.
    let p = write_tmp(&dir, "edge.urdf", &urdf("1e6 0 0", "0 0 0.5"));
    let out = run_audit(
        &[
            p.to_str().unwrap(),
            "--from",
            "base",
            "--to",
            "lidar",
            "--format",
            "json",
        ],
        20,
    );
    assert_eq!(out.code, Some(0), "{out:?}");
    let v: serde_json::Value = serde_json::from_str(&out.stdout).expect("json");
    assert!(!out.stdout.contains("NaN") && !out.stdout.contains("null, null"));
    assert_eq!(v["lever_arm_m"].as_f64(), Some(1e6));
    // 50 m in a metre field: the named warning.
    let l = load(
        "mm.yaml",
        &fast_lio("50, 0, 0", "1, 0, 0, 0, 1, 0, 0, 0, 1"),
    )
    .unwrap();
    assert_eq!(codes(&l), vec![Code::MillimetresInMetreField]);
    // `audit check` reports a 1e12 m file as a finding naming the file.
    let p = write_tmp(
        &dir,
        "check_big.yaml",
        &fast_lio("1e12, 0, 0", "1, 0, 0, 0, 1, 0, 0, 0, 1"),
    );
    let out = run_audit(&["check", p.to_str().unwrap()], 20);
    assert!(matches!(out.code, Some(1) | Some(2)), "{out:?}");
    assert!(
        (out.stdout.clone() + &out.stderr).contains("check_big.yaml"),
        "{out:?}"
    );
}

// ------------------------------------------------------------------ angles

#[test]
fn angles_of_1e6_rad_are_the_rotation_mod_2pi() {
    for a in [1e6f64, -1e6, 1e15, 1e300] {
        let l = load("ang.urdf", &urdf("0.1 0 0", &format!("{a:e} 0 {a:e}"))).unwrap();
        let t = &l.edges[0].transform;
        assert!(ortho_err(t) < 1e-12, "{a}: {t:?}");
        assert!(t.rotation().iter().all(|x| x.is_finite()));
        // sin/cos reduce the argument exactly; reducing by hand loses about
        // a / 2pi ulps of 2pi, so compare only where that is small.
        if a.abs() <= 1e6 {
            let red = a.rem_euclid(std::f64::consts::TAU);
            let want = rpy_to_matrix(red, 0.0, red);
            assert!(
                (t.rotation() - want).norm() < 1e-8,
                "{a}: {t:?} vs {want:?}"
            );
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let p = write_tmp(&dir, "ang.launch", &launch("0.1 0 0 1e6 -1e6 1e6"));
    let out = run_audit(
        &[
            p.to_str().unwrap(),
            "--from",
            "base_link",
            "--to",
            "lidar",
            "--format",
            "json",
        ],
        20,
    );
    assert_eq!(out.code, Some(0), "{out:?}");
    assert!(!out.stdout.contains("NaN"));
    let _: serde_json::Value = serde_json::from_str(&out.stdout).expect("json");
}

// ------------------------------------------------------------------ points

#[test]
fn collinear_and_identical_points_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let mut col = String::from("x,y,z,nx,ny,nz\n");
    let mut same = col.clone();
    let mut planar_normals = col.clone();
    for i in 0..50 {
        col.push_str(&format!("{},{},{},0,0,1\n", i, 2 * i, -i));
        same.push_str("1,2,3,0,0,1\n");
        planar_normals.push_str(&format!("{},{},0,0,0,1\n", i % 7, i / 7));
    }
    for (name, text) in [("collinear.csv", &col), ("identical.csv", &same)] {
        let p = write_tmp(&dir, name, text);
        let out = run_audit(&["degeneracy", p.to_str().unwrap()], 60);
        assert_eq!(out.code, Some(2), "{name}: {out:?}");
        assert!(out.stderr.contains(name), "{name}: {}", out.stderr);
        assert!(out.stderr.contains("collinear"), "{name}: {}", out.stderr);
        assert!(!out.stdout.contains("NaN"));
    }
    // A plane of points (a real degeneracy, not an input error): a report.
    let p = write_tmp(&dir, "plane.csv", &planar_normals);
    let out = run_audit(&["degeneracy", p.to_str().unwrap()], 60);
    assert!(matches!(out.code, Some(0) | Some(1)), "{out:?}");
    assert!(!out.stdout.contains("NaN"), "{}", out.stdout);
    // NaN coordinates are skipped with a warning (PCL marks invalid points so).
    let mut with_nan = planar_normals.clone();
    with_nan.push_str("nan,0,0,0,0,1\n");
    let p = write_tmp(&dir, "with_nan.csv", &with_nan);
    let out = run_audit(&["degeneracy", p.to_str().unwrap()], 60);
    assert!(matches!(out.code, Some(0) | Some(1)), "{out:?}");
    assert!(out.stdout.contains("skipped"), "{}", out.stdout);
    assert!(
        !out.stdout
            .lines()
            .filter(|l| !l.starts_with("warning"))
            .any(|l| l.contains("NaN")),
        "{}",
        out.stdout
    );
}

#[test]
fn huge_joint_axis_is_normalised_not_zeroed() {
    // An axis whose squared norm overflows: normalised by a scaled norm (the
    // motion is not silently lost), with the `non-unit-axis` warning.
    for jt in ["prismatic", "revolute"] {
        let text = format!(
            "<robot name=\"r\"><link name=\"base\"/><link name=\"lidar\"/><joint name=\"j\" type=\"{jt}\"><parent link=\"base\"/><child link=\"lidar\"/><axis xyz=\"1e300 1e300 0\"/><limit lower=\"0\" upper=\"1\" effort=\"1\" velocity=\"1\"/><origin xyz=\"0 0 0\" rpy=\"0 0 0\"/></joint></robot>\n"
        );
        let mut opts = LoadOptions::default();
        opts.joints.insert("j".into(), 0.5);
        let l = load_str(&text, Path::new("axis.urdf"), &opts).unwrap();
        assert_eq!(codes(&l), vec![Code::NonUnitAxis], "{jt}");
        assert!(
            l.warnings[0].to_string().contains("1e300"),
            "{}",
            l.warnings[0]
        );
        let t = &l.edges[0].transform;
        assert!(ortho_err(t) < 1e-12);
        let s = 0.5 / 2f64.sqrt();
        if jt == "prismatic" {
            assert!(
                (t.translation() - nalgebra::Vector3::new(s, s, 0.0)).norm() < 1e-12,
                "{t:?}"
            );
        } else {
            let want = Transform::from_axis_angle([1.0, 1.0, 0.0], 0.5, [0.0; 3]).unwrap();
            assert!((t.rotation() - want.rotation()).norm() < 1e-12, "{t:?}");
        }
    }
}
