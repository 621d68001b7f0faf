//! URDF as ROS computes it: the conformance cases authored in
//! tests/fixtures/urdf_conformance (author.py; each tagged with the behaviour
//! it tests and citing the upstream test of that behaviour, SOURCES.md) run
//! through the binary and compared with what urdfdom 6.0.0 makes of them
//! (measured by generate.py) and with the pose the case's numbers give in
//! closed form where author.py writes one. Every case that differs must be
//! listed in docs/urdf-differences.md, and every listed case must still
//! differ.
//!
//! Also here: the behaviour the suite led to (version handling, unattached
//! links in `--frames`, `--joint` on a fixed joint, positions outside
//! `<limit>`).

use crate::common::audit;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const DIR: &str = "tests/fixtures/urdf_conformance";
const DIFFERENCES: &str = "docs/urdf-differences.md";
/// Poses agree when every entry of the 4x4 matrices agrees to this: urdfdom
/// prints 17 digits and both sides compose a few f64 products.
const POSE_TOL: f64 = 1e-9;
/// Marks a pose that differs from the one the case's numbers give by hand: no
/// row of the table can excuse it.
const OFF_CLOSED_FORM: &str = "pose differs from the closed form";
/// Marks a case audit accepts although urdfdom refuses it, without saying so.
const NO_WARNING: &str = "WITHOUT a refused-by-ros warning";

/// The file of `case` (`None`: a whole upstream file that the test-data
/// folder, docs/test-data.md, does not have here); the authored cases are in
/// DIR/cases.
fn case_file(case: &Value) -> Option<PathBuf> {
    match case.get("test_data").and_then(Value::as_str) {
        Some(real) => crate::common::testdata::file(real),
        None => Some(PathBuf::from(DIR).join(case["file"].as_str().expect("file"))),
    }
}

fn manifest() -> Vec<Value> {
    let text = std::fs::read_to_string(Path::new(DIR).join("manifest.json")).expect("manifest");
    let v: Value = serde_json::from_str(&text).expect("manifest json");
    v["cases"].as_array().expect("cases").clone()
}

fn matrix(v: &Value) -> [[f64; 4]; 4] {
    let mut m = [[0.0; 4]; 4];
    for (i, row) in v.as_array().expect("rows").iter().enumerate() {
        for (j, x) in row.as_array().expect("row").iter().enumerate() {
            m[i][j] = x.as_f64().expect("number");
        }
    }
    m
}

fn max_diff(a: &[[f64; 4]; 4], b: &[[f64; 4]; 4]) -> f64 {
    let mut d: f64 = 0.0;
    for i in 0..4 {
        for j in 0..4 {
            d = d.max((a[i][j] - b[i][j]).abs());
        }
    }
    d
}

/// The command that runs one case: its query as `--from/--to/--joint` with a
/// JSON report, or `--frames` without a query.
fn case_command(case: &Value) -> assert_cmd::Command {
    let mut cmd = audit();
    cmd.arg(case_file(case).expect("a case that is there"));
    match case.get("query") {
        Some(q) => {
            cmd.args(["--from", q["from"].as_str().expect("from")]);
            cmd.args(["--to", q["to"].as_str().expect("to")]);
            cmd.args(["--format", "json"]);
            if let Some(j) = q.get("joints").and_then(Value::as_object) {
                for (name, v) in j {
                    cmd.args(["--joint", &format!("{name}={}", v.as_f64().expect("value"))]);
                }
            }
        }
        None => {
            cmd.arg("--frames");
        }
    }
    cmd
}

type Pose = [[f64; 4]; 4];

/// The 4x4 pose of a JSON report's `transform`.
fn report_pose(stdout: &[u8]) -> Pose {
    let rep: Value = serde_json::from_slice(stdout).expect("json report");
    let r = &rep["transform"]["rotation_matrix"];
    let d = &rep["transform"]["translation_m"];
    let mut m = [[0.0; 4]; 4];
    m[3][3] = 1.0;
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = r[i][j].as_f64().expect("r");
        }
        m[i][3] = d[i].as_f64().expect("d");
    }
    m
}

/// What the tool makes of one case: `Ok((pose, stderr))` (`pose` is `None`
/// without a query) or `Err(stderr)` when it refuses (exit 2; any other exit
/// fails the test).
fn run_case(case: &Value) -> Result<(Option<Pose>, String), String> {
    let out = case_command(case).output().expect("run");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    match out.status.code() {
        Some(0) => {}
        Some(2) => return Err(stderr),
        other => panic!(
            "{}: exit {other:?} (a crash, not a refusal): {stderr}",
            case["id"]
        ),
    }
    let pose = case.get("query").map(|_| report_pose(&out.stdout));
    Ok((pose, stderr))
}

/// How the tool differs from urdfdom or from the closed form, if it does.
fn difference(case: &Value) -> Option<String> {
    let ros = &case["urdfdom"];
    let ros_accepts = ros["outcome"] == "accepted";
    let tool = run_case(case);
    let mut why = Vec::new();
    match (&tool, ros_accepts) {
        (Ok((_, err)), false) => {
            why.push("urdfdom refuses, audit accepts".to_string());
            // Accepting what ROS refuses is only honest with a warning.
            if !err.contains("warning[refused-by-ros]") {
                why.push(NO_WARNING.to_string());
            }
        }
        (Err(e), true) => why.push(format!(
            "urdfdom accepts, audit refuses: {}",
            e.lines().last().unwrap_or("")
        )),
        _ => {}
    }
    if let Ok((Some(pose), _)) = &tool {
        if let Some(p) = ros.get("pose") {
            let d = max_diff(pose, &matrix(p));
            if d > POSE_TOL {
                why.push(format!("pose differs from urdfdom's by {d:e}"));
            }
        }
        if let Some(cf) = case.get("closed_form") {
            let d = max_diff(pose, &matrix(cf));
            if d > POSE_TOL {
                why.push(format!("{OFF_CLOSED_FORM} by {d:e}"));
            }
        }
    }
    (!why.is_empty()).then(|| why.join("; "))
}

/// Case ids listed in the table of docs/urdf-differences.md (first cell,
/// in backticks).
fn listed_differences() -> BTreeMap<String, String> {
    let text = std::fs::read_to_string(DIFFERENCES).expect("docs/urdf-differences.md");
    text.lines()
        .filter_map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            let id = cells.get(1)?.strip_prefix('`')?.strip_suffix('`')?;
            Some((
                id.to_string(),
                cells.get(4).copied().unwrap_or("").to_string(),
            ))
        })
        .collect()
}

#[test]
fn conformance_suite_matches_the_differences_table() {
    let all = manifest();
    assert!(all.len() >= 100, "{} cases", all.len());
    let id = |c: &Value| c["id"].as_str().expect("id").to_string();
    let (cases, absent): (Vec<&Value>, Vec<&Value>) =
        all.iter().partition(|c| case_file(c).is_some());
    let absent: Vec<String> = absent.into_iter().map(id).collect();
    let differing: BTreeMap<String, String> = cases
        .iter()
        .filter_map(|c| difference(c).map(|d| (id(c), d)))
        .collect();
    // For maintenance: every difference, one a line, to start the table from.
    if let Some(path) = std::env::var_os("URDF_CONFORMANCE_DUMP") {
        let text: String = differing
            .iter()
            .map(|(id, d)| format!("{id}: {d}\n"))
            .collect();
        std::fs::write(path, text).expect("dump");
    }
    let listed = listed_differences();
    let unlisted: Vec<String> = differing
        .iter()
        .filter(|(id, _)| !listed.contains_key(*id))
        .map(|(id, d)| format!("{id}: {d}"))
        .collect();
    let stale: Vec<&String> = listed
        .keys()
        .filter(|id| !differing.contains_key(*id) && !absent.contains(id))
        .collect();
    assert!(
        unlisted.is_empty() && stale.is_empty(),
        "cases that differ from urdfdom or their closed form but are not in {DIFFERENCES}:\n{}\nlisted cases that no longer differ (or do not exist):\n{stale:?}",
        unlisted.join("\n")
    );
    let silent: Vec<&String> = differing
        .iter()
        .filter(|(_, d)| d.contains(NO_WARNING))
        .map(|(id, _)| id)
        .collect();
    assert!(
        silent.is_empty(),
        "urdfdom refuses, audit accepts silently: {silent:?}"
    );
    let off: Vec<String> = differing
        .iter()
        .filter(|(_, d)| d.contains(OFF_CLOSED_FORM))
        .map(|(id, d)| format!("{id}: {d}"))
        .collect();
    assert!(
        off.is_empty(),
        "audit's pose is not the closed form: {off:?}"
    );
    for (id, reason) in &listed {
        assert!(!reason.is_empty(), "{id}: listed without a reason");
    }
}

/// urdfdom's own locale test (urdf_unit_test.cpp) runs its cases under
/// `LC_ALL=nl_NL.UTF-8` (a decimal comma): the decimal cases must give the
/// pose urdfdom measured under that locale too.
#[test]
fn number_parsing_ignores_the_locale() {
    let decimal: Vec<Value> = manifest()
        .into_iter()
        .filter(|c| c["id"].as_str().is_some_and(|id| id.ends_with("_doubles")))
        .collect();
    assert_eq!(decimal.len(), 3);
    for case in &decimal {
        let out = case_command(case)
            .env("LC_ALL", "nl_NL.UTF-8")
            .env("LANG", "nl_NL.UTF-8")
            .output()
            .expect("run");
        assert_eq!(out.status.code(), Some(0), "{}", case["id"]);
        let d = max_diff(&report_pose(&out.stdout), &matrix(&case["urdfdom"]["pose"]));
        assert!(d < POSE_TOL, "{}: {d:e} from urdfdom's pose", case["id"]);
    }
}

fn write(name: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join(name);
    std::fs::write(&p, text).expect("write");
    (dir, p)
}

const QUAT_1_0: &str = "<robot name=\"r\">\n  <link name=\"a\"/>\n  <link name=\"b\"/>\n  <joint name=\"j\" type=\"fixed\">\n    <parent link=\"a\"/>\n    <child link=\"b\"/>\n    <origin xyz=\"1 0 0\" quat_xyzw=\"0 0 0.7071067811865476 0.7071067811865476\"/>\n  </joint>\n</robot>\n";

fn rotation_10(stdout: &[u8]) -> f64 {
    let rep: Value = serde_json::from_slice(stdout).expect("json");
    rep["transform"]["rotation_matrix"][1][0]
        .as_f64()
        .expect("r10")
}

/// A 1.0 file's quat_xyzw: the identity ROS computes and a warning naming the
/// way out; `--urdf-version 1.1` reads the quaternion, with a warning that ROS
/// does not.
#[test]
fn quat_xyzw_in_a_1_0_file_gives_ros_pose_and_one_warning() {
    let (_d, p) = write("q.urdf", QUAT_1_0);
    let out = audit()
        .arg(&p)
        .args(["--from", "a", "--to", "b", "--format", "json"])
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(0));
    assert!(rotation_10(&out.stdout).abs() < 1e-15, "identity rotation");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.matches("warning[").count(), 1, "{err}");
    assert!(
        err.contains("warning[quat-xyzw-ignored]") && err.contains(":7:5:"),
        "{err}"
    );
    assert!(err.contains("--urdf-version 1.1"), "{err}");

    let out = audit()
        .arg(&p)
        .args(["--from", "a", "--to", "b", "--format", "json"])
        .args(["--urdf-version", "1.1"])
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(0));
    assert!((rotation_10(&out.stdout) - 1.0).abs() < 1e-12, "90 deg yaw");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("warning[assumed-convention]") && err.contains("ROS ignores it"),
        "{err}"
    );

    // A 1.1 file read as 1.0: ignored, and the warning says ROS applies it.
    let (_d2, p11) = write(
        "q11.urdf",
        &QUAT_1_0.replace("<robot name=\"r\">", "<robot name=\"r\" version=\"1.1\">"),
    );
    let out = audit()
        .arg(&p11)
        .args([
            "--from",
            "a",
            "--to",
            "b",
            "--format",
            "json",
            "--urdf-version",
            "1.0",
        ])
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(0));
    assert!(rotation_10(&out.stdout).abs() < 1e-15, "identity rotation");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("warning[quat-xyzw-ignored]") && err.contains("ROS applies it"),
        "{err}"
    );

    for bad in ["1", "1.3", "1.1.0"] {
        audit()
            .arg(&p)
            .args(["--frames", "--urdf-version", bad])
            .assert()
            .code(2);
    }
}

/// A malformed version is refused at the `<robot>` line with urdfdom's reason.
#[test]
fn malformed_version_is_refused_with_file_and_line() {
    for (v, why) in [
        ("1", "form x.y"),
        ("1.1.0", "form x.y"),
        ("a.b", "not an integer"),
        ("", "form x.y"),
        ("1.3", "expected 1.0, 1.1 or 1.2"),
    ] {
        let text = format!("<?xml version=\"1.0\"?>\n<robot name=\"r\" version=\"{v}\">\n  <link name=\"a\"/>\n  <link name=\"b\"/>\n  <joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>\n</robot>\n");
        let (_d, p) = write("v.urdf", &text);
        let out = audit().arg(&p).arg("--frames").output().expect("run");
        assert_eq!(out.status.code(), Some(2), "{v:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("v.urdf:2:1: <robot version>"), "{v:?}: {err}");
        assert!(
            err.contains(why) && err.contains("ROS (urdfdom) refuses"),
            "{v:?}: {err}"
        );
    }
}

/// A link no joint attaches is its own root in `--frames`, with a note, and a
/// warning that ROS refuses such a file.
#[test]
fn unattached_link_is_listed_as_its_own_root() {
    let text = "<robot name=\"r\">\n  <link name=\"base\"/>\n  <link name=\"lidar\"/>\n  <link name=\"spare\"/>\n  <joint name=\"j\" type=\"fixed\"><parent link=\"base\"/><child link=\"lidar\"/></joint>\n</robot>\n";
    let (_d, p) = write("u.urdf", text);
    let out = audit().arg(&p).arg("--frames").output().expect("run");
    assert_eq!(out.status.code(), Some(0));
    let tree = String::from_utf8_lossy(&out.stdout);
    let spare = tree
        .lines()
        .find(|l| l.starts_with("spare"))
        .unwrap_or_else(|| panic!("no root line for spare in:\n{tree}"));
    assert!(spare.contains("u.urdf:4:3, no edge attaches it"), "{spare}");
    assert!(tree.lines().any(|l| l == "base"), "{tree}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("warning[refused-by-ros]") && err.contains("'spare' (line 4)"),
        "{err}"
    );
    // --rename reaches a link no joint attaches.
    let out = audit()
        .arg(&p)
        .args(["--frames", "--rename", "spare=spare_link"])
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout)
        .lines()
        .any(|l| l.starts_with("spare_link  [")));
    // Not connected: a frame error naming both trees.
    let out = audit()
        .arg(&p)
        .args(["--from", "base", "--to", "spare"])
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("tree rooted at 'spare'"));
}

const ARM: &str = "<robot name=\"r\">\n  <link name=\"a\"/>\n  <link name=\"b\"/>\n  <link name=\"c\"/>\n  <joint name=\"shoulder\" type=\"revolute\">\n    <parent link=\"a\"/><child link=\"b\"/>\n    <axis xyz=\"0 0 1\"/>\n    <limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>\n  </joint>\n  <joint name=\"mount\" type=\"fixed\"><parent link=\"b\"/><child link=\"c\"/></joint>\n</robot>\n";

/// `--joint` on a fixed joint: one error (exit 2), naming the movable joints.
#[test]
fn joint_on_a_fixed_joint_is_one_message() {
    let (_d, p) = write("arm.urdf", ARM);
    let out = audit()
        .arg(&p)
        .args(["--from", "a", "--to", "c", "--joint", "mount=0.3"])
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("arm.urdf:10:3")
            && err.contains("joint 'mount' is fixed")
            && err.contains("this file has: shoulder"),
        "{err}"
    );
}

/// A position outside `<limit>` is used as given (robot_state_publisher does
/// not clamp; pytransform3d would), with a warning naming the limit.
#[test]
fn joint_outside_limit_is_used_with_a_warning() {
    let (_d, p) = write("arm.urdf", ARM);
    let out = audit()
        .arg(&p)
        .args([
            "--from",
            "a",
            "--to",
            "c",
            "--joint",
            "shoulder=2",
            "--format",
            "json",
        ])
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(0));
    assert!(
        (rotation_10(&out.stdout) - 2f64.sin()).abs() < 1e-15,
        "not clamped to 1"
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.matches("warning[").count(), 1, "{err}");
    assert!(
        err.contains("warning[joint-outside-limit]")
            && err.contains("lower=\"-1\" upper=\"1\"> (line 8)")
            && err.contains("robot_state_publisher"),
        "{err}"
    );
    // Inside the limit: nothing to say.
    let out = audit()
        .arg(&p)
        .args(["--from", "a", "--to", "c", "--joint", "shoulder=1"])
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(0));
    assert!(!String::from_utf8_lossy(&out.stderr).contains("warning["));
    // --strict: the same warning stops the command (exit 2, no report), and a
    // value within the limit still passes.
    let strict = |joint: &str| {
        audit()
            .arg(&p)
            .args(["--from", "a", "--to", "c", "--strict", "--joint", joint])
            .output()
            .expect("run")
    };
    let out = strict("shoulder=2");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(out.stdout.is_empty());
    assert!(
        err.contains("warning[joint-outside-limit]")
            && err.contains("--strict: expected no warnings, found 1 (joint-outside-limit)"),
        "{err}"
    );
    assert_eq!(strict("shoulder=1").status.code(), Some(0));
}
