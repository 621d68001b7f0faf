//! Issue 12: every numeric option is checked before any work, the message
//! naming the option; no JSON number becomes `null` because an option
//! underflowed; `--joint` values that look like degrees on a revolute joint
//! get a named warning.

use crate::common::run_cli;

const ANYMAL: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/calibrations/anymal-d.urdf");

/// Refused with exit 2, the message naming `option` and quoting `value`.
fn refused(args: &[&str], option: &str, value: &str) {
    let (code, out, err) = run_cli(args);
    assert_eq!(code, 2, "{args:?}: {out}{err}");
    assert!(out.is_empty(), "{args:?}: {out}");
    assert!(
        err.contains(option) && err.contains(value),
        "{args:?}: {err}"
    );
}

#[test]
fn detector_options_out_of_range_are_refused_naming_the_option() {
    refused(&["tunnel", "--tau", "nan"], "--tau", "nan");
    refused(&["tunnel", "--tau", "-1"], "--tau", "-1");
    refused(&["tunnel", "--tau", "0"], "--tau", "0");
    refused(
        &["simulate", "--shift", "1,0,0", "--noise", "1e308"],
        "--noise",
        "1e308",
    );
    refused(
        &["simulate", "--shift", "1,0,0", "--noise", "-0.1"],
        "--noise",
        "-0.1",
    );
    refused(
        &["simulate", "--shift", "1,0,0", "--voxel", "inf"],
        "--voxel",
        "inf",
    );
    refused(
        &["simulate", "--shift", "1,0,0", "--ell", "1e-308"],
        "--ell",
        "1e-308",
    );
    refused(
        &["calibrate-threshold", "--noise", "0,1e308"],
        "--noise",
        "1e308",
    );
    refused(&["degeneracy", "x.csv", "--tau", "inf"], "--tau", "inf");
}

#[test]
fn band_options_that_would_overflow_are_refused_and_the_extremes_stay_numbers() {
    let rig = [ANYMAL, "--from", "base", "--to", "lidar"];
    refused(
        &[&rig[..], &["--ell", "1e-308"]].concat(),
        "--ell",
        "1e-308",
    );
    refused(
        &[&rig[..], &["--kappa", "1e-320", "--lambda", "1"]].concat(),
        "--kappa",
        "1e-320",
    );
    refused(
        &[&rig[..], &["--kappa", "1", "--lambda", "1e308"]].concat(),
        "--lambda",
        "1e308",
    );
    let (code, out, err) = run_cli(
        &[
            &rig[..],
            &[
                "--ell", "1e-6,1e6", "--kappa", "1e-100", "--lambda", "1e100", "--format", "json",
            ],
        ]
        .concat(),
    );
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let bands = v["certificate"].as_array().unwrap();
    assert_eq!(bands.len(), 2);
    for b in bands {
        for x in [&b["ell_m"], &b["delta_eff"], &b["band"][0], &b["band"][1]] {
            assert!(x.as_f64().is_some_and(f64::is_finite), "{b}");
        }
    }
    let kc = v["kappa_check"].to_string();
    assert!(!kc.contains("null"), "{kc}");
}

/// A chain base -> rotor (continuous `spin`), and a mimic of `spin` off the
/// path with a large multiplier.
const SPIN: &str = r#"<robot name="s">
  <link name="base"/><link name="rotor"/><link name="lidar"/><link name="side"/>
  <joint name="spin" type="continuous"><parent link="base"/><child link="rotor"/><axis xyz="0 0 1"/></joint>
  <joint name="mount" type="fixed"><parent link="rotor"/><child link="lidar"/><origin xyz="0.2 0 0"/></joint>
  <joint name="follower" type="continuous"><parent link="base"/><child link="side"/><axis xyz="0 0 1"/>
    <mimic joint="spin" multiplier="1e300"/></joint>
</robot>
"#;

#[test]
fn joint_values_are_bounded_and_degrees_are_named() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("spin.urdf");
    std::fs::write(&p, SPIN).unwrap();
    let p = p.to_str().unwrap();
    let rig = [p, "--from", "base", "--to", "lidar", "--format", "json"];

    let (code, out, err) = run_cli(&[&rig[..], &["--joint", "spin=1e308"]].concat());
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("--joint") && err.contains("spin") && err.contains("1e308"),
        "{err}"
    );
    assert!(!err.contains("follower") && !err.contains("mimic"), "{err}");

    // 45 on a continuous joint: radians taken, with a named warning.
    let (code, out, err) = run_cli(&[&rig[..], &["--joint", "spin=45"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("warning[degrees-in-radian-field]"), "{err}");
    assert!(
        err.contains("spin.urdf:3:3") && err.contains("45 deg = 0.785398 rad"),
        "{err}"
    );
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let x = v["transform"]["translation_m"][0].as_f64().unwrap();
    assert!((x - 0.2 * 45f64.cos()).abs() < 1e-12, "{x}");

    // 1.5 rad: no warning.
    let (code, _, err) = run_cli(&[&rig[..], &["--joint", "spin=1.5"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("degrees-in-radian-field"), "{err}");
}
