//! Issue 31: `--format mcap` and `--output`. The files are read back with the
//! `mcap` crate's reader and every message validated against Foxglove's own
//! schemas (docs/schemas/external/foxglove/) with `jsonschema`, and their
//! numbers compared with the JSON report of the same command. (The
//! independent reader is Foxglove's Python package: python-tests/test_mcap.py,
//! run by `.ci/run`.) `--output` writes every format through the atomic
//! writer and never over an input.

use crate::common::run_cli;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

const ANYMAL: &str = "tests/fixtures/urdf/anymal_c_lidar.urdf";
const CORRIDOR: &str = "tests/fixtures/mcap/corridor_utm.csv";

/// A file's messages by topic (decoded JSON), its metadata record, and the
/// schema names; every message checked against Foxglove's schema of its
/// channel, which must be the one embedded.
pub struct Read {
    pub topics: BTreeMap<String, Vec<Value>>,
    pub schemas: BTreeMap<String, String>,
    pub metadata: BTreeMap<String, String>,
}

pub fn read(path: &Path) -> Read {
    let bytes = std::fs::read(path).unwrap();
    let mut r = Read {
        topics: BTreeMap::new(),
        schemas: BTreeMap::new(),
        metadata: BTreeMap::new(),
    };
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let ch = &m.channel;
        let schema = ch.schema.as_ref().expect("a schema");
        assert_eq!(
            (schema.encoding.as_str(), ch.message_encoding.as_str()),
            ("jsonschema", "json")
        );
        let file = schema.name.strip_prefix("foxglove.").expect("foxglove.*");
        let theirs = std::fs::read(format!("docs/schemas/external/foxglove/{file}.json")).unwrap();
        assert_eq!(
            &*schema.data,
            &theirs[..],
            "{}: Foxglove's bytes",
            schema.name
        );
        let v: Value = serde_json::from_slice(&theirs).unwrap();
        let validator = jsonschema::validator_for(&v).unwrap();
        let msg: Value = serde_json::from_slice(&m.data).unwrap();
        let errors: Vec<String> = validator
            .iter_errors(&msg)
            .map(|e| format!("{e} at {}", e.instance_path))
            .collect();
        assert!(errors.is_empty(), "{}: {errors:?}", ch.topic);
        assert!(!m.data.windows(4).any(|w| w == b"null"), "{}", ch.topic);
        assert_eq!((m.log_time, m.publish_time), (0, 0));
        r.schemas.insert(ch.topic.clone(), schema.name.clone());
        r.topics.entry(ch.topic.clone()).or_default().push(msg);
    }
    for rec in mcap::read::LinearReader::new(&bytes).unwrap() {
        if let mcap::records::Record::Metadata(md) = rec.unwrap() {
            assert_eq!(md.name, "extrinsic-audit");
            r.metadata = md.metadata;
        }
    }
    r
}

fn json(args: &[&str]) -> Value {
    let (code, out, err) = run_cli(&[args, &["--format", "json"]].concat());
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).unwrap()
}

fn export(dir: &Path, name: &str, args: &[&str]) -> Read {
    let out = dir.join(name);
    let o = out.to_str().unwrap();
    let (code, stdout, err) = run_cli(&[args, &["--format", "mcap", "--output", o]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.is_empty(),
        "nothing on standard output with --output"
    );
    read(&out)
}

fn entity<'a>(r: &'a Read, id: &str) -> &'a Value {
    r.topics["/audit/scene"][0]["entities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["id"] == id)
        .unwrap_or_else(|| panic!("no entity {id}"))
}

fn fact(e: &Value, key: &str) -> String {
    e["metadata"]
        .as_array()
        .unwrap()
        .iter()
        .find(|kv| kv["key"] == key)
        .and_then(|kv| kv["value"].as_str())
        .unwrap_or_else(|| panic!("no {key}"))
        .to_string()
}

fn xyz(v: &Value) -> [f64; 3] {
    ["x", "y", "z"].map(|k| v[k].as_f64().unwrap())
}

#[test]
fn a_rig_is_every_edge_a_screw_axis_and_a_lever_arm_with_the_reports_numbers() {
    let d = tempfile::tempdir().unwrap();
    let args = [ANYMAL, "--from", "base", "--to", "lidar"];
    let rep = json(&args);
    let tree = json(&[ANYMAL, "--frames", "--from", "base", "--to", "lidar"]);
    let r = export(d.path(), "rig.mcap", &args);
    let topics: Vec<&str> = r.topics.keys().map(String::as_str).collect();
    assert_eq!(topics, ["/audit/scene", "/tf"]);
    assert_eq!(r.schemas["/tf"], "foxglove.FrameTransforms");
    assert_eq!(r.topics["/tf"].len(), 1);
    let tf = r.topics["/tf"][0]["transforms"].as_array().unwrap();
    let edges = tree["edges"].as_array().unwrap();
    assert_eq!(tf.len(), edges.len());
    for (t, e) in tf.iter().zip(edges) {
        assert_eq!(t["parent_frame_id"], e["parent"]);
        assert_eq!(t["child_frame_id"], e["child"]);
        assert_eq!(t["translation"]["x"], e["translation_m"][0]);
        assert_eq!(t["translation"]["z"], e["translation_m"][2]);
    }
    assert_eq!(r.metadata["chain"], "base -> lidar_cage -> lidar");
    let sc = entity(&r, "screw_axis");
    assert_eq!(
        fact(sc, "h_m").parse::<f64>().unwrap(),
        rep["screw"]["translation_along_axis_m"].as_f64().unwrap()
    );
    assert_eq!(
        fact(sc, "pitch_m_per_rad").parse::<f64>().unwrap(),
        rep["screw"]["pitch_m_per_rad"].as_f64().unwrap()
    );
    let text = sc["texts"][0]["text"].as_str().unwrap();
    assert!(
        text.starts_with("screw axis: h = -0.1422 m, pitch = "),
        "{text}"
    );
    let lever = &entity(&r, "lever_arm")["arrows"][0];
    let len = lever["shaft_length"].as_f64().unwrap() + lever["head_length"].as_f64().unwrap();
    assert!((len - rep["lever_arm_m"].as_f64().unwrap()).abs() < 1e-15);
    assert_eq!(xyz(&lever["pose"]["position"]), [0.0; 3]);
    for f in ["base", "lidar"] {
        let ax = entity(&r, &format!("axes/{f}"));
        assert_eq!(ax["frame_id"], f);
        assert_eq!(ax["arrows"].as_array().unwrap().len(), 3);
    }
}

#[test]
fn a_scan_is_its_points_with_shares_and_its_degenerate_translation() {
    let d = tempfile::tempdir().unwrap();
    let rep = json(&["degeneracy", CORRIDOR]);
    let r = export(d.path(), "scan.mcap", &["degeneracy", CORRIDOR]);
    let topics: Vec<&str> = r.topics.keys().map(String::as_str).collect();
    assert_eq!(topics, ["/audit/points", "/audit/scene", "/tf"]);
    let pd = rep["families"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["family"] == "point_displacement")
        .unwrap();
    let eig: Value = serde_json::from_str(&r.metadata["point_displacement_eigenvalues"]).unwrap();
    assert_eq!(eig, pd["eigenvalues"]);
    let cloud = &r.topics["/audit/points"][0];
    assert_eq!(cloud["frame_id"], "scan");
    assert_eq!(cloud["point_stride"], 16);
    use base64::Engine as _;
    let raw = base64::engine::general_purpose::STANDARD
        .decode(cloud["data"].as_str().unwrap())
        .unwrap();
    assert_eq!(raw.len(), 16 * rep["points"].as_u64().unwrap() as usize);
    let share: f64 = raw
        .chunks(16)
        .map(|p| f64::from(f32::from_le_bytes(p[12..16].try_into().unwrap())))
        .sum();
    assert!((share - 1.0).abs() < 1e-5, "{share}");
    // The centroid in the pose, 500 km from the frame's origin.
    assert!((xyz(&cloud["pose"]["position"])[0] - 500_000.0).abs() < 10.0);
    let deg = entity(&r, "degenerate/0");
    assert_eq!(deg["frame_id"], "body");
    let dir: Value = serde_json::from_str(&fact(deg, "direction")).unwrap();
    assert_eq!(dir, rep["degenerate_subspace"][0]["screw"]["direction"]);
}

#[test]
fn a_report_without_a_scene_refuses_mcap_naming_the_formats_it_takes() {
    let (code, out, err) = run_cli(&["tunnel", "--format", "mcap"]);
    assert_eq!(code, 2, "{out}");
    assert!(out.is_empty());
    assert!(
        err.contains("--format mcap writes a 3D scene for Foxglove (a rig, the frame tree, `audit degeneracy`); expected a scene, found a report without one: this report takes text, markdown, json, github or csv"),
        "{err}"
    );
}

#[test]
fn output_writes_any_format_to_a_file_as_standard_output_has_it() {
    let d = tempfile::tempdir().unwrap();
    let args = [
        ANYMAL, "--from", "base", "--to", "lidar", "--format", "json",
    ];
    let (_, stdout, _) = run_cli(&args);
    let out = d.path().join("rig.json");
    let (code, printed, err) = run_cli(&[&args[..], &["--output", out.to_str().unwrap()]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(printed.is_empty());
    assert_eq!(std::fs::read_to_string(&out).unwrap(), stdout);
    // The same bytes every time (no clock in the scene).
    let a = d.path().join("a.mcap");
    let b = d.path().join("b.mcap");
    for p in [&a, &b] {
        let (code, _, err) = run_cli(&[
            ANYMAL,
            "--frames",
            "--format",
            "mcap",
            "--output",
            p.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

#[test]
fn output_never_replaces_an_input_a_hard_link_to_one_or_a_directory() {
    let d = tempfile::tempdir().unwrap();
    let urdf = d.path().join("robot.urdf");
    std::fs::copy(ANYMAL, &urdf).unwrap();
    let link = d.path().join("link.urdf");
    std::fs::hard_link(&urdf, &link).unwrap();
    let before = std::fs::read(&urdf).unwrap();
    let u = urdf.to_str().unwrap();
    for target in [u, link.to_str().unwrap()] {
        let (code, _, err) = run_cli(&[
            u, "--from", "base", "--to", "lidar", "--format", "mcap", "--output", target,
        ]);
        assert_eq!(code, 2, "{target}");
        assert!(
            err.contains(&format!(
                "--output {target}: refusing to write over an input of the command ({u})"
            )),
            "{err}"
        );
    }
    let (code, _, err) = run_cli(&["degeneracy", CORRIDOR, "--output", CORRIDOR]);
    assert_eq!(code, 2);
    assert!(err.contains("refusing to write over an input"), "{err}");
    let dir = d.path().to_str().unwrap();
    let (code, _, err) = run_cli(&[u, "--frames", "--output", dir]);
    assert_eq!(code, 2);
    assert!(err.contains("expected a file, found a directory"), "{err}");
    assert_eq!(std::fs::read(&urdf).unwrap(), before);
    let names: Vec<_> = std::fs::read_dir(d.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "no file left behind: {names:?}");
}

#[test]
fn a_run_is_one_message_per_scan_streamed_to_its_output_never_over_the_bag() {
    let d = tempfile::tempdir().unwrap();
    let bag = d.path().join("run.mcap");
    std::fs::copy("tests/fixtures/run/run.mcap", &bag).unwrap();
    let before = std::fs::read(&bag).unwrap();
    let b = bag.to_str().unwrap();
    let out = d.path().join("timeline.mcap");
    let o = out.to_str().unwrap();
    let lines = d.path().join("scans.jsonl");
    let l = lines.to_str().unwrap();
    let (code, stdout, err) = run_cli(&["run", b, "--format", "mcap", "--output", o, "--jsonl", l]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(stdout, "", "the MCAP file is the output");
    let bytes = std::fs::read(&out).unwrap();
    let mut stamps = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic == "/audit/run" {
            let schema = m.channel.schema.as_ref().unwrap();
            assert_eq!(schema.name, "extrinsic_audit.RunScan");
            let ours = std::fs::read("docs/schemas/mcap/RunScan.json").unwrap();
            assert_eq!(&*schema.data, &ours[..]);
            let v: Value = serde_json::from_slice(&ours).unwrap();
            let msg: Value = serde_json::from_slice(&m.data).unwrap();
            assert!(jsonschema::validator_for(&v).unwrap().is_valid(&msg));
            stamps.push(m.log_time);
        }
    }
    let want: Vec<u64> = std::fs::read_to_string(&lines)
        .unwrap()
        .lines()
        .map(|x| {
            let v: Value = serde_json::from_str(x).unwrap();
            v["stamp_ns"].as_u64().unwrap()
        })
        .collect();
    assert_eq!(stamps.len(), 8);
    assert_eq!(stamps, want);
    // Never over the bag (nor without --output: the file goes back over
    // its chunks, which a pipe cannot).
    let (code, _, err) = run_cli(&["run", b, "--format", "mcap", "--output", b]);
    assert_eq!(code, 2);
    assert!(err.contains("refusing to write over an input"), "{err}");
    let (code, _, err) = run_cli(&["run", b, "--format", "mcap"]);
    assert_eq!(code, 2);
    assert!(err.contains("give --output FILE.mcap"), "{err}");
    assert_eq!(std::fs::read(&bag).unwrap(), before);
}
