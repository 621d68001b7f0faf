//! The CI integrations of `audit check` (issue 11): the pre-commit hook run by
//! the real `pre-commit` (from PyPI, in a venv in the test's temp dir) in a
//! throwaway ROS-package repository, and the GitHub Actions workflow example.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// docs/ci/extrinsics.yml as JSON.
fn workflow() -> Value {
    let text = std::fs::read_to_string(root().join("docs/ci/extrinsics.yml")).unwrap();
    serde_saphyr::from_str(&text).expect("valid YAML")
}

#[test]
fn github_workflow_example_is_complete() {
    let w = workflow();
    assert!(w["on"]["pull_request"].is_null() || w["on"]["pull_request"].is_object());
    assert!(
        w["on"].get("pull_request").is_some(),
        "runs on pull requests"
    );
    assert_eq!(w["permissions"]["security-events"], "write", "SARIF upload");
    let jobs = w["jobs"].as_object().expect("jobs");
    assert_eq!(jobs.len(), 1);
    let job = jobs.values().next().unwrap();
    assert_eq!(job["runs-on"], "ubuntu-latest");
    let steps = job["steps"].as_array().expect("steps");
    let uses: Vec<&str> = steps.iter().filter_map(|s| s["uses"].as_str()).collect();
    let runs: Vec<&str> = steps.iter().filter_map(|s| s["run"].as_str()).collect();
    for action in [
        "actions/checkout@",
        "actions/cache@",
        "github/codeql-action/upload-sarif@",
    ] {
        assert!(
            uses.iter().any(|u| u.starts_with(action)),
            "{action}: {uses:?}"
        );
    }
    let all = runs.join("\n");
    for part in [
        "cargo install --locked",
        "--format github",
        "--confine \"$GITHUB_WORKSPACE\"",
        "--format sarif > audit-check.sarif",
        "--format markdown >> \"$GITHUB_STEP_SUMMARY\"",
    ] {
        assert!(all.contains(part), "{part}: {all}");
    }
    let upload = steps
        .iter()
        .find(|s| {
            s["uses"]
                .as_str()
                .is_some_and(|u| u.contains("upload-sarif"))
        })
        .unwrap();
    assert_eq!(upload["with"]["sarif_file"], "audit-check.sarif");
    assert_eq!(upload["if"], "always()", "uploaded when the gate fails too");
    // Every step is a `uses` or a `run`.
    assert!(steps
        .iter()
        .all(|s| s["uses"].is_string() != s["run"].is_string()));
}

fn sh(cmd: &mut Command) -> Output {
    cmd.output().expect("spawn")
}

fn ok(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// `pre-commit` (and `check-jsonschema`) in a venv under `dir`, or why not.
fn venv_tools(dir: &Path) -> Result<PathBuf, String> {
    let venv = dir.join("venv");
    let o = sh(Command::new("python3").args(["-m", "venv"]).arg(&venv));
    if !o.status.success() {
        return Err(format!("python3 -m venv failed: {}", ok(&o)));
    }
    let o = sh(Command::new(venv.join("bin/pip")).args([
        "install",
        "-q",
        "pre-commit",
        "check-jsonschema",
    ]));
    if !o.status.success() {
        return Err(format!("pip install pre-commit failed: {}", ok(&o)));
    }
    Ok(venv.join("bin"))
}

fn git(dir: &Path, args: &[&str]) -> Output {
    sh(Command::new("git")
        .current_dir(dir)
        .args(args)
        .env("GIT_AUTHOR_NAME", "t")
        .env("GIT_AUTHOR_EMAIL", "t@example.invalid")
        .env("GIT_COMMITTER_NAME", "t")
        .env("GIT_COMMITTER_EMAIL", "t@example.invalid"))
}

fn write(dir: &Path, rel: &str, text: &str) {
    let p = dir.join(rel);
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(p, text).unwrap();
}

fn fast_lio(x: f64) -> String {
    format!("mapping:\n  extrinsic_T: [ {x}, 0.02326, -0.0284 ]\n  extrinsic_R: [ 1, 0, 0,\n                 0, 1, 0,\n                 0, 0, 1 ]\n")
}

fn static_tf_launch(r: [&str; 3]) -> String {
    format!(
        "from launch import LaunchDescription\nfrom launch_ros.actions import Node\n\n\ndef generate_launch_description():\n    return LaunchDescription([\n        Node(\n            package='tf2_ros',\n            executable='static_transform_publisher',\n            arguments=['0.1', '0', '0.2', '{}', '{}', '{}', 'base_link', 'lidar'],\n        ),\n    ])\n",
        r[0], r[1], r[2]
    )
}

/// A ROS 2 package with its calibration and unrelated files.
fn ros_package(repo: &Path) {
    write(repo, "package.xml", "<?xml version=\"1.0\"?>\n<package format=\"3\">\n  <name>my_robot</name>\n  <version>0.1.0</version>\n  <description>x</description>\n  <maintainer email=\"a@b.c\">a</maintainer>\n  <license>BSD</license>\n</package>\n");
    write(
        repo,
        "CMakeLists.txt",
        "cmake_minimum_required(VERSION 3.8)\nproject(my_robot)\n",
    );
    write(
        repo,
        "config/nav2_params.yaml",
        "controller_server:\n  ros__parameters:\n    controller_frequency: 20.0\n",
    );
    write(repo, "launch/bringup.launch.py", "from launch import LaunchDescription\n\n\ndef generate_launch_description():\n    return LaunchDescription([])\n");
    write(
        repo,
        "launch/static_tf.launch.py",
        &static_tf_launch(["0", "0", "0"]),
    );
    write(repo, "calibration/fast_lio.yaml", &fast_lio(0.04165));
}

/// Commit what is staged; the hook's verdict is the commit's.
fn commit(repo: &Path, env: &[(&str, &Path)], msg: &str) -> (bool, String) {
    let mut c = Command::new("git");
    c.current_dir(repo)
        .args(["commit", "-q", "-m", msg])
        .env("GIT_AUTHOR_NAME", "t")
        .env("GIT_AUTHOR_EMAIL", "t@example.invalid")
        .env("GIT_COMMITTER_NAME", "t")
        .env("GIT_COMMITTER_EMAIL", "t@example.invalid");
    for (k, v) in env {
        c.env(k, v);
    }
    let o = sh(&mut c);
    (o.status.success(), ok(&o))
}

#[test]
fn pre_commit_hook_in_a_ros_repository() {
    let tmp = tempfile::tempdir().unwrap();
    let bin = match venv_tools(tmp.path()) {
        Ok(b) => b,
        Err(why) => {
            eprintln!("SKIPPED pre_commit_hook_in_a_ros_repository: {why}");
            return;
        }
    };
    // The hook repository: this repository's hook definition and entry script.
    let hooks = tmp.path().join("hooks");
    std::fs::create_dir_all(hooks.join("tools")).unwrap();
    std::fs::copy(
        root().join(".pre-commit-hooks.yaml"),
        hooks.join(".pre-commit-hooks.yaml"),
    )
    .unwrap();
    std::fs::copy(
        root().join("tools/pre-commit-audit-check"),
        hooks.join("tools/pre-commit-audit-check"),
    )
    .unwrap();
    assert!(git(&hooks, &["init", "-q"]).status.success());
    git(&hooks, &["add", "-A"]);
    assert!(git(&hooks, &["commit", "-q", "-m", "hooks"])
        .status
        .success());
    let rev = String::from_utf8(git(&hooks, &["rev-parse", "HEAD"]).stdout).unwrap();

    let repo = tmp.path().join("ros");
    std::fs::create_dir_all(&repo).unwrap();
    assert!(git(&repo, &["init", "-q"]).status.success());
    ros_package(&repo);
    write(
        &repo,
        ".pre-commit-config.yaml",
        &format!(
            "repos:\n  - repo: {}\n    rev: {}\n    hooks:\n      - id: audit-check\n        args: [--baseline, calibration/baseline.json]\n",
            hooks.display(),
            rev.trim()
        ),
    );
    let audit = assert_cmd::cargo::cargo_bin("audit");
    let o = sh(Command::new(&audit).current_dir(&repo).args([
        "check",
        "calibration",
        "launch/static_tf.launch.py",
        "--write-baseline",
        "calibration/baseline.json",
    ]));
    assert!(o.status.success(), "{}", ok(&o));
    let home = tmp.path().join("pre-commit-home");
    let env: Vec<(&str, &Path)> = vec![("PRE_COMMIT_HOME", &home), ("AUDIT_BIN", &audit)];
    let mut install = Command::new(bin.join("pre-commit"));
    install.current_dir(&repo).arg("install");
    assert!(sh(&mut install).status.success());

    // 1. The whole package: package.xml, CMakeLists.txt, nav2 parameters and
    //    .pre-commit-config.yaml are not the hook's files; the launch file that
    //    starts no static transform passes as `ignored`.
    git(&repo, &["add", "-A"]);
    let (pass, out) = commit(&repo, &env, "package");
    assert!(pass, "{out}");
    assert!(
        out.contains("audit check (extrinsic calibrations)") && out.contains("Passed"),
        "{out}"
    );

    // 2. A recalibration: the baseline alone is committed first (accepted),
    //    then the file it describes.
    write(&repo, "calibration/fast_lio.yaml", &fast_lio(0.04665));
    let o = sh(Command::new(&audit).current_dir(&repo).args([
        "check",
        "calibration",
        "launch/static_tf.launch.py",
        "--write-baseline",
        "calibration/baseline.json",
    ]));
    assert!(o.status.success(), "{}", ok(&o));
    git(&repo, &["add", "calibration/baseline.json"]);
    let (pass, out) = commit(&repo, &env, "baseline only");
    assert!(pass, "a commit of only the baseline: {out}");
    git(&repo, &["add", "-A"]);
    let (pass, out) = commit(&repo, &env, "recalibration");
    assert!(pass, "{out}");

    // 3. Drift without a new baseline: refused, naming the file and line.
    write(&repo, "calibration/fast_lio.yaml", &fast_lio(0.05665));
    git(&repo, &["add", "-A"]);
    let (pass, out) = commit(&repo, &env, "drift");
    assert!(!pass, "{out}");
    assert!(
        out.contains("calibration/fast_lio.yaml:2") && out.contains("drift"),
        "{out}"
    );
    git(
        &repo,
        &["checkout", "-q", "HEAD", "--", "calibration/fast_lio.yaml"],
    );

    // 4. The LiDAR turned by a half-turn in a .launch.py: drift, refused (the
    //    pattern reads launch files).
    write(
        &repo,
        "launch/static_tf.launch.py",
        &static_tf_launch(["0", "0", "3.14159265358979"]),
    );
    git(&repo, &["add", "-A"]);
    let (pass, out) = commit(&repo, &env, "launch");
    assert!(!pass, "a changed .launch.py is checked: {out}");
    assert!(
        out.contains("static_tf.launch.py") && out.contains("drift"),
        "{out}"
    );
    git(&repo, &["reset", "-q", "--hard", "HEAD"]);

    // 5. Only package files and parameters change: the hook has nothing to do.
    write(
        &repo,
        "package.xml",
        "<?xml version=\"1.0\"?>\n<package format=\"3\"><name>my_robot</name></package>\n",
    );
    write(
        &repo,
        "CMakeLists.txt",
        "cmake_minimum_required(VERSION 3.10)\n",
    );
    write(
        &repo,
        "config/nav2_params.yaml",
        "controller_server:\n  ros__parameters:\n    controller_frequency: 10.0\n",
    );
    git(&repo, &["add", "-A"]);
    let (pass, out) = commit(&repo, &env, "package files");
    assert!(pass, "{out}");
    assert!(out.contains("(no files to check)Skipped"), "{out}");

    // The workflow example against GitHub's workflow schema (vendored by
    // check-jsonschema).
    let o = sh(Command::new(bin.join("check-jsonschema"))
        .args(["--builtin-schema", "vendor.github-workflows"])
        .arg(root().join("docs/ci/extrinsics.yml")));
    assert!(o.status.success(), "{}", ok(&o));
}
