//! Issue 12: only regular files are read, every read is bounded by the bytes
//! actually read. A FIFO, a device or a symlink to one is refused at once with
//! "not a regular file", naming it, in every command that reads files.

use crate::common::hostile::{run_audit, write_tmp, Output};
use std::path::{Path, PathBuf};

const FASTLIO: &str = "mapping:\n  extrinsic_T: [0.04165, 0.02326, -0.0284]\n  extrinsic_R: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n";

fn mkfifo(dir: &Path, name: &str) -> PathBuf {
    let p = dir.join(name);
    let st = std::process::Command::new("mkfifo")
        .arg(&p)
        .status()
        .expect("mkfifo");
    assert!(st.success(), "mkfifo {p:?}");
    p
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// Refused with exit 2 within one second, the message naming the file.
fn refused(o: &Output, name: &str) {
    assert_eq!(
        o.code,
        Some(2),
        "stdout:\n{}\nstderr:\n{}",
        o.stdout,
        o.stderr
    );
    let all = format!("{}{}", o.stdout, o.stderr);
    assert!(all.contains("not a regular file"), "{all}");
    assert!(all.contains(name), "{all}");
}

#[test]
fn audit_refuses_a_fifo() {
    let d = tempfile::tempdir().unwrap();
    let f = mkfifo(d.path(), "fifo.yaml");
    let o = run_audit(&[s(&f)], 1);
    refused(&o, "fifo.yaml");
    assert!(o.stderr.contains("a FIFO"), "{}", o.stderr);
}

#[test]
fn audit_refuses_dev_zero_and_a_symlink_to_dev_urandom() {
    let o = run_audit(&["/dev/zero"], 1);
    refused(&o, "/dev/zero");
    assert!(o.stderr.contains("a character device"), "{}", o.stderr);
    let d = tempfile::tempdir().unwrap();
    let z = d.path().join("z.yaml");
    std::os::unix::fs::symlink("/dev/urandom", &z).unwrap();
    refused(&run_audit(&[s(&z)], 1), "z.yaml");
}

#[test]
fn check_refuses_a_fifo_and_a_device_link_in_a_directory() {
    let d = tempfile::tempdir().unwrap();
    write_tmp(&d, "good.yaml", FASTLIO);
    mkfifo(d.path(), "fifo.yaml");
    refused(&run_audit(&["check", s(d.path())], 1), "fifo.yaml");

    let d2 = tempfile::tempdir().unwrap();
    write_tmp(&d2, "good.yaml", FASTLIO);
    std::os::unix::fs::symlink("/dev/zero", d2.path().join("z.yaml")).unwrap();
    refused(&run_audit(&["check", s(d2.path())], 1), "z.yaml");
}

#[test]
fn audit_refuses_a_socket() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("s.yaml");
    let _l = std::os::unix::net::UnixListener::bind(&p).unwrap();
    let o = run_audit(&[s(&p)], 1);
    refused(&o, "s.yaml");
    assert!(o.stderr.contains("a socket"), "{}", o.stderr);
}

#[test]
fn survey_refuses_a_fifo_in_a_directory() {
    let d = tempfile::tempdir().unwrap();
    mkfifo(d.path(), "rig.toml");
    refused(&run_audit(&["survey", s(d.path())], 1), "rig.toml");
}

#[test]
fn check_refuses_a_fifo_baseline() {
    let d = tempfile::tempdir().unwrap();
    let good = write_tmp(&d, "good.yaml", FASTLIO);
    let b = mkfifo(d.path(), "fifo.json");
    let o = run_audit(&["check", s(&good), "--baseline", s(&b)], 1);
    refused(&o, "fifo.json");
    let o = run_audit(&["check", s(&good), "--baseline", "/dev/zero"], 1);
    refused(&o, "/dev/zero");
}

#[test]
fn degeneracy_refuses_a_fifo_and_dev_zero() {
    let d = tempfile::tempdir().unwrap();
    let f = mkfifo(d.path(), "fifo");
    refused(&run_audit(&["degeneracy", s(&f)], 1), "fifo");
    refused(&run_audit(&["degeneracy", "/dev/zero"], 1), "/dev/zero");
}

#[test]
fn standard_input_is_read_for_one_file_and_bounded() {
    let out = crate::common::audit()
        .args(["-", "--format", "json"])
        .write_stdin(FASTLIO)
        .output()
        .unwrap();
    let so = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{so}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_str(&so).unwrap();
    assert_eq!(
        v["transform"]["translation_m"][0].as_f64(),
        Some(0.04165),
        "{v}"
    );

    let big = "#".repeat(5000) + "\n" + FASTLIO;
    let out = crate::common::audit()
        .args(["-", "--max-file-size", "1000"])
        .write_stdin(big)
        .output()
        .unwrap();
    let se = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{se}");
    assert!(se.contains("more than 1000 bytes"), "{se}");
}

/// `degeneracy --initial-guess-file` reads through the safe reader: a FIFO or
/// a device is refused at once (it was read to its end, waiting on a FIFO
/// forever), before either scan is read.
#[test]
fn degeneracy_refuses_a_fifo_or_a_device_as_the_initial_guess() {
    let d = tempfile::tempdir().unwrap();
    let f = mkfifo(d.path(), "guess.txt");
    for guess in [s(&f), "/dev/zero"] {
        let o = run_audit(
            &[
                "degeneracy",
                "source.pcd",
                "--target",
                "target.pcd",
                "--initial-guess-file",
                guess,
            ],
            1,
        );
        refused(&o, guess);
    }
}

/// `audit.toml` is read through the safe reader, bounded: a manifest over
/// its cap (1 MiB) is refused, naming it, instead of being read whole.
#[test]
fn check_refuses_an_oversized_manifest() {
    let d = tempfile::tempdir().unwrap();
    write_tmp(&d, "good.yaml", FASTLIO);
    let manifest = format!("# {}\n", "x".repeat(2 << 20));
    write_tmp(&d, "audit.toml", &manifest);
    let o = run_audit(&["check", s(d.path())], 1);
    assert_eq!(o.code, Some(2), "{}{}", o.stdout, o.stderr);
    assert!(o.stderr.contains("audit.toml"), "{}", o.stderr);
    assert!(
        o.stderr.contains("expected at most 1048576 bytes"),
        "{}",
        o.stderr
    );
}
