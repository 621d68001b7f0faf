//! Gaps of issue 28 inside claimed formats: ROS 2 launch.py files whose
//! publisher arguments come from a helper function or a loop of the same file
//! (read statically; expected edges from running the file in Python with
//! stand-ins for the launch classes, `launch_py/make_expected.py`), what such
//! a reader must refuse (naming the line), and a `/tf` dump in which an edge
//! off the queried chain changes between messages.

use crate::common::run_cli;
use extrinsic_audit::internals::formats::load_file;
use extrinsic_audit::LoadOptions;
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/formats/launch_py")
}

#[test]
fn launch_py_helpers_and_loops_match_python() {
    let exp: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir().join("expected.json")).unwrap())
            .unwrap();
    for (file, want) in exp["fixtures"].as_object().unwrap() {
        let l = load_file(&dir().join(file), &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        let want = want["edges"].as_array().unwrap();
        assert_eq!(l.edges.len(), want.len(), "{file}");
        for (e, w) in l.edges.iter().zip(want) {
            assert_eq!(
                (e.parent.as_str(), e.child.as_str()),
                (w["parent"].as_str().unwrap(), w["child"].as_str().unwrap()),
                "{file}"
            );
            let m = e.transform.matrix4();
            for i in 0..4 {
                for j in 0..4 {
                    let x = w["matrix"][i][j].as_f64().unwrap();
                    assert!(
                        (m[(i, j)] - x).abs() <= 1e-15,
                        "{file}: {} [{i}][{j}] {} vs {x}",
                        e.child,
                        m[(i, j)]
                    );
                }
            }
        }
    }
}

#[test]
fn launch_py_launch_configuration_in_a_loop_follows_arg() {
    let f = dir().join("helpers_loops.launch.py");
    let mut o = LoadOptions::default();
    o.xacro_args = [("base_frame".to_string(), "chassis".to_string())].into();
    let l = load_file(&f, &o).unwrap();
    let parents: Vec<(&str, &str)> = l
        .edges
        .iter()
        .map(|e| (e.parent.as_str(), e.child.as_str()))
        .collect();
    assert!(
        parents.contains(&("chassis", "camera1_link"))
            && parents.contains(&("chassis", "imu_link")),
        "{parents:?}"
    );
    assert!(
        parents.contains(&("base_link", "front_lidar")),
        "the helper's parent is a literal: {parents:?}"
    );
}

/// What a static reader cannot know is refused at its line, saying why.
#[test]
fn launch_py_what_cannot_be_known_is_refused_naming_the_line() {
    let d = tempfile::tempdir().unwrap();
    let stp = |args: &str| {
        format!(
            "Node(package='tf2_ros', executable='static_transform_publisher', arguments={args})"
        )
    };
    let cases = [
        // A helper of another package (tiago_description's launch_pal).
        (
            format!("from launch_pal.arm_utils import get_arm\n\ndef generate_launch_description():\n    return LaunchDescription([{}])\n", stp("['0', '0', '1', '0', '0', '0', 'base', get_arm('tiago')]")),
            "get_arm(...) (line 4) is a function or action of another module",
        ),
        // A loop over what another module returns.
        (
            format!("from frames import all_frames\n\nfor f in all_frames():\n    {}\n", stp("['0', '0', '1', '0', '0', '0', 'base', f]")),
            "inside the `for` at line 3",
        ),
        // A branch the file cannot decide.
        (
            format!("import os\n\nif os.environ.get('ROBOT'):\n    {}\n", stp("['0', '0', '1', '0', '0', '0', 'base', 'lidar']")),
            "under the `if` at line 3",
        ),
        // A name bound twice.
        (
            format!("z = '1'\nz = '2'\n{}\n", stp("['0', '0', z, '0', '0', '0', 'base', 'lidar']")),
            "`z` is bound more than once (lines 1 and 2)",
        ),
        // A construct outside the subset, where an argument needs it.
        (
            format!("h = lambda: '1'\n{}\n", stp("['0', '0', h(), '0', '0', '0', 'base', 'lidar']")),
            "a lambda is not evaluated",
        ),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let p = d.path().join(format!("case{i}.launch.py"));
        std::fs::write(&p, text).unwrap();
        let (code, _, err) = run_cli(&[p.to_str().unwrap(), "--frames"]);
        assert_eq!(code, 2, "case {i}: {err}");
        assert!(err.contains(want), "case {i}: expected {want:?} in {err}");
    }
    // The same constructs away from any publisher do not matter.
    let p = d.path().join("fine.launch.py");
    std::fs::write(
        &p,
        format!(
            "import os\nh = lambda: 1\nif os.environ.get('X'):\n    pass\n{}\n",
            stp("['0', '0', '1', '0', '0', '0', 'base', 'lidar']")
        ),
    )
    .unwrap();
    let (code, out, err) = run_cli(&[p.to_str().unwrap(), "--frames"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("lidar"), "{out}");
}

/// `ros2 topic echo /tf`: base_link -> lidar is the same in every message,
/// odom -> base_link moves. The mount is read; only a query through the
/// moving edge is refused, naming the messages.
#[test]
fn tf_echo_conflict_is_scoped_to_the_changed_edge() {
    let f = "tests/fixtures/formats/ros2_tf_echo_moving.yaml";
    let (code, out, err) = run_cli(&[
        f,
        "--from",
        "base_link",
        "--to",
        "lidar",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        v["transform"]["translation_m"],
        serde_json::json!([-0.011, -0.02329, 0.04412])
    );
    assert!(
        !err.contains("warning"),
        "an edge off the chain raises nothing: {err}"
    );
    let (code, _, err) = run_cli(&[f, "--from", "odom", "--to", "lidar"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("odom -> base_link")
            && err.contains("changes between the messages of the dump (lines 7 and 15)"),
        "{err}"
    );
}
