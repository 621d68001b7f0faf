//! `audit survey` on any file the tool reads, given a frame pair (`--from/--to`
//! for all, `PATH:FROM:TO` per path), next to rig TOMLs that keep their
//! declared pairs; and `survey --plot`: a well-formed SVG naming every rig,
//! never written over an input.

use crate::common::run_cli;
use serde_json::Value;
use std::collections::BTreeSet;

fn survey_json(args: &[&str]) -> (Value, String) {
    let mut a = vec!["survey"];
    a.extend_from_slice(args);
    a.extend_from_slice(&["--format", "json"]);
    let (code, out, err) = run_cli(&a);
    assert_eq!(code, 0, "{a:?}: {err}");
    (serde_json::from_str(&out).expect("JSON"), err)
}

fn row<'a>(v: &'a Value, id: &str) -> &'a Value {
    v["rigs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["id"] == id)
        .unwrap_or_else(|| panic!("no row {id} in {v}"))
}

fn close(a: &Value, b: f64, tol: f64) {
    let x = a.as_f64().unwrap();
    assert!((x - b).abs() <= tol, "{x} vs {b}");
}

fn expected_diff() -> Value {
    let p = format!(
        "{}/tests/fixtures/diff/expected.json",
        env!("CARGO_MANIFEST_DIR")
    );
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

#[test]
fn a_directory_of_urdfs_with_a_frame_pair() {
    use crate::common::testdata::{file, ANYMAL_C, ANYMAL_D, PR2};
    // The real robots, copied into a directory of their own at run time.
    let dir = tempfile::tempdir().expect("tempdir");
    for (name, real) in [("anymal_c", ANYMAL_C), ("anymal_d", ANYMAL_D), ("pr2", PR2)] {
        let Some(p) = file(real) else { return };
        std::fs::copy(p, dir.path().join(format!("{name}.urdf"))).expect("copy");
    }
    let d = format!("{}/", dir.path().display());
    let (v, err) = survey_json(&[&d, "--from", "base", "--to", "lidar"]);
    let ids: Vec<&str> = v["rigs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["id"].as_str().unwrap())
        .collect();
    assert_eq!(
        ids,
        [format!("{d}anymal_c.urdf"), format!("{d}anymal_d.urdf")]
    );
    // numpy / pytransform3d (tests/fixtures/diff/gen_expected.py).
    let x = &expected_diff()["anymal_c_vs_d"];
    for (id, side) in [("anymal_c", "old"), ("anymal_d", "new")] {
        let r = row(&v, &format!("{d}{id}.urdf"));
        close(
            &r["lever_arm_m"],
            x[side]["lever_arm_m"].as_f64().unwrap(),
            1e-12,
        );
        let h = r["screw_translation_m"].as_f64().unwrap().abs();
        assert!((h - x[side]["abs_h_m"].as_f64().unwrap()).abs() < 1e-9);
        assert_eq!(
            (r["from"].as_str(), r["to"].as_str()),
            (Some("base"), Some("lidar"))
        );
    }
    // The robots without those frames are named on stderr, with why.
    assert!(
        err.contains(&format!("warning[ignored]: {d}pr2.urdf"))
            && err.contains("unknown frame 'base'"),
        "{err}"
    );
    assert_eq!(v["summary"]["count"], 2);
}

#[test]
fn a_pair_per_file_across_formats() {
    let (v, _) = survey_json(&[
        "tests/fixtures/formats/fastlio_avia.yaml:imu:lidar",
        "tests/fixtures/formats/ros1_static_tf.launch:imu:os_lidar",
        "calibrations/fastlio-avia.toml",
    ]);
    assert_eq!(v["rigs"].as_array().unwrap().len(), 3);
    // FAST-LIO avia: extrinsic_T = [0.04165, 0.02326, -0.0284], R = I.
    let y = row(&v, "tests/fixtures/formats/fastlio_avia.yaml");
    let lever = (0.04165f64.powi(2) + 0.02326f64.powi(2) + 0.0284f64.powi(2)).sqrt();
    close(&y["lever_arm_m"], lever, 1e-15);
    close(&y["angle_deg"], 0.0, 0.0);
    // The rig TOML of the same numbers keeps its declared pair and metadata.
    let t = row(&v, "fastlio-avia");
    assert_eq!(t["sensor"], "Livox Avia");
    assert_eq!(t["lever_arm_m"], y["lever_arm_m"]);
    // The launch file's row is the rig report of the same pair.
    let l = row(&v, "tests/fixtures/formats/ros1_static_tf.launch");
    let (code, out, err) = run_cli(&[
        "tests/fixtures/formats/ros1_static_tf.launch",
        "--from",
        "imu",
        "--to",
        "os_lidar",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let rep: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(l["lever_arm_m"], rep["lever_arm_m"]);
    assert_eq!(
        l["screw_translation_m"],
        rep["screw"]["translation_along_axis_m"]
    );
    assert_eq!(l["band_l1"], rep["certificate"][1]["band"]);
}

#[test]
fn rig_tomls_keep_their_pairs_beside_a_urdf() {
    // calibrations/ with a pair: every rig TOML as before, plus the URDF.
    let (plain, _) = survey_json(&["calibrations/"]);
    let (v, err) = survey_json(&["calibrations/", "--from", "imu_link", "--to", "lidar"]);
    let n = plain["rigs"].as_array().unwrap().len();
    assert_eq!(v["rigs"].as_array().unwrap().len(), n + 1, "{err}");
    for r in plain["rigs"].as_array().unwrap() {
        assert_eq!(row(&v, r["id"].as_str().unwrap()), r);
    }
    let urdf = row(&v, "calibrations/anymal-d.urdf");
    let toml = row(&plain, "anymal-d-lidar-imu");
    assert_eq!(urdf["lever_arm_m"], toml["lever_arm_m"]);
    // baseline.json is not a calibration: skipped with a warning.
    assert!(err.contains("calibrations/baseline.json"), "{err}");
}

#[test]
fn a_named_file_without_a_pair_is_an_error() {
    let (code, _, err) = run_cli(&["survey", "tests/fixtures/urdf/anymal_c_lidar.urdf"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--from FRAME --to FRAME") && err.contains("FILE:FROM:TO"),
        "{err}"
    );
    let (code, _, err) = run_cli(&["survey", "tests/fixtures/urdf/"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("no rig files (*.toml)") && err.contains("--from"),
        "{err}"
    );
    let (code, _, err) = run_cli(&[
        "survey",
        "tests/fixtures/urdf/anymal_c_lidar.urdf:base:nowhere",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("nowhere"), "{err}");
    let (code, _, err) = run_cli(&["survey", "calibrations/", "--from", "imu"]);
    assert_eq!(code, 2, "{err}");
}

/// Every `<text>` of an SVG, trimmed.
fn svg_texts(svg: &str) -> BTreeSet<String> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed XML");
    assert!(doc.root_element().has_tag_name("svg"));
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .map(|t| t.trim().to_string())
        .collect()
}

/// Each `<text>` whose content is one of `labels`: its box `[left, top,
/// right, bottom]` (px) from the SVG's own x, y and font size (plotters
/// anchors text at its top-left, `dy="0.76em"`), the width at 0.5 em a
/// character (a sans-serif face's average advance).
fn label_boxes(svg: &str, labels: &BTreeSet<String>) -> Vec<(String, [f64; 4])> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed XML");
    let num = |n: &roxmltree::Node, a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| {
            let t = n.text()?.trim().to_string();
            if !labels.contains(&t) {
                return None;
            }
            let (x, y, size) = (num(&n, "x"), num(&n, "y"), num(&n, "font-size"));
            let w = t.chars().count() as f64 * size * 0.5;
            Some((t, [x, y, x + w, y + size]))
        })
        .collect()
}

/// Issue 33: the rigs at `|h| = 0` (pure translations and zero-pitch rigs,
/// on one line) had labels drawn over each other. No two rig labels of the
/// shipped survey's plot overlap, measured on the SVG's own coordinates.
#[test]
fn no_two_rig_labels_of_the_plot_overlap() {
    let dir = tempfile::tempdir().unwrap();
    let plot = dir.path().join("survey.svg");
    let (v, _) = survey_json(&["calibrations/", "--all", "--plot", plot.to_str().unwrap()]);
    let ids: BTreeSet<String> = v["rigs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["id"].as_str().unwrap().to_string())
        .collect();
    let at_zero = v["rigs"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| {
            r["screw_translation_m"]
                .as_f64()
                .is_none_or(|h| h.abs() < 1e-3)
        })
        .count();
    assert!(at_zero >= 5, "the shipped rigs have {at_zero} at |h| = 0");
    let boxes = label_boxes(&std::fs::read_to_string(&plot).unwrap(), &ids);
    assert_eq!(boxes.len(), ids.len());
    for (i, (a, p)) in boxes.iter().enumerate() {
        for (b, q) in &boxes[i + 1..] {
            let meet = p[0] < q[2] && q[0] < p[2] && p[1] < q[3] && q[1] < p[3];
            assert!(!meet, "the labels {a} {p:?} and {b} {q:?} overlap");
        }
    }
}

#[test]
fn the_plot_names_every_rig_and_marks_zero_pitch() {
    let dir = tempfile::tempdir().unwrap();
    let plot = dir.path().join("survey.svg");
    let p = plot.to_str().unwrap();
    let (v, _) = survey_json(&["calibrations/", "--all", "--plot", p]);
    let texts = svg_texts(&std::fs::read_to_string(&plot).unwrap());
    for r in v["rigs"].as_array().unwrap() {
        assert!(
            texts.contains(r["id"].as_str().unwrap()),
            "{} not in the plot",
            r["id"]
        );
    }
    let zero = v["rigs"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["zero_pitch"] == true)
        .count();
    assert!(
        texts.contains(&format!(
            "zero pitch (ringed): adapted metric M0 exists ({zero})"
        )),
        "{texts:?}"
    );
    let max = v["summary"]["lever_arm_max_m"].as_f64().unwrap();
    assert!(
        texts
            .iter()
            .any(|t| t.starts_with("largest lever arm:") && t.ends_with(&format!("({max:.3} m)"))),
        "{texts:?}"
    );
}

#[test]
fn the_plot_never_overwrites_an_input() {
    let dir = tempfile::tempdir().unwrap();
    let rig = dir.path().join("rig.toml");
    std::fs::copy("calibrations/fastlio-avia.toml", &rig).unwrap();
    let odd = dir.path().join("rig.svg");
    std::fs::copy("calibrations/fastlio-avia.toml", &odd).unwrap();
    let before = std::fs::read(&odd).unwrap();
    let d = dir.path().to_str().unwrap();
    let cases = [
        // An input named .svg (read with --input-format-free detection: a TOML).
        vec![odd.to_str().unwrap().to_string(), format!("{d}/./rig.svg")],
        // Not an .svg name: refused before anything is read.
        vec![
            rig.to_str().unwrap().to_string(),
            rig.to_str().unwrap().to_string(),
        ],
        // A directory that does not exist.
        vec![
            rig.to_str().unwrap().to_string(),
            format!("{d}/no/such/dir/p.svg"),
        ],
    ];
    for c in cases {
        let (code, out, err) = run_cli(&["survey", &c[0], "--plot", &c[1]]);
        assert_eq!(code, 2, "{c:?}: {err}");
        assert!(out.is_empty(), "{c:?}: the survey ran: {out}");
        assert!(err.contains("--plot"), "{err}");
    }
    assert_eq!(std::fs::read(&odd).unwrap(), before);
    assert_eq!(
        std::fs::read(&rig).unwrap(),
        std::fs::read("calibrations/fastlio-avia.toml").unwrap()
    );
}

#[test]
fn hostile_rig_ids_stay_text_in_the_plot() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string("calibrations/fastlio-avia.toml")
        .unwrap()
        .replace("id = \"fastlio-avia\"", "id = \"<b>&amp;\\\"x\\u202e\"");
    std::fs::write(dir.path().join("h.toml"), text).unwrap();
    let plot = dir.path().join("out").with_extension("svg");
    let (v, _) = survey_json(&[
        dir.path().join("h.toml").to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
    ]);
    assert_eq!(v["rigs"][0]["id"], "<b>&amp;\"x\u{202e}");
    let texts = svg_texts(&std::fs::read_to_string(&plot).unwrap());
    assert!(texts.contains("<b>&amp;\"x\\u{202e}"), "{texts:?}");
}

/// A xacro whose `$(find pkg)` needs `--package-path` is surveyed like any
/// file once the path is given (the same flag as `audit`): base_link -> lidar
/// is the VLP-16 macro's mount origin (0.1, 0, 0.25), turned by pi/2 about z,
/// plus its 0.0377 m scan offset along z, so the lever arm is
/// sqrt(0.1^2 + 0.2877^2) in closed form.
#[test]
fn a_xacro_with_find_is_surveyed_with_package_path() {
    let dir = tempfile::tempdir().expect("tempdir");
    let input = crate::common::vlp16_rig_xacro(dir.path());
    let target = format!("{}:base_link:lidar", input.display());
    let (code, _, err) = run_cli(&["survey", &target, "--format", "json"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--package-path"), "{err}");
    let pkg = crate::real_dir!(crate::common::testdata::VELODYNE_SIMULATOR);
    let pkg = pkg.to_str().unwrap();
    let (v, err) = survey_json(&[&target, "--package-path", pkg]);
    let r = row(&v, &input.display().to_string());
    close(&r["lever_arm_m"], 0.1f64.hypot(0.25 + 0.0377), 1e-12);
    // The mount turns by pi/2 about z: the rotation angle is 90 deg.
    close(&r["angle_deg"], 90.0, 1e-9);
    assert!(!err.contains("error"), "{err}");
}

fn key_invert_expected() -> Value {
    let p = format!(
        "{}/tests/fixtures/diff/key_invert_expected.json",
        env!("CARGO_MANIFEST_DIR")
    );
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// `survey --key`: one matrix of GEODE gamma's config (several matrices, one
/// key given twice); its lever arm, angle and h from numpy.
#[test]
fn key_reads_one_matrix_of_each_file() {
    let x = &key_invert_expected()["geode_T_IMU_LiDAR"];
    let file = "tests/fixtures/formats/geode_gamma_opencv.yaml:IMU:LiDAR";
    let (v, err) = survey_json(&[file, "--key", "T_IMU_LiDAR"]);
    assert!(!err.contains("ambiguous-key"), "{err}");
    let r = row(&v, "tests/fixtures/formats/geode_gamma_opencv.yaml");
    close(&r["lever_arm_m"], x["lever_arm_m"].as_f64().unwrap(), 1e-12);
    close(&r["angle_deg"], x["angle_deg"].as_f64().unwrap(), 1e-9);
    close(
        &r["screw_translation_m"],
        x["screw_translation_m"].as_f64().unwrap(),
        1e-12,
    );
    let (_, err) = survey_json(&[file]);
    assert!(err.contains("ambiguous-key"), "{err}");
    // The key decides what is read: the camera pair lacks the IMU.
    let (code, _, err) = run_cli(&["survey", file, "--key", "T_CamL_CamR"]);
    assert_eq!(code, 2, "{err}");
}

/// `survey --invert`: Kalibr's `T_imu_cam` read as the pose of imu in each
/// camera; cam0 -> cam1 is then A inv(B) instead of inv(A) B (numpy).
#[test]
fn invert_reads_the_files_the_other_way() {
    let x = &key_invert_expected();
    let file = "tests/fixtures/extrinsics/kalibr_openvins_euroc_imucam_chain.yaml:cam0:cam1";
    let id = "tests/fixtures/extrinsics/kalibr_openvins_euroc_imucam_chain.yaml";
    for (args, want) in [
        (vec![file], &x["kalibr_cam0_cam1"]),
        (vec![file, "--invert"], &x["kalibr_cam0_cam1_inverted"]),
    ] {
        let (v, _) = survey_json(&args);
        let r = row(&v, id);
        for k in ["lever_arm_m", "screw_translation_m"] {
            close(&r[k], want[k].as_f64().unwrap(), 1e-12);
        }
        close(&r["angle_deg"], want["angle_deg"].as_f64().unwrap(), 1e-9);
    }
    // The two readings differ by 49 um of lever arm: the flag is applied.
    let d = x["kalibr_cam0_cam1_inverted"]["lever_arm_m"]
        .as_f64()
        .unwrap()
        - x["kalibr_cam0_cam1"]["lever_arm_m"].as_f64().unwrap();
    assert!(d > 4e-5, "{d}");
}

/// `survey --xacro external` expands a xacro with the `xacro` program, as
/// `audit --xacro external` does (the one flag group): a stand-in program on
/// PATH prints base -> lidar at z = 0.5 m, where the file itself (expanded
/// natively) puts lidar at x = 0.3 m.
#[cfg(unix)]
#[test]
fn xacro_external_reaches_the_survey() {
    let dir = tempfile::tempdir().expect("tempdir");
    crate::common::fake_xacro(dir.path());
    let input = dir.path().join("r.urdf.xacro");
    std::fs::write(
        &input,
        r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="x" value="0.3"/>
  <link name="base"/>
  <link name="lidar"/>
  <joint name="j" type="fixed">
    <parent link="base"/><child link="lidar"/><origin xyz="${x} 0 0"/>
  </joint>
</robot>
"#,
    )
    .expect("write");
    let target = format!("{}:base:lidar", input.display());
    let id = input.display().to_string();
    let lever = |mode: &str| {
        let out = crate::common::audit()
            .env("PATH", dir.path())
            .args(["survey", &target, "--xacro", mode, "--format", "json"])
            .output()
            .expect("run");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{err}");
        let v: Value = serde_json::from_slice(&out.stdout).expect("json");
        row(&v, &id)["lever_arm_m"].as_f64().expect("lever arm")
    };
    assert_eq!(lever("native"), 0.3);
    assert_eq!(lever("external"), 0.5);
}
