//! `check` and `survey` at fleet scale (issue 29): the same output on any
//! number of worker threads, a baseline larger than the old 64 MiB read cap
//! written and read back, and concurrent `--write-baseline` writers that
//! lose no update (issue 27: the advisory lock over read-merge-write).

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn audit(jobs: usize) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_audit"));
    c.env("NO_COLOR", "1")
        .env("AUDIT_JOBS", jobs.to_string())
        .stdin(Stdio::null());
    c
}

fn run(jobs: usize, args: &[&str]) -> Output {
    audit(jobs).args(args).output().expect("run audit")
}

/// A stand-alone rig file: `id`, a lever arm that depends on `k`, and a
/// rotation matrix rounded as published (so that some files warn).
fn rig(id: &str, k: usize) -> String {
    let x = 0.04 + k as f64 * 1e-4;
    let r = if k.is_multiple_of(5) {
        // Orthonormal only to ~1e-5: a non-orthonormal-rotation warning.
        "[[0.99999, 0, 0], [0, 1, 0], [0, 0, 1]]"
    } else {
        "[[0, -1, 0], [1, 0, 0], [0, 0, 1]]"
    };
    format!(
        r#"[rig]
id = "{id}"
sensor = "s"
platform = "p"
dataset = "d"
category = "factory"
licence = "MIT"
direction = "pose of lidar in imu"
from = "imu"
to = "lidar"

[rig.source]
repo = "r/r"
path = "p"
commit = "c"

[[transform]]
parent = "imu"
child = "lidar"
unit = "m"
translation = [{x}, 0.02, -0.03]
rotation_matrix = {r}
source_key = "k"
"#
    )
}

fn write_rigs(dir: &Path, prefix: &str, n: usize) -> Vec<PathBuf> {
    std::fs::create_dir_all(dir).unwrap();
    (0..n)
        .map(|k| {
            let p = dir.join(format!("{prefix}{k:03}.toml"));
            std::fs::write(&p, rig(&format!("{prefix}-{k}"), k)).unwrap();
            p
        })
        .collect()
}

#[test]
fn check_and_survey_say_the_same_on_any_number_of_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("rigs");
    write_rigs(&dir.join("a"), "r", 150);
    write_rigs(&dir.join("b"), "s", 150);
    // Findings among them: a file that does not parse, one without the frames.
    std::fs::write(dir.join("a/r007.toml"), "[rig]\nid = 1\n").unwrap();
    std::fs::write(
        dir.join("b/s100.toml"),
        rig("s-100", 100).replace("to = \"lidar\"", "to = \"camera\""),
    )
    .unwrap();
    let base = tmp.path().join("baseline.json");
    let d = dir.to_str().unwrap();
    let b = base.to_str().unwrap();
    let w = run(1, &["check", d, "--write-baseline", b]);
    assert_eq!(
        w.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&w.stderr)
    );
    // One file drifts, one is new: the comparison says so in every run.
    std::fs::write(dir.join("a/r010.toml"), rig("r-10", 11)).unwrap();
    write_rigs(&dir.join("c"), "t", 1);
    let clean = tmp.path().join("clean");
    write_rigs(&clean.join("a"), "r", 150);
    write_rigs(&clean.join("b"), "s", 150);
    let c = clean.to_str().unwrap();
    let runs: [&[&str]; 3] = [
        &["check", d, "--baseline", b, "--format", "json"],
        &["survey", c, "--format", "json", "--all"],
        &["survey", c, "--sort", "lever-arm"],
    ];
    for args in runs {
        let one = run(1, args);
        assert!(
            !one.stdout.is_empty(),
            "{}",
            String::from_utf8_lossy(&one.stderr)
        );
        for jobs in [2, 3, 8] {
            let many = run(jobs, args);
            assert_eq!(
                many.status.code(),
                one.status.code(),
                "{args:?} on {jobs} threads"
            );
            assert_eq!(
                String::from_utf8_lossy(&many.stdout),
                String::from_utf8_lossy(&one.stdout),
                "{args:?} on {jobs} threads"
            );
            assert_eq!(many.stderr, one.stderr, "{args:?} on {jobs} threads");
        }
    }
    let report: serde_json::Value =
        serde_json::from_slice(&run(2, runs[0]).stdout).expect("check JSON");
    let codes: Vec<&str> = report["findings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["code"].as_str().unwrap())
        .collect();
    for code in [
        "parse",
        "frames",
        "drift",
        "new-file",
        "non-orthonormal-rotation",
    ] {
        assert!(codes.contains(&code), "no {code} in {codes:?}");
    }
}

/// A URDF chain of `n` links (fixed joints with a non-trivial origin): one
/// baseline entry of `n - 1` edges, about 250 bytes each.
fn chain(n: usize) -> String {
    let mut s = String::from("<?xml version=\"1.0\"?>\n<robot name=\"chain\">\n");
    for k in 0..n {
        s.push_str(&format!("<link name=\"l{k}\"/>\n"));
    }
    for k in 1..n {
        s.push_str(&format!(
            "<joint name=\"j{k}\" type=\"fixed\"><parent link=\"l{}\"/><child link=\"l{k}\"/><origin xyz=\"0.01 0.002 -0.003\" rpy=\"0.001 -0.002 0.003\"/></joint>\n",
            k - 1
        ));
    }
    s.push_str("</robot>\n");
    s
}

#[test]
fn a_baseline_past_the_old_64_mib_cap_is_written_and_read_back() {
    // 300 robots of 1,000 links: a baseline of about 75 MB, past the 64 MiB
    // that `check --baseline` used to refuse. Generated here, not committed.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("robots");
    std::fs::create_dir(&dir).unwrap();
    let text = chain(1000);
    let n = 300;
    for k in 0..n {
        std::fs::write(dir.join(format!("robot{k:03}.urdf")), &text).unwrap();
    }
    let base = tmp.path().join("baseline.json");
    let (d, b) = (dir.to_str().unwrap(), base.to_str().unwrap());
    let w = run(2, &["check", d, "--write-baseline", b, "--format", "json"]);
    assert_eq!(
        w.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&w.stderr)
    );
    let written: serde_json::Value = serde_json::from_slice(&w.stdout).unwrap();
    assert_eq!(
        written["baseline_written"]["added"]
            .as_array()
            .unwrap()
            .len(),
        n
    );
    let size = std::fs::metadata(&base).unwrap().len();
    assert!(size > 64 * 1024 * 1024, "baseline is only {size} bytes");
    let r = run(2, &["check", d, "--baseline", b, "--format", "json"]);
    assert_eq!(
        r.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert_eq!(report["files_checked"], n);
    assert_eq!(report["findings"], serde_json::json!([]));
    // And it still catches a change in one of the 300.
    std::fs::write(
        dir.join("robot123.urdf"),
        text.replacen("xyz=\"0.01 0.002 -0.003\"", "xyz=\"0.02 0.002 -0.003\"", 1),
    )
    .unwrap();
    let r = run(2, &["check", d, "--baseline", b, "--format", "json"]);
    assert_eq!(r.status.code(), Some(1));
    let report: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    let f = report["findings"].as_array().unwrap();
    assert_eq!(f.len(), 1, "{f:?}");
    assert_eq!(f[0]["code"], "drift");
    assert!(f[0]["message"].as_str().unwrap().contains("edge l0 -> l1"));
}

#[test]
fn concurrent_baseline_writers_lose_no_update() {
    // Three writers, each its own 20 files, into one baseline at once; ten
    // rounds. Every entry each writer reports added must be there after, and
    // the baseline must hold every writer's files.
    let tmp = tempfile::tempdir().unwrap();
    let writers = 3;
    for round in 0..10 {
        let root = tmp.path().join(format!("round{round}"));
        let base = root.join("baseline.json");
        let dirs: Vec<PathBuf> = (0..writers)
            .map(|w| {
                let d = root.join(format!("w{w}"));
                write_rigs(&d, &format!("w{w}r"), 20);
                d
            })
            .collect();
        let children: Vec<_> = dirs
            .iter()
            .map(|d| {
                audit(1)
                    .args(["check", d.to_str().unwrap(), "--format", "json"])
                    .arg("--write-baseline")
                    .arg(&base)
                    .stdout(Stdio::piped())
                    .stderr(Stdio::piped())
                    .spawn()
                    .unwrap()
            })
            .collect();
        let mut added = Vec::new();
        for c in children {
            let out = c.wait_with_output().unwrap();
            assert_eq!(
                out.status.code(),
                Some(0),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            for k in v["baseline_written"]["added"].as_array().unwrap() {
                added.push(k.as_str().unwrap().to_string());
            }
        }
        let text = std::fs::read_to_string(&base).unwrap();
        let b: serde_json::Value = serde_json::from_str(&text).unwrap();
        let files = b["files"].as_object().unwrap();
        assert_eq!(files.len(), writers * 20, "round {round}");
        assert_eq!(added.len(), writers * 20, "round {round}: {added:?}");
        for k in &added {
            assert!(
                files.contains_key(k),
                "round {round}: {k} reported added, not there"
            );
        }
    }
}
