//! Every JSON output validates against its committed schema in docs/schemas
//! (JSON Schema 2020-12, checked with the `jsonschema` crate).

use crate::common::run_cli;
use serde_json::Value;

pub fn schema(name: &str) -> jsonschema::Validator {
    let path = format!(
        "{}/docs/schemas/{name}.schema.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let s: Value = serde_json::from_str(&std::fs::read_to_string(&path).expect("schema"))
        .expect("schema JSON");
    jsonschema::validator_for(&s).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn assert_valid(name: &str, args: &[&str]) {
    let (code, out, err) = run_cli(args);
    assert!(code == 0 || code == 1, "{args:?}: exit {code}: {err}");
    let v: Value = serde_json::from_str(&out).expect("JSON output");
    let errors: Vec<String> = schema(name)
        .iter_errors(&v)
        .map(|e| format!("{} at {}", e, e.instance_path))
        .collect();
    assert!(errors.is_empty(), "{args:?} against {name}: {errors:#?}");
}

/// The ANYmal C rig report as JSON (its base -> lidar chain, written here).
const ANYMAL_JSON: [&str; 7] = [
    "tests/fixtures/urdf/anymal_c_lidar.urdf",
    "--from",
    "base",
    "--to",
    "lidar",
    "--format",
    "json",
];

/// One JSON run of every command whose `--format` takes `json`, with the
/// schema it must match (`docs/schemas/NAME.schema.json`). The first argument
/// names the command (a file: the rig report); `report_contract` fails when a
/// command takes `--format json` and has no entry here.
pub const SCHEMAS: [(&str, &[&str]); 12] = [
    ("rig-report", &ANYMAL_JSON),
    (
        "frames",
        &[
            "tests/fixtures/urdf/anymal_c_lidar.urdf",
            "--frames",
            "--format",
            "json",
        ],
    ),
    (
        "survey",
        &["survey", "calibrations/", "--all", "--format", "json"],
    ),
    ("check", &["check", "calibrations/", "--format", "json"]),
    ("tunnel", &["tunnel", "--format", "json"]),
    (
        "simulate",
        &[
            "simulate",
            "--shift",
            "0.3,0,0.2",
            "--rotate-rpy",
            "0,0,1.57",
            "--scene",
            "tunnel",
            "--format",
            "json",
        ],
    ),
    (
        "degeneracy",
        &[
            "degeneracy",
            "tests/fixtures/detector/tunnel_small_le.ply",
            "--shift",
            "1,0,0",
            "--format",
            "json",
        ],
    ),
    (
        "calibrate-threshold",
        &[
            "calibrate-threshold",
            "--seeds",
            "1",
            "--noise",
            "0",
            "--voxel",
            "0.1",
            "--format",
            "json",
        ],
    ),
    (
        "degeneracy-sweep",
        &[
            "sweep",
            "tests/fixtures/detector/tunnel_small_le.ply",
            "--format",
            "json",
        ],
    ),
    (
        "diff",
        &[
            "diff",
            "tests/fixtures/diff/whole_old.urdf",
            "tests/fixtures/diff/whole_new.urdf",
            "--format",
            "json",
        ],
    ),
    (
        "spread",
        &[
            "spread",
            "tests/fixtures/spread/kitti-repeat",
            "--format",
            "json",
        ],
    ),
    (
        "run",
        &["run", "tests/fixtures/run/pcd_seq", "--format", "json"],
    ),
];

/// Every entry of [`SCHEMAS`]: the command's JSON matches its schema.
#[test]
fn every_command_s_json_matches_its_schema() {
    for (name, args) in SCHEMAS {
        assert_valid(name, args);
    }
}

/// More runs of some commands (options that add fields) against the schemas.
#[test]
fn json_outputs_match_the_committed_schemas() {
    let kappa = [&ANYMAL_JSON[..], &["--kappa", "0.01", "--lambda", "0.004"]].concat();
    assert_valid("rig-report", &kappa);
    for d in ["lio-sam", "dcreg", "fast-lio"] {
        assert_valid(
            "rig-report",
            &[&ANYMAL_JSON[..], &["--detector", d]].concat(),
        );
    }
    // A detector's own configuration among the files: `detector.config`.
    for cfg in ["dcreg_icp.yaml", "xicp_icp.yaml"] {
        let cfg = format!("tests/fixtures/detectors/config/{cfg}");
        assert_valid(
            "rig-report",
            &[&ANYMAL_JSON[..1], &[cfg.as_str()], &ANYMAL_JSON[1..]].concat(),
        );
    }
    // Calibrations that name the pair otherwise (`PATH:FROM:TO`).
    let renamed = "tests/fixtures/spread/kitti-renamed";
    let (a, b) = (
        format!("{renamed}/kitti-repeat-1.toml"),
        format!("{renamed}/kitti-repeat-2.toml:imu_link:velodyne"),
    );
    assert_valid("spread", &["spread", &a, &b, "--format", "json"]);
    for set in ["kitti-repeat", "pure-translation"] {
        let dir = format!("tests/fixtures/spread/{set}");
        assert_valid(
            "spread",
            &["spread", &dir, "--tolerance", "5,0.5", "--format", "json"],
        );
    }
    assert_valid(
        "degeneracy",
        &[
            "degeneracy",
            "tests/fixtures/detector/tunnel_small_le.ply",
            "--estimate-normals",
            "--voxel",
            "0.1",
            "--normal-radius",
            "1",
            "--min-planarity",
            "0.2",
            "--show-matrices",
            "--format",
            "json",
        ],
    );
    assert_valid(
        "degeneracy-sweep",
        &[
            "sweep",
            "tests/fixtures/detector/tunnel_small_le.ply",
            "--estimate-normals",
            "--voxel",
            "0.1",
            "--normal-radius",
            "1",
            "--rig",
            "tests/fixtures/urdf/anymal_c_lidar.urdf",
            "--from",
            "base",
            "--to",
            "lidar",
            "--format",
            "json",
        ],
    );
}

/// The detector commands' JSON (the calibration on a reduced sweep), each
/// with `schema_version` and a `warnings` array like every other command.
#[test]
fn detector_json_outputs_match_their_schemas() {
    assert_valid(
        "tunnel",
        &["tunnel", "--shift", "0,2,0", "--format", "json"],
    );
}

/// Every command's JSON carries `schema_version` 1 and a `warnings` array
/// (a count in the check report, whose findings list every warning).
#[test]
fn every_json_output_has_a_version_and_warnings() {
    let runs: [&[&str]; 6] = [
        &ANYMAL_JSON,
        &[
            "tests/fixtures/formats/ros1_static_tf.launch",
            "--frames",
            "--format",
            "json",
        ],
        &["survey", "calibrations/", "--format", "json"],
        &["tunnel", "--format", "json"],
        &[
            "simulate", "--shift", "0.3,0,0", "--scene", "corridor", "--format", "json",
        ],
        &[
            "degeneracy",
            "tests/fixtures/detector/tunnel_small_le.ply",
            "--format",
            "json",
        ],
    ];
    for args in runs {
        let (_, out, _) = run_cli(args);
        let v: Value = serde_json::from_str(&out).expect("JSON output");
        assert_eq!(v["schema_version"], 1, "{args:?}");
        assert!(v["warnings"].is_array(), "{args:?}");
    }
    // The check report moved to version 2 when its `warnings` count became
    // the array every other report has.
    let (_, out, _) = run_cli(&["check", "calibrations/", "--format", "json"]);
    let v: Value = serde_json::from_str(&out).expect("JSON output");
    assert_eq!(v["schema_version"], 2);
    let ws = v["warnings"].as_array().expect("an array");
    let findings = v["findings"].as_array().expect("findings");
    assert_eq!(
        ws.len(),
        findings
            .iter()
            .filter(|f| f["severity"] == "warning")
            .count()
    );
    assert!(schema("check").is_valid(&v));
    // The survey's warnings (GEODE's four-digit rotation matrices) reach the JSON.
    let (_, out, err) = run_cli(&["survey", "calibrations/", "--format", "json"]);
    let v: Value = serde_json::from_str(&out).unwrap();
    let ws = v["warnings"].as_array().unwrap();
    assert!(ws.iter().any(|w| w
        .as_str()
        .unwrap()
        .contains("geode-alpha-vlp16.toml:23:1: rotation matrix is orthonormal only")));
    // On stderr the four rounded rotations are one note (issue 33).
    assert_eq!(ws.len(), 4, "{ws:?}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("note: 4 rigs: rotation rounded"), "{err}");
}

/// A format a command cannot produce is an error naming the formats it
/// takes (the full lists: `render::tests`), not other output.
#[test]
fn an_unsupported_format_is_refused() {
    let (code, out, err) = run_cli(&[
        "tests/fixtures/urdf/anymal_c_lidar.urdf",
        "--frames",
        "--format",
        "sarif",
    ]);
    assert_eq!(code, 2, "{out}");
    assert!(out.is_empty());
    assert!(
        err.contains("--format sarif lists the findings of `audit check`; expected findings, found a picture (the frame tree): this report takes text, markdown, json, dot, mermaid"),
        "{err}"
    );
    let (code, out, err) = run_cli(&["tunnel", "--format", "sarif"]);
    assert_eq!(code, 2, "{out}");
    assert!(
        err.contains("--format sarif lists the findings of `audit check`; expected findings, found a report without one: this report takes text, markdown, json, github"),
        "{err}"
    );
    // A picture of a report that has none: every command takes the picture
    // formats' names, and refuses them but for the frame tree.
    for args in [
        &["survey", "calibrations/", "--format", "dot"][..],
        &["calibrations/fastlio-avia.toml", "--format", "svg"],
    ] {
        let (code, out, err) = run_cli(args);
        assert_eq!(code, 2, "{args:?}: {out}");
        assert!(out.is_empty(), "{args:?}");
        assert!(
            err.contains("draws the frame tree (`audit FILE... --frames`); expected a picture, found a report without one: this report takes text, markdown, json, github"),
            "{args:?}: {err}"
        );
    }
}

/// A URDF written here: base -> torso (revolute) -> mount -> lidar, and an
/// IMU on the base, so that a frame tree has depth, a movable joint and a
/// chain through both.
fn authored_urdf(dir: &tempfile::TempDir) -> String {
    let x = r#"<robot name="authored">
  <link name="base"/><link name="torso"/><link name="mount"/><link name="lidar"/><link name="imu"/>
  <joint name="torso_joint" type="revolute"><parent link="base"/><child link="torso"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="mount_joint" type="fixed"><parent link="torso"/><child link="mount"/>
    <origin xyz="0.1 0 0.2" rpy="0 0.2 0"/></joint>
  <joint name="lidar_joint" type="fixed"><parent link="mount"/><child link="lidar"/>
    <origin xyz="0 0 0.05" rpy="0 0 1.5707963"/></joint>
  <joint name="imu_joint" type="fixed"><parent link="base"/><child link="imu"/>
    <origin xyz="-0.1 0.02 0"/></joint>
</robot>
"#;
    let p = crate::common::hostile::write_tmp(dir, "authored.urdf", x);
    p.to_str().unwrap().to_string()
}

/// The frame tree's JSON on several real trees validates against its schema,
/// with `schema_version` first and `warnings` last, the warnings being those
/// printed on standard error.
#[test]
fn frame_trees_match_their_schema() {
    let dir = tempfile::tempdir().unwrap();
    let urdf = authored_urdf(&dir);
    let runs: [&[&str]; 6] = [
        &[&urdf],
        &[&urdf, "--from", "imu", "--to", "lidar"],
        &["tests/fixtures/formats/ros1_tf_static_echo.yaml"],
        &[
            "tests/fixtures/formats/ros1_static_tf.launch",
            "--from",
            "imu",
            "--to",
            "os_lidar",
        ],
        // Two files, one graph; GEODE's four-digit rotation gives a warning,
        // and the dump's `imu` beside GEODE's `IMU` a confusable-frame-name.
        &[
            "calibrations/geode-alpha-vlp16.toml",
            "tests/fixtures/formats/ros1_tf_static_echo.yaml",
        ],
        &[
            "calibrations/geode-alpha-vlp16.toml",
            "--from",
            "IMU",
            "--to",
            "LiDAR",
        ],
    ];
    let s = schema("frames");
    let mut warned = 0;
    for extra in runs {
        let args = [extra, &["--frames", "--format", "json"]].concat();
        let (code, out, err) = run_cli(&args);
        assert_eq!(code, 0, "{args:?}: {err}");
        let v: Value = serde_json::from_str(&out).expect("JSON output");
        let errors: Vec<String> = s
            .iter_errors(&v)
            .map(|e| format!("{} at {}", e, e.instance_path))
            .collect();
        assert!(errors.is_empty(), "{args:?}: {errors:#?}");
        assert!(out.starts_with("{\n  \"schema_version\": 1,\n"), "{out}");
        let last_key = out.rfind("\n  \"").map(|i| &out[i + 4..]);
        assert!(
            last_key.is_some_and(|k| k.starts_with("warnings\"")),
            "{out}"
        );
        let ws = v["warnings"].as_array().unwrap();
        assert_eq!(ws.len(), err.lines().count(), "{args:?}: {err}");
        warned += ws.len();
    }
    assert_eq!(
        warned, 3,
        "the GEODE rig's warning, in both runs that read it, and imu beside IMU"
    );
    // The authored URDF: five frames, the chain imu -> base -> torso -> mount -> lidar.
    let (_, out, _) = run_cli(&[
        &urdf, "--from", "imu", "--to", "lidar", "--frames", "--format", "json",
    ]);
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["frames"].as_array().unwrap().len(), 5);
    assert_eq!(
        v["chain"]["path"],
        serde_json::json!(["imu", "base", "torso", "mount", "lidar"])
    );
    let torso = &v["edges"].as_array().unwrap()[0];
    assert_eq!(
        (&torso["child"], &torso["joint_type"]),
        (&"torso".into(), &"revolute".into())
    );
}

/// A change that makes a document wrong.
type Spoil = fn(&mut Value);

/// The frame-tree schema refuses what is not a frame tree.
#[test]
fn the_frame_tree_schema_refuses_a_wrong_document() {
    let s = schema("frames");
    let (_, out, _) = run_cli(&[
        "tests/fixtures/formats/ros1_static_tf.launch",
        "--frames",
        "--format",
        "json",
    ]);
    let good: Value = serde_json::from_str(&out).unwrap();
    assert!(s.is_valid(&good));
    let wrong: [(&str, Spoil); 6] = [
        ("no warnings", |v| {
            v.as_object_mut().unwrap().remove("warnings");
        }),
        ("a warning not a string", |v| {
            v["warnings"] = serde_json::json!([1])
        }),
        ("another version", |v| v["schema_version"] = 2.into()),
        ("an unknown joint type", |v| {
            v["edges"][0]["joint_type"] = "helical".into()
        }),
        ("a translation of two numbers", |v| {
            v["edges"][0]["translation_m"] = serde_json::json!([0.0, 1.0])
        }),
        ("an unknown field", |v| {
            v["frames"][0]["colour"] = "red".into()
        }),
    ];
    for (what, spoil) in wrong {
        let mut v = good.clone();
        spoil(&mut v);
        assert!(!s.is_valid(&v), "accepted {what}");
    }
    // Another report is not a frame tree either.
    let (_, out, _) = run_cli(&["tunnel", "--format", "json"]);
    assert!(!s.is_valid(&serde_json::from_str::<Value>(&out).unwrap()));
}

#[test]
fn the_schemas_refuse_a_wrong_report() {
    // A validator that accepts anything would make the test above worthless.
    let s = schema("rig-report");
    assert!(!s.is_valid(&serde_json::json!({"schema_version": 1})));
    let (_, out, _) = run_cli(&ANYMAL_JSON);
    let mut v: Value = serde_json::from_str(&out).unwrap();
    v["screw"]["kind"] = "helical".into();
    assert!(!s.is_valid(&v));
}
