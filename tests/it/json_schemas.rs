//! Every JSON output validates against its committed schema in docs/schemas
//! (JSON Schema 2020-12, checked with the `jsonschema` crate).

use crate::common::run_cli;
use serde_json::Value;

fn schema(name: &str) -> jsonschema::Validator {
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

#[test]
fn json_outputs_match_the_committed_schemas() {
    assert_valid("rig-report", &ANYMAL_JSON);
    let kappa = [&ANYMAL_JSON[..], &["--kappa", "0.01", "--lambda", "0.004"]].concat();
    assert_valid("rig-report", &kappa);
    assert_valid(
        "survey",
        &["survey", "calibrations/", "--all", "--format", "json"],
    );
    assert_valid("check", &["check", "calibrations/", "--format", "json"]);
    assert_valid(
        "degeneracy",
        &[
            "degeneracy",
            "tests/fixtures/detector/tunnel_small_le.ply",
            "--shift",
            "1,0,0",
            "--format",
            "json",
        ],
    );
    assert_valid(
        "degeneracy",
        &[
            "degeneracy",
            "tests/fixtures/detector/scans/ground_crop.pcd",
            "--estimate-normals",
            "--voxel",
            "0.1",
            "--normal-radius",
            "0.5",
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
            "tests/fixtures/detector/scans/ground_crop.pcd",
            "--estimate-normals",
            "--voxel",
            "0.1",
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
    assert_valid("tunnel", &["tunnel", "--format", "json"]);
    assert_valid(
        "tunnel",
        &["tunnel", "--shift", "0,2,0", "--format", "json"],
    );
    assert_valid(
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
    );
    assert_valid(
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
    );
}

/// Every command's JSON carries `schema_version` 1 and a `warnings` array
/// (a count in the check report, whose findings list every warning).
#[test]
fn every_json_output_has_a_version_and_warnings() {
    let runs: [&[&str]; 5] = [
        &ANYMAL_JSON,
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
    assert_eq!(ws.len(), err.lines().count(), "{err}");
}

/// A format a command cannot produce is an error, not other output.
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
        err.contains("--frames --format sarif: expected text, json, dot, mermaid, svg or markdown"),
        "{err}"
    );
    let (code, out, err) = run_cli(&["tunnel", "--format", "sarif"]);
    assert_eq!(code, 2, "{out}");
    assert!(
        err.contains("--format sarif lists the findings of `audit check`"),
        "{err}"
    );
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
