//! `audit check` as a CI gate (issue 11): the severity policy, the shipped data
//! and its baseline, baseline keys, refused writes, finding locations, the
//! per-robot manifest and the walk. Every test runs the real binary in a temp
//! directory.

use crate::common::run_cli;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// A FAST-LIO config (imu -> lidar) with rotation rows `r` and translation `t`.
pub fn fast_lio(t: [f64; 3], r: [[f64; 3]; 3]) -> String {
    let row = |k: usize| format!("{}, {}, {}", r[k][0], r[k][1], r[k][2]);
    format!(
        "mapping:\n  extrinsic_T: [ {}, {}, {} ]\n  extrinsic_R: [ {},\n                 {},\n                 {} ]\n",
        t[0],
        t[1],
        t[2],
        row(0),
        row(1),
        row(2)
    )
}

/// The identity scaled by `s`: `||R^T R - I||_F = sqrt(3) (s^2 - 1)`.
pub fn scaled(s: f64) -> [[f64; 3]; 3] {
    [[s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]]
}

pub const AVIA_T: [f64; 3] = [0.04165, 0.02326, -0.0284];

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `audit check ARGS --format json`: (exit code, report or Null, stderr).
pub fn check_json(args: &[&str]) -> (i32, Value, String) {
    let mut a = vec!["check"];
    a.extend_from_slice(args);
    a.extend_from_slice(&["--format", "json"]);
    let (code, out, err) = run_cli(&a);
    (code, serde_json::from_str(&out).unwrap_or(Value::Null), err)
}

/// (code, severity) of every finding.
pub fn findings(j: &Value) -> Vec<(String, String)> {
    j["findings"]
        .as_array()
        .map(|a| {
            a.iter()
                .map(|f| {
                    (
                        f["code"].as_str().unwrap().to_string(),
                        f["severity"].as_str().unwrap().to_string(),
                    )
                })
                .collect()
        })
        .unwrap_or_default()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn rounding_is_a_warning_beyond_it_an_error() {
    let dir = tempfile::tempdir().unwrap();
    // 1e-4 scaling: ||R^T R - I||_F = sqrt(3) (1.0001^2 - 1) = 3.464e-4 <= 5e-3.
    let small = write(dir.path(), "small.yaml", &fast_lio(AVIA_T, scaled(1.0001)));
    let (code, j, err) = check_json(&[s(&small)]);
    assert_eq!(code, 0, "{j}{err}");
    assert_eq!(
        findings(&j),
        [("non-orthonormal-rotation".into(), "warning".into())]
    );
    let msg = j["findings"][0]["message"].as_str().unwrap();
    assert!(msg.contains("3.464e-4"), "{msg}");
    // --deny CODE and --deny-warnings turn it into a problem.
    for flags in [
        &["--deny", "non-orthonormal-rotation"][..],
        &["--deny-warnings"][..],
    ] {
        let mut a = vec![s(&small)];
        a.extend_from_slice(flags);
        let (code, j, _) = check_json(&a);
        assert_eq!(code, 1, "{flags:?}");
        assert_eq!(findings(&j)[0].1, "error");
    }
    // 2e-3 scaling: sqrt(3) (1.002^2 - 1) = 6.935e-3 > 5e-3: an error.
    let big = write(dir.path(), "big.yaml", &fast_lio(AVIA_T, scaled(1.002)));
    let (code, j, _) = check_json(&[s(&big)]);
    assert_eq!(code, 1, "{j}");
    assert_eq!(
        findings(&j),
        [("non-orthonormal-rotation".into(), "error".into())]
    );
    // The text output names the code at its severity.
    let (_, out, _) = run_cli(&["check", s(&big)]);
    assert!(out.contains("error[non-orthonormal-rotation]"), "{out}");
    // --allow accepts it; --allow wins over --deny.
    let (code, j, _) = check_json(&[s(&big), "--allow", "non-orthonormal-rotation"]);
    assert_eq!(code, 0);
    assert_eq!(findings(&j)[0].1, "warning");
    let (code, _, _) = check_json(&[
        s(&big),
        "--allow",
        "non-orthonormal-rotation",
        "--deny",
        "non-orthonormal-rotation",
    ]);
    assert_eq!(code, 0);
    // Unknown codes are usage errors that list the codes.
    let (code, _, err) = run_cli(&["check", s(&small), "--deny", "no-such-code"]);
    assert_eq!(code, 2);
    assert!(err.contains("removed-file"), "{err}");
}

fn tf_static(q: [f64; 4]) -> String {
    format!(
        "transforms:\n- header:\n    frame_id: imu\n  child_frame_id: lidar\n  transform:\n    translation: {{x: 0.1, y: 0.0, z: 0.0}}\n    rotation: {{x: {}, y: {}, z: {}, w: {}}}\n",
        q[0], q[1], q[2], q[3]
    )
}

#[test]
fn quaternion_norm_policy() {
    let dir = tempfile::tempdir().unwrap();
    // Norm 1.001 (three printed digits): a warning, the gate passes.
    let q1 = write(dir.path(), "a.yaml", &tf_static([0.0, 0.0, 0.0, 1.001]));
    let (code, j, _) = check_json(&[s(&q1)]);
    assert_eq!(code, 0, "{j}");
    assert_eq!(
        findings(&j),
        [("non-unit-quaternion".into(), "warning".into())]
    );
    // Norm 1.01: an error.
    let q2 = write(dir.path(), "b.yaml", &tf_static([0.0, 0.0, 0.0, 1.01]));
    let (code, j, _) = check_json(&[s(&q2)]);
    assert_eq!(code, 1, "{j}");
    assert_eq!(
        findings(&j),
        [("non-unit-quaternion".into(), "error".into())]
    );
}

/// The shipped calibrations pass their own gate, alone and against the
/// shipped baseline.
#[test]
fn shipped_calibrations_pass_the_gate() {
    let (code, j, err) = check_json(&["calibrations/"]);
    assert_eq!(code, 0, "{j}{err}");
    assert_eq!(j["problems"], 0);
    assert_eq!(
        j["warnings"].as_array().map(Vec::len),
        Some(4),
        "GEODE's and M3DGR's rounded matrices"
    );
    let (code, j, err) = check_json(&["calibrations/", "--baseline", "calibrations/baseline.json"]);
    assert_eq!(code, 0, "{j}{err}");
    assert_eq!(j["problems"], 0);
}

/// calibrations/baseline.json is what `--write-baseline` writes today;
/// `BLESS=1` rewrites it.
#[test]
fn shipped_baseline_is_current() {
    let shipped = Path::new("calibrations/baseline.json");
    // A hidden name in the same directory: the same keys, never walked.
    let fresh =
        Path::new("calibrations").join(format!(".baseline-test.{}.json", std::process::id()));
    let (code, out, err) = run_cli(&["check", "calibrations/", "--write-baseline", s(&fresh)]);
    let new = std::fs::read(&fresh);
    let _ = std::fs::remove_file(&fresh);
    assert_eq!(code, 0, "{out}{err}");
    let new = new.unwrap();
    if std::fs::read(shipped).ok().as_deref() != Some(&new[..]) {
        if std::env::var_os("BLESS").is_some() {
            std::fs::write(shipped, &new).unwrap();
        } else {
            panic!(
                "calibrations/baseline.json is out of date; regenerate with\n  BLESS=1 cargo test --test it check_gate::shipped_baseline_is_current"
            );
        }
    }
}

/// Run `audit ARGS` in `cwd`: (exit code, stdout, stderr).
pub fn run_in(cwd: &Path, args: &[&str]) -> (i32, String, String) {
    let out = crate::common::audit()
        .current_dir(cwd)
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn baseline_keys(p: &Path) -> Vec<String> {
    let b: Value = serde_json::from_slice(&std::fs::read(p).unwrap()).unwrap();
    b["files"].as_object().unwrap().keys().cloned().collect()
}

fn codes_of(out: &str) -> Vec<String> {
    let j: Value = serde_json::from_str(out).unwrap();
    findings(&j).into_iter().map(|(c, _)| c).collect()
}

/// A tree `cal/` with two rigs, and its baseline `cal/baseline.json`.
fn tree() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal");
    std::fs::create_dir(&cal).unwrap();
    write(&cal, "a.yaml", &fast_lio(AVIA_T, scaled(1.0)));
    write(&cal, "b.yaml", &fast_lio([0.1, 0.0, 0.0], scaled(1.0)));
    let (code, out, err) = run_in(
        dir.path(),
        &["check", "cal/", "--write-baseline", "cal/baseline.json"],
    );
    assert_eq!(code, 0, "{out}{err}");
    (dir, cal)
}

#[test]
fn baseline_keys_are_normalised_relative_paths() {
    let (dir, cal) = tree();
    assert_eq!(
        baseline_keys(&cal.join("baseline.json")),
        ["a.yaml", "b.yaml"]
    );
    let abs = format!("{}/", cal.display());
    // The same files however they are named: no new-file, exit 0.
    for (cwd, args) in [
        (
            dir.path(),
            vec!["./cal//", "--baseline", "cal/baseline.json"],
        ),
        (
            dir.path(),
            vec!["cal/./", "--baseline", "./cal/baseline.json"],
        ),
        (
            dir.path(),
            vec![&abs[..], "--baseline", "cal/baseline.json"],
        ),
        (cal.as_path(), vec![".", "--baseline", "baseline.json"]),
        (
            cal.as_path(),
            vec!["a.yaml", "b.yaml", "--baseline", "../cal/baseline.json"],
        ),
    ] {
        let mut a = vec!["check"];
        a.extend(args.iter().copied());
        a.extend(["--format", "json"]);
        let (code, out, err) = run_in(cwd, &a);
        assert_eq!(code, 0, "{a:?}: {out}{err}");
        assert_eq!(codes_of(&out), Vec::<String>::new(), "{a:?}");
    }
    // A baseline elsewhere: keys relative to its directory.
    let (code, _, err) = run_in(dir.path(), &["check", "cal", "--write-baseline", "ci.json"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        baseline_keys(&dir.path().join("ci.json")),
        ["cal/a.yaml", "cal/b.yaml"]
    );
}

#[cfg(unix)]
#[test]
fn symlinks_inside_the_root_are_resolved() {
    let (dir, cal) = tree();
    // A link to a file of the root is that file (one key); a directory linked
    // from outside the root is keyed where it is found.
    std::os::unix::fs::symlink("a.yaml", cal.join("alias.yaml")).unwrap();
    let outside = dir.path().join("outside");
    std::fs::create_dir(&outside).unwrap();
    write(&outside, "c.yaml", &fast_lio([0.2, 0.0, 0.0], scaled(1.0)));
    std::os::unix::fs::symlink(&outside, cal.join("sub")).unwrap();
    let (code, out, err) = run_in(
        dir.path(),
        &["check", "cal", "--write-baseline", "cal/baseline.json"],
    );
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("checked 3 files"), "{out}");
    assert_eq!(
        baseline_keys(&cal.join("baseline.json")),
        ["a.yaml", "b.yaml", "sub/c.yaml"]
    );
}

#[cfg(unix)]
#[test]
fn non_utf8_file_names_get_their_own_keys() {
    use std::os::unix::ffi::OsStrExt;
    let dir = tempfile::tempdir().unwrap();
    let name = |b: &[u8]| dir.path().join(std::ffi::OsStr::from_bytes(b));
    let (ff, fe) = (name(b"r\xff.yaml"), name(b"r\xfe.yaml"));
    std::fs::write(&ff, fast_lio(AVIA_T, scaled(1.0))).unwrap();
    std::fs::write(&fe, fast_lio(AVIA_T, scaled(1.0))).unwrap();
    std::fs::write(name(b"100%.yaml"), fast_lio(AVIA_T, scaled(1.0))).unwrap();
    let base = dir.path().join("baseline.json");
    let (code, _, err) = run_cli(&["check", s(dir.path()), "--write-baseline", s(&base)]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        baseline_keys(&base),
        ["100%25.yaml", "r%FE.yaml", "r%FF.yaml"]
    );
    // Drift in one of the two: found, on that file only.
    std::fs::write(&ff, fast_lio([0.05, 0.02326, -0.0284], scaled(1.0))).unwrap();
    let (code, j, _) = check_json(&[s(dir.path()), "--baseline", s(&base)]);
    assert_eq!(code, 1);
    let f = j["findings"].as_array().unwrap();
    let drift: Vec<&Value> = f.iter().filter(|f| f["code"] == "drift").collect();
    assert_eq!(
        drift.len(),
        1,
        "the edge (a FAST-LIO file declares no pair): {j}"
    );
    assert!(f
        .iter()
        .all(|f| f["file"].as_str().unwrap().ends_with("r\u{fffd}.yaml")));
    assert!(codes_of(&j.to_string()).iter().all(|c| c == "drift"), "{j}");
}

#[test]
fn a_removed_file_is_a_finding_until_pruned() {
    let (dir, cal) = tree();
    std::fs::remove_file(cal.join("b.yaml")).unwrap();
    let (code, out, _) = run_in(
        dir.path(),
        &[
            "check",
            "cal",
            "--baseline",
            "cal/baseline.json",
            "--format",
            "json",
        ],
    );
    assert_eq!(code, 1, "{out}");
    assert_eq!(codes_of(&out), ["removed-file"]);
    let j: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["findings"][0]["file"], "cal/b.yaml");
    // Checking a subset: the other file exists, so it is not "removed".
    write(&cal, "b.yaml", &fast_lio([0.1, 0.0, 0.0], scaled(1.0)));
    let (code, out, _) = run_in(
        dir.path(),
        &["check", "cal/a.yaml", "--baseline", "cal/baseline.json"],
    );
    assert_eq!(code, 0, "{out}");
    std::fs::remove_file(cal.join("b.yaml")).unwrap();
    // Accepted with --prune, which says what it removed.
    let (code, out, _) = run_in(
        dir.path(),
        &[
            "check",
            "cal",
            "--write-baseline",
            "cal/baseline.json",
            "--prune",
        ],
    );
    assert_eq!(code, 0);
    assert!(
        out.contains("0 added, 1 removed, 0 updated, 1 unchanged"),
        "{out}"
    );
    assert!(out.contains("removed: b.yaml"), "{out}");
    let (code, _, _) = run_in(
        dir.path(),
        &["check", "cal", "--baseline", "cal/baseline.json"],
    );
    assert_eq!(code, 0);
}

/// FAST-LIO's Avia rig file declaring `imu -> to`, with an extra edge
/// `lidar -> os` written from line 34.
fn rig(to: &str) -> String {
    let avia = std::fs::read_to_string("calibrations/fastlio-avia.toml").unwrap();
    let text = avia.replace("to = \"lidar\"", &format!("to = \"{to}\""));
    format!(
        "{text}\n[[transform]]\nparent = \"lidar\"\nchild = \"os\"\nunit = \"m\"\ntranslation = [0.0, 0.0, 0.03]\nrotation_matrix = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\nsource_key = \"x\"\n"
    )
}

#[test]
fn a_changed_frame_pair_names_both_pairs() {
    let dir = tempfile::tempdir().unwrap();
    let r = write(dir.path(), "rig.toml", &rig("lidar"));
    let base = dir.path().join("baseline.json");
    let (code, _, err) = run_cli(&["check", s(&r), "--write-baseline", s(&base)]);
    assert_eq!(code, 0, "{err}");
    write(dir.path(), "rig.toml", &rig("os"));
    let (code, j, _) = check_json(&[s(&r), "--baseline", s(&base)]);
    assert_eq!(code, 1);
    let f = &j["findings"][0];
    assert_eq!(f["code"], "pair-changed", "{j}");
    let m = f["message"].as_str().unwrap();
    assert!(
        m.contains("imu -> lidar (baseline)") && m.contains("imu -> os (now)"),
        "{m}"
    );
    let text = rig("os");
    let at = |l: &str| 1 + text.lines().position(|x| x == l).unwrap();
    let line = f["line"].as_u64().unwrap() as usize;
    assert!(
        (at("parent = \"lidar\"") - 1..=at("source_key = \"x\"")).contains(&line),
        "the new pair's last edge (its [[transform]]): {j}"
    );
}

#[test]
fn malformed_baseline_entries_are_refused_naming_the_entry() {
    let (dir, cal) = tree();
    let base = cal.join("baseline.json");
    let text = std::fs::read_to_string(&base).unwrap();
    let mut good: Value = serde_json::from_str(&text).unwrap();
    type Edit = Box<dyn Fn(&mut Value)>;
    let cases: Vec<(Edit, &str)> = vec![
        (
            Box::new(|b| b["files"]["a.yaml"]["edges"][0]["quaternion_xyzw"] = serde_json::json!([0, 0, 0, 0])),
            "files[\"a.yaml\"].edges[0] (imu -> lidar): expected a unit quaternion_xyzw, found norm 0e0",
        ),
        (
            Box::new(|b| {
                b["files"]["b.yaml"]["edges"][0]
                    .as_object_mut()
                    .unwrap()
                    .remove("translation_m");
            }),
            "files[\"b.yaml\"]: missing field `translation_m`",
        ),
        (
            Box::new(|b| b["schema_version"] = serde_json::json!(7)),
            "expected baseline schema_version 1, found 7",
        ),
        (
            Box::new(|b| b["files"]["a.yaml"]["edges"][0]["translation_m"][0] = serde_json::json!("x")),
            "files[\"a.yaml\"]: invalid type: string \"x\", expected f64",
        ),
    ];
    for (edit, expect) in cases {
        let mut b = good.clone();
        edit(&mut b);
        std::fs::write(&base, serde_json::to_string(&b).unwrap()).unwrap();
        let (code, out, err) = run_in(
            dir.path(),
            &["check", "cal", "--baseline", "cal/baseline.json"],
        );
        assert_eq!(code, 2, "{expect}: {out}{err}");
        assert!(err.contains(expect), "{expect}: {err}");
    }
    // A number beyond f64 cannot be stored either.
    let huge = text.replacen("0.04165", "1e999", 1);
    std::fs::write(&base, huge).unwrap();
    let (code, _, err) = run_in(
        dir.path(),
        &["check", "cal", "--baseline", "cal/baseline.json"],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("baseline.json:"), "{err}");
    good["schema_version"] = serde_json::json!(1);
}

/// Every file under `dir` with its bytes (a refused write must leave them).
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let m = std::fs::symlink_metadata(&p).unwrap();
        if m.is_file() {
            out.push((p.clone(), std::fs::read(&p).unwrap()));
        } else if m.is_dir() {
            out.extend(snapshot(&p));
        } else {
            out.push((p, Vec::new()));
        }
    }
    out.sort();
    out
}

#[test]
fn write_baseline_refuses_inputs_and_non_regular_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("d");
    std::fs::create_dir(&d).unwrap();
    let urdf = std::fs::read_to_string("calibrations/anymal-d.urdf").unwrap();
    let robot = write(&d, "robot.urdf", &urdf);
    write(&d, "notes.json", "{\"not\": \"a baseline\"}");
    std::fs::create_dir(d.join("subdir")).unwrap();
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("subdir", d.join("to_dir.json")).unwrap();
        std::os::unix::fs::symlink("robot.urdf", d.join("to_robot.json")).unwrap();
        let fifo = d.join("fifo.json");
        let ok = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(ok.is_ok_and(|s| s.success()), "mkfifo");
    }
    let before = snapshot(dir.path());
    let mut targets = vec![
        ("d/robot.urdf", "one of the checked calibration files"),
        ("d/subdir", "found a directory"),
        ("d/notes.json", "exists and is not a baseline"),
        ("d/nodir/b.json", "expected an existing directory"),
    ];
    if cfg!(unix) {
        targets.extend([
            ("d/to_dir.json", "found a symlink to a directory"),
            ("d/to_robot.json", "one of the checked calibration files"),
            ("d/fifo.json", "not a regular file"),
            ("/dev/null", "not a regular file"),
        ]);
    }
    for (t, why) in targets {
        for input in ["d/robot.urdf", "d"] {
            let (code, out, err) = run_in(
                dir.path(),
                &["check", input, "--exclude", "*.json", "--write-baseline", t],
            );
            assert_eq!(code, 2, "{input} -> {t}: {out}{err}");
            assert!(
                err.contains("refused, nothing written") && err.contains(why),
                "{t}: {err}"
            );
            assert_eq!(snapshot(dir.path()), before, "{t}: nothing touched");
        }
    }
    assert_eq!(std::fs::read_to_string(&robot).unwrap(), urdf);
}

#[cfg(unix)]
#[test]
fn write_baseline_keeps_the_mode_and_updates_only_checked_entries() {
    use std::os::unix::fs::PermissionsExt;
    let (dir, cal) = tree();
    let base = cal.join("baseline.json");
    std::fs::set_permissions(&base, std::fs::Permissions::from_mode(0o600)).unwrap();
    // b.yaml recalibrated; a new file c.yaml; only b.yaml and c.yaml checked.
    write(&cal, "b.yaml", &fast_lio([0.2, 0.0, 0.0], scaled(1.0)));
    write(&cal, "c.yaml", &fast_lio([0.3, 0.0, 0.0], scaled(1.0)));
    let (code, out, err) = run_in(
        dir.path(),
        &[
            "check",
            "cal/b.yaml",
            "cal/c.yaml",
            "--write-baseline",
            "cal/baseline.json",
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains("1 added, 0 removed, 1 updated, 0 unchanged"),
        "{out}"
    );
    assert!(
        out.contains("added: c.yaml") && out.contains("updated: b.yaml"),
        "{out}"
    );
    assert_eq!(
        baseline_keys(&base),
        ["a.yaml", "b.yaml", "c.yaml"],
        "a.yaml kept"
    );
    let mode = std::fs::metadata(&base).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o600);
    // In the JSON report too.
    let (_, out, _) = run_in(
        dir.path(),
        &[
            "check",
            "cal/c.yaml",
            "--write-baseline",
            "cal/baseline.json",
            "--prune",
            "--format",
            "json",
        ],
    );
    let j: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        j["baseline_written"]["removed"],
        serde_json::json!(["a.yaml", "b.yaml"])
    );
    assert_eq!(j["baseline_written"]["unchanged"], 1);
    assert_eq!(baseline_keys(&base), ["c.yaml"]);
}

/// `tree()` with a.yaml moved by 2 mm along x: (dir, cal).
fn drifted_tree() -> (tempfile::TempDir, PathBuf) {
    let (dir, cal) = tree();
    write(
        &cal,
        "a.yaml",
        &fast_lio([0.04365, 0.02326, -0.0284], scaled(1.0)),
    );
    (dir, cal)
}

#[test]
fn drift_findings_carry_the_edge_line_and_old_new_values() {
    let (dir, _cal) = drifted_tree();
    let args = ["check", "cal", "--baseline", "cal/baseline.json"];
    let (code, out, _) = run_in(dir.path(), &[&args[..], &["--format", "json"]].concat());
    assert_eq!(code, 1);
    let j: Value = serde_json::from_str(&out).unwrap();
    let f = &j["findings"][0];
    assert_eq!(f["code"], "drift");
    assert_eq!(f["file"], "cal/a.yaml");
    // `extrinsic_T:` is on line 2, column 3 of the FAST-LIO file.
    assert_eq!(
        (f["line"].as_u64(), f["column"].as_u64()),
        (Some(2), Some(3)),
        "{f}"
    );
    let m = f["message"].as_str().unwrap();
    for part in [
        "edge imu -> lidar drifted since the baseline beyond the translation tolerance",
        "translation [41.650, 23.260, -28.400] mm -> [43.650, 23.260, -28.400] mm",
        "moved 2.000 mm (tolerance 1.000 mm)",
        "rotation moved 0.0000 deg (tolerance 0.05 deg)",
    ] {
        assert!(m.contains(part), "{part}: {m}");
    }
    // GitHub annotation on that line.
    let (_, out, _) = run_in(dir.path(), &[&args[..], &["--format", "github"]].concat());
    assert!(
        out.contains("::error file=cal/a.yaml,line=2,col=3,title=drift::edge imu -> lidar drifted"),
        "{out}"
    );
    // A rotation of 0.1 deg about z: beyond the rotation tolerance only.
    let (c, sn) = (0.1f64.to_radians().cos(), 0.1f64.to_radians().sin());
    let rot = [[c, -sn, 0.0], [sn, c, 0.0], [0.0, 0.0, 1.0]];
    write(&dir.path().join("cal"), "a.yaml", &fast_lio(AVIA_T, rot));
    let (_, out, _) = run_in(dir.path(), &[&args[..], &["--format", "json"]].concat());
    let j: Value = serde_json::from_str(&out).unwrap();
    let m = j["findings"][0]["message"].as_str().unwrap();
    assert!(
        m.contains("beyond the rotation tolerance") && m.contains("rotation moved 0.1000 deg"),
        "{m}"
    );
}

#[test]
fn sarif_output_is_valid_sarif_2_1_0() {
    let (dir, cal) = drifted_tree();
    write(&cal, "c.yaml", &fast_lio(AVIA_T, scaled(1.0001)));
    std::fs::remove_file(cal.join("b.yaml")).unwrap();
    let (code, out, err) = run_in(
        dir.path(),
        &[
            "check",
            "cal",
            "--baseline",
            "cal/baseline.json",
            "--format",
            "sarif",
        ],
    );
    assert_eq!(code, 1, "{err}");
    let log: Value = serde_json::from_str(&out).unwrap();
    let path = format!(
        "{}/docs/schemas/external/sarif-2.1.0-rtm.5.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let schema: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let v = jsonschema::validator_for(&schema).unwrap();
    let errors: Vec<String> = v
        .iter_errors(&log)
        .map(|e| format!("{e} at {}", e.instance_path))
        .collect();
    assert!(errors.is_empty(), "{errors:#?}\n{out}");
    // The schema refuses a wrong log (the validator is live).
    let mut bad = log.clone();
    bad["runs"][0]["results"][0]["level"] = Value::from("fatal");
    assert!(!v.is_valid(&bad));
    let results = log["runs"][0]["results"].as_array().unwrap();
    let by = |rule: &str| {
        results
            .iter()
            .find(|r| r["ruleId"] == rule)
            .unwrap_or_else(|| panic!("{rule}: {out}"))
    };
    let drift = by("drift");
    assert_eq!(drift["level"], "error");
    let loc = &drift["locations"][0]["physicalLocation"];
    assert_eq!(loc["artifactLocation"]["uri"], "cal/a.yaml");
    assert_eq!(loc["region"]["startLine"], 2);
    assert_eq!(by("non-orthonormal-rotation")["level"], "warning");
    assert_eq!(
        by("removed-file")["locations"][0]["physicalLocation"]["artifactLocation"]["uri"],
        "cal/b.yaml"
    );
    let rules = log["runs"][0]["tool"]["driver"]["rules"]
        .as_array()
        .unwrap();
    let removed = rules.iter().find(|r| r["id"] == "removed-file").unwrap();
    assert!(
        removed["shortDescription"]["text"]
            .as_str()
            .unwrap()
            .contains("no longer exists")
            || removed["shortDescription"]["text"]
                .as_str()
                .unwrap()
                .contains("is gone")
    );
}

#[test]
fn markdown_is_a_job_summary() {
    let (dir, _cal) = drifted_tree();
    let (code, out, _) = run_in(
        dir.path(),
        &[
            "check",
            "cal",
            "--baseline",
            "cal/baseline.json",
            "--format",
            "markdown",
        ],
    );
    assert_eq!(code, 1);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "**audit check: FAILED**");
    assert!(
        lines.contains(&"| severity | code | where | message |"),
        "{out}"
    );
    assert!(
        out.contains("| **error** | `drift` | `cal/a.yaml:2:3` | edge imu -> lidar drifted"),
        "{out}"
    );
    assert!(
        out.trim_end()
            .ends_with("checked 2 files: 1 problem, 0 warnings"),
        "{out}"
    );
    let (code, out, _) = run_in(dir.path(), &["check", "cal/b.yaml", "--format", "markdown"]);
    assert_eq!(code, 0);
    assert!(out.starts_with("**audit check: passed**\n"), "{out}");
}

/// A tf_static dump with the edges `(parent, child, [x, y, z])`, identity
/// rotations; edge `k` is written from line `2 + 6 k` (its `- header:`).
fn tf_edges(edges: &[(&str, &str, [f64; 3])]) -> String {
    let mut s = String::from("transforms:\n");
    for (p, c, t) in edges {
        s.push_str(&format!(
            "- header:\n    frame_id: {p}\n  child_frame_id: {c}\n  transform:\n    translation: {{x: {}, y: {}, z: {}}}\n    rotation: {{x: 0.0, y: 0.0, z: 0.0, w: 1.0}}\n",
            t[0], t[1], t[2]
        ));
    }
    s
}

#[test]
fn a_manifest_loads_each_robots_files_together() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "a.yaml", &tf_edges(&[("imu", "lidar", [0.1, 0.0, 0.0])]));
    write(d, "b.yaml", &tf_edges(&[("imu", "lidar", [0.2, 0.0, 0.0])]));
    write(
        d,
        "c.yaml",
        &tf_edges(&[
            ("lidar", "base", [0.0, 0.0, 0.1]),
            ("base", "imu", [0.0, 0.0, -0.1]),
        ]),
    );
    write(
        d,
        "mount.yaml",
        &tf_edges(&[("base", "imu_link", [0.0, 0.0, 0.5])]),
    );
    // Without a manifest each file is its own robot: no conflict.
    let (code, j, _) = check_json(&[s(d)]);
    assert_eq!(code, 0, "{j}");
    assert_eq!(j["files_checked"], 4);

    // The same edge with other values in two files of one robot.
    let m = write(
        d,
        "audit.toml",
        "[[robot]]\nname = \"r1\"\nfiles = [\"a.yaml\", \"b.yaml\"]\n",
    );
    let (code, j, _) = check_json(&[s(d)]);
    assert_eq!(code, 1, "{j}");
    assert_eq!(
        j["files_checked"], 4,
        "audit.toml is not a calibration file"
    );
    let f = &j["findings"][0];
    assert_eq!(
        (f["code"].as_str(), f["file"].as_str()),
        (
            Some("redundant-edge-disagrees"),
            Some(&*format!("{}", d.join("b.yaml").display()))
        )
    );
    let msg = f["message"].as_str().unwrap();
    let (a, b) = (d.join("a.yaml"), d.join("b.yaml"));
    // Issue 30: two sources of one edge are a disagreement with both values.
    assert!(
        msg.contains("two sources that disagree by 100.000 mm"),
        "{msg}"
    );
    assert!(
        msg.contains(&format!("{}:2:3", a.display()))
            && msg.contains(&format!("{}:2:3", b.display())),
        "{msg}"
    );

    // A cycle across two files.
    std::fs::write(
        &m,
        "[[robot]]\nname = \"r2\"\nfiles = [\"a.yaml\", \"c.yaml\"]\n",
    )
    .unwrap();
    let (code, j, _) = check_json(&[s(d)]);
    assert_eq!(code, 1);
    assert!(
        j["findings"][0]["message"]
            .as_str()
            .unwrap()
            .contains("closes a cycle"),
        "{j}"
    );

    // Renames and pairs: base -> lidar composed across two files (0.1, 0, 0.5).
    std::fs::write(
        &m,
        "[[robot]]\nname = \"r3\"\nfiles = [\"mount.yaml\", \"a.yaml\"]\nrenames = [{ file = \"a.yaml\", old = \"imu\", new = \"imu_link\" }]\npairs = [\"base:lidar\"]\n",
    )
    .unwrap();
    let (code, j, _) = check_json(&[s(d), "--max-lever-arm", "0.5"]);
    assert_eq!(code, 1, "{j}");
    let lever: Vec<&Value> = j["findings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["code"] == "lever-arm")
        .collect();
    assert_eq!(lever.len(), 1, "{j}");
    // sqrt(0.1^2 + 0.5^2) = 0.509902
    assert!(
        lever[0]["message"]
            .as_str()
            .unwrap()
            .contains("lever arm 0.509902 m"),
        "{j}"
    );
    // The pair is baselined (in the robot's first file) and compared.
    let base = d.join("base.json");
    let (code, _, err) = run_cli(&["check", s(d), "--write-baseline", s(&base)]);
    assert_eq!(code, 0, "{err}");
    let b: Value = serde_json::from_slice(&std::fs::read(&base).unwrap()).unwrap();
    assert_eq!(b["files"]["mount.yaml"]["pairs"][0]["parent"], "base");
    assert_eq!(b["files"]["mount.yaml"]["pairs"][0]["child"], "lidar");

    // Mistakes in the manifest: exit 2 naming the manifest.
    for (text, expect) in [
        ("[[robot]]\nname = \"x\"\nfiles = [\"nope.yaml\"]\n", "expected the file \"nope.yaml\""),
        ("[[robot]]\nname = \"x\"\nfiles = [\"a.yaml\"]\nrenames = [{ old = \"gps\", new = \"g\" }]\n", "expected a frame `gps`"),
        ("[[robot]]\nname = \"x\"\nfiles = [\"a.yaml\"]\npairs = [\"nocolon\"]\n", "expected a pair FROM:TO"),
        ("[[robot]]\nname = \"x\"\nfiles = [\"a.yaml\", \"./a.yaml\"]\n", "listed twice"),
        ("[[robot]]\nname = \"x\"\nfile = [\"a.yaml\"]\n", "unknown field `file`"),
    ] {
        std::fs::write(&m, text).unwrap();
        let (code, out, err) = run_cli(&["check", s(d)]);
        assert_eq!(code, 2, "{text}: {out}");
        assert!(err.contains(expect) && err.contains("audit.toml"), "{text}: {err}");
    }
}

/// A mirror image: a rotation matrix with det -1 (refused as `invalid`).
const MIRROR: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]];

#[test]
fn the_walk_has_no_silent_limit() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("cal");
    // A mirror-image rotation 20 levels down (the old walk stopped at 17).
    let mut deep = root.clone();
    for i in 0..20 {
        deep.push(format!("d{i}"));
    }
    std::fs::create_dir_all(&deep).unwrap();
    write(&deep, "m.yaml", &fast_lio(AVIA_T, MIRROR));
    let (code, j, _) = check_json(&[s(&root)]);
    assert_eq!(code, 1, "{j}");
    assert_eq!(findings(&j), [("invalid".into(), "error".into())]);
    // Beyond MAX_WALK_DEPTH (64): a `limit` finding naming the directory.
    for i in 20..70 {
        deep.push(format!("d{i}"));
    }
    std::fs::create_dir_all(&deep).unwrap();
    write(&deep, "m.yaml", &fast_lio(AVIA_T, MIRROR));
    let (code, j, _) = check_json(&[s(&root)]);
    assert_eq!(code, 1);
    let f: Vec<&Value> = j["findings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["code"] == "limit")
        .collect();
    assert_eq!(f.len(), 1, "{j}");
    assert!(
        f[0]["message"]
            .as_str()
            .unwrap()
            .contains("expected at most 64"),
        "{j}"
    );
    assert!(f[0]["file"].as_str().unwrap().ends_with("/d64"), "{j}");
}

#[cfg(unix)]
#[test]
fn symlinked_directories_are_followed_once() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("cal");
    let other = dir.path().join("other");
    std::fs::create_dir_all(root.join("sub")).unwrap();
    std::fs::create_dir_all(&other).unwrap();
    write(&root, "a.yaml", &fast_lio(AVIA_T, scaled(1.0)));
    // A mirror image behind a symlinked directory: found.
    write(&other, "m.yaml", &fast_lio(AVIA_T, MIRROR));
    std::os::unix::fs::symlink(&other, root.join("linked")).unwrap();
    // Loops: a link to the root and one to a sibling.
    std::os::unix::fs::symlink("..", root.join("sub/up")).unwrap();
    std::os::unix::fs::symlink("../linked", root.join("sub/again")).unwrap();
    let (code, j, _) = check_json(&[s(&root)]);
    assert_eq!(code, 1, "{j}");
    assert_eq!(j["files_checked"], 2, "each file once: {j}");
    let f = findings(&j);
    assert!(f.contains(&("invalid".into(), "error".into())), "{f:?}");
    let notes = f.iter().filter(|(c, _)| c == "ignored").count();
    assert_eq!(notes, 2, "the loop and the second link are reported: {j}");
    // A FIFO named like a calibration file is refused (exit 2), never opened.
    let fifo = root.join("pipe.yaml");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let (code, out, err) = run_cli(&[
        "check",
        s(&root),
        "--exclude",
        "linked",
        "--exclude",
        "again",
    ]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("not a regular file") && err.contains("pipe.yaml"),
        "{err}"
    );
}

#[test]
fn exclude_globs_and_the_default_file_set() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    std::fs::create_dir_all(root.join("config/old")).unwrap();
    write(root, "a.yaml", &fast_lio(AVIA_T, scaled(1.0)));
    write(
        &root.join("config"),
        "b.yaml",
        &fast_lio(AVIA_T, scaled(1.0)),
    );
    write(
        &root.join("config/old"),
        "c.yaml",
        &fast_lio(AVIA_T, MIRROR),
    );
    // Never calibrations in a ROS package: skipped by default.
    write(
        root,
        "package.xml",
        "<package format=\"3\"><name>x</name></package>",
    );
    write(
        root,
        "CMakeLists.txt",
        "cmake_minimum_required(VERSION 3.8)\n",
    );
    write(root, "notes.md", "not a calibration file");
    let count = |extra: &[&str]| {
        let mut a = vec![s(root)];
        a.extend_from_slice(extra);
        let (code, j, _) = check_json(&a);
        (code, j["files_checked"].as_u64().unwrap_or(0))
    };
    assert_eq!(count(&[]), (1, 3));
    assert_eq!(count(&["--exclude", "old"]), (0, 2));
    assert_eq!(count(&["--exclude", "config/old/*"]), (0, 2));
    assert_eq!(count(&["--exclude", "config/**"]), (0, 1));
    // Nothing left: a usage error, not a green run.
    assert_eq!(count(&["--exclude", "*.yaml"]), (2, 0));
    // docs/check.md lists the registry's walk extensions.
    let mut exts: Vec<&str> = extrinsic_audit::internals::formats::FORMATS
        .iter()
        .flat_map(|f| f.walk.iter().copied())
        .collect();
    exts.sort();
    exts.dedup();
    let doc = std::fs::read_to_string("docs/check.md").unwrap();
    let line = doc
        .lines()
        .find(|l| l.starts_with("Walk extensions:"))
        .expect("a `Walk extensions:` line");
    let listed: Vec<&str> = line
        .trim_start_matches("Walk extensions:")
        .split(',')
        .map(|x| x.trim().trim_matches('`'))
        .collect();
    assert_eq!(listed, exts, "docs/check.md is out of date");
}

#[test]
fn a_missing_baseline_says_how_to_write_one() {
    let (dir, _cal) = tree();
    let (code, _, err) = run_in(dir.path(), &["check", "cal", "--baseline", "cal/none.json"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("write one first with `audit check PATHS --write-baseline cal/none.json`"),
        "{err}"
    );
    // --help says where the policy is.
    let (_, out, _) = run_cli(&["check", "--help"]);
    assert!(
        out.contains("docs/check.md") && out.contains("--deny-warnings"),
        "{out}"
    );
}
