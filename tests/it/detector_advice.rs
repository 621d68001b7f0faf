//! `audit FILE --detector NAME`: what the user's own detector does on each
//! shipped rig, its threshold carried into the `--from` frame by the
//! certificate band (numpy's band values: the unit tests of
//! `analysis::detectors` against tests/fixtures/detectors/detector_checks.json).

use crate::common::run_cli;
use serde_json::Value;

fn report(args: &[&str]) -> Value {
    let (code, out, err) = run_cli(args);
    assert_eq!(code, 0, "{args:?}: {err}");
    serde_json::from_str(&out).unwrap()
}

/// On every shipped rig: LIO-SAM's threshold 100 acts in the rig's `from`
/// frame between 100 s_min^2 (1 - |sin p|) and 100 s_max^2 (1 + |sin p|), the
/// band the rig report prints at l = 1 m and the pitch of its rotation;
/// the statement cites LIO-SAM's source and names both numbers.
#[test]
fn lio_sam_threshold_band_on_every_shipped_rig() {
    let mut n = 0;
    for entry in std::fs::read_dir("calibrations").unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let path = p.to_str().unwrap();
        let v = report(&[
            path,
            "--detector",
            "lio-sam",
            "--ell",
            "1",
            "--format",
            "json",
        ]);
        let a = &v["detector"];
        let band = &v["certificate"][0]["band"];
        let r20 = v["transform"]["rotation_matrix"][2][0].as_f64().unwrap();
        let s = r20.abs(); // |sin p|, p = asin(-R[2][0])
        let want = [
            100.0 * band[0].as_f64().unwrap() * (1.0 - s),
            100.0 * band[1].as_f64().unwrap() * (1.0 + s),
        ];
        let got = &a["threshold_in_from"];
        for k in 0..2 {
            let g = got[k].as_f64().unwrap();
            assert!(
                (g - want[k]).abs() <= 1e-9 * want[k].max(1.0),
                "{path}: {got} against {want:?}"
            );
        }
        let st = a["statement"].as_str().unwrap();
        assert!(
            st.contains(&format!("between {:.2} and {:.2}", want[0], want[1])),
            "{path}: {st}"
        );
        assert!(a["detector"]["source"]
            .as_str()
            .unwrap()
            .contains("TixiaoShan/LIO-SAM @ 0be1fbe6"));
        n += 1;
    }
    assert!(n >= 30, "{n} rigs");
}

/// A FAST-LIO config reveals FAST-LIO without the flag: no detector, and a
/// threshold added on its IMU-frame H said in numbers of this rig.
#[test]
fn a_fast_lio_config_reveals_its_odometry() {
    let v = report(&[
        "tests/fixtures/formats/fastlio_avia.yaml",
        "--format",
        "json",
    ]);
    let a = &v["detector"];
    assert_eq!(a["detector"]["name"], "fast-lio");
    assert_eq!(a["detector"]["dependence"], "no_detector");
    assert!(a["threshold_in_from"].is_null());
    assert!(a["statement"]
        .as_str()
        .unwrap()
        .starts_with("FAST-LIO has no degeneracy detector"));
    let (code, out, _) = run_cli(&["tests/fixtures/formats/fastlio_avia.yaml"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("Your detector: FAST-LIO") && out.contains("To do (FAST-LIO):"),
        "{out}"
    );
    // DCReg on the same rig: frame-dependent, unbounded; a typo lists the names.
    let v = report(&[
        "tests/fixtures/formats/fastlio_avia.yaml",
        "--detector",
        "dcreg",
        "--format",
        "json",
    ]);
    assert_eq!(v["detector"]["frame_dependent"], true);
    assert!(v["detector"]["threshold_in_from"].is_null());
    let (code, _, err) = run_cli(&[
        "tests/fixtures/formats/fastlio_avia.yaml",
        "--detector",
        "lio_sa",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("expected one of lio-sam, lego-loam"), "{err}");
}

/// The headline's "To do" in markdown (one line, the report's first).
fn to_do(args: &[&str]) -> String {
    let mut a = args.to_vec();
    a.extend(["--format", "markdown"]);
    let (code, out, err) = run_cli(&a);
    assert_eq!(code, 0, "{args:?}: {err}");
    let first = out.lines().next().unwrap();
    first[first.find("To do").expect(first)..]
        .trim_end_matches("**")
        .to_string()
}

/// The "To do" says this rig's numbers: the certificate band at l = 1 m (as
/// the JSON has it), the lever arm, and h when the pitch rules out M0; so no
/// two shipped rigs with different numbers share a sentence (it was one
/// sentence on 37 of 38).
#[test]
fn the_to_do_line_names_this_rigs_band_lever_arm_and_pitch() {
    let mut sentences = std::collections::HashSet::new();
    let mut rigs = std::collections::HashSet::new();
    for entry in std::fs::read_dir("calibrations").unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let path = p.to_str().unwrap();
        let v = report(&[path, "--format", "json"]);
        if v["screw"]["kind"] == "identity" {
            continue; // "Every metric is frame-invariant here: use any."
        }
        let line = to_do(&[path]);
        let lever = v["lever_arm_m"].as_f64().unwrap();
        let c = v["certificate"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["ell_m"] == 1.0)
            .unwrap();
        let band = [
            c["band"][0].as_f64().unwrap(),
            c["band"][1].as_f64().unwrap(),
        ];
        if lever > 0.0 {
            // ratio(): four significant digits.
            let sig4 = |x: f64| format!("{:.*}", (3 - x.log10().floor() as i32).max(0) as usize, x);
            assert!(
                line.contains(&format!(
                    "{} to {} times itself (lever arm {lever:.3} m, l = 1 m)",
                    sig4(band[0]),
                    sig4(band[1])
                )),
                "{path}: {line} ({band:?})"
            );
        } else {
            assert!(
                line.contains("unchanged (zero lever arm)"),
                "{path}: {line}"
            );
        }
        if v["screw"]["kind"] == "pure_translation" {
            // No screw axis and no h: the verdict is "nonzero" (infinite
            // pitch, issue 33) and the line says why in the lever arm's terms.
            assert!(
                line.contains(&format!(
                    "no constant metric is invariant under a pure translation of {lever:.3} m"
                )),
                "{path}: {line}"
            );
        } else if v["screw"]["pitch_verdict"] == "nonzero" {
            let h = v["screw"]["translation_along_axis_m"].as_f64().unwrap();
            assert!(
                line.contains("rules out an adapted metric M0"),
                "{path}: {line}"
            );
            let said: f64 = line
                .split("h = ")
                .nth(1)
                .unwrap()
                .split(' ')
                .next()
                .unwrap()
                .parse()
                .unwrap();
            assert!((said - h).abs() <= 1e-3 * h.abs(), "{path}: {line} ({h})");
        }
        rigs.insert(format!(
            "{} {} {lever:.3} {band:?} {}",
            v["from"], v["to"], v["screw"]["translation_along_axis_m"]
        ));
        sentences.insert(line);
    }
    assert!(rigs.len() >= 30, "{} rigs", rigs.len());
    assert_eq!(sentences.len(), rigs.len());
}

/// A LiDAR 1 m above the IMU, level: the band at |d| / l = 1 is [1 / phi^2,
/// phi^2] (closed form, phi the golden ratio); with `--detector lio-sam` the
/// "To do" is LIO-SAM's step, its threshold 100 scaled into [38.20, 261.80].
#[test]
fn the_to_do_line_takes_the_detectors_step() {
    let dir = tempfile::tempdir().unwrap();
    let rig = dir.path().join("up.toml");
    std::fs::write(
        &rig,
        "[rig]\nid = \"up\"\nsensor = \"s\"\nplatform = \"p\"\ndataset = \"d\"\n\
         category = \"cad-or-nominal\"\nlicence = \"authored\"\ndirection = \"x\"\nfrom = \"imu\"\nto = \"lidar\"\n\n\
         [rig.source]\nrepo = \"a/b\"\npath = \"p\"\ncommit = \"0000000000000000000000000000000000000000\"\n\n\
         [[transform]]\nparent = \"imu\"\nchild = \"lidar\"\nunit = \"m\"\nsource_key = \"k\"\n\
         translation = [0.0, 0.0, 1.0]\nrpy = [0.0, 0.0, 0.0]\n",
    )
    .unwrap();
    let path = rig.to_str().unwrap();
    let phi2 = ((1.0 + 5f64.sqrt()) / 2.0).powi(2);
    assert_eq!(format!("{:.4} {:.3}", 1.0 / phi2, phi2), "0.3820 2.618");
    assert_eq!(
        to_do(&[path]),
        "To do: use the point-displacement metric (frame-invariant on every rig): no constant metric is invariant under a pure translation of 1.000 m, and an eigenvalue threshold tuned in lidar acts in imu as 0.3820 to 2.618 times itself (lever arm 1.000 m, l = 1 m)."
    );
    let line = to_do(&[path, "--detector", "lio-sam"]);
    assert!(
        line.starts_with("To do (LIO-SAM): do not carry the threshold 100 to a detector in imu (or the IMU) on this rig without scaling it into [38.20, 261.80]"),
        "{line}"
    );
    assert!(
        line.ends_with("no constant metric is invariant under a pure translation of 1.000 m."),
        "{line}"
    );
}

const CONFIG: &str = "tests/fixtures/detectors/config";

/// numpy's bands for the configured thresholds on the authored rig
/// (detector_checks.py section 10: eigenvalues of `A^T A`, `H_B = I`).
fn configured_examples() -> Vec<(f64, [f64; 2])> {
    let path = "tests/fixtures/detectors/detector_checks.json";
    let v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v["configured_threshold_examples"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            let b = &e["threshold_in_base_link"];
            (
                e["tau"].as_f64().unwrap(),
                [b[0].as_f64().unwrap(), b[1].as_f64().unwrap()],
            )
        })
        .collect()
}

/// An authored DCReg configuration beside the rig reveals DCReg without
/// `--detector`, with the file's thresholds (25 and 150, not the defaults 10
/// and 120); its eigenvalue threshold 150 acts in base_link between numpy's
/// two numbers, which differ from the default 120's; the file adds no edge.
#[test]
fn a_dcreg_configuration_reveals_dcreg_with_its_thresholds() {
    let rig = format!("{CONFIG}/rig_base_lidar.toml");
    let cfg = format!("{CONFIG}/dcreg_icp.yaml");
    let v = report(&[&rig, &cfg, "--format", "json"]);
    let a = &v["detector"];
    assert_eq!(a["detector"]["name"], "dcreg");
    assert_eq!(a["detector"]["threshold"], 25.0);
    let c = &a["config"];
    assert_eq!(c["file"], cfg.as_str());
    assert!(c["source"]
        .as_str()
        .unwrap()
        .starts_with("JokerJohn/DCReg @ 18b173c862e9"));
    let th = c["thresholds"].as_array().unwrap();
    assert_eq!(th.len(), 2);
    assert_eq!(th[0]["key"], "degeneracy.condition_threshold");
    assert_eq!(
        (th[0]["value"].as_f64(), th[0]["line"].as_u64()),
        (Some(25.0), Some(17))
    );
    assert!(th[0]["threshold_in_from"].is_null());
    assert_eq!(th[1]["key"], "degeneracy.eigenvalue_threshold");
    assert_eq!(
        (th[1]["value"].as_f64(), th[1]["line"].as_u64()),
        (Some(150.0), Some(18))
    );
    let examples = configured_examples();
    let (tau, want) = examples[0];
    assert_eq!(tau, 150.0);
    let got = [
        th[1]["threshold_in_from"][0].as_f64().unwrap(),
        th[1]["threshold_in_from"][1].as_f64().unwrap(),
    ];
    for k in 0..2 {
        assert!(
            (got[k] - want[k]).abs() <= 1e-9 * want[k],
            "{got:?} against {want:?}"
        );
    }
    // The default threshold's band is another pair of numbers.
    let (tau0, default) = examples[1];
    assert_eq!(tau0, 120.0);
    assert!((got[0] - default[0]).abs() > 1.0 && (got[1] - default[1]).abs() > 1.0);
    let st = a["statement"].as_str().unwrap();
    let between = format!("between {:.2} and {:.2}", want[0], want[1]);
    assert!(
        st.contains("your configuration replaces the defaults: degeneracy.condition_threshold = 25 (dcreg_icp.yaml:17; DEGENERACY_THRES_COND, default 10)")
            && st.contains(&between),
        "{st}"
    );
    assert!(a["step"].as_str().unwrap().contains(&between));
    // The configuration adds no edge: one source, the rig.
    assert_eq!(
        v["sources"].as_array().unwrap().len(),
        1,
        "{}",
        v["sources"]
    );
    // The text report says it in the detector's section.
    let (code, out, err) = run_cli(&[&rig, &cfg]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("Your detector: DCReg") && out.contains(&between),
        "{out}"
    );
}

/// An authored X-ICP (libpointmatcher) configuration reveals X-ICP with its
/// method's thresholds; they are frame-invariant: no band.
#[test]
fn an_xicp_configuration_reveals_xicp_with_its_thresholds() {
    let rig = format!("{CONFIG}/rig_base_lidar.toml");
    let cfg = format!("{CONFIG}/xicp_icp.yaml");
    let v = report(&[&rig, &cfg, "--format", "json"]);
    let a = &v["detector"];
    assert_eq!(a["detector"]["name"], "x-icp");
    assert_eq!(a["detector"]["threshold"], 250.0);
    assert_eq!(a["frame_dependent"], false);
    let th = a["config"]["thresholds"].as_array().unwrap();
    let keys: Vec<(&str, f64, u64)> = th
        .iter()
        .map(|t| {
            (
                t["key"].as_str().unwrap(),
                t["value"].as_f64().unwrap(),
                t["line"].as_u64().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        keys,
        [
            (
                "degeneracyAwareness.OptimizedEqualityConstraints.enoughInformationThreshold",
                250.0,
                10
            ),
            (
                "degeneracyAwareness.OptimizedEqualityConstraints.insufficientInformationThreshold",
                120.0,
                11
            ),
        ]
    );
    assert!(th.iter().all(|t| t["threshold_in_from"].is_null()));
    // --detector naming another detector than the file's is refused.
    let (code, _, err) = run_cli(&[&rig, &cfg, "--detector", "dcreg"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("names another detector"), "{err}");
}

/// Bad values in a detector configuration: exit 2, the file and the line
/// of the value, what was expected and what was found.
#[test]
fn bad_detector_configuration_values_exit_2_at_their_line() {
    let dir = tempfile::tempdir().unwrap();
    let rig = format!("{CONFIG}/rig_base_lidar.toml");
    let text = std::fs::read_to_string(format!("{CONFIG}/dcreg_icp.yaml")).unwrap();
    for (from, to, line, want) in [
        ("condition_threshold: 25.0", "condition_threshold: ten", 17, "expected a number for `degeneracy.condition_threshold` (DEGENERACY_THRES_COND), found a string `ten`"),
        ("condition_threshold: 25.0", "condition_threshold: 0.5", 17, "expected at least 1"),
        ("eigenvalue_threshold: 150.0", "eigenvalue_threshold: -3", 18, "expected a positive number for `degeneracy.eigenvalue_threshold`"),
        ("eigenvalue_threshold: 150.0", "eigenvalue_threshold: [1, 2]", 18, "found a list"),
        ("  eigenvalue_threshold: 150.0\n", "", 17, "expected `degeneracy.eigenvalue_threshold` (DEGENERACY_THRES_EIG)"),
    ] {
        let bad = dir.path().join("icp.yaml");
        assert!(text.contains(from));
        std::fs::write(&bad, text.replace(from, to)).unwrap();
        let (code, out, err) = run_cli(&[&rig, bad.to_str().unwrap()]);
        assert_eq!(code, 2, "{to}: {out}{err}");
        let at = format!("icp.yaml:{line}:");
        assert!(err.contains(&at) && err.contains(want), "{to}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    // A configuration alone: no calibration beside it.
    let (code, _, err) = run_cli(&[&format!("{CONFIG}/dcreg_icp.yaml")]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("expected calibration files beside the detector configuration"),
        "{err}"
    );
}

/// `audit check` over a tree that keeps a detector's configuration beside
/// the calibrations (DCReg's icp.yaml, X-ICP's): the file is noted as that
/// detector's configuration and its values are checked as the detector
/// reads them, instead of failing the gate as "no transform found"; a bad
/// value fails the gate at its line.
#[test]
fn check_notes_a_detector_configuration_and_checks_its_values() {
    let dir = tempfile::tempdir().unwrap();
    for f in ["rig_base_lidar.toml", "dcreg_icp.yaml", "xicp_icp.yaml"] {
        std::fs::copy(format!("{CONFIG}/{f}"), dir.path().join(f)).unwrap();
    }
    let d = dir.path().to_str().unwrap();
    let (code, out, err) = run_cli(&["check", d]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains("DCReg configuration: detector thresholds, no sensor extrinsic"),
        "{out}"
    );
    assert!(out.contains("X-ICP configuration"), "{out}");
    assert!(!out.contains("no transform found"), "{out}");
    let text = std::fs::read_to_string(dir.path().join("dcreg_icp.yaml")).unwrap();
    let bad = text.replace("condition_threshold: 25.0", "condition_threshold: ten");
    std::fs::write(dir.path().join("dcreg_icp.yaml"), bad).unwrap();
    let (code, out, err) = run_cli(&["check", d]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(out.contains("dcreg_icp.yaml:17:"), "{out}");
    assert!(out.contains("found a string `ten`"), "{out}");
}
