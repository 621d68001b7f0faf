//! `audit diff OLD NEW`: real pairs (ANYmal C against ANYmal D, the ANYmal D
//! URDF against its rig TOML) and authored ones (FAST-LIO and Kalibr-style
//! extrinsics of ANYmal D with known changes, frames matched with renames),
//! every figure checked against tests/fixtures/diff/expected.json (numpy +
//! pytransform3d, gen_expected.py beside it); the JSON against
//! docs/schemas/diff.schema.json; exit 1 beyond --tolerance, 0 within, 2 on
//! bad input.

use crate::common::run_cli;
use serde_json::Value;

const D: &str = "calibrations/anymal-d.urdf";
const D_TOML: &str = "calibrations/anymal-d-lidar-imu.toml";
const FASTLIO: &str = "tests/fixtures/diff/anymal_d_fastlio.yaml";

fn expected() -> Value {
    let p = format!(
        "{}/tests/fixtures/diff/expected.json",
        env!("CARGO_MANIFEST_DIR")
    );
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

fn validator() -> jsonschema::Validator {
    let p = format!(
        "{}/docs/schemas/diff.schema.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let s: Value = serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
    jsonschema::validator_for(&s).expect("schema")
}

/// `audit diff ARGS --format json`: (exit code, the validated report).
fn diff_json(args: &[&str]) -> (i32, Value) {
    let mut a = vec!["diff"];
    a.extend_from_slice(args);
    a.extend_from_slice(&["--format", "json"]);
    let (code, out, err) = run_cli(&a);
    assert!(code == 0 || code == 1, "{a:?}: exit {code}: {err}");
    let v: Value = serde_json::from_str(&out).expect("JSON");
    let errors: Vec<String> = validator()
        .iter_errors(&v)
        .map(|e| format!("{e} at {}", e.instance_path))
        .collect();
    assert!(errors.is_empty(), "{errors:#?}");
    assert_eq!(v["exceeded"].as_array().unwrap().is_empty(), code == 0);
    (code, v)
}

fn close(a: &Value, b: &Value, tol: f64) {
    let (x, y) = (a.as_f64().unwrap(), b.as_f64().unwrap());
    assert!((x - y).abs() <= tol, "{x} vs {y}");
}

fn edge<'a>(v: &'a Value, parent: &str, child: &str) -> &'a Value {
    v["edges"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["parent"] == parent && e["child"] == child)
        .unwrap_or_else(|| panic!("no edge {parent} -> {child}"))
}

#[test]
fn anymal_c_against_anymal_d() {
    let anymal_c = crate::real!(crate::common::testdata::ANYMAL_C);
    let anymal_c = anymal_c.to_str().unwrap();
    let x = &expected()["anymal_c_vs_d"];
    let (code, v) = diff_json(&[anymal_c, D, "--from", "base", "--to", "lidar"]);
    assert_eq!(code, 1);
    let c = &v["chain"];
    close(
        &c["translation_change_mm"],
        &x["chain"]["translation_change_mm"],
        1e-9,
    );
    close(
        &c["rotation_change_deg"],
        &x["chain"]["rotation_change_deg"],
        1e-6,
    );
    for side in ["old", "new"] {
        close(&c["lever_arm_m"][side], &x[side]["lever_arm_m"], 1e-12);
        close(&c["angle_deg"][side], &x[side]["angle_deg"], 1e-6);
        let h = c["screw_translation_m"][side].as_f64().unwrap().abs();
        close(&h.into(), &x[side]["abs_h_m"], 1e-9);
        let l1 = c["bands"]
            .as_array()
            .unwrap()
            .iter()
            .find(|b| b["ell_m"] == 1.0)
            .unwrap();
        for i in 0..2 {
            close(&l1["band"][side][i], &x[side]["band_l1"][i], 1e-12);
        }
        for i in 0..3 {
            close(
                &c["translation_m"][side][i],
                &x[side]["translation_m"][i],
                1e-12,
            );
        }
    }
    // The IMU moved by half a metre and turned over between the two robots.
    let imu = edge(&v, "base", "imu_link");
    assert_eq!(imu["status"], "changed");
    assert_eq!(imu["exceeds"], true);
    close(
        &imu["translation_change_mm"],
        &x["edge_base_imu_link"]["translation_change_mm"],
        1e-9,
    );
    close(
        &imu["rotation_change_deg"],
        &x["edge_base_imu_link"]["rotation_change_deg"],
        1e-6,
    );
    // ANYmal C reaches the LiDAR through lidar_cage, ANYmal D through lidar_parent.
    for (p, ch, status) in [
        ("base", "lidar_cage", "removed"),
        ("lidar_cage", "lidar", "removed"),
        ("base", "lidar_parent", "added"),
        ("lidar_parent", "lidar", "added"),
    ] {
        let e = edge(&v, p, ch);
        assert_eq!(
            (e["status"].as_str(), e["on_chain"].as_bool()),
            (Some(status), Some(true))
        );
    }
    // Text and markdown carry the same verdict.
    let (code, md, _) = run_cli(&[
        "diff", anymal_c, D, "--from", "base", "--to", "lidar", "--format", "markdown",
    ]);
    assert_eq!(code, 1);
    assert!(
        md.contains("beyond the tolerance")
            && md.contains("| lever arm (m) | 0.3908 | 0.3482 | -0.0426 |"),
        "{md}"
    );
    assert!(
        md.contains("| base -> lidar_parent (chain) | added |"),
        "{md}"
    );
}

#[test]
fn a_urdf_against_its_rig_toml_is_unchanged() {
    let x = &expected()["urdf_vs_toml"];
    // The rig TOML declares imu_link -> lidar: no --from/--to needed.
    let (code, v) = diff_json(&[D, D_TOML]);
    assert_eq!(code, 0);
    assert_eq!(
        (v["from"].as_str(), v["to"].as_str()),
        (Some("imu_link"), Some("lidar"))
    );
    close(
        &v["chain"]["translation_change_mm"],
        &x["chain"]["translation_change_mm"],
        1e-9,
    );
    close(
        &v["chain"]["rotation_change_deg"],
        &x["chain"]["rotation_change_deg"],
        1e-6,
    );
    close(
        &v["chain"]["lever_arm_m"]["old"],
        &x["old"]["lever_arm_m"],
        1e-12,
    );
    let unchanged: Vec<(&str, &str)> = v["edges"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["status"] == "unchanged")
        .map(|e| (e["parent"].as_str().unwrap(), e["child"].as_str().unwrap()))
        .collect();
    assert_eq!(
        unchanged,
        [
            ("base", "imu_link"),
            ("base", "lidar_parent"),
            ("lidar_parent", "lidar")
        ]
    );
    assert!(v["edges"]
        .as_array()
        .unwrap()
        .iter()
        .all(|e| e["status"] != "changed"));
    let (code, text, _) = run_cli(&["diff", D, D_TOML]);
    assert_eq!(code, 0);
    assert!(
        text.starts_with("imu_link -> lidar: no change beyond the tolerance"),
        "{text}"
    );
}

#[test]
fn a_urdf_against_a_fastlio_extrinsic_with_renames() {
    let x = &expected()["urdf_vs_fastlio"];
    let args = [
        D,
        FASTLIO,
        "--from",
        "imu_link",
        "--to",
        "lidar",
        "--rename",
        "anymal_d_fastlio.yaml:imu=imu_link",
    ];
    let (code, v) = diff_json(&args);
    assert_eq!(code, 1, "2.2 mm and 0.2 deg exceed 1 mm, 0.05 deg");
    close(
        &v["chain"]["translation_change_mm"],
        &x["chain"]["translation_change_mm"],
        1e-9,
    );
    close(
        &v["chain"]["rotation_change_deg"],
        &x["chain"]["rotation_change_deg"],
        1e-9,
    );
    close(
        &v["chain"]["lever_arm_m"]["new"],
        &x["new"]["lever_arm_m"],
        1e-12,
    );
    let h = v["chain"]["screw_translation_m"]["new"]
        .as_f64()
        .unwrap()
        .abs();
    close(&h.into(), &x["new"]["abs_h_m"], 1e-9);
    assert_eq!(edge(&v, "imu_link", "lidar")["status"], "added");
    // Within a looser tolerance: exit 0.
    let loose = [&args[..], &["--tolerance", "2.5,0.25"]].concat();
    assert_eq!(diff_json(&loose).0, 0);
    let tight = [&args[..], &["--tolerance", "2.5,0.15"]].concat();
    assert_eq!(diff_json(&tight).0, 1);
}

#[test]
fn a_file_against_itself_is_unchanged_everywhere() {
    let anymal_c = crate::real!(crate::common::testdata::ANYMAL_C);
    let anymal_c = anymal_c.to_str().unwrap();
    let (code, v) = diff_json(&[anymal_c, anymal_c, "--from", "base", "--to", "lidar"]);
    assert_eq!(code, 0);
    assert_eq!(v["chain"]["translation_change_mm"], 0.0);
    assert!(v["edges"]
        .as_array()
        .unwrap()
        .iter()
        .all(|e| e["status"] == "unchanged"));
    assert!(v["chain"]["detectors"]
        .as_array()
        .unwrap()
        .iter()
        .all(|d| d["changed"] == false));
}

#[test]
fn bad_input_exits_2_with_a_message() {
    let anymal_c = "tests/fixtures/urdf/anymal_c_lidar.urdf";
    let cases: [(&[&str], &str); 6] = [
        (
            &[
                "diff",
                anymal_c,
                "no/such.urdf",
                "--from",
                "base",
                "--to",
                "lidar",
            ],
            "no/such.urdf",
        ),
        (
            &[
                "diff",
                anymal_c,
                D,
                "--from",
                "base",
                "--to",
                "lidar",
                "--tolerance",
                "1",
            ],
            "LENGTH,ANGLE",
        ),
        (
            &[
                "diff",
                anymal_c,
                D,
                "--from",
                "base",
                "--to",
                "lidar",
                "--tolerance",
                "1,-2",
            ],
            "-2",
        ),
        (&["diff", anymal_c, D, "--from", "base"], "--to"),
        (
            &["diff", anymal_c, D, "--from", "base", "--to", "nowhere"],
            "nowhere",
        ),
        (
            &[
                "diff",
                anymal_c,
                D,
                "--from",
                "base",
                "--to",
                "lidar",
                "--rename",
                "x.yaml:imu=i",
            ],
            "--rename",
        ),
    ];
    for (args, needle) in cases {
        let (code, _, err) = run_cli(args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn a_urdf_against_a_kalibr_matrix_within_tolerance() {
    let anymal_c = crate::real!(crate::common::testdata::ANYMAL_C);
    let anymal_c = anymal_c.to_str().unwrap();
    let x = &expected()["urdf_vs_kalibr"];
    let (code, v) = diff_json(&[
        D,
        "tests/fixtures/diff/anymal_d_kalibr.yaml",
        "--from",
        "imu_link",
        "--to",
        "lidar",
        "--rename",
        "anymal_d_kalibr.yaml:imu=imu_link",
    ]);
    assert_eq!(code, 0, "0.55 mm and 0.02 deg are within 1 mm, 0.05 deg");
    let c = &v["chain"];
    close(
        &c["translation_change_mm"],
        &x["chain"]["translation_change_mm"],
        1e-9,
    );
    close(
        &c["rotation_change_deg"],
        &x["chain"]["rotation_change_deg"],
        1e-9,
    );
    close(&c["lever_arm_m"]["new"], &x["new"]["lever_arm_m"], 1e-12);
    close(&c["angle_deg"]["new"], &x["new"]["angle_deg"], 1e-9);
    // OLD is an exact half-turn (h >= 0 by convention), NEW 0.02 deg short of
    // one: the axis, and the sign of h, flip between them; |h| barely moves.
    let (ho, hn) = (
        c["screw_translation_m"]["old"].as_f64().unwrap(),
        c["screw_translation_m"]["new"].as_f64().unwrap(),
    );
    assert!(ho > 0.0 && hn < 0.0, "{ho} {hn}");
    assert!((hn.abs() - x["new"]["abs_h_m"].as_f64().unwrap()).abs() < 1e-9);
    assert_eq!(c["screw_sign_flip_at_half_turn"], true);
    let (_, text, _) = run_cli(&[
        "diff",
        D,
        "tests/fixtures/diff/anymal_d_kalibr.yaml",
        "--from",
        "imu_link",
        "--to",
        "lidar",
        "--rename",
        "anymal_d_kalibr.yaml:imu=imu_link",
    ]);
    assert!(
        text.contains("|h| 0.0003 (sign flips at the half-turn)"),
        "{text}"
    );
    // A rig far from a half-turn never gets the note.
    let (_, same) = diff_json(&[anymal_c, anymal_c, "--from", "base", "--to", "lidar"]);
    assert_eq!(same["chain"]["screw_sign_flip_at_half_turn"], false);
}

fn key_invert_expected() -> Value {
    let p = format!(
        "{}/tests/fixtures/diff/key_invert_expected.json",
        env!("CARGO_MANIFEST_DIR")
    );
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

const GEODE_TOML: &str = "calibrations/geode-gamma-avia.toml";
const GEODE_YAML: &str = "tests/fixtures/formats/geode_gamma_opencv.yaml";

/// Per side `--key-new`: GEODE gamma's own config (several matrices, one key
/// given twice with different values) against its rig TOML: only
/// `T_IMU_LiDAR` is read, so nothing changed and no other edge is listed.
#[test]
fn key_new_reads_one_matrix_of_a_file_with_several() {
    let x = &key_invert_expected()["diff_toml_vs_key"];
    let (code, v) = diff_json(&[GEODE_TOML, GEODE_YAML, "--key-new", "T_IMU_LiDAR"]);
    assert_eq!(code, 0);
    assert_eq!(
        (v["from"].as_str(), v["to"].as_str()),
        (Some("IMU"), Some("LiDAR"))
    );
    close(
        &v["chain"]["translation_change_mm"],
        &x["translation_change_mm"],
        1e-9,
    );
    close(
        &v["chain"]["rotation_change_deg"],
        &x["rotation_change_deg"],
        1e-9,
    );
    assert_eq!(v["edges"].as_array().unwrap().len(), 1, "{v}");
    assert_eq!(edge(&v, "IMU", "LiDAR")["status"], "unchanged");
    // The report says how each file was read (nothing for a plain one).
    assert_eq!(
        v["new_read"],
        serde_json::json!({"key": "T_IMU_LiDAR", "inverted": false})
    );
    assert!(v.get("old_read").is_none(), "{v}");
    // Without the key every matrix is read: the camera pair is an added edge,
    // and the twice-given key is reported.
    let (_, _, err) = run_cli(&["diff", GEODE_TOML, GEODE_YAML, "--key-new", "T_IMU_LiDAR"]);
    assert!(!err.contains("ambiguous-key"), "{err}");
    let (code, v) = diff_json(&[GEODE_TOML, GEODE_YAML]);
    assert_eq!(code, 0);
    assert_eq!(edge(&v, "CamL", "CamR")["status"], "added");
    // The key applies to its side only: the rig TOML ignores --key-old with a warning.
    let (code, _, err) = run_cli(&["diff", GEODE_TOML, GEODE_YAML, "--key-old", "T_IMU_LiDAR"]);
    assert_eq!(code, 0);
    assert!(
        err.contains("--invert and --key do not apply to a rig TOML"),
        "{err}"
    );
    // A key the file lacks is bad input.
    let (code, _, err) = run_cli(&["diff", GEODE_TOML, GEODE_YAML, "--key-new", "T_nope"]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = run_cli(&[
        "diff",
        GEODE_TOML,
        GEODE_YAML,
        "--key",
        "a",
        "--key-new",
        "b",
    ]);
    assert_eq!(code, 2, "{err}");
}

/// `--invert` inverts both files, as `--key` picks a key in both: the same
/// report as `--invert-old --invert-new`, both sides marked inverted.
#[test]
fn invert_reads_both_files_the_other_way() {
    let common = [GEODE_TOML, GEODE_YAML, "--key-new", "T_IMU_LiDAR"];
    let (code, both) = diff_json(&[&common[..], &["--invert"]].concat());
    let (code_each, each) = diff_json(&[&common[..], &["--invert-old", "--invert-new"]].concat());
    assert_eq!(code, code_each);
    assert_eq!(both, each);
    assert_eq!(both["old_read"]["inverted"], true);
    assert_eq!(both["new_read"]["inverted"], true);
    // Inverting one side only moves the chain (exit 1); both sides, not.
    let (code_new, _) = diff_json(&[&common[..], &["--invert-new"]].concat());
    assert_eq!((code, code_new), (0, 1));
}

/// `--invert-new`: the new file's numbers read as the pose of the parent in
/// the child: IMU -> LiDAR is the inverse of T_IMU_LiDAR, a change of
/// |d_inv - d| and twice the angle (numpy, key_invert_expected.json); the
/// lever arm, angle and h of a single inverted edge are the same.
#[test]
fn invert_new_reads_the_other_direction() {
    let x = &key_invert_expected();
    let (code, v) = diff_json(&[
        GEODE_TOML,
        GEODE_YAML,
        "--key-new",
        "T_IMU_LiDAR",
        "--invert-new",
    ]);
    assert_eq!(code, 1);
    let c = &v["chain"];
    let want = &x["diff_toml_vs_key_inverted"];
    close(
        &c["translation_change_mm"],
        &want["translation_change_mm"],
        1e-9,
    );
    close(
        &c["rotation_change_deg"],
        &want["rotation_change_deg"],
        1e-9,
    );
    let g = &x["geode_T_IMU_LiDAR"];
    close(&c["lever_arm_m"]["new"], &g["lever_arm_m"], 1e-12);
    close(&c["angle_deg"]["new"], &g["angle_deg"], 1e-9);
    close(
        &c["screw_translation_m"]["new"],
        &g["screw_translation_m"],
        1e-12,
    );
    assert_eq!(edge(&v, "IMU", "LiDAR")["status"], "changed");
    assert_eq!(v["new_read"]["inverted"], true);
    let (_, text, _) = run_cli(&[
        "diff",
        GEODE_TOML,
        GEODE_YAML,
        "--key-new",
        "T_IMU_LiDAR",
        "--invert-new",
    ]);
    assert!(
        text.contains(&format!("new: {GEODE_YAML} (key T_IMU_LiDAR, inverted)\n")),
        "{text}"
    );
    // Inverting both sides of the same numbers changes nothing.
    let (code, v) = diff_json(&[
        GEODE_YAML,
        GEODE_YAML,
        "--key",
        "T_IMU_LiDAR",
        "--invert-old",
        "--invert-new",
        "--from",
        "IMU",
        "--to",
        "LiDAR",
    ]);
    assert_eq!(code, 0);
    close(
        &v["chain"]["translation_change_mm"],
        &serde_json::json!(0.0),
        1e-12,
    );
}

/// A rig TOML `imu -> lidar` whose transform is `body` (its rotation form,
/// unit and flags), for the convention-mistake pairs.
fn mistake_rig(dir: &std::path::Path, name: &str, body: &str) -> String {
    let text = format!(
        "[rig]\nid = \"{name}\"\nsensor = \"s\"\nplatform = \"p\"\ndataset = \"d\"\n\
         category = \"cad-or-nominal\"\nlicence = \"authored\"\ndirection = \"pose of lidar in imu\"\n\
         from = \"imu\"\nto = \"lidar\"\n\n[rig.source]\nrepo = \"a/b\"\npath = \"p\"\n\
         commit = \"0000000000000000000000000000000000000000\"\n\n[[transform]]\n\
         parent = \"imu\"\nchild = \"lidar\"\nsource_key = \"k\"\n{body}\n"
    );
    let p = dir.join(format!("{name}.toml"));
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

/// The same numbers read under two conventions (each file's own rule, as
/// its reader applies it): the diff names the mistake that maps one onto the
/// other, and none on a genuine recalibration.
#[test]
fn diff_names_the_convention_mistake_between_two_files() {
    let dir = tempfile::tempdir().unwrap();
    let base = "unit = \"m\"\ntranslation = [0.215, -0.043, 0.318]\n";
    let old = mistake_rig(
        dir.path(),
        "old",
        &format!("{base}rpy = [0.12, -0.35, 1.1]"),
    );
    let cases = [
        (
            "inverse",
            format!("{base}rpy = [0.12, -0.35, 1.1]\ninvert = true"),
            "new equals old inverted",
        ),
        (
            "rpy_as_ypr",
            format!("{base}ypr = [0.12, -0.35, 1.1]"),
            "with its roll, pitch, yaw read as yaw, pitch, roll",
        ),
        (
            "mm",
            "unit = \"mm\"\ntranslation = [0.215, -0.043, 0.318]\nrpy = [0.12, -0.35, 1.1]"
                .to_string(),
            "new equals old with its translation in metres read as millimetres",
        ),
        (
            "degrees",
            format!("{base}rpy = [0.0020944, -0.0061087, 0.0191986]"),
            "with its angles in degrees read as radians",
        ),
    ];
    for (name, body, says) in cases {
        let new = mistake_rig(dir.path(), name, &body);
        let (code, out, err) = run_cli(&["diff", &old, &new]);
        assert_eq!(code, 1, "{name}: {err}");
        assert!(out.contains(says), "{name}: {out}");
        let (_, json, _) = run_cli(&["diff", &old, &new, "--format", "json"]);
        let v: Value = serde_json::from_str(&json).unwrap();
        assert!(validator().is_valid(&v), "{name}");
        let m = v["mistakes"].as_array().unwrap();
        assert!(
            !m.is_empty() && m.iter().all(|m| m["residual_mm"].as_f64().unwrap() <= 1.0),
            "{name}: {m:?}"
        );
    }
    // A 3 mm, 0.2 deg recalibration: a change, no mistake named.
    let new = mistake_rig(
        dir.path(),
        "recal",
        "unit = \"m\"\ntranslation = [0.218, -0.045, 0.319]\nrpy = [0.123, -0.352, 1.102]",
    );
    let (code, json, _) = run_cli(&["diff", &old, &new, "--format", "json"]);
    assert_eq!(code, 1);
    let v: Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["mistakes"], serde_json::json!([]));
}

const WHOLE_OLD: &str = "tests/fixtures/diff/whole_old.urdf";
const WHOLE_NEW: &str = "tests/fixtures/diff/whole_new.urdf";
const WHOLE_WITHIN: &str = "tests/fixtures/diff/whole_within.urdf";

fn whole_expected() -> Value {
    let p = format!(
        "{}/tests/fixtures/diff/whole_expected.json",
        env!("CARGO_MANIFEST_DIR")
    );
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// The change of `parent -> child` in `v` against whole_expected.json's.
fn edge_change(v: &Value, x: &Value, parent: &str, child: &str) {
    let e = edge(v, parent, child);
    let x = &x[format!("{parent} -> {child}")];
    close(
        &e["translation_change_mm"],
        &x["translation_change_mm"],
        1e-9,
    );
    close(&e["rotation_change_deg"], &x["rotation_change_deg"], 1e-7);
}

#[test]
fn two_urdfs_without_from_to_compare_every_edge() {
    // Issue 33: no --from/--to and no rig declared: the whole files.
    let x = &whole_expected()["old_vs_new"];
    let (code, v) = diff_json(&[WHOLE_OLD, WHOLE_NEW]);
    assert_eq!(code, 1);
    assert_eq!(v["schema_version"], 2);
    assert!(v["chain"].is_null() && v["from"].is_null() && v["to"].is_null());
    edge_change(&v, x, "base", "lidar");
    edge_change(&v, x, "base", "imu_link");
    let status = |p: &str, c: &str| edge(&v, p, c)["status"].as_str().unwrap().to_string();
    assert_eq!(status("base", "lidar"), "changed");
    assert_eq!(status("base", "imu_link"), "unchanged");
    assert_eq!(status("lidar", "camera"), "removed");
    assert_eq!(status("base", "gps"), "added");
    assert_eq!(
        v["exceeded"],
        serde_json::json!([
            "1 common edge(s) moved",
            "1 edge(s) only in OLD",
            "1 edge(s) only in NEW"
        ])
    );
    let (code, text, _) = run_cli(&["diff", WHOLE_OLD, WHOLE_NEW, "--color", "never"]);
    assert_eq!(code, 1);
    assert!(
        text.starts_with("every edge: 1 common edge(s) moved;"),
        "{text}"
    );
    for row in ["base -> lidar", "lidar -> camera", "base -> gps"] {
        assert!(text.lines().any(|l| l.contains(row)), "{row}: {text}");
    }
    assert!(
        !text.contains("Chain") && !text.contains("Detector families"),
        "{text}"
    );
}

#[test]
fn two_urdfs_within_tolerance_exit_0_and_one_sided_edges_fail() {
    let x = &whole_expected()["old_vs_within"];
    let (code, v) = diff_json(&[WHOLE_OLD, WHOLE_WITHIN]);
    assert_eq!(code, 0, "{v}");
    edge_change(&v, x, "base", "lidar");
    assert_eq!(edge(&v, "base", "lidar")["exceeds"], false);
    let (code, md, _) = run_cli(&["diff", WHOLE_OLD, WHOLE_WITHIN, "--format", "markdown"]);
    assert_eq!(code, 0);
    assert!(md.contains("no change beyond the tolerance"), "{md}");
    // A tighter tolerance fails on the moved edge alone.
    let (code, v) = diff_json(&[WHOLE_OLD, WHOLE_WITHIN, "--tolerance", "0.1mm,1deg"]);
    assert_eq!(
        (code, &v["exceeded"]),
        (1, &serde_json::json!(["1 common edge(s) moved"]))
    );
    // An edge in one file only fails a whole-file diff, and not a chain's.
    let (code, v) = diff_json(&[WHOLE_WITHIN, WHOLE_NEW, "--tolerance", "1m,1deg"]);
    assert_eq!(code, 1, "{v}");
    let chained = [
        WHOLE_WITHIN,
        WHOLE_NEW,
        "--tolerance",
        "1m,1deg",
        "--from",
        "base",
        "--to",
        "imu_link",
    ];
    assert_eq!(diff_json(&chained).0, 0);
}

#[test]
fn two_yamls_without_from_to_compare_their_edge() {
    let x = &whole_expected()["fastlio_vs_kalibr"];
    let kalibr = "tests/fixtures/diff/anymal_d_kalibr.yaml";
    let (code, v) = diff_json(&[FASTLIO, kalibr]);
    assert_eq!(code, 1);
    edge_change(&v, x, "imu", "lidar");
    assert_eq!(v["edges"].as_array().unwrap().len(), 1);
    // --from/--to add the chain's quantities on the same pair.
    let (code, v) = diff_json(&[FASTLIO, kalibr, "--from", "imu", "--to", "lidar"]);
    assert_eq!(code, 1);
    close(
        &v["chain"]["translation_change_mm"],
        &x["imu -> lidar"]["translation_change_mm"],
        1e-9,
    );
}

#[test]
fn the_screw_kind_is_named_as_the_rig_report_names_it() {
    // One name per concept: `pure translation` in text, as the rig report.
    let args = [WHOLE_OLD, WHOLE_NEW, "--from", "base", "--to", "imu_link"];
    let (_, text, _) = run_cli(&[&["diff"], &args[..], &["--color", "never"]].concat());
    let row = text.lines().find(|l| l.contains("screw kind")).unwrap();
    assert!(
        row.contains("pure translation") && !row.contains("pure_translation"),
        "{row}"
    );
    let (_, rig, _) = run_cli(&[
        WHOLE_OLD, "--from", "base", "--to", "imu_link", "--color", "never",
    ]);
    let row = rig.lines().find(|l| l.contains("screw kind")).unwrap();
    assert!(row.contains("pure translation"), "{row}");
}
