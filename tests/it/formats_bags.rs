//! Bags: `/tf_static` and `/robot_description` from MCAP, rosbag2 sqlite3 and
//! ROS 1 bags written by independent writers (tests/fixtures/bags/make_bags.py:
//! rosbags and mcap), compared to the transforms that were written
//! (expected.json) to 1e-12, through the library and the binary; truncated and
//! corrupt bags give clear errors and never panic.

use crate::common::audit;
use extrinsic_audit::internals::formats::bag;
use extrinsic_audit::internals::formats::{load_file, Parsed};
use extrinsic_audit::BagOptions;
use extrinsic_audit::Code;
use extrinsic_audit::{Edge, LoadOptions};
use serde_json::Value;
use std::path::{Path, PathBuf};

const DIR: &str = "tests/fixtures/bags";

/// The three containers of one scenario: MCAP, ROS 1, rosbag2 sqlite3 folder,
/// and the folder's .db3 file on its own (for `updates` also the variants below).
fn containers(name: &str) -> Vec<PathBuf> {
    let d = Path::new(DIR);
    let mut v = vec![
        d.join(format!("{name}.mcap")),
        d.join(format!("{name}.bag")),
        d.join(format!("{name}_db3")),
        d.join(format!("{name}_db3/{name}_db3.db3")),
    ];
    if name == "updates" {
        // ROS 1 chunks compressed with bz2 and lz4; ROS 1 messages in MCAP; a
        // rosbag2 folder with MCAP storage.
        v.push(d.join("updates_bz2.bag"));
        v.push(d.join("updates_lz4.bag"));
        v.push(d.join("updates_ros1.mcap"));
        v.push(d.join("updates_mcapdir"));
        // rosbag2 folders compressed with zstd per file and per message.
        for mode in ["file", "message"] {
            for storage in ["sqlite3", "mcap"] {
                v.push(d.join(format!("updates_{mode}_zstd_{storage}")));
            }
        }
    }
    v
}

fn expected() -> Value {
    let t = std::fs::read_to_string(Path::new(DIR).join("expected.json")).expect("expected.json");
    serde_json::from_str(&t).expect("json")
}

fn load(p: &Path) -> Parsed {
    load_file(p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn v3(v: &Value) -> [f64; 3] {
    [0, 1, 2].map(|i| v[i].as_f64().expect("number"))
}

fn v4(v: &Value) -> [f64; 4] {
    [0, 1, 2, 3].map(|i| v[i].as_f64().expect("number"))
}

/// Rotation matrix of a unit quaternion x y z w (closed form, written here).
fn matrix(q: [f64; 4]) -> [[f64; 3]; 3] {
    let [x, y, z, w] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - z * w),
            2.0 * (x * z + y * w),
        ],
        [
            2.0 * (x * y + z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - x * w),
        ],
        [
            2.0 * (x * z - y * w),
            2.0 * (y * z + x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

fn assert_close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-12,
        "{what}: got {got}, expected {want}"
    );
}

fn assert_edge(e: &Edge, want: &Value, what: &str) {
    assert_eq!(e.parent, want["parent"].as_str().unwrap(), "{what}");
    let d = e.transform.translation();
    for (i, w) in v3(&want["translation"]).iter().enumerate() {
        assert_close(d[i], *w, &format!("{what} translation[{i}]"));
    }
    let r = e.transform.rotation();
    let m = matrix(v4(&want["rotation_xyzw"]));
    for i in 0..3 {
        for j in 0..3 {
            assert_close(r[(i, j)], m[i][j], &format!("{what} R[{i}][{j}]"));
        }
    }
}

fn edge<'a>(l: &'a Parsed, child: &str, what: &str) -> &'a Edge {
    l.edges
        .iter()
        .find(|e| e.child == child)
        .unwrap_or_else(|| panic!("{what}: no edge to {child} in {:?}", l.edges))
}

fn assert_edges(l: &Parsed, want: &Value, what: &str) {
    let want = want.as_array().expect("list");
    assert_eq!(l.edges.len(), want.len(), "{what}: {:?}", l.edges);
    for w in want {
        let child = w["child"].as_str().unwrap();
        assert_edge(edge(l, child, what), w, &format!("{what} {child}"));
    }
}

#[test]
fn tf_static_updates_latest_wins_with_a_named_warning() {
    let x = expected();
    for p in containers("updates") {
        let what = p.display().to_string();
        let l = load(&p);
        assert_edges(&l, &x["updates"], &what);
        let lidar = edge(&l, "lidar", &what);
        assert_eq!(lidar.provenance.format, bag::FORMAT);
        assert!(
            lidar
                .provenance
                .key
                .starts_with("/tf_static message #1 at t=2.000000000 s ("),
            "{what}: {}",
            lidar.provenance.key
        );
        assert!(
            lidar
                .provenance
                .key
                .ends_with("transforms[0] base_link -> lidar"),
            "{what}"
        );
        let file = lidar.provenance.location.file.as_deref().expect("file");
        assert!(file.starts_with(&p), "{what}: {}", file.display());
        // imu_link is repeated unchanged in message #2: no warning for it, and
        // the latest message is the one cited.
        assert!(edge(&l, "imu_link", &what)
            .provenance
            .key
            .contains("message #2"));
        let ws: Vec<_> = l
            .warnings
            .iter()
            .filter(|w| w.code == Code::Ignored)
            .collect();
        assert_eq!(ws.len(), 1, "{what}: {:?}", l.warnings);
        let m = &ws[0].message;
        assert!(m.contains("frame 'lidar' is set twice"), "{m}");
        assert!(
            m.contains("/tf_static message #0 at t=1.000000000 s"),
            "{m}"
        );
        assert!(m.contains("superseded by /tf_static message #1"), "{m}");
        assert_eq!(l.warnings.len(), 1, "{what}: {:?}", l.warnings);
    }
}

#[test]
fn robot_description_edges_point_at_the_bag() {
    let x = expected();
    for p in containers("description") {
        let what = p.display().to_string();
        let l = load(&p);
        assert_edges(&l, &x["description"], &what);
        assert!(l.warnings.is_empty(), "{what}: {:?}", l.warnings);
        // imu and lidar come from /tf_static (what ran); the wheel only from the URDF.
        assert!(edge(&l, "lidar", &what)
            .provenance
            .key
            .starts_with("/tf_static message #0"));
        let wheel = edge(&l, "wheel", &what);
        assert_eq!(wheel.provenance.format, "urdf");
        let k = &wheel.provenance.key;
        assert!(
            k.starts_with("/robot_description message #0 at t=0.500000000 s ("),
            "{k}"
        );
        assert!(
            k.contains("joint \"wheel_joint\" <origin>, description line 15"),
            "{k}"
        );
        assert!(wheel
            .provenance
            .location
            .file
            .as_deref()
            .expect("file")
            .starts_with(&p));
        assert_eq!(wheel.provenance.location.line, None);
    }
}

#[test]
fn unrelated_topics_before_tf_static_are_skipped() {
    let x = expected();
    for p in containers("unrelated") {
        let l = load(&p);
        assert_edges(&l, &x["unrelated"], &p.display().to_string());
    }
}

#[test]
fn tf_on_request_keeps_the_constant_transforms() {
    let x = expected();
    let mut opts = BagOptions::default();
    opts.tf_topics = vec!["/tf".into()];
    for p in containers("unrelated") {
        let what = p.display().to_string();
        // By default /tf is not read.
        assert_eq!(load(&p).edges.len(), 2, "{what}");
        let l = bag::load_with(&p, &LoadOptions::default(), &opts).expect("load");
        assert_eq!(l.edges.len(), 3, "{what}: {:?}", l.edges);
        let cam = edge(&l, "camera", &what);
        assert_edge(cam, &x["unrelated_tf_constant"][0], &what);
        let k = &cam.provenance.key;
        assert!(k.starts_with("/tf message #0 at t=0.150000000 s ("), "{k}");
        assert!(
            k.ends_with("base_link -> camera (constant over 3 samples)"),
            "{k}"
        );
        assert_eq!(l.warnings.len(), 1, "{what}: {:?}", l.warnings);
        assert!(
            l.warnings[0].message.contains("frame 'base_link' moves"),
            "{:?}",
            l.warnings
        );
        assert!(l.edges.iter().all(|e| e.child != "base_link"));
    }
}

/// A compressed split names the compressed file in provenance, and a
/// metadata.yaml that claims a compression the files do not have is a clear
/// error naming the message.
#[test]
fn compressed_rosbag2_provenance_and_lies() {
    let d = Path::new(DIR).join("updates_file_zstd_sqlite3");
    let l = load(&d);
    let f = l.edges[0].provenance.location.file.as_ref().expect("file");
    assert!(f.ends_with("updates_file_zstd_sqlite3.db3.zstd"), "{f:?}");
    assert!(
        l.edges[0].provenance.key.contains("decompressed"),
        "{:?}",
        l.edges[0].provenance
    );

    let tmp = tempfile::tempdir().expect("tempdir");
    let src = Path::new(DIR).join("updates_db3");
    for f in ["metadata.yaml", "updates_db3.db3"] {
        std::fs::copy(src.join(f), tmp.path().join(f)).expect("copy");
    }
    let meta = tmp.path().join("metadata.yaml");
    let text = std::fs::read_to_string(&meta).expect("read");
    let lie = text
        .replace("compression_mode: ''", "compression_mode: message")
        .replace("compression_format: ''", "compression_format: zstd");
    assert_ne!(lie, text, "the fixture's metadata names its compression");
    std::fs::write(&meta, lie).expect("write");
    let e = load_file(tmp.path(), &LoadOptions::default()).expect_err("refused");
    assert!(e.message.contains("expected zstd-compressed bytes"), "{e}");
    std::fs::write(
        &meta,
        text.replace("compression_format: ''", "compression_format: lz4")
            .replace("compression_mode: ''", "compression_mode: file"),
    )
    .expect("write");
    let e = load_file(tmp.path(), &LoadOptions::default()).expect_err("refused");
    assert!(e.message.contains("expected zstd"), "{e}");
}

/// The CLI's topic flags reach the reader: `--tf-topic /tf` adds the
/// constant `base_link -> camera`; `--tf-static-topic` replaces /tf_static.
#[test]
fn cli_topic_flags_choose_what_is_read() {
    for p in containers("unrelated") {
        let f = p.to_str().expect("utf-8");
        let (code, out, err) = crate::common::run_cli(&[f, "--frames"]);
        assert_eq!(code, 0, "{err}");
        assert!(!out.contains("camera"), "{out}");
        let (code, out, err) = crate::common::run_cli(&[f, "--frames", "--tf-topic", "/tf"]);
        assert_eq!(code, 0, "{err}");
        assert!(out.contains("camera"), "{out}");
        let (code, _, err) = crate::common::run_cli(&[
            f,
            "--frames",
            "--tf-static-topic",
            "/no_such_topic",
            "--description-topic",
            "/none",
        ]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("/no_such_topic"), "{err}");
    }
}

#[test]
fn only_the_asked_topics_are_read() {
    // Without /tf_static there is only the description.
    let mut opts = BagOptions::default();
    opts.static_topics = vec![];
    for p in containers("description") {
        let l = bag::load_with(&p, &LoadOptions::default(), &opts).expect("load");
        assert_eq!(l.edges.len(), 3, "{}", p.display());
        assert!(l.edges.iter().all(|e| e.provenance.format == "urdf"));
    }
    // /tf_static read as if it were /tf: imu_link never moves, lidar does.
    let mut opts = BagOptions::default();
    opts.static_topics = vec![];
    opts.tf_topics = vec!["/tf_static".into()];
    opts.description_topics = vec![];
    opts.parameter_topics = vec![];
    for p in containers("updates") {
        let what = p.display().to_string();
        let l = bag::load_with(&p, &LoadOptions::default(), &opts).expect("load");
        let children: Vec<&str> = l.edges.iter().map(|e| e.child.as_str()).collect();
        assert_eq!(children, ["imu_link", "lidar_optical"], "{what}");
        assert!(
            l.edges[0]
                .provenance
                .key
                .ends_with("(constant over 2 samples)"),
            "{what}"
        );
        assert_edge(&l.edges[0], &expected()["updates"][0], &what);
        assert!(
            l.warnings
                .iter()
                .any(|w| w.message.contains("frame 'lidar' moves")),
            "{what}: {:?}",
            l.warnings
        );
    }
}

fn load_err(p: &Path) -> String {
    match load_file(p, &LoadOptions::default()) {
        Ok(l) => panic!("{}: expected an error, read {:?}", p.display(), l.edges),
        Err(e) => {
            // A folder's errors name the file inside it.
            let file = e.location.file.as_deref().expect("file");
            assert!(file.starts_with(p), "{e}");
            e.to_string()
        }
    }
}

#[test]
fn truncated_bags_are_clear_errors() {
    let d = Path::new(DIR);
    let e = load_err(&d.join("truncated.mcap"));
    assert!(
        e.contains(
            "MCAP file ended in the middle of a record, at byte 568 of 568 (truncated or corrupt?)"
        ),
        "{e}"
    );
    let e = load_err(&d.join("truncated.bag"));
    assert!(
        e.contains("index_pos 5972: expected an index inside the 4327-byte file"),
        "{e}"
    );
    assert!(e.contains("rosbag reindex"), "{e}");
    let e = load_err(&d.join("truncated.db3"));
    assert!(e.contains("rosbag2 sqlite3"), "{e}");
    assert!(e.contains("malformed"), "{e}");
}

#[test]
fn corrupt_messages_name_topic_message_and_offset() {
    for p in containers("corrupt_message") {
        let e = load_err(&p);
        assert!(
            e.contains("/tf_static message #0 at t=1.000000000 s ("),
            "{e}"
        );
        assert!(
            e.contains("transforms count 2147483647: expected at most 0 in the 0 bytes left"),
            "{e}"
        );
    }
}

#[test]
fn a_bag_without_transforms_lists_its_topics() {
    for p in containers("no_tf") {
        let e = load_err(&p);
        assert!(e.contains("expected transforms on /tf_static or a URDF on /robot_description, found no message on them (topics: /chatter, /tf)"), "{e}");
    }
}

#[test]
fn every_prefix_and_byte_flip_is_an_error_or_a_result_never_a_panic() {
    let dir = tempfile::tempdir().expect("tmp");
    for name in ["updates.mcap", "updates.bag", "description.mcap"] {
        let data = std::fs::read(Path::new(DIR).join(name)).expect("read");
        let p = dir.path().join(name);
        let step = (data.len() / 150).max(1);
        for cut in (0..data.len()).step_by(step) {
            std::fs::write(&p, &data[..cut]).expect("write");
            if load_file(&p, &LoadOptions::default()).is_ok() {
                // Only a bag cut after its index may still read (never the case here).
                panic!("{name} cut at {cut}: read without an error");
            }
        }
        for at in (8..data.len()).step_by(step) {
            let mut d = data.clone();
            d[at] ^= 0xa5;
            std::fs::write(&p, &d).expect("write");
            let _ = load_file(&p, &LoadOptions::default());
        }
    }
}

#[test]
fn is_bag_by_extension_folder_and_magic() {
    let d = Path::new(DIR);
    assert!(bag::is_bag(&d.join("updates.mcap")));
    assert!(bag::is_bag(&d.join("updates.bag")));
    assert!(bag::is_bag(&d.join("updates_db3")));
    assert!(bag::is_bag(&d.join("truncated.db3")));
    assert!(!bag::is_bag(&d.join("robot.urdf")));
    assert!(!bag::is_bag(d));
    let dir = tempfile::tempdir().expect("tmp");
    let p = dir.path().join("recording.bin");
    std::fs::copy(d.join("updates.mcap"), &p).expect("copy");
    assert!(bag::is_bag(&p));
    assert_eq!(load(&p).edges.len(), 3);
}

fn stdout_ok(args: &[&str]) -> (String, String) {
    let out = audit().args(args).output().expect("run");
    let (o, e) = (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    );
    assert_eq!(out.status.code(), Some(0), "{args:?}: {e}");
    (o, e)
}

#[test]
fn cli_frames_of_a_bag() {
    for p in containers("updates") {
        let f = p.to_str().unwrap();
        let (o, e) = stdout_ok(&[f, "--frames"]);
        for frame in ["base_link", "imu_link", "lidar", "lidar_optical"] {
            assert!(o.contains(frame), "{f}: {o}");
        }
        assert!(e.contains("warning[ignored]"), "{f}: {e}");
    }
}

#[test]
fn cli_chain_from_a_bag_equals_the_written_transforms() {
    let x = expected();
    let want = &x["updates_base_link_to_lidar_optical"];
    let m = matrix(v4(&want["rotation_xyzw"]));
    for p in containers("updates") {
        let f = p.to_str().unwrap();
        let (o, _) = stdout_ok(&[
            f,
            "--from",
            "base_link",
            "--to",
            "lidar_optical",
            "--format",
            "json",
        ]);
        let j: Value = serde_json::from_str(&o).expect("json");
        for (i, w) in v3(&want["translation"]).iter().enumerate() {
            assert_close(j["transform"]["translation_m"][i].as_f64().unwrap(), *w, f);
        }
        for (i, row) in m.iter().enumerate() {
            for (k, w) in row.iter().enumerate() {
                assert_close(
                    j["transform"]["rotation_matrix"][i][k].as_f64().unwrap(),
                    *w,
                    f,
                );
            }
        }
        // base_link -> lidar: one edge, the updated one.
        let (o, _) = stdout_ok(&[
            f,
            "--from",
            "base_link",
            "--to",
            "lidar",
            "--format",
            "json",
        ]);
        let j: Value = serde_json::from_str(&o).expect("json");
        for (i, w) in v3(&x["updates"][1]["translation"]).iter().enumerate() {
            assert_close(j["transform"]["translation_m"][i].as_f64().unwrap(), *w, f);
        }
    }
}

#[test]
fn cli_bag_mixed_with_a_urdf_reports_the_conflict() {
    let urdf = format!("{DIR}/robot.urdf");
    for p in containers("updates") {
        let f = p.to_str().unwrap();
        let out = audit().args([f, &urdf, "--frames"]).output().expect("run");
        let e = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{f}: {e}");
        assert!(
            e.contains("edge base_link -> lidar given twice with different values"),
            "{e}"
        );
        assert!(e.contains(&format!("first at {}", p.display())), "{e}");
        assert!(
            e.contains("/tf_static message #1 at t=2.000000000 s"),
            "{e}"
        );
        assert!(
            e.contains("robot.urdf:11:3 (joint \"lidar_joint\" <origin>)"),
            "{e}"
        );
    }
    // The description bags ran with the file's values: duplicates, no conflict.
    for p in containers("description") {
        let f = p.to_str().unwrap();
        let (_, e) = stdout_ok(&[f, &urdf, "--frames"]);
        assert_eq!(e.matches("warning[duplicate-edge]").count(), 3, "{f}: {e}");
    }
}

#[test]
fn mcap_chunks_without_wanted_topics_are_never_read() {
    // Overwrite every chunk that holds no /tf_static message with garbage: the
    // bag still reads, so those chunks were skipped through the index.
    let src = Path::new(DIR).join("unrelated.mcap");
    let mut data = std::fs::read(&src).expect("read");
    let summary = mcap::Summary::read(&data)
        .expect("summary")
        .expect("has one");
    let tf: Vec<u16> = summary
        .channels
        .values()
        .filter(|c| c.topic == "/tf_static")
        .map(|c| c.id)
        .collect();
    let mut wiped = 0;
    for ci in &summary.chunk_indexes {
        if ci.message_index_offsets.keys().any(|k| tf.contains(k)) {
            continue;
        }
        let start = ci.compressed_data_offset().expect("offset") as usize;
        data[start..start + ci.compressed_size as usize].fill(0xff);
        wiped += 1;
    }
    assert!(
        wiped >= 3,
        "expected several /chatter-only chunks, found {wiped}"
    );
    let dir = tempfile::tempdir().expect("tmp");
    let p = dir.path().join("wiped.mcap");
    std::fs::write(&p, &data).expect("write");
    assert_edges(&load(&p), &expected()["unrelated"], "wiped.mcap");
    // ...and reading those chunks would have failed.
    let mut opts = BagOptions::default();
    opts.static_topics = vec!["/tf_static".into(), "/chatter".into()];
    let e = bag::load_with(&p, &LoadOptions::default(), &opts).expect_err("garbage chunk");
    assert!(e.message.contains("chunk at byte"), "{e}");
}

#[test]
fn robot_description_from_a_parameter_event() {
    let x = expected();
    for name in ["param_description.mcap", "param_description_db3"] {
        let p = Path::new(DIR).join(name);
        let l = load(&p);
        assert_edges(&l, &x["description"], name);
        let k = &edge(&l, "lidar", name).provenance.key;
        assert!(
            k.starts_with("/parameter_events message #1 at t=0.300000000 s ("),
            "{k}"
        );
        assert!(k.contains("(parameter robot_description of node /robot_state_publisher): joint \"lidar_joint\" <origin>, description line 11"), "{k}");
        // The decoy from another node, earlier, is named and not used.
        assert_eq!(l.warnings.len(), 1, "{name}: {:?}", l.warnings);
        assert_eq!(l.warnings[0].code, Code::Ignored);
        assert!(
            l.warnings[0]
                .message
                .contains("node /other_node) differs from the latest"),
            "{:?}",
            l.warnings
        );
    }
}

#[test]
fn cli_check_walks_bags_and_takes_a_rosbag2_folder_as_one_input() {
    let dir = tempfile::tempdir().expect("tmp");
    let d = Path::new(DIR);
    std::fs::copy(d.join("updates.mcap"), dir.path().join("updates.mcap")).expect("copy");
    std::fs::copy(d.join("updates.bag"), dir.path().join("updates.bag")).expect("copy");
    let folder = dir.path().join("rec/updates_db3");
    std::fs::create_dir_all(&folder).expect("mkdir");
    for f in ["metadata.yaml", "updates_db3.db3"] {
        std::fs::copy(d.join("updates_db3").join(f), folder.join(f)).expect("copy");
    }
    let out = audit()
        .args([
            "check",
            dir.path().to_str().unwrap(),
            "--pair",
            "base_link:lidar",
        ])
        .output()
        .expect("run");
    let e = String::from_utf8_lossy(&out.stderr);
    let o = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{o}\n{e}");
    assert!(
        format!("{o}{e}").contains("checked 3 files: 0 problems, 3 warnings"),
        "{o}\n{e}"
    );
    assert!(!e.contains("metadata.yaml"), "{e}");
}
