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

/// The hook's `files` and `exclude` patterns, as pre-commit reads them (Python
/// `re.search` on the path relative to the repository), applied to `paths`:
/// for each, whether the hook gets the file. `None` without python3.
fn hook_matches(paths: &[&str]) -> Option<Vec<bool>> {
    let hooks: Value = serde_saphyr::from_str(
        &std::fs::read_to_string(root().join(".pre-commit-hooks.yaml")).unwrap(),
    )
    .expect("valid YAML");
    let hook = &hooks[0];
    let script = "import json, re, sys\nf, x, paths = json.load(sys.stdin)\nprint(json.dumps([bool(re.search(f, p)) and not re.search(x, p) for p in paths]))";
    let mut child = Command::new("python3")
        .args(["-c", script])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .ok()?;
    let input = serde_json::json!([hook["files"], hook["exclude"], paths]).to_string();
    use std::io::Write as _;
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", ok(&o));
    Some(serde_json::from_slice(&o.stdout).unwrap())
}

/// Every extension `audit check` walks (the format registry's) reaches the
/// hook under a calibration folder, xacro files anywhere (issue 33: `.xacro`
/// was skipped), and the ROS package's own files never.
#[test]
fn pre_commit_pattern_covers_every_walk_extension() {
    let mut exts: Vec<&str> = extrinsic_audit::internals::formats::FORMATS
        .iter()
        .flat_map(|f| f.walk.iter().copied())
        .collect();
    exts.sort();
    exts.dedup();
    let walked: Vec<String> = exts
        .iter()
        .map(|e| format!("calibration/robot{e}"))
        .collect();
    let mut paths: Vec<&str> = walked.iter().map(String::as_str).collect();
    let anywhere = [
        "urdf/robot.urdf.xacro",
        "description/urdf/sensors.xacro",
        "robot.urdf",
        "launch/static_tf.launch.py",
    ];
    let never = [
        "package.xml",
        "calibration/package.xml",
        "CMakeLists.txt",
        "config/nav2_params.yaml",
        ".pre-commit-config.yaml",
        "audit.toml",
    ];
    paths.extend(anywhere);
    paths.extend(never);
    let Some(got) = hook_matches(&paths) else {
        eprintln!("SKIPPED pre_commit_pattern_covers_every_walk_extension: no python3");
        return;
    };
    let expected: Vec<bool> = (0..walked.len() + anywhere.len())
        .map(|_| true)
        .chain(never.iter().map(|_| false))
        .collect();
    let wrong: Vec<_> = paths
        .iter()
        .zip(got.iter().zip(&expected))
        .filter(|(_, (g, e))| g != e)
        .collect();
    assert!(
        wrong.is_empty(),
        "path, (hook gets it, expected): {wrong:?}"
    );
}

/// action.yml: a composite action whose inputs are the ones its script reads,
/// each step running tools/action-check through bash.
#[test]
fn github_action_is_a_composite_of_its_script() {
    let text = std::fs::read_to_string(root().join("action.yml")).unwrap();
    let a: Value = serde_saphyr::from_str(&text).expect("valid YAML");
    for key in ["name", "description"] {
        assert!(a[key].as_str().is_some_and(|s| !s.is_empty()), "{key}");
    }
    assert_eq!(a["runs"]["using"], "composite");
    let inputs = a["inputs"].as_object().expect("inputs");
    let names: Vec<&str> = inputs.keys().map(String::as_str).collect();
    assert_eq!(
        names,
        ["args", "baseline", "format", "paths", "sarif-file"],
        "inputs (sorted)"
    );
    for (name, i) in inputs {
        assert!(i["description"].is_string(), "{name}: description");
        assert!(i["default"].is_string(), "{name}: default");
    }
    let steps = a["runs"]["steps"].as_array().expect("steps");
    assert_eq!(steps.len(), 2);
    for s in steps {
        // A composite step's `run` needs its `shell` (GitHub's schema).
        assert_eq!(s["shell"], "bash", "{s}");
        let run = s["run"].as_str().unwrap();
        assert!(
            run.contains("$GITHUB_ACTION_PATH/tools/action-check"),
            "{run}"
        );
    }
    let env = &steps[1]["env"];
    for name in &names {
        let var = format!("INPUT_{}", name.to_uppercase().replace('-', "_"));
        assert_eq!(
            env[var.as_str()],
            format!("${{{{ inputs.{name} }}}}"),
            "{var}"
        );
    }
    assert_eq!(
        a["outputs"]["sarif-file"]["value"],
        "${{ steps.check.outputs.sarif-file }}"
    );
    assert_eq!(steps[1]["id"], "check");
}

/// The action's script: a dry run prints the commands it would run (the
/// install from the action's checkout, the check with every input), and a real
/// run with AUDIT_BIN gates a drift (exit 1) and writes the SARIF file.
#[test]
fn github_action_script_dry_run_and_real_run() {
    let tmp = tempfile::tempdir().unwrap();
    let script = root().join("tools/action-check");
    let audit = assert_cmd::cargo::cargo_bin("audit");
    let run = |args: &[&str], env: &[(&str, &str)]| {
        let mut c = Command::new("bash");
        c.arg(&script).args(args).current_dir(tmp.path());
        for k in ["AUDIT_BIN", "GITHUB_WORKSPACE", "GITHUB_OUTPUT"] {
            c.env_remove(k);
        }
        c.env("AUDIT_ACTION_ROOT", tmp.path().join("root"));
        for (k, v) in env {
            c.env(k, v);
        }
        sh(&mut c)
    };
    let o = run(&["install"], &[("AUDIT_ACTION_DRY_RUN", "1")]);
    assert!(o.status.success(), "{}", ok(&o));
    let printed = String::from_utf8_lossy(&o.stdout).to_string();
    let root_dir = tmp.path().join("root");
    let expected = format!(
        "cargo\ninstall\n--locked\n--quiet\n--path\n{}\n--root\n{}\n--bin\naudit\n---\n",
        root().display(),
        root_dir.display()
    );
    assert_eq!(printed, expected);
    let o = run(
        &["check"],
        &[
            ("AUDIT_ACTION_DRY_RUN", "1"),
            ("INPUT_PATHS", "calibration\nlaunch/tf.launch.py"),
            ("INPUT_BASELINE", "calibration/baseline.json"),
            ("INPUT_FORMAT", "sarif"),
            ("INPUT_SARIF_FILE", "out.sarif"),
            ("INPUT_ARGS", "--deny-warnings --max-lever-arm 0.5"),
            ("GITHUB_WORKSPACE", "/ws"),
        ],
    );
    assert!(o.status.success(), "{}", ok(&o));
    let lines: Vec<String> = String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(String::from)
        .collect();
    let bin = root_dir.join("bin/audit").display().to_string();
    assert_eq!(
        lines,
        [
            bin.as_str(),
            "check",
            "calibration",
            "launch/tf.launch.py",
            "--baseline",
            "calibration/baseline.json",
            "--confine",
            "/ws",
            "--deny-warnings",
            "--max-lever-arm",
            "0.5",
            "--format",
            "sarif",
            "--output",
            "out.sarif",
            "---"
        ]
    );
    let o = run(&["check"], &[("INPUT_FORMAT", "json")]);
    assert_eq!(o.status.code(), Some(2), "{}", ok(&o));
    assert!(ok(&o).contains("expected github or sarif, found 'json'"));

    // The real run: a baseline, then a drift of 5 mm.
    write(tmp.path(), "calibration/fast_lio.yaml", &fast_lio(0.04165));
    let o = sh(Command::new(&audit).current_dir(tmp.path()).args([
        "check",
        "calibration",
        "--write-baseline",
        "calibration/baseline.json",
    ]));
    assert!(o.status.success(), "{}", ok(&o));
    let audit_s = audit.display().to_string();
    let real = |format: &str| {
        run(
            &["check"],
            &[
                ("AUDIT_BIN", audit_s.as_str()),
                ("INPUT_PATHS", "calibration"),
                ("INPUT_BASELINE", "calibration/baseline.json"),
                ("INPUT_FORMAT", format),
            ],
        )
    };
    assert!(real("github").status.success());
    assert!(run(&["install"], &[("AUDIT_BIN", audit_s.as_str())])
        .status
        .success());
    write(tmp.path(), "calibration/fast_lio.yaml", &fast_lio(0.04665));
    let o = real("github");
    assert_eq!(o.status.code(), Some(1), "{}", ok(&o));
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("::error file=calibration/fast_lio.yaml"),
        "{}",
        ok(&o)
    );
    let o = real("sarif");
    assert_eq!(o.status.code(), Some(1), "{}", ok(&o));
    let sarif: Value = serde_json::from_str(
        &std::fs::read_to_string(tmp.path().join("audit-check.sarif")).unwrap(),
    )
    .unwrap();
    assert_eq!(sarif["version"], "2.1.0");
}
