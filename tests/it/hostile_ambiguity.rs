//! Issue 27, silent wrong answers: input that two readers would read two
//! ways is refused or named, never answered quietly. A JSON key given twice
//! is an error in every JSON format (file, line, both occurrences); a frame
//! name that looks like another frame of the graph, or is padded with white
//! space, is a named warning that says which frame it resembles; duplicate
//! points of a raw scan are merged (and counted) before normals, so copies
//! never stand in for neighbours.

use crate::common::run_cli;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// `(line, column)` of the `n`-th (0-based) occurrence of `needle`.
fn place(text: &str, needle: &str, n: usize) -> (usize, usize) {
    let at = text.match_indices(needle).nth(n).unwrap().0;
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, col)
}

const OUSTER_FLAT: &str = r#"{
  "prod_sn": "122150000001",
  "lidar_to_sensor_transform": [-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1],
  "imu_to_sensor_transform": [1, 0, 0, 6.253, 0, 1, 0, -11.775, 0, 0, 1, 7.645, 0, 0, 0, 1]
}
"#;

/// Every JSON format, each with one key given twice (the transform itself,
/// a field of a record, a key the reader does not use): exit 2, the message
/// at the second occurrence naming both.
#[test]
fn a_json_key_given_twice_is_refused_in_every_json_format() {
    let d = tempfile::tempdir().unwrap();
    let flat_dup = OUSTER_FLAT.replace(
        "  \"imu_to_sensor_transform\"",
        "  \"lidar_to_sensor_transform\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1],\n  \"imu_to_sensor_transform\"",
    );
    let unused_dup = OUSTER_FLAT.replace("{\n", "{\n  \"prod_sn\": \"x\",\n");
    let nested = r#"{"lidar_intrinsics": {"lidar_to_sensor_transform": [-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1],
  "lidar_to_sensor_transform": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1]}}
"#;
    let extr = std::fs::read_to_string("tests/fixtures/extrinsics/ouster_extrinsics_example.json")
        .unwrap()
        .replace("\"p_y\"", "\"p_x\": 0.5,\n      \"p_y\"");
    let av2 = std::fs::read_to_string(
        "tests/fixtures/extrinsics/av2/av2_test_log_egovehicle_SE3_sensor.json",
    )
    .unwrap()
    .replacen("\"tx_m\"", "\"tx_m\": 9.0,\n  \"tx_m\"", 1);
    let nus = std::fs::read_to_string("tests/fixtures/extrinsics/nuscenes/calibrated_sensor.json")
        .unwrap()
        .replacen(
            "\"translation\"",
            "\"translation\": [0, 0, 0],\n\"translation\"",
            1,
        );
    let fast_lio = "{\"mapping\": {\"extrinsic_T\": [0.1, 0, 0], \"extrinsic_R\": [1, 0, 0, 0, 1, 0, 0, 0, 1],\n  \"extrinsic_T\": [0.2, 0, 0]}}\n";
    let keyed = "{\"T_imu_lidar\": [[1, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],\n \"T_imu_lidar\": [[1, 0, 0, 0.2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}\n";
    let cases: [(&str, &str, &str, &[&str]); 8] = [
        ("flat.json", &flat_dup, "\"lidar_to_sensor_transform\"", &[]),
        ("unused.json", &unused_dup, "\"prod_sn\"", &[]),
        ("nested.json", nested, "\"lidar_to_sensor_transform\"", &[]),
        ("extrinsic_parameters.json", &extr, "\"p_x\"", &[]),
        ("egovehicle_SE3_sensor.json", &av2, "\"tx_m\"", &[]),
        ("calibrated_sensor.json", &nus, "\"translation\"", &[]),
        ("fast_lio.json", fast_lio, "\"extrinsic_T\"", &[]),
        (
            "matrices.json",
            keyed,
            "\"T_imu_lidar\"",
            &["--key", "T_imu_lidar"],
        ),
    ];
    for (name, text, key, extra) in cases {
        let f = write(d.path(), name, text);
        let (l1, c1) = place(text, key, 0);
        let (l2, c2) = place(text, key, 1);
        let args = [&[f.to_str().unwrap()][..], extra].concat();
        let (code, out, err) = run_cli(&args);
        assert_eq!(code, 2, "{name}: {out}{err}");
        let at = format!("{}:{l2}:{c2}: ", f.display());
        let both = format!("(line {l1}, column {c1} and line {l2}, column {c2})");
        assert!(
            err.contains(&at) && err.contains("given twice in one object") && err.contains(&both),
            "{name}: {err}"
        );
        // The check gate refuses it as a finding naming the file.
        let (code, out, _) = run_cli(&["check", f.to_str().unwrap()]);
        assert_eq!(code, 1, "{name}: {out}");
        assert!(out.contains("given twice in one object"), "{name}: {out}");
    }
    // Without the second copy each file loads.
    let f = write(d.path(), "ok.json", OUSTER_FLAT);
    assert_eq!(run_cli(&[f.to_str().unwrap(), "--frames"]).0, 0);
    // A sensor.json beside a nuScenes file is held to the same rule.
    let n = d.path().join("n");
    std::fs::create_dir(&n).unwrap();
    let good = std::fs::read_to_string("tests/fixtures/extrinsics/nuscenes/calibrated_sensor.json")
        .unwrap();
    let f = write(&n, "calibrated_sensor.json", &good);
    let sensors = std::fs::read_to_string("tests/fixtures/extrinsics/nuscenes/sensor.json")
        .unwrap()
        .replacen("\"channel\"", "\"channel\": \"CAM_X\",\n\"channel\"", 1);
    write(&n, "sensor.json", &sensors);
    let (code, _, err) = run_cli(&[f.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("sensor.json:") && err.contains("given twice"),
        "{err}"
    );
}

fn tf(parent: &str, child: &str, z: f64) -> String {
    format!("ros2 run tf2_ros static_transform_publisher 0 0 {z} 0 0 0 '{parent}' '{child}'\n")
}

/// The graph's warnings (code, message) of `audit FILE --frames --format json`.
fn frame_warnings(f: &Path) -> Vec<(String, String)> {
    let (code, out, err) = run_cli(&[f.to_str().unwrap(), "--frames", "--format", "json"]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    // Each `warning[CODE]: FILE:LINE:COL: message`.
    v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| {
            let w = w.as_str().unwrap();
            let (code, msg) = w
                .strip_prefix("warning[")
                .unwrap()
                .split_once("]: ")
                .unwrap();
            (code.to_string(), msg.to_string())
        })
        .collect()
}

/// Each kind of look-alike (a confusable letter, a zero-width space, NFKC,
/// case, white space at an end) against `base_link`, and a padded name that
/// resembles nothing: one named warning each, saying which frame; distinct
/// names get none; `check --deny-warnings` fails on them.
#[test]
fn look_alike_frame_names_are_named_with_the_frame_they_resemble() {
    let d = tempfile::tempdir().unwrap();
    let alikes = [
        ("base_l\u{456}nk", "U+0456"),
        ("base_\u{200b}link", "UTS #39"),
        ("\u{ff42}ase_link", "NFKC"),
        ("Base_Link", "only in case"),
        ("base_link ", "white space"),
    ];
    let mut text = tf("base_link", "lidar", 0.1);
    for (i, (a, _)) in alikes.iter().enumerate() {
        text += &tf(a, &format!("sensor{i}"), 0.2);
    }
    text += &tf(" imu", "camera", 0.3);
    let f = write(d.path(), "tf.txt", &text);
    let ws = frame_warnings(&f);
    assert_eq!(ws.len(), alikes.len() + 1, "{ws:#?}");
    for ((code, msg), (name, how)) in ws.iter().zip(alikes) {
        assert_eq!(code, "confusable-frame-name", "{msg}");
        assert!(
            msg.contains(&format!(
                "frame \"{name}\" resembles frame \"base_link\" (at {}:1:1)",
                f.display()
            )) && msg.contains(how),
            "{msg}"
        );
    }
    assert_eq!(ws[alikes.len()].0, "padded-frame-name");
    assert!(ws[alikes.len()].1.contains("frame \" imu\""), "{ws:?}");

    // Across the files of one robot, too; and the gate can be made to fail.
    let a = write(d.path(), "a.txt", &tf("base_link", "lidar", 0.1));
    let b = write(d.path(), "b.txt", &tf("base_lіnk", "imu", 0.2));
    let (code, _, err) = run_cli(&[a.to_str().unwrap(), b.to_str().unwrap(), "--frames"]);
    assert_eq!(code, 0);
    assert!(
        err.contains("warning[confusable-frame-name]") && err.contains("b.txt:1:1"),
        "{err}"
    );
    let (code, out, _) = run_cli(&["check", b.to_str().unwrap(), "--deny-warnings"]);
    assert_eq!(code, 0, "one file alone has no look-alike: {out}");
    let g = write(d.path(), "g.txt", &text);
    let (code, out, _) = run_cli(&["check", g.to_str().unwrap(), "--deny-warnings"]);
    assert_eq!(code, 1, "{out}");

    // Distinct names, however close in spelling, are not look-alikes.
    let mut plain = String::new();
    for (p, c) in [
        ("base_link", "base_footprint"),
        ("base_link", "cam0"),
        ("cam0", "cam1"),
        ("base_link", "lidar_link"),
    ] {
        plain += &tf(p, c, 0.1);
    }
    let f = write(d.path(), "plain.txt", &plain);
    assert_eq!(frame_warnings(&f), Vec::<(String, String)>::new());
}

/// `degeneracy --estimate-normals --format json` of a CSV of points.
fn raw_normals(f: &Path) -> (i32, Value, String) {
    let (code, out, err) = run_cli(&[
        "degeneracy",
        f.to_str().unwrap(),
        "--estimate-normals",
        "--format",
        "json",
    ]);
    (code, serde_json::from_str(&out).unwrap_or(Value::Null), err)
}

fn csv(points: &[[f64; 3]], copies: usize) -> String {
    let mut s = String::from("x,y,z\n");
    for _ in 0..copies {
        for p in points {
            s += &format!("{:?},{:?},{:?}\n", p[0], p[1], p[2]);
        }
    }
    s
}

/// 60 isolated points are refused (no point has 8 neighbours within 0.3 m);
/// the same 60 repeated 50 times are refused the same way, with the count of
/// copies merged. A dense patch of a plane and a tilted wall, given once or
/// three times over, near the origin or 4,000 km from it, gives the same
/// kept points and the same H, and reports the copies merged.
#[test]
fn duplicate_points_are_merged_and_counted_before_normals() {
    let d = tempfile::tempdir().unwrap();
    let sparse: Vec<[f64; 3]> = (0..60)
        .map(|i| [(i % 10) as f64, (i / 10) as f64, 0.5 * (i % 3) as f64])
        .collect();
    let (code, _, alone) = raw_normals(&write(d.path(), "sparse.csv", &csv(&sparse, 1)));
    assert_eq!(code, 2, "{alone}");
    assert!(
        alone.contains("no point got a normal: 60 points, none with 8"),
        "{alone}"
    );
    let (code, _, copied) = raw_normals(&write(d.path(), "copies.csv", &csv(&sparse, 50)));
    assert_eq!(code, 2, "{copied}");
    assert!(
        copied.contains("no point got a normal: 60 points (2940 duplicates merged), none with 8"),
        "{copied}"
    );

    for origin in [[0.0, 0.0, 0.0], [4.0e6, -3.5e6, 120.0]] {
        // A floor and a wall, 0.1 m apart, 400 points each.
        let mut patch = Vec::new();
        for i in 0..20 {
            for j in 0..20 {
                let (u, v) = (i as f64 * 0.1, j as f64 * 0.1);
                patch.push([origin[0] + u, origin[1] + v, origin[2]]);
                patch.push([origin[0] + u, origin[1] + 3.0, origin[2] + 0.5 + v]);
            }
        }
        let (code, once, err) = raw_normals(&write(d.path(), "once.csv", &csv(&patch, 1)));
        assert_eq!(code, 0, "{err}");
        let (code, thrice, err) = raw_normals(&write(d.path(), "thrice.csv", &csv(&patch, 3)));
        assert_eq!(code, 0, "{err}");
        assert_eq!(once["normals"]["duplicates_merged"], 0);
        assert_eq!(thrice["normals"]["duplicates_merged"], 2 * patch.len());
        assert_eq!(thrice["normals"]["points_read"], 3 * patch.len());
        assert_eq!(once["normals"]["kept"], thrice["normals"]["kept"]);
        assert!(once["normals"]["kept"].as_u64().unwrap() > 0);
        assert_eq!(once["matrices"], thrice["matrices"], "origin {origin:?}");
    }
}
