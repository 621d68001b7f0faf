//! `audit check` as a CI gate (issue 11): the severity policy, the shipped data
//! and its baseline, baseline keys, refused writes, finding locations, the
//! per-robot manifest and the walk. Every test runs the real binary in a temp
//! directory.

use crate::common::run_cli;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// A FAST-LIO config (imu -> lidar) with rotation rows `r` and translation `t`.
pub fn fast_lio(t: [f64; 3], r: [[f64; 3]; 3]) -> String {
    let row = |k: usize| format!("{}, {}, {}", r[k][0], r[k][1], r[k][2]);
    format!(
        "mapping:\n  extrinsic_T: [ {}, {}, {} ]\n  extrinsic_R: [ {},\n                 {},\n                 {} ]\n",
        t[0],
        t[1],
        t[2],
        row(0),
        row(1),
        row(2)
    )
}

/// The identity scaled by `s`: `||R^T R - I||_F = sqrt(3) (s^2 - 1)`.
pub fn scaled(s: f64) -> [[f64; 3]; 3] {
    [[s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]]
}

pub const AVIA_T: [f64; 3] = [0.04165, 0.02326, -0.0284];

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `audit check ARGS --format json`: (exit code, report or Null, stderr).
pub fn check_json(args: &[&str]) -> (i32, Value, String) {
    let mut a = vec!["check"];
    a.extend_from_slice(args);
    a.extend_from_slice(&["--format", "json"]);
    let (code, out, err) = run_cli(&a);
    (code, serde_json::from_str(&out).unwrap_or(Value::Null), err)
}

/// (code, severity) of every finding.
pub fn findings(j: &Value) -> Vec<(String, String)> {
    j["findings"]
        .as_array()
        .map(|a| {
            a.iter()
                .map(|f| {
                    (
                        f["code"].as_str().unwrap().to_string(),
                        f["severity"].as_str().unwrap().to_string(),
                    )
                })
                .collect()
        })
        .unwrap_or_default()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn rounding_is_a_warning_beyond_it_an_error() {
    let dir = tempfile::tempdir().unwrap();
    // 1e-4 scaling: ||R^T R - I||_F = sqrt(3) (1.0001^2 - 1) = 3.464e-4 <= 5e-3.
    let small = write(dir.path(), "small.yaml", &fast_lio(AVIA_T, scaled(1.0001)));
    let (code, j, err) = check_json(&[s(&small)]);
    assert_eq!(code, 0, "{j}{err}");
    assert_eq!(
        findings(&j),
        [("non-orthonormal-rotation".into(), "warning".into())]
    );
    let msg = j["findings"][0]["message"].as_str().unwrap();
    assert!(msg.contains("3.464e-4"), "{msg}");
    // --deny CODE and --deny-warnings turn it into a problem.
    for flags in [
        &["--deny", "non-orthonormal-rotation"][..],
        &["--deny-warnings"][..],
    ] {
        let mut a = vec![s(&small)];
        a.extend_from_slice(flags);
        let (code, j, _) = check_json(&a);
        assert_eq!(code, 1, "{flags:?}");
        assert_eq!(findings(&j)[0].1, "error");
    }
    // 2e-3 scaling: sqrt(3) (1.002^2 - 1) = 6.935e-3 > 5e-3: an error.
    let big = write(dir.path(), "big.yaml", &fast_lio(AVIA_T, scaled(1.002)));
    let (code, j, _) = check_json(&[s(&big)]);
    assert_eq!(code, 1, "{j}");
    assert_eq!(
        findings(&j),
        [("non-orthonormal-rotation".into(), "error".into())]
    );
    // The text output names the code at its severity.
    let (_, out, _) = run_cli(&["check", s(&big)]);
    assert!(out.contains("error[non-orthonormal-rotation]"), "{out}");
    // --allow accepts it; --allow wins over --deny.
    let (code, j, _) = check_json(&[s(&big), "--allow", "non-orthonormal-rotation"]);
    assert_eq!(code, 0);
    assert_eq!(findings(&j)[0].1, "warning");
    let (code, _, _) = check_json(&[
        s(&big),
        "--allow",
        "non-orthonormal-rotation",
        "--deny",
        "non-orthonormal-rotation",
    ]);
    assert_eq!(code, 0);
    // Unknown codes are usage errors that list the codes.
    let (code, _, err) = run_cli(&["check", s(&small), "--deny", "no-such-code"]);
    assert_eq!(code, 2);
    assert!(err.contains("removed-file"), "{err}");
}

fn tf_static(q: [f64; 4]) -> String {
    format!(
        "transforms:\n- header:\n    frame_id: imu\n  child_frame_id: lidar\n  transform:\n    translation: {{x: 0.1, y: 0.0, z: 0.0}}\n    rotation: {{x: {}, y: {}, z: {}, w: {}}}\n",
        q[0], q[1], q[2], q[3]
    )
}

#[test]
fn quaternion_norm_policy() {
    let dir = tempfile::tempdir().unwrap();
    // Norm 1.001 (three printed digits): a warning, the gate passes.
    let q1 = write(dir.path(), "a.yaml", &tf_static([0.0, 0.0, 0.0, 1.001]));
    let (code, j, _) = check_json(&[s(&q1)]);
    assert_eq!(code, 0, "{j}");
    assert_eq!(
        findings(&j),
        [("non-unit-quaternion".into(), "warning".into())]
    );
    // Norm 1.01: an error.
    let q2 = write(dir.path(), "b.yaml", &tf_static([0.0, 0.0, 0.0, 1.01]));
    let (code, j, _) = check_json(&[s(&q2)]);
    assert_eq!(code, 1, "{j}");
    assert_eq!(
        findings(&j),
        [("non-unit-quaternion".into(), "error".into())]
    );
}

/// The shipped calibrations pass their own gate, alone and against the
/// shipped baseline.
#[test]
fn shipped_calibrations_pass_the_gate() {
    let (code, j, err) = check_json(&["calibrations/"]);
    assert_eq!(code, 0, "{j}{err}");
    assert_eq!(j["problems"], 0);
    assert_eq!(j["warnings"], 4, "GEODE's and M3DGR's rounded matrices");
    let (code, j, err) = check_json(&["calibrations/", "--baseline", "calibrations/baseline.json"]);
    assert_eq!(code, 0, "{j}{err}");
    assert_eq!(j["problems"], 0);
}

/// calibrations/baseline.json is what `--write-baseline` writes today;
/// `BLESS=1` rewrites it.
#[test]
fn shipped_baseline_is_current() {
    let shipped = Path::new("calibrations/baseline.json");
    // A hidden name in the same directory: the same keys, never walked.
    let fresh =
        Path::new("calibrations").join(format!(".baseline-test.{}.json", std::process::id()));
    let (code, out, err) = run_cli(&["check", "calibrations/", "--write-baseline", s(&fresh)]);
    let new = std::fs::read(&fresh);
    let _ = std::fs::remove_file(&fresh);
    assert_eq!(code, 0, "{out}{err}");
    let new = new.unwrap();
    if std::fs::read(shipped).ok().as_deref() != Some(&new[..]) {
        if std::env::var_os("BLESS").is_some() {
            std::fs::write(shipped, &new).unwrap();
        } else {
            panic!(
                "calibrations/baseline.json is out of date; regenerate with\n  BLESS=1 cargo test --test it check_gate::shipped_baseline_is_current"
            );
        }
    }
}
