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

/// Wait for `c` at most `limit` of wall time; kill it and return `None` past
/// that. With the exit status comes the CPU time the child used (user +
/// system, from `wait4`'s rusage of that one child), which a loaded machine
/// does not inflate the way it inflates wall time.
pub fn wait_timeout(c: &mut Child, limit: Duration) -> Option<(ExitStatus, Duration)> {
    use std::os::unix::process::ExitStatusExt;
    let pid = c.id() as libc::pid_t;
    let t = Instant::now();
    let mut status: libc::c_int = 0;
    // SAFETY: an all-zero rusage is a valid value to be overwritten.
    let mut ru: libc::rusage = unsafe { std::mem::zeroed() };
    loop {
        // SAFETY: `pid` is our own unreaped child (std reaps only in wait /
        // try_wait, which are not called on it); the pointers are valid.
        let r = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut ru) };
        assert!(r >= 0, "wait4: {}", std::io::Error::last_os_error());
        if r == pid {
            let tv = |t: libc::timeval| {
                Duration::from_secs(t.tv_sec as u64) + Duration::from_micros(t.tv_usec as u64)
            };
            return Some((
                ExitStatus::from_raw(status),
                tv(ru.ru_utime) + tv(ru.ru_stime),
            ));
        }
        if t.elapsed() > limit {
            let _ = c.kill();
            // SAFETY: as above; reaps the killed child.
            unsafe { libc::wait4(pid, &mut status, 0, &mut ru) };
            return None;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Run `audit ARGS` with `NO_COLOR` and an empty PATH (no xacro); panic when it
/// uses more than `secs` seconds of CPU time or dies of a signal / panic
/// (101). A hang (a child blocked, or spinning) is killed after
/// [`HANG_GUARD_SLACK`] times `secs` of wall time.
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
    let wall = secs * HANG_GUARD_SLACK;
    let status = wait_timeout(&mut c, Duration::from_secs(wall));
    let stdout = String::from_utf8_lossy(&ho.join().unwrap()).into_owned();
    let stderr = String::from_utf8_lossy(&he.join().unwrap()).into_owned();
    let (status, cpu) =
        status.unwrap_or_else(|| panic!("audit {args:?} still ran after {wall} s: a hang"));
    assert!(
        cpu < Duration::from_secs(secs),
        "audit {args:?} used {cpu:?} of CPU time, expected well under {secs} s (a blow-up)"
    );
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

/// Wall time a hung child is given, in multiples of its CPU-time bound: these
/// are guards against a hang or a blow-up (an alias bomb expanded, a quadratic
/// parse), not speed targets (those live in BENCHMARKS.md). What they assert
/// is CPU time, which a loaded 2-core CI machine does not inflate; the wall
/// bound only stops a child that would never end.
const HANG_GUARD_SLACK: u64 = 10;

/// CPU time (s) the calling thread has used: the clock of the in-process hang
/// guards ([`cpu_now`], [`assert_quick`]), blind to other processes' load.
fn thread_cpu_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec.
    let r = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(r, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID)");
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// The start of an in-process hang guard: this thread's CPU time now.
#[derive(Clone, Copy)]
pub struct CpuStart(f64);

pub fn cpu_now() -> CpuStart {
    CpuStart(thread_cpu_seconds())
}

/// The work this thread did since `t` took less than `secs` of CPU time (its
/// own CPU time: other tests and other processes do not count, so load cannot
/// fail it; an in-process hang never returns here and is cargo's to report).
pub fn assert_quick(t: CpuStart, secs: u64, what: &str) {
    let e = thread_cpu_seconds() - t.0;
    assert!(
        e < secs as f64,
        "{what}: used {e:.2} s of CPU time, expected well under {secs} s (a hang or a blow-up)"
    );
}
