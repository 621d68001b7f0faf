//! Output safety (issue 7): `--write-baseline` (the one file the tool writes)
//! goes through `pipeline::write_atomic`: a temporary file in the same directory,
//! written, fsynced, renamed over the target. An interrupted run leaves the old
//! baseline, complete; a failed write leaves the old state and no temporary.
//!
//! Kill test: `audit check BIG --write-baseline B` is SIGKILLed 30 times at
//! deterministic delays spread over the measured length of a full run (denser
//! near its end, where the write happens). After every kill B must be exactly
//! the old baseline or exactly the new one. A killed process may leave its own
//! temporary `.B.json.<random>.tmp` (SIGKILL runs no clean-up): one such file
//! is allowed and removed; any other stray file fails the test.

use extrinsic_audit::internals::pipeline::write_atomic;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn audit() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_audit"));
    c.env("NO_COLOR", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    c
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let p = e.path();
        if p.is_dir() {
            copy_dir(&p, &to.join(e.file_name()));
        } else {
            std::fs::copy(&p, to.join(e.file_name())).unwrap();
        }
    }
}

/// Run `audit check DIR --write-baseline OUT` to completion in `cwd`.
fn write_baseline(cwd: &Path, dir: &str, out: &str) -> Duration {
    let t = Instant::now();
    let o = audit()
        .current_dir(cwd)
        .args(["check", dir, "--write-baseline", out])
        .output()
        .unwrap();
    assert!(
        matches!(o.status.code(), Some(0) | Some(1)),
        "{:?} {}",
        o.status,
        String::from_utf8_lossy(&o.stderr)
    );
    t.elapsed()
}

fn others(dir: &Path, keep: &[&str]) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let n = p.file_name().unwrap().to_str().unwrap();
            !keep.contains(&n)
        })
        .collect()
}

/// A temporary of the baseline `B.json`: `.B.json.` + 12 random characters + `.tmp`.
fn is_temporary(p: &Path) -> bool {
    let n = p.file_name().unwrap().to_str().unwrap();
    n.strip_prefix(".B.json.")
        .and_then(|r| r.strip_suffix(".tmp"))
        .is_some_and(|r| r.len() == 12 && r.chars().all(|c| c.is_ascii_alphanumeric()))
}

#[test]
fn killed_mid_write_leaves_old_or_new_baseline() {
    let tmp = tempfile::tempdir().unwrap();
    let root = tmp.path();
    // Small tree -> old baseline; big tree (10 copies) -> new baseline.
    copy_dir(Path::new("calibrations"), &root.join("rigs/c0"));
    for i in 1..10 {
        copy_dir(Path::new("calibrations"), &root.join(format!("rigs/c{i}")));
    }
    copy_dir(Path::new("calibrations"), &root.join("small/c0"));
    let out = root.join("out");
    std::fs::create_dir(&out).unwrap();

    write_baseline(root, "small", "out/B.json");
    let old = std::fs::read(out.join("B.json")).unwrap();
    // The new baseline: the big tree's entries merged into the old one (the
    // entries of files not checked are kept without --prune).
    write_baseline(root, "rigs", "out/B.json");
    let new = std::fs::read(out.join("B.json")).unwrap();
    std::fs::write(out.join("B.json"), &old).unwrap();
    assert_ne!(old, new);
    assert!(new.len() > 100_000, "new baseline is {} bytes", new.len());
    let _: serde_json::Value = serde_json::from_slice(&old).unwrap();

    // Length of a full run over the big tree (best of 3).
    let full = (0..3)
        .map(|_| {
            std::fs::write(out.join("B.json"), &old).unwrap();
            write_baseline(root, "rigs", "out/B.json")
        })
        .min()
        .unwrap();
    std::fs::write(out.join("B.json"), &old).unwrap();

    let (mut saw_old, mut saw_new, mut temps) = (0, 0, 0);
    for i in 0..30u32 {
        // Spread over [0, 1.1 x full]; the last third densely near the end.
        let frac = if i < 20 {
            i as f64 / 20.0
        } else {
            0.85 + (i - 20) as f64 * 0.025
        };
        let delay = full.mul_f64(frac);
        let mut child = audit()
            .current_dir(root)
            .args(["check", "rigs", "--write-baseline", "out/B.json"])
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let pid = child.id();
        std::thread::sleep(delay);
        let _ = child.kill(); // SIGKILL; no-op if it already finished
        let _ = child.wait();
        let now = std::fs::read(out.join("B.json")).expect("baseline must exist");
        if now == old {
            saw_old += 1;
        } else if now == new {
            saw_new += 1;
        } else {
            panic!(
                "kill {i} after {delay:?}: baseline is neither old nor new ({} bytes)",
                now.len()
            );
        }
        let _: serde_json::Value = serde_json::from_slice(&now).expect("baseline parses");
        // The killed process's own temporary may remain; nothing else may.
        let left = others(&out, &["B.json"]);
        assert!(left.len() <= 1, "kill {i} (pid {pid}): {left:?}");
        for p in left {
            assert!(is_temporary(&p), "stray file after kill {i}: {p:?}");
            temps += 1;
            std::fs::remove_file(&p).unwrap();
        }
        // Back to the old state for the next round.
        std::fs::write(out.join("B.json"), &old).unwrap();
    }
    eprintln!("30 timed kills: {saw_old} left the old baseline, {saw_new} the new one, {temps} left their temporary");
    assert!(saw_old > 0, "no kill landed before the rename");

    // Kills aimed at the write itself: poll for the process's temporary and
    // kill it the moment it appears (between create and rename).
    let mut mid_write = 0;
    for i in 0..10 {
        let mut child = audit()
            .current_dir(root)
            .args(["check", "rigs", "--write-baseline", "out/B.json"])
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let t = Instant::now();
        let mut seen = false;
        while t.elapsed() < full * 20 {
            if !others(&out, &["B.json"]).is_empty() {
                seen = true;
                break;
            }
            if child.try_wait().unwrap().is_some() {
                break;
            }
            std::hint::spin_loop();
        }
        let _ = child.kill();
        let _ = child.wait();
        let now = std::fs::read(out.join("B.json")).unwrap();
        assert!(
            now == old || now == new,
            "aimed kill {i}: baseline is neither old nor new"
        );
        if seen && now == old {
            mid_write += 1;
        }
        let left = others(&out, &["B.json"]);
        assert!(left.len() <= 1, "aimed kill {i}: {left:?}");
        for p in left {
            assert!(is_temporary(&p), "stray file after aimed kill {i}: {p:?}");
            std::fs::remove_file(&p).unwrap();
        }
        std::fs::write(out.join("B.json"), &old).unwrap();
    }
    eprintln!("10 aimed kills: {mid_write} landed mid-write and left the old baseline");
    assert!(
        mid_write > 0,
        "no aimed kill landed between create and rename"
    );
}

#[test]
fn failed_rename_keeps_old_state_and_removes_temporary() {
    let tmp = tempfile::tempdir().unwrap();
    let root = tmp.path();
    copy_dir(Path::new("calibrations"), &root.join("rigs"));
    // The target is an existing, non-empty directory: refused before anything
    // is written (rename(2) over a directory, the failure after the temporary
    // exists, is `write_atomic_library`'s case).
    std::fs::create_dir_all(root.join("B.json/inside")).unwrap();
    std::fs::write(root.join("B.json/inside/keep.txt"), "keep").unwrap();
    let before = others(root, &[]);
    let o = audit()
        .current_dir(root)
        .args(["check", "rigs", "--write-baseline", "B.json"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("B.json"), "message names the file: {err}");
    assert!(err.contains("refused, nothing written"), "{err}");
    assert_eq!(
        std::fs::read_to_string(root.join("B.json/inside/keep.txt")).unwrap(),
        "keep"
    );
    assert_eq!(others(root, &[]), before, "temporary left behind");

    // The target's directory does not exist: exit 2 naming the file.
    let o = audit()
        .current_dir(root)
        .args(["check", "rigs", "--write-baseline", "no/such/dir/B.json"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("no/such/dir/B.json"), "{err}");
}

#[test]
fn write_atomic_library() {
    let tmp = tempfile::tempdir().unwrap();
    let p = tmp.path().join("b.json");
    std::fs::write(&p, "old").unwrap();
    write_atomic(&p, b"new").unwrap();
    assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
    assert_eq!(others(tmp.path(), &["b.json"]), Vec::<PathBuf>::new());
    // Over a directory: an error naming the file; the directory and nothing else.
    let d = tmp.path().join("d");
    std::fs::create_dir_all(d.join("x")).unwrap();
    let e = write_atomic(&d, b"new").unwrap_err().to_string();
    assert!(e.contains("cannot write") && e.contains('d'), "{e}");
    assert!(d.join("x").is_dir());
    assert_eq!(others(tmp.path(), &["b.json", "d"]), Vec::<PathBuf>::new());
    // A file at the name the writer once used (`.NAME.tmp.PID`) is never
    // opened: the temporary's name is random and created exclusively.
    let stale = tmp
        .path()
        .join(format!(".b.json.tmp.{}", std::process::id()));
    std::fs::write(&stale, "x".repeat(10_000)).unwrap();
    write_atomic(&p, b"fresh").unwrap();
    assert_eq!(std::fs::read_to_string(&p).unwrap(), "fresh");
    assert_eq!(std::fs::read_to_string(&stale).unwrap(), "x".repeat(10_000));
    // A relative path with no directory part writes into the current directory
    // (not exercised here: tests share the process's working directory).
}
