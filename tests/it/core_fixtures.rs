//! Compare the SE(3) core with independent reference values computed by
//! pytransform3d / numpy (tests/fixtures/core/generate.py says how to rerun it).
//! Everything to 1e-12 (absolute, scaled by the size of the quantity when > 1).

// Index loops over fixed-size vectors read more clearly than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use extrinsic_audit::analyze;
use extrinsic_audit::internals::analysis::metric::adapted_metric;
use extrinsic_audit::internals::geometry::certificate::{
    adjoint_singular_values, ata_minus_i_rel, band, certificates, delta_eff,
};
use extrinsic_audit::internals::tolerances::DEFAULT_PITCH_TOL;
use extrinsic_audit::{QuatOrder, ScrewKind, Transform};
use serde_json::Value;

const TOL: f64 = 1e-12;

fn load(name: &str) -> Value {
    let path = format!("{}/tests/fixtures/core/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("fixture readable");
    serde_json::from_str(&text).expect("fixture is JSON")
}

fn f(v: &Value) -> f64 {
    v.as_f64().expect("number")
}
fn v3(v: &Value) -> [f64; 3] {
    let a = v.as_array().expect("array");
    [f(&a[0]), f(&a[1]), f(&a[2])]
}
fn v4(v: &Value) -> [f64; 4] {
    let a = v.as_array().expect("array");
    [f(&a[0]), f(&a[1]), f(&a[2]), f(&a[3])]
}
fn m3(v: &Value) -> [[f64; 3]; 3] {
    let a = v.as_array().expect("array");
    [v3(&a[0]), v3(&a[1]), v3(&a[2])]
}
fn m4(v: &Value) -> [[f64; 4]; 4] {
    let a = v.as_array().expect("array");
    [v4(&a[0]), v4(&a[1]), v4(&a[2]), v4(&a[3])]
}
fn close(name: &str, what: &str, got: f64, want: f64) {
    let scale = want.abs().max(1.0);
    assert!(
        (got - want).abs() <= TOL * scale,
        "{name}: {what}: got {got:e}, want {want:e}, diff {:e}",
        (got - want).abs()
    );
}

fn build(c: &Value) -> Transform {
    let how = c["how"].as_str().expect("how");
    let i = &c["inputs"];
    let mut w = Vec::new();
    let t = match how {
        "quaternion_xyzw" => {
            Transform::from_quaternion(v4(&i["q"]), QuatOrder::Xyzw, v3(&i["d"]), &mut w)
        }
        "quaternion_wxyz" => {
            Transform::from_quaternion(v4(&i["q"]), QuatOrder::Wxyz, v3(&i["d"]), &mut w)
        }
        "rpy" => Transform::from_rpy(v3(&i["rpy"]), v3(&i["d"])),
        "ypr" => Transform::from_ypr(v3(&i["ypr"]), v3(&i["d"])),
        "axis_angle" => Transform::from_axis_angle(v3(&i["axis"]), f(&i["angle"]), v3(&i["d"])),
        "rotation_vector" => Transform::from_rotation_vector(v3(&i["v"]), v3(&i["d"])),
        "matrix3" => Transform::from_matrix3(m3(&i["r"]), v3(&i["d"]), &mut w),
        "compose" => {
            let a = Transform::from_matrix4(m4(&i["a"]), &mut w).expect("a");
            let b = Transform::from_matrix4(m4(&i["b"]), &mut w).expect("b");
            Ok(a.compose(&b))
        }
        "inverse" => Transform::from_matrix4(m4(&i["a"]), &mut w).map(|a| a.inverse()),
        other => panic!("unknown constructor {other}"),
    }
    .expect("valid transform");
    assert!(w.is_empty(), "{}: unexpected warnings {w:?}", c["name"]);
    t
}

#[test]
fn transforms_match_pytransform3d() {
    let root = load("transforms.json");
    let cases = root["cases"].as_array().expect("cases");
    assert!(cases.len() >= 30, "expected ~30 reference transforms");
    for c in cases {
        let name = c["name"].as_str().expect("name");
        let t = build(c);
        let r = m3(&c["rotation"]);
        for (i, row) in r.iter().enumerate() {
            for (j, x) in row.iter().enumerate() {
                close(name, "R", t.rotation()[(i, j)], *x);
            }
        }
        let d = v3(&c["translation"]);
        for k in 0..3 {
            close(name, "d", t.translation()[k], d[k]);
        }
        let q = t.quaternion_xyzw();
        let qw = v4(&c["quaternion_xyzw"]);
        for k in 0..4 {
            close(name, "quaternion", q[k], qw[k]);
        }
        let a = t.adjoint();
        let aw = c["adjoint"].as_array().expect("adjoint");
        for (i, row) in aw.iter().enumerate() {
            for (j, x) in row.as_array().expect("row").iter().enumerate() {
                close(name, "Ad", a[(i, j)], f(x));
            }
        }
        close(name, "lever arm", t.lever_arm(), f(&c["lever_arm"]));
        let sv = adjoint_singular_values(t.lever_arm());
        for (k, x) in c["singular_values"]
            .as_array()
            .expect("sv")
            .iter()
            .enumerate()
        {
            close(name, "singular value", sv[k], f(x));
        }
        close(
            name,
            "||A^T A - I||/||I||",
            ata_minus_i_rel(t.lever_arm()),
            f(&c["ata_minus_i_rel"]),
        );

        let s = t.screw(DEFAULT_PITCH_TOL);
        let sw = &c["screw"];
        assert_eq!(
            s.kind.name(),
            sw["kind"].as_str().expect("kind"),
            "{name}: kind"
        );
        close(name, "angle", s.angle, f(&sw["angle"]));
        match (s.axis, sw["axis"].as_array()) {
            (Some(e), Some(_)) => {
                let ew = v3(&sw["axis"]);
                for k in 0..3 {
                    close(name, "axis", e[k], ew[k]);
                }
                close(name, "h", s.translation_along_axis.expect("h"), f(&sw["h"]));
                close(name, "pitch", s.pitch.expect("pitch"), f(&sw["pitch"]));
                let cw = v3(&sw["axis_point"]);
                let cp = s.axis_point.expect("axis point");
                for k in 0..3 {
                    close(name, "axis point", cp[k], cw[k]);
                }
            }
            (None, None) => {}
            (got, _) => panic!("{name}: axis {got:?} vs {}", sw["axis"]),
        }
        // h is the same for the inverse.
        if let Some(h) = s.translation_along_axis {
            let hi = t.inverse().screw(DEFAULT_PITCH_TOL).translation_along_axis;
            close(name, "h(T^-1)", hi.expect("h inverse"), h);
        }

        let am = adapted_metric(&t, DEFAULT_PITCH_TOL);
        match c["adapted_metric"].as_array() {
            Some(mw) => {
                assert!(am.exists, "{name}: adapted metric expected");
                let m = am.matrix.expect("matrix");
                for (i, row) in mw.iter().enumerate() {
                    for (j, x) in row.as_array().expect("row").iter().enumerate() {
                        close(name, "M0", m[(i, j)], f(x));
                    }
                }
                assert!(am.invariance_residual.expect("residual") <= TOL, "{name}");
            }
            None => assert!(!am.exists, "{name}: no adapted metric expected"),
        }
        // analyze() agrees with the pieces.
        let an = analyze(&t, &[1.0], DEFAULT_PITCH_TOL).expect("analyze");
        assert_eq!(an.screw, s);
        assert_eq!(an.adapted_metric.exists, am.exists);
    }
}

#[test]
fn bands_match_numpy_svd() {
    let root = load("bands.json");
    for b in root["bands"].as_array().expect("bands") {
        let lever = f(&b["lever_arm"]);
        let ell = f(&b["ell"]);
        let de = delta_eff(lever, ell).expect("delta_eff");
        close("band", "delta_eff", de, f(&b["delta_eff"]));
        let want = b["band"].as_array().expect("band");
        let got = band(de);
        close("band", "lower", got[0], f(&want[0]));
        close("band", "upper", got[1], f(&want[1]));
        let c = certificates(lever, &[ell]).expect("certificates");
        assert_eq!(c.as_slice()[0].band, got);
    }
}

#[test]
fn liosam_mid360_9axis_by_hand() {
    // LIO-SAM Mid-360 9-axis config: R = Rx(pi) = diag(1, -1, -1), d = (0, 0, -0.05),
    // the LiDAR's pose in the IMU frame (p_imu = R p_lidar + d).
    // By hand: phi = pi, the axis is x (R + I has its only non-zero column on x);
    // h = e . d = 0 exactly (zero pitch, an exact half-turn, so the sign of e is
    // the canonical +x). Axis point c = d_perp / 2 = (0, 0, -0.025): the LiDAR is
    // turned upside down about the line {y = 0, z = -0.025} parallel to x.
    // Check: R (p - c) + c at p = 0 gives -R c + c = (0, 0, 0.025) + (0, 0, -0.025)
    // ... = (0, 0, -0.05) = d.
    // M0 = [[I + |c|^2 I - c c^T, [c]x], [-[c]x, I]] with |c|^2 = 6.25e-4:
    //   top-left diag(1.000625, 1.000625, 1); [c]x = [[0, 0.025, 0], [-0.025, 0, 0], [0, 0, 0]].
    // offdiag = sqrt(2) * 0.025; ||M0 - I||/||I|| = 0.025 sqrt((6.25e-4 + 2)/3).
    // Adjoint: delta = 0.05, s_max = 0.025 + sqrt(1.000625).
    let mut w = Vec::new();
    let t = Transform::from_matrix3(
        [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
        [0.0, 0.0, -0.05],
        &mut w,
    )
    .expect("rotation");
    let a = analyze(&t, &[1.0, 0.25], DEFAULT_PITCH_TOL).expect("analyze");
    assert_eq!(a.screw.kind, ScrewKind::ZeroPitch);
    assert!(a.screw.half_turn);
    assert_eq!(a.screw.translation_along_axis, Some(0.0));
    assert_eq!(a.axis.expect("axis").as_slice(), &[1.0, 0.0, 0.0]);
    let c = a.screw.axis_point.expect("c");
    close("mid360", "c", c.x, 0.0);
    close("mid360", "c", c.y, 0.0);
    close("mid360", "c", c.z, -0.025);
    let m = a.adapted_metric.matrix.expect("M0");
    let want: [[f64; 6]; 6] = [
        [1.000625, 0.0, 0.0, 0.0, 0.025, 0.0],
        [0.0, 1.000625, 0.0, -0.025, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
        [0.0, -0.025, 0.0, 1.0, 0.0, 0.0],
        [0.025, 0.0, 0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
    ];
    for i in 0..6 {
        for j in 0..6 {
            close("mid360", "M0", m[(i, j)], want[i][j]);
        }
    }
    assert!(a.adapted_metric.invariance_residual.expect("res") <= 1e-16);
    close(
        "mid360",
        "offdiag",
        a.adapted_metric.offdiag_norm.expect("offdiag"),
        2f64.sqrt() * 0.025,
    );
    close(
        "mid360",
        "rel diff",
        a.adapted_metric.rel_diff_identity.expect("rel"),
        0.025 * ((6.25e-4 + 2.0) / 3.0f64).sqrt(),
    );
    close(
        "mid360",
        "s_max",
        a.adjoint.singular_values[0],
        0.025 + 1.000625f64.sqrt(),
    );
    close(
        "mid360",
        "delta_eff l=0.25",
        a.certificate.as_slice()[1].delta_eff,
        0.2,
    );
}
