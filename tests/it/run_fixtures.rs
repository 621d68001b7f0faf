//! `audit run` on runs written by independent writers (tests/fixtures/run:
//! rosbags and mcap wrote the bags, numpy computed `expected.json`; the
//! scripts beside them): every container of the same run gives the same
//! eigenvalues as numpy in the scan frame and every body frame, the same
//! label changes, the same pairs; hostile scans are skipped with their
//! reason and the good ones still reported; KITTI and PCD sequences.
//! Tolerances from expected.json's `_meta.tolerances`.

use crate::common::{audit, nums};
use serde_json::Value;
use std::path::{Path, PathBuf};

const DIR: &str = "tests/fixtures/run";

fn expected() -> &'static Value {
    static E: std::sync::OnceLock<Value> = std::sync::OnceLock::new();
    E.get_or_init(|| {
        let t = std::fs::read_to_string(Path::new(DIR).join("expected.json")).unwrap();
        serde_json::from_str(&t).unwrap()
    })
}

/// `audit run ARGS --jsonl F` in the fixtures' folder: the output and the
/// records of F.
pub fn run_with_records(args: &[&str]) -> (std::process::Output, Vec<Value>) {
    let dir = tempfile::tempdir().unwrap();
    let jl = dir.path().join("r.jsonl");
    let out = audit()
        .current_dir(DIR)
        .arg("run")
        .args(args)
        .arg("--jsonl")
        .arg(&jl)
        .output()
        .unwrap();
    let recs = std::fs::read_to_string(&jl)
        .unwrap_or_default()
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    (out, recs)
}

/// `audit run ARGS --jsonl F`: the exit code, stderr and the records of F.
pub fn run_records(args: &[&str]) -> (i32, String, Vec<Value>) {
    let (out, recs) = run_with_records(args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code().unwrap_or(-1), err, recs)
}

/// Eigenvalues within expected.json's tolerance: relative 1e-9 where
/// |lambda| > 1e-9 max|lambda|, absolute 1e-9 max|lambda| otherwise.
fn assert_eigen(got: &[f64], want: &[f64], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}");
    let big = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (g, w) in got.iter().zip(want) {
        let ok = if w.abs() > 1e-9 * big {
            (g - w).abs() <= 1e-9 * w.abs()
        } else {
            (g - w).abs() <= 1e-9 * big
        };
        assert!(ok, "{what}: {got:?} vs numpy {want:?}");
    }
}

/// The families of one frame of a record, by key.
fn families<'a>(rec: &'a Value, frame: &str) -> &'a Vec<Value> {
    let f = rec["frames"].as_array().unwrap().iter();
    let f = f.clone().find(|f| f["frame"] == frame);
    f.unwrap_or_else(|| panic!("no frame {frame} in {}", rec["index"]))["families"]
        .as_array()
        .unwrap()
}

/// A record's families of `frame` against numpy's `want` (family key -> entry).
fn assert_families(rec: &Value, frame: &str, want: &Value, what: &str) {
    let fams = families(rec, frame);
    assert_eq!(fams.len(), 8, "{what}");
    for f in fams {
        let key = f["family"].as_str().unwrap();
        let w = &want[key];
        let what = format!("{what}, {frame}, {key}");
        assert_eigen(&nums(&f["eigenvalues"]), &nums(&w["eigenvalues"]), &what);
        assert_eq!(f["degenerate_count"], w["degenerate_count"], "{what}");
        assert_eq!(f["footprint"], w["footprint"], "{what}");
        let t = f["threshold"].as_f64().unwrap();
        assert!(
            (t - w["threshold"].as_f64().unwrap()).abs() <= 1e-12 * t.abs(),
            "{what}"
        );
    }
}

/// Decision, count and footprint changes of `frame` against the scan frame.
fn label_changes(rec: &Value, frame: &str) -> Vec<(String, [bool; 3])> {
    let scan = families(rec, "scan");
    let body = families(rec, frame);
    scan.iter()
        .zip(body)
        .map(|(a, b)| {
            let n = |f: &Value| f["degenerate_count"].as_u64().unwrap();
            let changed = [
                (n(a) > 0) != (n(b) > 0),
                n(a) != n(b),
                a["footprint"] != b["footprint"],
            ];
            (a["family"].as_str().unwrap().to_string(), changed)
        })
        .collect()
}

fn assert_label_changes(rec: &Value, frame: &str, want: &Value, what: &str) {
    for (key, got) in label_changes(rec, frame) {
        let w = &want[&key];
        let want = ["decision_changed", "count_changed", "footprint_changed"]
            .map(|k| w[k].as_bool().unwrap());
        assert_eq!(got, want, "{what}, {frame}, {key}: label changes");
    }
}

/// The KITTI sequence's pairs with three poses for five scans.
pub const SHORT_POSES: [&str; 6] = [
    "kitti_seq",
    "--pairs",
    "--poses",
    "kitti_seq/poses_short.txt",
    "--poses-format",
    "kitti-lidar",
];

const BODY: [&str; 4] = ["base_link", "imu_link", "rear_axle", "trailer_axle"];

#[test]
fn every_container_of_the_run_gives_numpys_eigenvalues_in_every_frame() {
    let run = &expected()["run"];
    let scans = run["scans"].as_array().unwrap();
    for c in run["containers"].as_array().unwrap() {
        let c = c.as_str().unwrap();
        let (code, err, recs) = run_records(&[c, "--all-frames"]);
        assert_eq!(code, 0, "{c}: {err}");
        assert_eq!(recs.len(), scans.len(), "{c}");
        for (r, s) in recs.iter().zip(scans) {
            let what = format!("{c} scan {}", s["index"]);
            assert_eq!(r["status"], "ok", "{what}");
            assert_eq!(r["stamp_ns"], s["stamp_ns"], "{what}");
            assert_eq!(r["points"], s["points"], "{what}");
            assert_eq!(r["nonfinite"], s["nonfinite_dropped"], "{what}");
            assert_eq!(r["normals"], "fields", "{what}");
            assert_families(r, "scan", &s["lidar"]["families"], &what);
            for f in BODY {
                assert_families(r, f, &s["frames"][f]["families"], &what);
                assert_label_changes(r, f, &s["label_changes"][f], &what);
            }
        }
    }
}

#[test]
fn a_far_body_frame_changes_decisions_and_point_displacement_never() {
    // The fixtures' label changes (so the comparison above can fail): the
    // trailer axle 6.28 m away flips unnormalized's decision on scans 0-3;
    // point displacement changes no decision or count in any frame (its
    // per-axis footprint may change: the axes are the frame's).
    let (_, _, recs) = run_records(&["run.mcap", "--all-frames"]);
    let flips = |frame: &str, fam: &str| -> Vec<u64> {
        recs.iter()
            .filter(|r| {
                label_changes(r, frame)
                    .iter()
                    .any(|(k, c)| k == fam && c[0])
            })
            .map(|r| r["index"].as_u64().unwrap())
            .collect()
    };
    assert_eq!(flips("trailer_axle", "unnormalized"), [0, 1, 2, 3]);
    assert_eq!(flips("base_link", "unnormalized"), Vec::<u64>::new());
    for f in BODY {
        for r in &recs {
            let pd = label_changes(r, f);
            assert_eq!(pd[7].0, "point_displacement");
            assert_eq!(pd[7].1[..2], [false; 2], "{f}");
        }
    }
}

#[test]
fn pairs_at_the_tf_pose_match_numpy() {
    let run = &expected()["run"];
    let pairs = run["pairs"].as_array().unwrap();
    for c in ["run.mcap", "run.bag", "run_db3"] {
        let (code, err, recs) = run_records(&[c, "--pairs", "--all-frames"]);
        assert_eq!(code, 0, "{c}: {err}");
        assert_eq!(recs.len(), pairs.len(), "{c}");
        for (r, p) in recs.iter().zip(pairs) {
            let what = format!("{c} pair {}", p["index"]);
            assert_eq!(r["index"], p["source"], "{what}");
            assert_eq!(r["pair"]["target_index"], p["target"], "{what}");
            assert_eq!(r["pair"]["correspondences"], p["correspondences"], "{what}");
            assert_families(r, "scan", &p["lidar"]["families"], &what);
            for f in BODY {
                assert_families(r, f, &p["frames"][f]["families"], &what);
            }
        }
    }
}

#[test]
fn hostile_scans_are_skipped_by_name_and_the_good_ones_reported() {
    let want = expected()["hostile"]["scans"]["/points"]
        .as_array()
        .unwrap();
    for c in ["hostile.mcap", "hostile.bag", "hostile_db3"] {
        let (code, err, recs) = run_records(&[c]);
        assert_eq!(code, 0, "{c}: {err}");
        assert!(!err.contains("panicked"), "{c}: {err}");
        assert_eq!(recs.len(), want.len(), "{c}");
        for (r, w) in recs.iter().zip(want) {
            let what = format!("{c} scan {}", w["index"]);
            match w["status"].as_str().unwrap() {
                "ok" | "ok_in_lidar_frame_only" => {
                    assert_eq!(r["status"], "ok", "{what}");
                    assert_eq!(r["points"], w["points"], "{what}");
                    assert_families(r, "scan", &w["lidar"]["families"], &what);
                }
                "empty" => assert_eq!(r["reason"], "empty", "{what}"),
                _ => {
                    assert_eq!(r["reason"], "invalid-cloud", "{what}");
                    assert_eq!(r["message"], w["reason"], "{what}");
                    let i = w["index"].as_u64().unwrap();
                    assert!(err.contains(&format!("scan {i} ")), "{what}: {err}");
                }
            }
        }
        // Scan 7's frame is on no transform: a named warning, not a skip.
        assert!(
            err.contains("warning[frame-missing]") && err.contains("lidar_rear"),
            "{err}"
        );
    }
}

#[test]
fn integer_and_mixed_coordinates_read_as_metres() {
    let want = expected()["fields"]["scans"]["/points"].as_array().unwrap();
    let (code, err, recs) = run_records(&["fields.mcap"]);
    assert_eq!(code, 0, "{err}");
    for (r, w) in recs.iter().zip(want) {
        let what = format!("fields scan {}", w["index"]);
        assert_eq!(r["points"], w["points"], "{what}");
        assert_families(r, "scan", &w["lidar"]["families"], &what);
    }
}

#[test]
fn two_pointcloud_topics_need_topic_and_each_matches_numpy() {
    let (code, err, _) = run_records(&["two_topics.mcap"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--topic") && err.contains("/room/points"),
        "{err}"
    );
    for t in ["/room/points", "/tunnel/points"] {
        let want = expected()["two_topics"]["scans"][t].as_array().unwrap();
        let (code, err, recs) = run_records(&["two_topics.mcap", "--topic", t]);
        assert_eq!(code, 0, "{err}");
        assert_eq!(recs.len(), want.len());
        for (r, w) in recs.iter().zip(want) {
            assert_families(
                r,
                "scan",
                &w["lidar"]["families"],
                &format!("{t} {}", w["index"]),
            );
        }
    }
}

#[test]
fn the_robot_description_gives_the_body_frames() {
    let want = expected()["description"]["scans"]["/points"]
        .as_array()
        .unwrap();
    let (code, err, recs) = run_records(&["description.mcap", "--all-frames"]);
    assert_eq!(code, 0, "{err}");
    for (r, w) in recs.iter().zip(want) {
        let what = format!("description scan {}", w["index"]);
        assert_families(r, "scan", &w["lidar"]["families"], &what);
        for f in BODY {
            assert_label_changes(r, f, &w["label_changes"][f], &what);
        }
    }
}

/// The first `len` bytes of `name` copied into `dir`.
fn cut(dir: &Path, name: &str, len: usize) -> PathBuf {
    let b = std::fs::read(Path::new(DIR).join(name)).unwrap();
    let file = Path::new(name).file_name().unwrap().to_string_lossy();
    let out = dir.join(file.replace("run", "run_truncated"));
    std::fs::write(&out, &b[..len]).unwrap();
    out
}

#[test]
fn a_truncated_bag_reports_the_scans_before_the_damage() {
    let t = &expected()["truncated"];
    let dir = tempfile::tempdir().unwrap();
    for (name, key) in [
        ("run.mcap", "run_truncated.mcap"),
        ("run.bag", "run_truncated.bag"),
    ] {
        let len = t[key]["bytes"][0].as_u64().unwrap() as usize;
        let f = cut(dir.path(), name, len);
        let (code, err, recs) = run_records(&[f.to_str().unwrap()]);
        let n = t[key]["points_messages_recovered"].as_u64().unwrap() as usize;
        // The damage is a named warning after the scans before it.
        assert_eq!(code, 0, "{key}: {err}");
        assert!(err.contains("warning[run-damaged]"), "{key}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(recs.len(), n, "{key}: {err}");
        let want = expected()["run"]["scans"].as_array().unwrap();
        for (r, w) in recs.iter().zip(want) {
            assert_families(r, "scan", &w["lidar"]["families"], key);
        }
    }
    // Python's sqlite3 cannot read the cut database at all: a clear error naming it.
    let len = t["run_truncated.db3"]["bytes"][0].as_u64().unwrap() as usize;
    let f = cut(dir.path(), "run_db3/run_db3.db3", len);
    let (code, err, _) = run_records(&[f.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("run_truncated_db3.db3") || err.contains(".db3"),
        "{err}"
    );
}

#[test]
fn kitti_sequence_with_estimated_normals_matches_numpy() {
    let want = expected()["kitti_seq"]["scans"].as_array().unwrap();
    for (voxel, key) in [("0", "no_voxel"), ("0.1", "voxel_0.1")] {
        let (code, err, recs) = run_records(&["kitti_seq", "--voxel", voxel]);
        assert_eq!(code, 0, "{err}");
        assert_eq!(recs.len(), want.len());
        for (r, w) in recs.iter().zip(want) {
            let what = format!("kitti {} {key}", w["index"]);
            assert_eq!(r["cells"], w["points"], "{what}");
            assert_eq!(r["points"], w[key]["kept"], "{what}");
            assert_eq!(r["normals"], "estimated");
            assert_families(r, "scan", &w[key]["lidar"]["families"], &what);
        }
    }
}

#[test]
fn kitti_pairs_agree_across_the_three_pose_files() {
    let want = expected()["kitti_seq"]["pairs_no_voxel"]
        .as_array()
        .unwrap();
    let runs: [&[&str]; 3] = [
        &[
            "--poses",
            "kitti_seq/poses.txt",
            "--poses-format",
            "kitti",
            "--calib",
            "kitti_seq/calib.txt",
        ],
        &[
            "--poses",
            "kitti_seq/poses_lidar.txt",
            "--poses-format",
            "kitti-lidar",
        ],
        &[
            "--poses",
            "kitti_seq/poses_tum.txt",
            "--poses-format",
            "tum",
        ],
    ];
    for extra in runs {
        let mut args = vec!["kitti_seq", "--voxel", "0", "--pairs"];
        args.extend_from_slice(extra);
        let (code, err, recs) = run_records(&args);
        assert_eq!(code, 0, "{extra:?}: {err}");
        assert_eq!(recs.len(), want.len(), "{extra:?}");
        for (r, w) in recs.iter().zip(want) {
            let what = format!("kitti pair {} {extra:?}", w["source"]);
            assert_eq!(r["pair"]["correspondences"], w["correspondences"], "{what}");
            assert_families(r, "scan", &w["lidar"]["families"], &what);
        }
    }
    // Three poses for five scans: the pairs without a pose are skipped by
    // name (never paired with a guessed pose), the others reported.
    let (code, err, recs) = run_records(&SHORT_POSES);
    assert_eq!(code, 0, "{err}");
    let ok: Vec<_> = recs
        .iter()
        .filter(|r| r["status"] == "ok")
        .map(|r| r["index"].clone())
        .collect();
    assert_eq!(ok, [1, 2]);
    assert!(
        err.contains("skipped (no-pose)") && err.contains("poses_short.txt"),
        "{err}"
    );
}

#[test]
fn a_folder_of_pcd_files_matches_numpy() {
    let want = expected()["pcd_seq"].as_array().unwrap();
    let (code, err, recs) = run_records(&["pcd_seq"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(recs.len(), want.len());
    for (r, w) in recs.iter().zip(want) {
        let what = format!("pcd {}", w["file"]);
        assert_eq!(r["points"], w["points"], "{what}");
        assert_families(r, "scan", &w["lidar"]["families"], &what);
    }
}
