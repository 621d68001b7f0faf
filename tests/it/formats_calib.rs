//! The calibration formats of issue 28, each read from its authored fixtures
//! (`tests/fixtures/formats/calib/<format>/`, numbers as published; see
//! SOURCES.md there) and compared with `expected.json`, which an independent
//! reader wrote (`make_expected.py`: PyYAML / json + numpy, rotations from
//! angles and quaternions by pytransform3d cross-checked with scipy). Every
//! `bad_` fixture must be refused, every other read with the edges expected
//! (frames and 4x4 to 1e-12, or to the projection the tool reports with a
//! `non-orthonormal-rotation` warning), detected without `--input-format`.

use extrinsic_audit::internals::formats::{detect_file, load_file, Parsed};
use extrinsic_audit::{Assume, Code, LoadOptions};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/formats/calib")
}

fn expected() -> Value {
    let text = std::fs::read_to_string(dir().join("expected.json")).expect("expected.json");
    serde_json::from_str(&text).expect("expected.json parses")
}

fn matrix(v: &Value) -> [[f64; 4]; 4] {
    let mut m = [[0.0; 4]; 4];
    for (i, row) in v.as_array().unwrap().iter().enumerate() {
        for (j, x) in row.as_array().unwrap().iter().enumerate() {
            m[i][j] = x.as_f64().unwrap();
        }
    }
    m
}

/// The tool's pose of `child` in `parent`, whichever way the edge is stored.
fn pose(l: &Parsed, parent: &str, child: &str) -> Option<[[f64; 4]; 4]> {
    l.edges.iter().find_map(|e| {
        let t = if (e.parent.as_str(), e.child.as_str()) == (parent, child) {
            e.transform
        } else if (e.parent.as_str(), e.child.as_str()) == (child, parent) {
            e.transform.inverse()
        } else {
            return None;
        };
        let m = t.matrix4();
        Some(std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)])))
    })
}

/// `||R^T R - I||_F` of the rotation block.
fn orthonormality(m: &[[f64; 4]; 4]) -> f64 {
    let mut s = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let d: f64 =
                (0..3).map(|k| m[k][i] * m[k][j]).sum::<f64>() - if i == j { 1.0 } else { 0.0 };
            s += d * d;
        }
    }
    s.sqrt()
}

fn opts(assume: Option<&str>) -> LoadOptions {
    let mut o = LoadOptions::default();
    o.assume = assume.map(|a| Assume::parse(a).unwrap());
    o
}

/// Check every fixture of `format` against expected.json; `assume` is passed
/// for the fixtures whose expected edges need it. Returns the loads, by file.
fn check_format(format: &str, assume: Option<&str>) -> Vec<(String, Parsed)> {
    let exp = expected();
    let mut out = Vec::new();
    let fixtures = exp["fixtures"].as_object().unwrap();
    let mine: Vec<_> = fixtures
        .iter()
        .filter(|(k, _)| k.starts_with(&format!("{format}/")))
        .collect();
    assert!(!mine.is_empty(), "{format}: no fixture in expected.json");
    for (rel, want) in mine {
        let file = dir().join(rel);
        let o = opts(assume);
        let found = detect_file(&file, &o).unwrap_or_else(|e| panic!("{rel}: {e}"));
        // roslaunch-eval/: launch XML with $(eval ...), read by launch-xml.
        let id = if format == "roslaunch-eval" {
            "launch-xml"
        } else {
            format
        };
        assert_eq!(found.name(), id, "{rel}: detected as");
        let got = load_file(&file, &o);
        if let Some(err) = want.get("error") {
            let e = got
                .err()
                .unwrap_or_else(|| panic!("{rel}: read, expected refused ({err})"));
            assert!(!e.message.is_empty(), "{rel}");
            continue;
        }
        let l = got.unwrap_or_else(|e| panic!("{rel}: {e}"));
        for edge in want["edges"].as_array().unwrap() {
            let (p, c) = (
                edge["parent"].as_str().unwrap(),
                edge["child"].as_str().unwrap(),
            );
            let m = pose(&l, p, c).unwrap_or_else(|| {
                panic!(
                    "{rel}: no edge {p} -> {c} in {:?}",
                    l.edges
                        .iter()
                        .map(|e| (&e.parent, &e.child))
                        .collect::<Vec<_>>()
                )
            });
            let want_m = matrix(&edge["matrix"]);
            // The tool projects a rotation written to a few digits onto SO(3)
            // (with a warning past 1e-6): it moves by at most ||R^T R - I||.
            let off = orthonormality(&want_m);
            for i in 0..4 {
                for j in 0..4 {
                    let tol = if i < 3 && j < 3 { 1e-12 + off } else { 1e-12 };
                    assert!(
                        (m[i][j] - want_m[i][j]).abs() <= tol,
                        "{rel}: {p} -> {c} [{i}][{j}] = {:e}, expected {:e}",
                        m[i][j],
                        want_m[i][j]
                    );
                }
            }
        }
        assert_eq!(
            l.edges.len(),
            want["edges"].as_array().unwrap().len(),
            "{rel}: edge count"
        );
        out.push((rel.clone(), l));
    }
    out
}

fn warned(l: &Parsed, code: Code, text: &str) -> bool {
    l.warnings
        .iter()
        .any(|w| w.code == code && w.message.contains(text))
}

fn refusal(rel: &str, assume: Option<&str>) -> String {
    load_file(&dir().join(rel), &opts(assume))
        .expect_err(rel)
        .message
}

#[test]
fn orb_slam3_settings_both_generations() {
    let loads = check_format("orb-slam3", None);
    assert_eq!(loads.len(), 2);
    assert!(
        refusal("orb-slam3/bad_t_b_c1_short.yaml", None).contains("expected 16 numbers, found 12")
    );
    assert!(refusal("orb-slam3/bad_tlr_4x4.yaml", None).contains("expected rows 3 cols 4"));
}

#[test]
fn fast_livo_camera_extrinsic_is_the_lidar_in_the_camera() {
    let loads = check_format("fast-livo", None);
    for (rel, l) in &loads {
        let cam = l.edges.iter().find(|e| e.child == "camera").expect(rel);
        assert_eq!(cam.parent, "lidar", "{rel}: stored lidar -> camera");
        assert!(cam.provenance.key.contains("stored inverted"), "{rel}");
    }
    assert!(refusal("fast-livo/bad_rcl_without_pcl.yaml", None).contains("`Pcl`"));
    assert!(
        refusal("fast-livo/bad_pcl_two_numbers.yaml", None).contains("expected 3 numbers, found 2")
    );
}

#[test]
fn autoware_calibration_parent_and_child_from_the_keys() {
    let loads = check_format("autoware-calibration", None);
    let kit = &loads
        .iter()
        .find(|(r, _)| r.ends_with("sensor_kit_calibration.yaml"))
        .unwrap()
        .1;
    assert_eq!(kit.edges.len(), 13);
    assert!(kit
        .edges
        .iter()
        .any(|e| e.child == "camera0/camera_link" && e.parent == "sensor_kit_base_link"));
    assert!(refusal("autoware-calibration/bad_missing_yaw.yaml", None).contains("expected `yaw`"));
    assert!(refusal("autoware-calibration/bad_text_value.yaml", None)
        .contains("expected a number, found a string"));
}

#[test]
fn euroc_t_bs_is_the_sensor_in_the_body() {
    check_format("euroc-sensor", None);
    assert!(refusal("euroc-sensor/bad_rows_cols_mismatch.yaml", None)
        .contains("expected rows 4 cols 4"));
    assert!(refusal("euroc-sensor/bad_bottom_row.yaml", None).contains("bottom row"));
    // EuRoC's own layout: the sensor is named after its directory.
    let tmp = tempfile::tempdir().unwrap();
    let cam = tmp.path().join("mav0/cam1");
    std::fs::create_dir_all(&cam).unwrap();
    std::fs::copy(
        dir().join("euroc-sensor/euroc_cam0_sensor.yaml"),
        cam.join("sensor.yaml"),
    )
    .unwrap();
    let l = load_file(&cam.join("sensor.yaml"), &LoadOptions::default()).unwrap();
    assert_eq!(
        (l.edges[0].parent.as_str(), l.edges[0].child.as_str()),
        ("body", "cam1")
    );
}

#[test]
fn basalt_t_imu_cam_is_each_camera_in_the_imu() {
    check_format("basalt-calib", None);
    assert!(refusal("basalt-calib/bad_missing_qw.json", None).contains("expected `qw`"));
    assert!(
        refusal("basalt-calib/bad_quaternion_norm.json", None).contains("quaternion norm 1.063015")
    );
}

#[test]
fn r3live_camera_ext_is_the_camera_in_the_imu() {
    check_format("r3live", None);
    assert!(refusal("r3live/bad_ext_r_eight.yaml", None).contains("expected 9 numbers, found 8"));
}

#[test]
fn glim_sensors_json_with_comments() {
    // T_lidar_camera needs --assume: the expected edges hold it.
    check_format("glim-sensors", Some("child-in-parent"));
    let l = load_file(
        &dir().join("glim-sensors/config_sensors.json"),
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(l.edges.len(), 1, "T_lidar_camera left out without --assume");
    assert!(warned(&l, Code::Ignored, "--assume child-in-parent"));
    assert!(refusal("glim-sensors/bad_t_lidar_imu_16.json", None)
        .contains("expected 7 numbers, found 16"));
    let e = refusal("glim-sensors/bad_unterminated_comment.json", None);
    assert!(e.contains("never closed"), "{e}");
}

#[test]
fn glim_comment_markers_inside_strings_stay_text() {
    let s = extrinsic_audit::internals::formats::glim::strip_json_comments(
        "{\"a\": \"x//y/*z*/\", // c\n\"b\": 1 /* d\n e */}",
    )
    .unwrap();
    assert_eq!(s, "{\"a\": \"x//y/*z*/\",     \n\"b\": 1     \n     }");
}

#[test]
fn apollo_extrinsics_tf_convention() {
    check_format("apollo-extrinsics", None);
    assert!(refusal("apollo-extrinsics/bad_missing_child.yaml", None)
        .contains("expected `child_frame_id`"));
}

#[test]
fn okvis_t_sc_and_the_untraced_t_bs() {
    check_format("okvis", Some("child-in-parent"));
    let l = load_file(
        &dir().join("okvis/okvis_euroc_config.yaml"),
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(l.edges.len(), 2, "T_BS left out without --assume");
    assert!(warned(&l, Code::Ignored, "imu_params.T_BS"));
    // parent-in-child reads T_BS the other way.
    let inv = load_file(
        &dir().join("okvis/okvis_euroc_config.yaml"),
        &opts(Some("parent-in-child")),
    )
    .unwrap();
    assert!(inv
        .edges
        .iter()
        .any(|e| e.parent == "body" && e.provenance.key.contains("--assume parent-in-child")));
    // Frame names are for files that name none.
    let e = refusal("okvis/okvis_euroc_config.yaml", Some("child-in-parent:a,b"));
    assert!(e.contains("the file names its frames"), "{e}");
    assert!(refusal("okvis/bad_t_sc_twelve.yaml", None).contains("expected 16 numbers, found 12"));
}

#[test]
fn opencalib_names_from_sensor_fields_and_the_majority_rule() {
    let loads = check_format("opencalib", None);
    let w = &loads
        .iter()
        .find(|(r, _)| r.contains("warn_key"))
        .unwrap()
        .1;
    assert!(warned(
        w,
        Code::AssumedConvention,
        "frames are taken from sensor_name"
    ));
    let g = &loads.iter().find(|(r, _)| r.contains("gnss-to")).unwrap().1;
    assert!(warned(
        g,
        Code::AssumedConvention,
        "run_lidar2imu.cpp:312-313"
    ));
    let c = &loads
        .iter()
        .find(|(r, _)| r.starts_with("opencalib/top_center"))
        .unwrap()
        .1;
    assert!(
        !c.warnings.iter().any(|w| w.code == Code::AssumedConvention),
        "{:?}",
        c.warnings
    );
    assert!(refusal("opencalib/bad_three_rows.json", None).contains("four rows of four"));
}

#[test]
fn livox_driver2_degrees_and_integer_millimetres() {
    // synthetic_two_lidars.json is authored (every shipped config is zeros).
    check_format("livox-driver2", None);
    assert!(refusal("livox-driver2/bad_float_millimetres.json", None)
        .contains("expected an integer number of millimetres"));
    assert!(refusal("livox-driver2/bad_missing_extrinsic.json", None).contains("zero silently"));
}

#[test]
fn matrix4_text_needs_assume() {
    check_format("matrix4-text", Some("child-in-parent:PARENT,CHILD"));
    let e = refusal("matrix4-text/euroc_cam0_in_body.txt", None);
    assert!(e.contains("--assume child-in-parent:PARENT,CHILD"), "{e}");
    let e = refusal(
        "matrix4-text/euroc_cam0_in_body.txt",
        Some("child-in-parent"),
    );
    assert!(e.contains("names no frames"), "{e}");
    // parent-in-child: the same frames, the inverse.
    let f = dir().join("matrix4-text/horizon_commas.txt");
    let a = load_file(&f, &opts(Some("child-in-parent:lidar,imu"))).unwrap();
    let b = load_file(&f, &opts(Some("parent-in-child:lidar,imu"))).unwrap();
    assert_eq!(
        (b.edges[0].parent.as_str(), b.edges[0].child.as_str()),
        ("lidar", "imu")
    );
    let d = b.edges[0].transform.translation() + a.edges[0].transform.translation();
    assert!(d.norm() < 1e-15, "identity rotation: the translation flips");
    assert!(refusal(
        "matrix4-text/bad_fifteen_numbers.txt",
        Some("child-in-parent:a,b")
    )
    .contains("found 15"));
    assert!(refusal(
        "matrix4-text/bad_bottom_row.txt",
        Some("child-in-parent:a,b")
    )
    .contains("bottom row"));
}

#[test]
fn lio_livox_extrinsic_tlb_is_the_imu_in_the_lidar() {
    let loads = check_format("lio-livox-launch", None);
    for (rel, l) in &loads {
        let e = &l.edges[0];
        assert_eq!(
            (e.parent.as_str(), e.child.as_str()),
            ("lidar", "imu"),
            "{rel}"
        );
        assert!(
            !l.warnings.iter().any(|w| w.code == Code::AssumedConvention),
            "{rel}: traced, not assumed"
        );
    }
    // horizon.launch: t = -(FAST-LIO's LiDAR-in-IMU horizon.yaml extrinsic_T).
    let h = &loads
        .iter()
        .find(|(r, _)| r.ends_with("horizon.launch"))
        .unwrap()
        .1;
    let t = h.edges[0].transform.translation();
    assert_eq!([t.x, t.y, t.z], [-0.05512, -0.02226, 0.0297]);
    assert!(refusal("lio-livox-launch/bad_tlb_twelve.launch", None).contains("found 12"));
}

#[test]
fn assume_flag_values() {
    assert_eq!(
        Assume::parse("parent-in-child:base_link,lidar").unwrap(),
        Assume {
            child_in_parent: false,
            frames: Some(("base_link".into(), "lidar".into()))
        }
    );
    assert!(Assume::parse("child-in-parent").unwrap().frames.is_none());
    for bad in [
        "lidar-in-imu",
        "child-in-parent:a",
        "child-in-parent:a,a",
        "child-in-parent:,b",
        "child-in-parent:a,b,c",
    ] {
        assert!(Assume::parse(bad).is_err(), "{bad}");
    }
}

#[test]
fn roslaunch_eval_in_args_and_conditions() {
    let loads = check_format("roslaunch-eval", None);
    let l = &loads
        .iter()
        .find(|(r, _)| r.ends_with("eval_static_tf.launch"))
        .unwrap()
        .1;
    // if="$(eval use_rear or robot == 'husky')" is False: not started.
    assert!(warned(l, Code::Ignored, "base_to_rear") || warned(l, Code::Ignored, "not started"));
    let e = refusal("roslaunch-eval/bad_dunder.launch", None);
    assert!(
        e.contains("double underscore") && e.contains("__import__"),
        "{e}"
    );
    let e = refusal("roslaunch-eval/bad_eval_inside_text.launch", None);
    assert!(
        e.contains("only when it is the whole attribute value"),
        "{e}"
    );
    // --arg overrides a default an $(eval) reads.
    let mut o = LoadOptions::default();
    o.xacro_args = [("robot".to_string(), "husky".to_string())].into();
    let h = load_file(&dir().join("roslaunch-eval/eval_static_tf.launch"), &o).unwrap();
    assert!(
        h.edges.iter().any(|e| e.child == "rear_bumper"),
        "robot == 'husky' starts the rear publisher"
    );
    assert!(
        !h.edges.iter().any(|e| e.child == "lidar"),
        "robot == 'jackal' is False"
    );
}
