//! Helpers for the hostile-input tests: run the binary with a time limit and
//! capture what it printed.

use std::io::Read;
use std::path::PathBuf;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

#[derive(Debug)]
pub struct Output {
    /// `None` when the process was killed by a signal (abort, stack overflow).
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

/// Wait for `c` at most `limit`; kill it and return `None` past that.
pub fn wait_timeout(c: &mut Child, limit: Duration) -> Option<ExitStatus> {
    let t = Instant::now();
    loop {
        if let Some(s) = c.try_wait().expect("wait") {
            return Some(s);
        }
        if t.elapsed() > limit {
            let _ = c.kill();
            let _ = c.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Run `audit ARGS` with `NO_COLOR` and an empty PATH (no xacro); panic when it
/// takes more than `secs` seconds or dies of a signal / panic (101).
pub fn run_audit(args: &[&str], secs: u64) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_audit"))
        .args(args)
        .env("NO_COLOR", "1")
        .env("PATH", "")
        .env("RUST_BACKTRACE", "0")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn audit");
    let mut so = c.stdout.take().unwrap();
    let mut se = c.stderr.take().unwrap();
    let ho = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = so.read_to_end(&mut s);
        s
    });
    let he = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = se.read_to_end(&mut s);
        s
    });
    let status = wait_timeout(&mut c, Duration::from_secs(secs));
    let stdout = String::from_utf8_lossy(&ho.join().unwrap()).into_owned();
    let stderr = String::from_utf8_lossy(&he.join().unwrap()).into_owned();
    let status = status.unwrap_or_else(|| panic!("audit {args:?} ran longer than {secs} s"));
    let code = status.code();
    assert!(
        code.is_some(),
        "audit {args:?} was killed by a signal (abort / stack overflow?): {status:?}\n{stderr}"
    );
    assert_ne!(code, Some(101), "audit {args:?} panicked:\n{stderr}");
    Output {
        code,
        stdout,
        stderr,
    }
}

pub fn write_tmp(dir: &tempfile::TempDir, name: &str, text: &str) -> PathBuf {
    let p = dir.path().join(name);
    std::fs::write(&p, text).expect("write");
    p
}

/// Slack on [`assert_quick`]'s bound: these are guards against a hang or a
/// blow-up (an alias bomb expanded, a quadratic parse), not speed targets (those
/// live in BENCHMARKS.md); a debug build on a loaded 2-core CI machine runs
/// several times slower than the `secs` an idle machine needs.
const HANG_GUARD_SLACK: u64 = 10;

/// The work started at `t` ended within `secs` (times [`HANG_GUARD_SLACK`]).
pub fn assert_quick(t: Instant, secs: u64, what: &str) {
    let e = t.elapsed();
    let bound = secs * HANG_GUARD_SLACK;
    assert!(
        e < Duration::from_secs(bound),
        "{what}: took {e:?}, expected well under {bound} s (a hang or a blow-up)"
    );
}
