//! Issue 12: a closed standard output (`audit ... | head -1`) ends the process
//! quietly with status 0, also when standard error goes to the same pipe.

use std::os::fd::{FromRawFd, OwnedFd};
use std::process::{Command, Stdio};

const FORMATS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/formats");

/// A pipe whose reading end is already closed: its writing end.
fn closed_pipe() -> OwnedFd {
    let mut fds = [0; 2];
    // SAFETY: `pipe` fills two new descriptors that nothing else owns.
    let rc = unsafe { libc::pipe(fds.as_mut_ptr()) };
    assert_eq!(rc, 0, "pipe");
    // SAFETY: both descriptors are fresh and owned here only.
    let (r, w) = unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
    drop(r);
    w
}

/// Exit status of `audit ARGS` writing into a closed pipe (stderr too when
/// `merged`, else stderr captured and returned).
fn into_closed_pipe(args: &[&str], merged: bool) -> (Option<i32>, String) {
    let w = closed_pipe();
    let mut c = Command::new(env!("CARGO_BIN_EXE_audit"));
    c.args(args).env("NO_COLOR", "1").stdin(Stdio::null());
    c.stdout(Stdio::from(w.try_clone().unwrap()));
    if merged {
        c.stderr(Stdio::from(w));
    } else {
        drop(w);
        c.stderr(Stdio::piped());
    }
    let out = c.output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_closed_stdout_ends_quietly_with_status_zero() {
    let urdf = format!("{FORMATS}/warthog_expanded.urdf");
    let cal = concat!(env!("CARGO_MANIFEST_DIR"), "/calibrations");
    let cases: [&[&str]; 4] = [
        &[&urdf, "--frames"],
        &[&urdf, "--from", "base_link", "--to", "mti10"],
        &["survey", cal, "--format", "markdown"],
        &["tunnel", "--format", "json"],
    ];
    for args in cases {
        let (code, err) = into_closed_pipe(args, false);
        assert_eq!(code, Some(0), "{args:?}: {err}");
        assert!(
            !err.contains("pipe") && !err.contains("error"),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn a_closed_pipe_for_stdout_and_stderr_is_not_a_panic() {
    // LIO-SAM's parameters give two warnings on stderr before the report.
    let f = crate::real!(crate::common::testdata::LIOSAM_PARAMS);
    let f = f.to_str().unwrap();
    let (code, _) = into_closed_pipe(&[f, "--from", "lidar", "--to", "imu"], true);
    assert_eq!(code, Some(0));
    // An error on a closed stderr still exits 2, without a panic (101).
    let (code, _) = into_closed_pipe(&["/nonexistent.yaml"], true);
    assert_eq!(code, Some(2));
}

#[test]
fn piping_into_head_prints_one_line_and_succeeds() {
    let cal = concat!(env!("CARGO_MANIFEST_DIR"), "/calibrations");
    let out = Command::new("bash")
        .arg("-c")
        .arg(format!(
            "\"$0\" survey {cal} 2>&1 | head -1; echo \"status=${{PIPESTATUS[0]}}\"",
        ))
        .arg(env!("CARGO_BIN_EXE_audit"))
        .output()
        .unwrap();
    let so = String::from_utf8_lossy(&out.stdout);
    assert_eq!(so.lines().count(), 2, "{so}");
    assert!(!so.contains("Broken pipe"), "{so}");
    assert!(so.ends_with("status=0\n"), "{so}");
}
