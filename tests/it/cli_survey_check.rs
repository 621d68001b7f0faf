//! `audit survey` and `audit check` on the shipped calibrations: numbers against
//! the independent survey fixture (tests/fixtures/survey/make_expected.py), the
//! README table's freshness, exit codes 0/1/2, baselines, drift, annotations.

use crate::common::schema;

use serde_json::Value;
use std::path::Path;

use crate::common::audit;

fn run(args: &[&str]) -> (i32, String, String) {
    let out = audit().args(args).output().expect("run");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn num(v: &Value) -> f64 {
    v.as_f64().expect("number")
}

#[test]
fn survey_json_matches_independent_values() {
    let (code, out, err) = run(&["survey", "calibrations/", "--format", "json"]);
    assert_eq!(code, 0, "{err}");
    let j: Value = serde_json::from_str(&out).unwrap();
    let errs = schema::check(&j, &schema::survey_spec(), "$");
    assert!(errs.is_empty(), "{errs:?}");
    let fx: Value = serde_json::from_str(
        &std::fs::read_to_string("tests/fixtures/survey/expected.json").unwrap(),
    )
    .unwrap();
    let expected: Vec<&Value> = fx["rigs"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["in_statistics"].as_bool().unwrap())
        .collect();
    let rigs = j["rigs"].as_array().unwrap();
    assert_eq!(rigs.len(), expected.len());
    assert!(rigs.len() >= 19);
    for e in expected {
        let id = e["id"].as_str().unwrap();
        let r = rigs
            .iter()
            .find(|r| r["id"] == id)
            .unwrap_or_else(|| panic!("{id}"));
        let near =
            |a: f64, b: f64, what: &str| assert!((a - b).abs() <= 1e-9, "{id} {what}: {a} vs {b}");
        near(num(&r["lever_arm_m"]), num(&e["lever_arm_m"]), "lever arm");
        near(num(&r["angle_deg"]), num(&e["angle_deg"]), "angle");
        near(num(&r["sigma_max"]), num(&e["sigma_max"]), "sigma_max");
        near(num(&r["band_l1"][0]), num(&e["band_l1"][0]), "band lower");
        near(num(&r["band_l1"][1]), num(&e["band_l1"][1]), "band upper");
        assert_eq!(r["zero_pitch"], e["zero_pitch"], "{id}");
        assert_eq!(
            r["adapted_metric_exists"], e["adapted_metric_exists"],
            "{id}"
        );
        match (r["screw_translation_m"].as_f64(), e["h"].as_f64()) {
            (None, None) => {}
            (Some(h), Some(hx)) if e["near_half_turn"].as_bool().unwrap() => {
                near(h.abs(), hx.abs(), "|h|")
            }
            (Some(h), Some(hx)) => near(h, hx, "h"),
            (a, b) => panic!("{id}: h {a:?} vs {b:?}"),
        }
    }
    let s = &j["summary"];
    let sx = &fx["summary"];
    assert_eq!(s["count"], sx["count"]);
    assert_eq!(s["nonzero_pitch_count"], sx["nonzero_pitch_count"]);
    for k in ["lever_arm_min_m", "lever_arm_median_m", "lever_arm_max_m"] {
        assert!((num(&s[k]) - num(&sx[k])).abs() <= 1e-12, "{k}");
    }
    // The zero-pitch rig of the issue.
    let z = rigs
        .iter()
        .find(|r| r["id"] == "liosam-mid360-9axis")
        .unwrap();
    assert_eq!(z["zero_pitch"], Value::Bool(true));
    assert_eq!(z["adapted_metric_exists"], Value::Bool(true));
}

#[test]
fn survey_table_summary_line() {
    let (code, out, _) = run(&["survey", "calibrations/"]);
    assert_eq!(code, 0);
    assert!(out.contains(
        "38 rigs; lever arm min 0.0315 m, median 0.0755 m, max 1.7707 m; 37 of 38 with nonzero pitch"
    ), "{out}");
    // Sorting and CSV.
    let (code, out, _) = run(&[
        "survey",
        "calibrations/",
        "--format",
        "csv",
        "--sort",
        "lever-arm",
    ]);
    assert_eq!(code, 0);
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[0].starts_with("id,sensor,platform,dataset,from,to,lever_arm_m"));
    assert_eq!(lines.len(), 39);
    assert!(
        lines[1].starts_with("ouster-os0-128-fw2.3,"),
        "smallest lever arm first"
    );
    assert!(
        lines[38].starts_with("mulran-os1-64-liosam,"),
        "largest last"
    );
    // --all lists the placeholders and the sidecar twin, marked.
    let (_, out, _) = run(&["survey", "calibrations/", "--all"]);
    assert!(out.contains("fastlio-ouster64 (placeholder)"));
    assert!(out.contains("(duplicate of anymal-d-lidar-imu)"));
    assert!(out.contains("38 rigs;"), "placeholders never counted");
}

/// calibrations/README.md carries the markdown survey; `BLESS=1` rewrites it.
#[test]
fn calibrations_readme_table_is_current() {
    let (code, table, _) = run(&["survey", "calibrations/", "--format", "markdown"]);
    assert_eq!(code, 0);
    let path = Path::new("calibrations/README.md");
    let readme = std::fs::read_to_string(path).unwrap();
    let (b, e) = ("<!-- survey:begin -->\n", "<!-- survey:end -->");
    let start = readme.find(b).expect("begin marker") + b.len();
    let end = readme.find(e).expect("end marker");
    let current = &readme[start..end];
    if current != table {
        if std::env::var_os("BLESS").is_some() {
            let new = format!("{}{}{}", &readme[..start], table, &readme[end..]);
            std::fs::write(path, new).unwrap();
        } else {
            panic!(
                "calibrations/README.md survey block is out of date; regenerate with\n  BLESS=1 cargo test --test cli_survey_check calibrations_readme_table_is_current"
            );
        }
    }
}

#[test]
fn check_shipped_calibrations() {
    // Four published rotations are printed with 4 to 6 digits: rounding, a
    // warning that does not fail the gate (docs/check.md).
    let (code, out, err) = run(&["check", "calibrations/"]);
    assert_eq!(code, 0, "{out}{err}");
    let flagged: Vec<&str> = out
        .lines()
        .filter(|l| l.contains("warning[non-orthonormal-rotation]"))
        .map(|l| l.split(':').next().unwrap())
        .collect();
    assert_eq!(
        flagged,
        [
            "calibrations/geode-alpha-vlp16.toml",
            "calibrations/geode-beta-os1-64.toml",
            "calibrations/geode-gamma-avia.toml",
            "calibrations/m3dgr-avia-d435i-imu.toml"
        ]
    );
    assert!(
        out.contains("||R^T R - I||_F = 1.272e-4"),
        "GEODE alpha's 4-digit rotation: {out}"
    );
    assert!(
        out.contains("checked 42 files: 0 problems, 4 warnings"),
        "{out}"
    );
    // Refused by name: a problem.
    let (code, out, _) = run(&[
        "check",
        "calibrations/",
        "--deny",
        "non-orthonormal-rotation",
    ]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("checked 42 files: 4 problems"), "{out}");
    let (code, _, _) = run(&["check", "calibrations/", "--allow", "no-such-warning"]);
    assert_eq!(code, 2);
}

/// A FAST-LIO config with the Avia rotation block `r` (row-major) and translation `t`.
fn fast_lio(t: [f64; 3], r: [i32; 9]) -> String {
    format!(
        "mapping:\n  extrinsic_T: [ {}, {}, {} ]\n  extrinsic_R: [ {}, {}, {},\n                 {}, {}, {},\n                 {}, {}, {}]\n",
        t[0], t[1], t[2], r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8]
    )
}

#[test]
fn check_exit_codes_findings_and_baseline() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("rig.yaml");
    // FAST-LIO style, Avia numbers.
    std::fs::write(
        &good,
        fast_lio([0.04165, 0.02326, -0.0284], [1, 0, 0, 0, 1, 0, 0, 0, 1]),
    )
    .unwrap();
    let base = dir.path().join("baseline.json");
    let (code, out, err) = run(&[
        "check",
        good.to_str().unwrap(),
        "--pair",
        "imu:lidar",
        "--write-baseline",
        base.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let b: Value = serde_json::from_str(&std::fs::read_to_string(&base).unwrap()).unwrap();
    assert_eq!(b["schema_version"], 1);
    // Keyed relative to the baseline's directory.
    let rec = &b["files"]["rig.yaml"];
    assert!((num(&rec["edges"][0]["translation_m"][0]) - 0.04165).abs() < 1e-15);
    assert_eq!(rec["pairs"][0]["screw_kind"], "pure_translation");

    let (good_s, base_s) = (good.to_str().unwrap(), base.to_str().unwrap());
    let against_baseline = |extra: &[&str]| {
        let mut a = vec!["check", good_s, "--pair", "imu:lidar", "--baseline", base_s];
        a.extend_from_slice(extra);
        run(&a)
    };
    // Unchanged: clean against the baseline.
    let (code, out, _) = against_baseline(&[]);
    assert_eq!(code, 0, "{out}");

    // Drift of 2 mm: a finding, exit 1, and a GitHub annotation.
    std::fs::write(
        &good,
        fast_lio([0.04365, 0.02326, -0.0284], [1, 0, 0, 0, 1, 0, 0, 0, 1]),
    )
    .unwrap();
    let (code, out, _) = against_baseline(&["--format", "github"]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("::error file="), "{out}");
    assert!(out.contains("title=drift::"), "{out}");
    assert!(out.contains("moved 2.000 mm (tolerance 1.000 mm)"), "{out}");
    // 2 mm is within a 5 mm tolerance.
    let (code, _, _) = against_baseline(&["--max-translation-drift", "0.005"]);
    assert_eq!(code, 0);

    // Verdict change: a rotation appears (pure translation -> general screw).
    std::fs::write(
        &good,
        fast_lio([0.04165, 0.02326, -0.0284], [0, -1, 0, 1, 0, 0, 0, 0, 1]),
    )
    .unwrap();
    let (code, out, _) = against_baseline(&["--format", "json"]);
    assert_eq!(code, 1);
    let j: Value = serde_json::from_str(&out).unwrap();
    let codes: Vec<&str> = j["findings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["code"].as_str().unwrap())
        .collect();
    assert!(
        codes.contains(&"verdict-changed") && codes.contains(&"drift"),
        "{codes:?}"
    );

    // Policy checks.
    let (code, out, _) = run(&[
        "check",
        good.to_str().unwrap(),
        "--pair",
        "imu:lidar",
        "--max-lever-arm",
        "0.05",
    ]);
    assert_eq!(code, 1);
    assert!(
        out.contains("lever arm 0.055519 m exceeds --max-lever-arm 0.05 m"),
        "{out}"
    );
    let (code, out, _) = run(&[
        "check",
        good.to_str().unwrap(),
        "--pair",
        "imu:lidar",
        "--require-zero-pitch",
    ]);
    assert_eq!(code, 1);
    assert!(out.contains("nonzero-pitch"), "{out}");
    let (code, _, _) = run(&[
        "check",
        "calibrations/liosam-mid360-9axis.toml",
        "--require-zero-pitch",
    ]);
    assert_eq!(code, 0, "the zero-pitch rig passes --require-zero-pitch");

    // A non-unit quaternion and a file that does not parse: findings (1).
    let bad = dir.path().join("bad");
    std::fs::create_dir(&bad).unwrap();
    std::fs::write(
        bad.join("echo.yaml"),
        "transforms:\n- header:\n    frame_id: imu\n  child_frame_id: lidar\n  transform:\n    translation: {x: 0.1, y: 0.0, z: 0.0}\n    rotation: {x: 0.0, y: 0.0, z: 0.0, w: 1.01}\n",
    )
    .unwrap();
    std::fs::write(
        bad.join("broken.urdf"),
        "<robot name=\"r\"><link name=\"a\"/>",
    )
    .unwrap();
    let (code, out, _) = run(&["check", bad.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("error[non-unit-quaternion]"), "{out}");
    assert!(out.contains("broken.urdf"), "{out}");

    // Unreadable input and usage errors: 2.
    let (code, _, err) = run(&["check", dir.path().join("missing.yaml").to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("missing.yaml"), "{err}");
    std::fs::write(&base, "{ not json").unwrap();
    let (code, _, err) = run(&[
        "check",
        good.to_str().unwrap(),
        "--baseline",
        base.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("baseline.json:1"), "{err}");
    let (code, _, _) = run(&["check", good.to_str().unwrap(), "--pair", "nocolon"]);
    assert_eq!(code, 2);
}

#[test]
fn check_pair_frames_must_exist() {
    let (code, out, _) = run(&[
        "check",
        "calibrations/fastlio-avia.toml",
        "--pair",
        "imu:velodyne",
    ]);
    assert_eq!(code, 1);
    assert!(
        out.contains("--pair imu:velodyne: no checked file has both frames"),
        "{out}"
    );
}
