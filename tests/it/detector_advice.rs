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
