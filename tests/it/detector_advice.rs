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
