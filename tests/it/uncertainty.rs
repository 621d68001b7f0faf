//! Issue 17: the precision of the numbers as written, the user's calibration
//! uncertainty, their first-order propagation (checked against Monte Carlo)
//! and the three-way pitch verdict.

use crate::common::run_cli;
use extrinsic_audit::internals::geometry::uncertainty::{
    compose_steps, literal_half_unit, outputs, propagate, tuple_half_units, Step,
};
use extrinsic_audit::internals::pipeline;
use extrinsic_audit::LoadOptions;
use extrinsic_audit::UserSigma;
use nalgebra::{Matrix6, Vector6};
use rand_core::{RngCore, SeedableRng};
use std::path::PathBuf;

const HALF_TURN: &str = "tests/fixtures/uncertainty/half_turn_3_1416.urdf";
const PI15: &str = "tests/fixtures/uncertainty/half_turn_pi15.urdf";

fn json(args: &[&str]) -> serde_json::Value {
    let mut a = args.to_vec();
    a.extend(["--format", "json"]);
    let (code, out, err) = run_cli(&a);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).expect("json")
}

/// `h`, its uncertainty and the verdict, as numbers and a string.
fn pitch(v: &serde_json::Value) -> (f64, f64, String) {
    let s = &v["screw"];
    (
        s["translation_along_axis_m"].as_f64().unwrap(),
        s["translation_along_axis_uncertainty_m"].as_f64().unwrap(),
        s["pitch_verdict"].as_str().unwrap().to_string(),
    )
}

#[test]
fn literals_carry_half_a_unit_of_their_last_decimal() {
    assert_eq!(literal_half_unit("3.1416"), Some(0.5e-4));
    assert_eq!(literal_half_unit("-0.1235"), Some(0.5e-4));
    assert_eq!(literal_half_unit("1e-3"), Some(0.5e-3));
    assert_eq!(literal_half_unit("1.5E2"), Some(5.0));
    assert_eq!(literal_half_unit("0"), None);
    assert_eq!(literal_half_unit("0.000"), None);
    assert_eq!(literal_half_unit("12"), None);
    // The shortest print of a double (xacro's ${pi/2}) is exact.
    assert_eq!(literal_half_unit("1.5707963267948966"), Some(0.0));
    assert_eq!(tuple_half_units(&["0", "0", "0.1235"]), [0.5e-4; 3]);
    assert_eq!(tuple_half_units(&["1", "0", "0"]), [0.0; 3]);
    // Decimals keep their own place; the integer adopts the finest.
    assert_eq!(
        tuple_half_units(&["0.1", "2", "0.25"]),
        [0.05, 0.005, 0.005]
    );
}

#[test]
fn half_turn_3_1416_is_zero_by_default_and_nonzero_with_pitch_tol_1e9() {
    // Expected values from make_expected.py (numpy, uniform Monte Carlo over
    // the written digits): h = -1.1882818509246e-06, sigma_h = 2.9123e-05.
    let v = json(&[HALF_TURN, "--from", "base", "--to", "lidar"]);
    let (h, u, verdict) = pitch(&v);
    assert!((h + 1.1882818509246001e-06).abs() < 1e-15, "{h}");
    assert!((u / 2.912332654844667e-05 - 1.0).abs() < 0.02, "{u}");
    assert_eq!(verdict, "zero");
    assert_eq!(v["screw"]["kind"], "zero_pitch");
    assert_eq!(v["uncertainty"]["source"], "rounding");
    assert_eq!(v["adapted_metric"]["exists"], true);
    let residual = v["adapted_metric"]["invariance_residual"].as_f64().unwrap();
    assert!(residual > 0.0 && residual < 1e-5, "{residual}");

    let v = json(&[
        HALF_TURN,
        "--from",
        "base",
        "--to",
        "lidar",
        "--pitch-tol",
        "1e-9",
    ]);
    assert_eq!(pitch(&v).2, "nonzero");
    assert_eq!(v["screw"]["kind"], "general");
    assert_eq!(v["adapted_metric"]["exists"], false);

    let (_, text, _) = run_cli(&[HALF_TURN, "--from", "base", "--to", "lidar"]);
    let first = text.lines().next().unwrap();
    assert!(
        first.contains("h = -1.188e-6 +- 2.907e-5 m (rounding), pitch zero"),
        "{first}"
    );
    assert!(first.contains("adapted metric M0 printed below"), "{first}");
}

#[test]
fn pi_to_15_digits_is_zero() {
    let v = json(&[PI15, "--from", "base", "--to", "lidar"]);
    let (h, u, verdict) = pitch(&v);
    assert!(h.abs() < 1e-15, "{h}");
    // The translation's four decimals dominate (make_expected.py: 2.8915e-05).
    assert!((u / 2.8915375277717606e-05 - 1.0).abs() < 0.02, "{u}");
    assert_eq!(verdict, "zero");
}

#[test]
fn anymal_c_stays_nonzero_by_default_and_with_sigma_r() {
    let base = [
        "tests/fixtures/urdf/anymal_c_lidar.urdf",
        "--from",
        "base",
        "--to",
        "lidar",
    ];
    let v = json(&base);
    assert_eq!(pitch(&v).2, "nonzero");
    let mut args = base.to_vec();
    args.extend(["--sigma-r", "0.1"]);
    let v = json(&args);
    let (h, u, verdict) = pitch(&v);
    assert_eq!(verdict, "nonzero");
    assert_eq!(v["uncertainty"]["source"], "both");
    assert!(h.abs() > 3.0 * u, "{h} {u}");
    // 0.1 deg on each of two edges' rotations moves h by about lever * angle.
    assert!(u > 1e-4 && u < 2e-3, "{u}");
}

#[test]
fn undecidable_states_the_precision_that_decides_it() {
    // hilti2023-hhs-hesai: |h| = 0.14 mm, within 3 x 2 mm of zero.
    let v = json(&[
        "calibrations/hilti2023-hhs-hesai.toml",
        "--sigma-t",
        "0.002",
    ]);
    let (h, _, verdict) = pitch(&v);
    assert_eq!(verdict, "undecidable");
    assert_eq!(v["adapted_metric"]["exists"], false);
    let need = v["screw"]["deciding_uncertainty_m"].as_f64().unwrap();
    // max(|h|, 1 mm) / 3
    assert!((need - h.abs().max(1e-3) / 3.0).abs() < 1e-12, "{need}");
    let (_, text, _) = run_cli(&[
        "calibrations/hilti2023-hhs-hesai.toml",
        "--sigma-t",
        "0.002",
    ]);
    assert!(
        text.contains(
            "pitch undecidable at this precision (decided with sigma_h below 3.333e-4 m)"
        ),
        "{text}"
    );
}

#[test]
fn pitch_tol_refuses_what_is_neither_auto_nor_a_length() {
    let (code, _, err) = run_cli(&[
        HALF_TURN,
        "--from",
        "base",
        "--to",
        "lidar",
        "--pitch-tol=-1",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("expected `auto` or a finite length"), "{err}");
    let (code, _, err) = run_cli(&[
        HALF_TURN,
        "--from",
        "base",
        "--to",
        "lidar",
        "--sigma-r",
        "90",
    ]);
    assert_eq!(code, 2, "{err}");
}

/// A standard normal pair (Box-Muller) from the generator.
fn normal(rng: &mut rand_pcg::Pcg64) -> f64 {
    let u = |r: &mut rand_pcg::Pcg64| ((r.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    let (a, b) = (u(rng), u(rng));
    (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
}

/// A square root of a covariance (symmetric eigen decomposition).
fn sqrt_cov(c: &Matrix6<f64>) -> Matrix6<f64> {
    let e = c.symmetric_eigen();
    let d = e.eigenvalues.map(|x| x.max(0.0).sqrt());
    e.eigenvectors * Matrix6::from_diagonal(&d)
}

fn std_dev(xs: &[f64]) -> f64 {
    let m = xs.iter().sum::<f64>() / xs.len() as f64;
    (xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (xs.len() - 1) as f64).sqrt()
}

#[test]
fn first_order_matches_monte_carlo_on_five_shipped_rigs() {
    let user = UserSigma {
        sigma_t_m: 0.002,
        sigma_r_rad: 0.1f64.to_radians(),
    };
    for rig in [
        "anymal-d-lidar-imu",
        "in2laama-vlp16-mti3",
        "m3dgr-avia-d435i-imu",
        "norlab-warthog-rs16left-mti10",
        "oxford-spires-hesai",
    ] {
        let path = PathBuf::from(format!("calibrations/{rig}.toml"));
        let loaded = pipeline::load(&[path], &LoadOptions::default()).unwrap();
        let (from, to) = loaded.frame_pair(None, None).unwrap();
        let chain = loaded.graph.transform(&from, &to).unwrap();
        let steps: Vec<Step> = chain
            .steps
            .iter()
            .map(|s| {
                let mut p = s.edge.precision.full();
                p.user = Some(user);
                Step {
                    transform: s.edge.transform,
                    inverted: s.inverted,
                    covariance: p.covariance(),
                }
            })
            .collect();
        let nominal = compose_steps(&steps, None).unwrap();
        assert!((nominal.translation() - chain.transform.translation()).norm() < 1e-12);
        let e0 = chain.transform.screw(1e-9).axis;
        let fo = propagate(&steps, e0.as_ref()).unwrap();
        let roots: Vec<Matrix6<f64>> = steps.iter().map(|s| sqrt_cov(&s.covariance)).collect();
        let mut rng = rand_pcg::Pcg64::seed_from_u64(17);
        let (mut lever, mut angle, mut h) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..10_000 {
            let mut xi = Vec::with_capacity(6 * steps.len());
            for r in &roots {
                let z = Vector6::from_fn(|_, _| normal(&mut rng));
                xi.extend((r * z).iter());
            }
            let y = outputs(&compose_steps(&steps, Some(&xi)).unwrap(), e0.as_ref());
            lever.push(y.lever_arm);
            angle.push(y.angle);
            h.push(y.h);
        }
        for (what, mc, first) in [
            ("lever arm", std_dev(&lever), fo.lever_arm_m),
            ("angle", std_dev(&angle), fo.angle_rad),
            ("h", std_dev(&h), fo.h_m.unwrap()),
        ] {
            let ratio = first / mc;
            eprintln!("{rig} {what}: first order {first:e}, Monte Carlo {mc:e}, ratio {ratio:.4}");
            assert!(
                (ratio - 1.0).abs() < 0.10,
                "{rig} {what}: first order {first:e}, Monte Carlo {mc:e}"
            );
        }
    }
}

#[test]
fn chain_covariance_matches_brute_force_with_inverted_steps() {
    use extrinsic_audit::internals::geometry::uncertainty::{chain_covariance, tangent_between};
    use extrinsic_audit::Transform;
    let t = |rpy: [f64; 3], d: [f64; 3]| Transform::from_rpy(rpy, d).unwrap();
    let cov = |k: f64| {
        Matrix6::from_fn(|i, j| {
            if i == j {
                k * (1.0 + i as f64)
            } else {
                0.1 * k
            }
        })
    };
    let steps = [
        (t([0.3, -0.2, 1.1], [0.1, 0.2, -0.3]), true, cov(1e-6)),
        (t([-1.0, 0.4, 2.5], [0.5, -0.1, 0.05]), false, cov(4e-6)),
        (t([2.9, 0.1, -0.7], [-0.2, 0.3, 0.4]), true, cov(2e-6)),
        (t([0.0, 1.2, 0.2], [0.0, 0.0, 0.9]), false, cov(3e-6)),
    ]
    .map(|(transform, inverted, covariance)| Step {
        transform,
        inverted,
        covariance,
    });
    let nominal = compose_steps(&steps, None).unwrap();
    let n = 6 * steps.len();
    let mut brute = Matrix6::zeros();
    for (i, s) in steps.iter().enumerate() {
        // G_i by central differences of the composed tangent.
        let mut g = Matrix6::zeros();
        for c in 0..6 {
            let mut x = vec![0.0; n];
            x[6 * i + c] = 1e-6;
            let p = tangent_between(&nominal, &compose_steps(&steps, Some(&x)).unwrap());
            x[6 * i + c] = -1e-6;
            let m = tangent_between(&nominal, &compose_steps(&steps, Some(&x)).unwrap());
            g.set_column(c, &((p - m) / 2e-6));
        }
        brute += g * s.covariance * g.transpose();
    }
    let fast = chain_covariance(&steps);
    assert!(
        (fast - brute).norm() < 1e-9 * brute.norm(),
        "{fast}\n{brute}"
    );
}

/// `h +- sigma` as the verdict table prints it.
fn h_cell(r: &serde_json::Value) -> String {
    match (
        r["screw_translation_m"].as_f64(),
        r["screw_translation_uncertainty_m"].as_f64(),
    ) {
        (Some(h), Some(u)) => format!("{h:.3e} ± {u:.1e}"),
        _ => "— (no rotation)".into(),
    }
}

/// The verdict table of calibrations/README.md: every rig, placeholders and
/// duplicates included, at the precision as written and with a typical
/// published calibration uncertainty (2 mm, 0.1 degree per edge).
fn verdict_table() -> String {
    let survey = |extra: &[&str]| -> serde_json::Value {
        let mut a = vec!["survey", "calibrations/", "--all", "--format", "json"];
        a.extend(extra);
        let (code, out, err) = run_cli(&a);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str(&out).unwrap()
    };
    let (plain, user) = (
        survey(&[]),
        survey(&["--sigma-t", "0.002", "--sigma-r", "0.1"]),
    );
    // Without a rotation the verdict is definite (issue 33): the identity's
    // `zero`, a pure translation's `nonzero`; the table says which.
    let verdict = |r: &serde_json::Value| {
        let v = r["pitch_verdict"]
            .as_str()
            .expect("every rig has a verdict");
        match (r["screw_translation_m"].is_null(), v) {
            (true, "zero") => "zero (identity)".to_string(),
            (true, _) => format!("{v} (pure translation)"),
            _ => v.to_string(),
        }
    };
    let mut t = String::from(
        "| id | h ± σ_h (m), as written | verdict | h ± σ_h (m), + 2 mm, 0.1° per edge | verdict |\n|---|---|---|---|---|\n",
    );
    let rigs = plain["rigs"].as_array().unwrap();
    for (a, b) in rigs.iter().zip(user["rigs"].as_array().unwrap()) {
        assert_eq!(a["id"], b["id"]);
        t.push_str(&format!(
            "| {} | {} | {} | {} | {} |\n",
            a["id"].as_str().unwrap(),
            h_cell(a),
            verdict(a),
            h_cell(b),
            verdict(b)
        ));
    }
    t
}

#[test]
fn calibrations_readme_lists_every_rig_verdict() {
    let path = std::path::Path::new("calibrations/README.md");
    let readme = std::fs::read_to_string(path).unwrap();
    let (b, e) = ("<!-- verdicts:begin -->\n", "<!-- verdicts:end -->");
    let start = readme.find(b).expect("begin marker") + b.len();
    let end = readme.find(e).expect("end marker");
    let table = verdict_table();
    if readme[start..end] != table {
        if std::env::var_os("BLESS").is_some() {
            let new = format!("{}{}{}", &readme[..start], table, &readme[end..]);
            std::fs::write(path, new).unwrap();
        } else {
            panic!(
                "calibrations/README.md verdict table is out of date; regenerate with\n  BLESS=1 cargo test --test it uncertainty::calibrations_readme"
            );
        }
    }
}

#[test]
fn closed_form_rpy_covariance_matches_the_constructor() {
    use extrinsic_audit::internals::geometry::uncertainty::{
        rounding_covariance, rounding_std, rpy_covariance,
    };
    use extrinsic_audit::Transform;
    let (rpy, d) = ([0.4, -1.1, 2.7], [0.12, -0.5, 0.03]);
    let halves = [5e-4, 5e-3, 5e-5, 5e-5, 5e-4, 5e-6];
    let params = [d[0], d[1], d[2], rpy[0], rpy[1], rpy[2]];
    let numeric = rounding_covariance(&params, &halves, |p| {
        Transform::from_rpy([p[3], p[4], p[5]], [p[0], p[1], p[2]])
    })
    .unwrap();
    let u = |i: usize| [0, 1, 2].map(|k| rounding_std(halves[i + k]));
    let closed = rpy_covariance(rpy, u(0), u(3)).unwrap();
    assert!(
        (numeric - closed).norm() < 1e-8 * closed.norm(),
        "{numeric}\n{closed}"
    );
}

#[test]
fn check_require_zero_pitch_follows_the_verdict() {
    let base = [
        "check",
        HALF_TURN,
        "--pair",
        "base:lidar",
        "--require-zero-pitch",
    ];
    let (code, out, err) = run_cli(&base);
    assert_eq!(code, 0, "{out}{err}");
    let mut strict = base.to_vec();
    strict.extend(["--pitch-tol", "1e-9"]);
    let (code, out, _) = run_cli(&strict);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("error[nonzero-pitch]") && out.contains("(--pitch-tol 1e-9)"),
        "{out}"
    );
    assert!(
        out.contains("+- 2.9e-5 m (rounding), verdict nonzero"),
        "{out}"
    );
}

#[test]
fn survey_counts_rigs_by_the_three_way_verdict() {
    let (code, out, err) = run_cli(&[
        "survey",
        "calibrations/",
        "--format",
        "json",
        "--sigma-t",
        "0.002",
        "--sigma-r",
        "0.1",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let s = &v["summary"];
    let n = |k: &str| s[k].as_u64().unwrap();
    assert_eq!(
        n("zero_pitch_count") + n("nonzero_pitch_count") + n("undecidable_pitch_count"),
        n("count")
    );
    // hilti2023-hhs-hesai (|h| = 0.14 mm) and hilti2022-hesai (5.3 mm) are
    // within 3 x 2 mm of zero: undecidable with a published calibration's
    // uncertainty.
    assert_eq!(n("undecidable_pitch_count"), 2);
    let verdict = |id: &str| {
        v["rigs"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["id"] == id)
            .map(|r| r["pitch_verdict"].clone())
            .unwrap()
    };
    assert_eq!(verdict("hilti2023-hhs-hesai"), "undecidable");
    assert_eq!(verdict("liosam-mid360-9axis"), "zero");
}

#[test]
fn rig_toml_states_its_own_calibration_uncertainty() {
    let text = std::fs::read_to_string("calibrations/hilti2023-hhs-hesai.toml").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let write = |extra: &str| {
        let p = dir.path().join("rig.toml");
        std::fs::write(&p, text.replacen("[rig]\n", &format!("[rig]\n{extra}"), 1)).unwrap();
        p.to_string_lossy().into_owned()
    };
    let p = write("sigma_t_m = 0.002\nsigma_r_deg = 0.1\n");
    let v = json(&[&p]);
    // The matrix is printed in full (exact as written): the file's own value only.
    assert_eq!(v["uncertainty"]["source"], "user");
    assert_eq!(pitch(&v).2, "undecidable");
    // The file's value wins over the command line's.
    let v = json(&[&p, "--sigma-t", "0"]);
    assert_eq!(pitch(&v).2, "undecidable");
    let p = write("sigma_t_m = -1\n");
    let (code, _, err) = run_cli(&[&p]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("sigma_t_m: expected a number in [0, 1]"),
        "{err}"
    );
}

#[test]
fn xacro_expressions_are_exact() {
    let v = json(&[
        "tests/fixtures/uncertainty/expressions.urdf.xacro",
        "--from",
        "base",
        "--to",
        "lidar",
    ]);
    assert_eq!(v["uncertainty"]["source"], "none");
    assert_eq!(v["uncertainty"]["edges_without_rounding"], 0);
    assert_eq!(v["lever_arm_uncertainty_m"], 0.0);
    assert_eq!(v["rotation"]["angle_uncertainty_rad"], 0.0);
    let (_, text, _) = run_cli(&[
        "tests/fixtures/uncertainty/expressions.urdf.xacro",
        "--from",
        "base",
        "--to",
        "lidar",
    ]);
    assert!(text.contains("m (exact as written)"), "{text}");
}
