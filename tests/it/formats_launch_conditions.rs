//! Issue 12: launch XML `if` / `unless` on nodes and groups, and `$(arg x)`
//! with a default declared in the same file (or `--arg x=VALUE`), decided as
//! roslaunch decides them; refused only when the file cannot say.

use crate::common::run_cli;
use std::path::PathBuf;

fn launch(dir: &tempfile::TempDir, body: &str) -> PathBuf {
    let p = dir.path().join("tf.launch");
    std::fs::write(&p, format!("<launch>\n{body}</launch>\n")).unwrap();
    p
}

fn stp(name: &str, args: &str, attrs: &str) -> String {
    format!("  <node pkg=\"tf\" type=\"static_transform_publisher\" name=\"{name}\" args=\"{args}\"{attrs}/>\n")
}

/// `audit FILE --format json --from base --to lidar ARGS`: (code, z of the
/// translation, stderr).
fn z_of(p: &std::path::Path, extra: &[&str]) -> (i32, Option<f64>, String) {
    let mut a = vec![
        p.to_str().unwrap(),
        "--from",
        "base",
        "--to",
        "lidar",
        "--format",
        "json",
    ];
    a.extend_from_slice(extra);
    let (code, out, err) = run_cli(&a);
    let z = serde_json::from_str::<serde_json::Value>(&out)
        .ok()
        .and_then(|v| v["transform"]["translation_m"][2].as_f64());
    (code, z, err)
}

#[test]
fn nodes_switched_off_by_if_unless_or_their_group_are_not_read() {
    let d = tempfile::tempdir().unwrap();
    let body = [
        "  <group if=\"false\">\n".to_string(),
        stp("g", "0 0 9 0 0 0 base lidar 10", ""),
        "  </group>\n".to_string(),
        stp("a", "0 0 8 0 0 0 base lidar 10", " if=\"False\""),
        stp("b", "0 0 7 0 0 0 base lidar 10", " unless=\"1\""),
        "  <group unless=\"0\"><group if=\"TRUE\">\n".to_string(),
        stp("live", "0 0 0.25 0 0 0 base lidar 10", ""),
        "  </group></group>\n".to_string(),
    ]
    .concat();
    let p = launch(&d, &body);
    let (code, z, err) = z_of(&p, &[]);
    assert_eq!((code, z), (0, Some(0.25)), "{err}");
    assert!(
        err.contains("tf.launch:3:3") && err.contains("if=\"false\" on its enclosing <group>"),
        "{err}"
    );
    assert!(
        err.contains("tf.launch:5:3") && err.contains("not started (if=\"False\")"),
        "{err}"
    );
    assert!(
        err.contains("tf.launch:6:3") && err.contains("not started (unless=\"1\")"),
        "{err}"
    );
}

#[test]
fn an_arg_with_a_default_in_the_file_is_resolved_and_arg_overrides_it() {
    let d = tempfile::tempdir().unwrap();
    let body = [
        "  <arg name=\"z\" default=\"0.5\"/>\n  <arg name=\"height\" default=\"$(arg z)\"/>\n",
        "  <arg name=\"publish\" default=\"true\"/>\n",
        "  <group if=\"$(arg publish)\">\n",
        &stp("lidar_tf", "0 0 $(arg height) 0 0 0 base lidar 10", ""),
        "  </group>\n",
    ]
    .concat();
    let p = launch(&d, &body);
    let (code, z, err) = z_of(&p, &[]);
    assert_eq!((code, z), (0, Some(0.5)), "{err}");
    let (code, z, err) = z_of(&p, &["--arg", "z=0.75"]);
    assert_eq!((code, z), (0, Some(0.75)), "{err}");
    let (code, _, err) = z_of(&p, &["--arg", "publish=false"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("tf.launch:6:"), "{err}");
    assert!(err.contains("every static_transform_publisher <node> is switched off (the first by if=\"$(arg publish)\" on its enclosing <group>)"), "{err}");
}

#[test]
fn a_value_the_file_cannot_give_is_refused_naming_the_arg_to_pass() {
    let d = tempfile::tempdir().unwrap();
    let p = launch(
        &d,
        &(String::from("  <arg name=\"z\"/>\n")
            + &stp("t", "0 0 $(arg z) 0 0 0 base lidar 10", "")),
    );
    let (code, _, err) = z_of(&p, &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("tf.launch:3:3"), "{err}");
    assert!(err.contains("pass --arg z=VALUE"), "{err}");
    let (code, z, err) = z_of(&p, &["--arg", "z=1.5"]);
    assert_eq!((code, z), (0, Some(1.5)), "{err}");

    let p = launch(
        &d,
        &stp(
            "t",
            "0 0 1 0 0 0 base lidar 10",
            " if=\"$(arg from_parent)\"",
        ),
    );
    let (code, _, err) = z_of(&p, &[]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("not declared in this file") && err.contains("pass --arg from_parent=VALUE"),
        "{err}"
    );

    // $(eval) is evaluated since issue 28 (formats_calib has its fixtures);
    // what depends on the machine that launches is refused.
    let p = launch(
        &d,
        &stp("t", "0 0 1 0 0 0 base lidar 10", " if=\"$(eval 1 == 1)\""),
    );
    assert_eq!(z_of(&p, &[]).0, 0);
    let p = launch(
        &d,
        &stp(
            "t",
            "0 0 1 0 0 0 base lidar 10",
            " if=\"$(eval env('ROBOT') == 'a')\"",
        ),
    );
    let (code, _, err) = z_of(&p, &[]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("depends on the machine that launches") && err.contains("--arg"),
        "{err}"
    );

    let p = launch(&d, &stp("t", "0 0 1 0 0 0 base lidar 10", " if=\"yes\""));
    let (code, _, err) = z_of(&p, &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("expected true, false, 1 or 0"), "{err}");
}

#[test]
fn a_default_that_names_itself_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = launch(
        &d,
        &(String::from("  <arg name=\"z\" default=\"$(arg z)\"/>\n")
            + &stp("t", "0 0 $(arg z) 0 0 0 base lidar 10", "")),
    );
    let (code, _, err) = z_of(&p, &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("nest more than"), "{err}");
}

#[test]
fn launch_yaml_conditions_and_args_are_decided_the_same_way() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("tf.launch.yaml");
    let text = r#"launch:
- arg: {name: z, default: "0.5"}
- arg: {name: on, default: "true"}
- group:
    if: "$(var on)"
    children:
    - node: {pkg: tf2_ros, exec: static_transform_publisher, args: "0 0 $(var z) 0 0 0 base lidar"}
- group:
    unless: "true"
    children:
    - node: {pkg: tf2_ros, exec: static_transform_publisher, args: "0 0 9 0 0 0 base lidar"}
- node: {pkg: tf2_ros, exec: static_transform_publisher, if: "false", args: "0 0 8 0 0 0 base lidar"}
"#;
    std::fs::write(&p, text).unwrap();
    let (code, z, err) = z_of(&p, &[]);
    assert_eq!((code, z), (0, Some(0.5)), "{err}");
    assert!(
        err.contains("not started (unless=\"true\" on its enclosing group)"),
        "{err}"
    );
    assert!(err.contains("not started (if=\"false\")"), "{err}");
    let (code, z, err) = z_of(&p, &["--arg", "z=0.25"]);
    assert_eq!((code, z), (0, Some(0.25)), "{err}");
    let (code, _, err) = z_of(&p, &["--arg", "on=0"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("switched off (the first by if=\"$(var on)\" on its enclosing group)"),
        "{err}"
    );
}

/// ROS 2 Python launch: `condition=IfCondition(...)` / `UnlessCondition(...)`
/// on a Node or its enclosing GroupAction, and `LaunchConfiguration('x')` in
/// the arguments, decided from `DeclareLaunchArgument` defaults and `--arg`.
#[test]
fn python_launch_conditions_and_launch_configurations() {
    let f = "tests/fixtures/formats/ros2_conditions.launch.py";
    let pose = |extra: &[&str], to: &str| {
        let mut a = vec![f, "--from", "base_link", "--to", to, "--format", "json"];
        a.extend_from_slice(extra);
        let (code, out, err) = run_cli(&a);
        let t = serde_json::from_str::<serde_json::Value>(&out)
            .ok()
            .map(|v| v["transform"]["translation_m"].clone());
        (code, t, err)
    };
    // Defaults: the new mount (0.3, 0, 0.4) to `lidar`, the camera group on.
    let (code, t, err) = pose(&[], "lidar");
    assert_eq!(code, 0, "{err}");
    assert_eq!(t, Some(serde_json::json!([0.3, 0.0, 0.4])));
    assert!(
        err.contains(":17:9: static_transform_publisher Node not started (if="),
        "{err}"
    );
    assert!(
        err.contains(":40:9:") && err.contains("(if=\"false\")"),
        "{err}"
    );
    assert_eq!(pose(&[], "camera").0, 0);
    // --arg flips the mount, renames the lidar frame, switches the group off.
    let args = [
        "--arg",
        "use_old_mount=true",
        "--arg",
        "lidar_frame=os",
        "--arg",
        "with_camera=0",
    ];
    let (code, t, err) = pose(&args, "os");
    assert_eq!(code, 0, "{err}");
    assert_eq!(t, Some(serde_json::json!([0.5, 0.0, 0.2])));
    assert!(err.contains("on its enclosing GroupAction"), "{err}");
    let (code, _, err) = pose(&args, "camera");
    assert_eq!(code, 2, "{err}");
}

/// A condition the file cannot decide is refused at its line, naming what is
/// expected; every Node off is an error naming the argument to pass.
#[test]
fn python_launch_conditions_that_cannot_be_decided() {
    let d = tempfile::tempdir().unwrap();
    let node = |cond: &str| {
        format!(
            "from launch_ros.actions import Node\nNode(\n    executable='static_transform_publisher',\n    condition={cond},\n    arguments=['0', '0', '1', '0', '0', '0', 'base', 'lidar'],\n)\n"
        )
    };
    let p = d.path().join("a.launch.py");
    // PythonExpression is evaluated as ROS 2's $(eval) since issue 28.
    std::fs::write(&p, node("IfCondition(PythonExpression(['1 == 1']))")).unwrap();
    assert_eq!(run_cli(&[p.to_str().unwrap(), "--frames"]).0, 0);
    std::fs::write(&p, node("IfCondition(EnvironmentVariable('LIDAR_ON'))")).unwrap();
    let (code, _, err) = run_cli(&[p.to_str().unwrap(), "--frames"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("a.launch.py:4:5") && err.contains("cannot be decided"),
        "{err}"
    );
    std::fs::write(&p, node("IfCondition(LaunchConfiguration('lidar_on'))")).unwrap();
    let (code, _, err) = run_cli(&[p.to_str().unwrap(), "--frames"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--arg lidar_on=VALUE") || err.contains("--arg 'lidar_on'=VALUE"),
        "{err}"
    );
    let (code, out, err) = run_cli(&[p.to_str().unwrap(), "--frames", "--arg", "lidar_on=true"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("lidar"), "{out}");
    std::fs::write(&p, node("UnlessCondition('true')")).unwrap();
    let (code, _, err) = run_cli(&[p.to_str().unwrap(), "--frames"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("every static_transform_publisher Node is switched off"),
        "{err}"
    );
}
