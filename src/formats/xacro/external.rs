//! The explicit fallback (`--xacro external`): run the `xacro` program found
//! on the search path and read its output as URDF. Line numbers then refer to
//! xacro's printed output, not to the source files.
//!
//! The child is bounded like the built-in expander: it runs in its own
//! process group, killed with the group after [`XACRO_MAX_SECONDS`], or as
//! soon as it prints more than the file-size cap on stdout, or when it has
//! exited (a background process it left holding its output would otherwise
//! hang the reader); its stderr is kept whole up to
//! [`XACRO_MAX_STDERR_BYTES`] so the cause of a failure reaches the user
//! (xacro's last line is only "when processing file: X").

use super::markers::advice;
use crate::diagnostic::{Error, Result};
use crate::formats::spec::{LoadOptions, Parsed};
use crate::formats::urdf;
use crate::tolerances::{XACRO_EXTERNAL_DRAIN_SECONDS, XACRO_MAX_SECONDS, XACRO_MAX_STDERR_BYTES};
use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

fn find_on_path(prog: &str, search: Option<&std::ffi::OsStr>) -> Option<std::path::PathBuf> {
    let path = match search {
        Some(s) => s.to_os_string(),
        None => std::env::var_os("PATH")?,
    };
    std::env::split_paths(&path)
        .map(|d| d.join(prog))
        .find(|p| p.is_file())
}

/// What a bounded child run gave.
#[derive(Debug)]
struct Bounded {
    status: ExitStatus,
    stdout: Vec<u8>,
    /// Stderr, at most the cap, with the count of bytes cut.
    stderr: Vec<u8>,
    stderr_cut: u64,
}

/// Why a bounded run stopped the child.
#[derive(Debug, PartialEq)]
enum Stopped {
    Timeout,
    TooMuchOutput,
    /// The child exited but its output pipe stayed open (a process outside
    /// its group holds it).
    HeldOutput,
}

/// Reads `r` keeping at most `cap` bytes; returns them and the count beyond.
/// With `stop_at_cap` it stops reading at the cap (the caller kills the child).
fn read_capped(mut r: impl Read, cap: u64, stop_at_cap: bool) -> (Vec<u8>, u64) {
    let mut kept = Vec::new();
    let mut cut = 0u64;
    let mut buf = [0u8; 8192];
    loop {
        match r.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(n) => {
                let room = cap.saturating_sub(kept.len() as u64) as usize;
                kept.extend_from_slice(&buf[..n.min(room)]);
                cut += (n - n.min(room)) as u64;
                if cut > 0 && stop_at_cap {
                    break;
                }
            }
        }
    }
    (kept, cut)
}

/// The child's own process group (Unix), so that killing the group also
/// ends what it started in the background.
fn own_group(cmd: &mut Command) {
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        cmd.process_group(0);
    }
    #[cfg(not(unix))]
    let _ = cmd;
}

/// Kill the child and, on Unix, every process of its group (a background
/// process the child left holding its pipes); then reap the child.
fn kill_group(child: &mut Child) {
    #[cfg(unix)]
    if let Ok(pid) = i32::try_from(child.id()) {
        // SAFETY: kill(2) with a negative pid signals the process group the
        // child leads (its own, `own_group`); no memory is involved.
        unsafe {
            libc::kill(-pid, libc::SIGKILL);
        }
    }
    let _ = child.kill();
    let _ = child.wait();
}

/// Runs `cmd` with stdin closed, in its own process group, killing the group
/// after `timeout` or as soon as stdout passes `out_cap` bytes. Once the
/// child has exited its group is killed too, and its output is waited for
/// at most [`XACRO_EXTERNAL_DRAIN_SECONDS`] (a process outside the group
/// holding a pipe is given up on): nothing the child starts can hang the
/// run.
fn run_bounded(
    mut cmd: Command,
    timeout: Duration,
    out_cap: u64,
    err_cap: u64,
) -> std::io::Result<std::result::Result<Bounded, Stopped>> {
    own_group(&mut cmd);
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()?;
    let over = Arc::new(AtomicBool::new(false));
    let (tx_out, rx_out) = mpsc::channel();
    if let Some(o) = child.stdout.take() {
        let over = Arc::clone(&over);
        std::thread::spawn(move || {
            let (kept, cut) = read_capped(o, out_cap, true);
            over.store(cut > 0, Ordering::Release);
            let _ = tx_out.send(kept);
        });
    }
    let (tx_err, rx_err) = mpsc::channel();
    if let Some(e) = child.stderr.take() {
        std::thread::spawn(move || {
            let _ = tx_err.send(read_capped(e, err_cap, false));
        });
    }
    let start = Instant::now();
    let stopped = loop {
        if over.load(Ordering::Acquire) {
            break Stopped::TooMuchOutput;
        }
        if let Some(status) = child.try_wait()? {
            // Whatever it left running in its group goes with it.
            kill_group(&mut child);
            let drain = Duration::from_secs_f64(XACRO_EXTERNAL_DRAIN_SECONDS);
            let Ok(stdout) = rx_out.recv_timeout(drain) else {
                break Stopped::HeldOutput;
            };
            if over.load(Ordering::Acquire) {
                break Stopped::TooMuchOutput;
            }
            let (stderr, stderr_cut) = rx_err.recv_timeout(drain).unwrap_or_default();
            return Ok(Ok(Bounded {
                status,
                stdout,
                stderr,
                stderr_cut,
            }));
        }
        if start.elapsed() >= timeout {
            break Stopped::Timeout;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    // The reader threads see end-of-file once the pipes close; they are not
    // joined (a process outside the group may still hold a pipe open).
    kill_group(&mut child);
    Ok(Err(stopped))
}

/// Expand `path` with the external `xacro` program, passing `--arg`s as
/// `name:=value`.
pub fn parse(path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let Some(xacro) = find_on_path("xacro", opts.xacro_search_path.as_deref()) else {
        return Err(Error::parse(format!(
            "--xacro external: the `xacro` program is not on PATH ({})",
            advice(path)
        )));
    };
    let mut cmd = Command::new(&xacro);
    cmd.arg(path)
        .args(opts.xacro_args.iter().map(|(k, v)| format!("{k}:={v}")));
    let out = run_bounded(
        cmd,
        Duration::from_secs_f64(XACRO_MAX_SECONDS),
        opts.max_file_size,
        XACRO_MAX_STDERR_BYTES,
    )
    .map_err(|e| Error::parse(format!("running {}: {e}", xacro.display())))?;
    let out = match out {
        Ok(o) => o,
        Err(Stopped::Timeout) => {
            return Err(Error::limit(format!(
                "--xacro external: {} was still running after {XACRO_MAX_SECONDS} s: expected an expansion in milliseconds (a macro bomb?); stopped it",
                xacro.display()
            )))
        }
        Err(Stopped::HeldOutput) => {
            return Err(Error::limit(format!(
                "--xacro external: {} exited but its output stayed open (a process it started outside its process group holds it): stopped waiting after {XACRO_EXTERNAL_DRAIN_SECONDS} s",
                xacro.display()
            )))
        }
        Err(Stopped::TooMuchOutput) => {
            return Err(Error::limit(format!(
                "--xacro external: {} printed more than {} bytes: expected a URDF within the file-size cap (--max-file-size); stopped it",
                xacro.display(),
                opts.max_file_size
            )))
        }
    };
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let cut = match out.stderr_cut {
            0 => String::new(),
            n => format!(" [{n} more bytes of stderr cut]"),
        };
        return Err(Error::parse(format!(
            "xacro could not expand this file ({}); its stderr:\n{}{cut}",
            out.status,
            err.trim_end()
        )));
    }
    let expanded = String::from_utf8(out.stdout)
        .map_err(|_| Error::parse("xacro printed something that is not UTF-8"))?;
    let mut loaded = urdf::parse(&expanded, path, opts)?;
    for e in &mut loaded.edges {
        e.provenance.key = format!("{} (line in xacro's expanded output)", e.provenance.key);
    }
    Ok(loaded)
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    fn sh(script: &str) -> Command {
        let mut c = Command::new("sh");
        c.arg("-c").arg(script);
        c
    }

    #[test]
    fn a_child_that_runs_too_long_is_killed_at_the_limit() {
        let t = Instant::now();
        let r = run_bounded(sh("sleep 30"), Duration::from_millis(300), 1 << 20, 1 << 10);
        assert_eq!(r.expect("spawned").err(), Some(Stopped::Timeout));
        assert!(t.elapsed() < Duration::from_secs(5), "{:?}", t.elapsed());
    }

    #[test]
    fn a_child_that_prints_without_end_is_stopped_at_the_cap() {
        let t = Instant::now();
        let r = run_bounded(sh("yes"), Duration::from_secs(20), 1 << 16, 1 << 10);
        assert_eq!(r.expect("spawned").err(), Some(Stopped::TooMuchOutput));
        assert!(t.elapsed() < Duration::from_secs(5), "{:?}", t.elapsed());
    }

    #[test]
    fn the_whole_stderr_is_kept_up_to_its_cap() {
        let r = run_bounded(
            sh("echo cause >&2; echo 'when processing file: x' >&2; exit 3"),
            Duration::from_secs(20),
            1 << 16,
            1 << 10,
        )
        .expect("spawned")
        .expect("exited");
        assert_eq!(r.status.code(), Some(3));
        assert_eq!(r.stderr, b"cause\nwhen processing file: x\n");
        assert_eq!(r.stderr_cut, 0);
        let r = run_bounded(
            sh("head -c 5000 /dev/zero >&2"),
            Duration::from_secs(20),
            16,
            100,
        )
        .expect("spawned")
        .expect("exited");
        assert_eq!((r.stderr.len(), r.stderr_cut), (100, 4900));
    }

    /// A background process the child leaves holding its stdout does not
    /// hang the run, and is killed with the child's process group (at the
    /// child's exit, and at the time limit).
    #[test]
    fn a_background_process_holding_the_output_is_killed_with_the_group() {
        let dir = tempfile::tempdir().expect("tempdir");
        let pidfile = dir.path().join("bg.pid");
        // Alive: it exists and is not a zombie waiting for its new parent
        // (Linux's /proc; elsewhere, signal 0).
        let alive = |pidfile: &Path| {
            let pid: i32 = std::fs::read_to_string(pidfile)
                .expect("pid")
                .trim()
                .parse()
                .expect("int");
            match std::fs::read_to_string(format!("/proc/{pid}/stat")) {
                Ok(stat) => !stat
                    .rsplit(')')
                    .next()
                    .unwrap_or("")
                    .trim_start()
                    .starts_with('Z'),
                Err(_) if Path::new("/proc/self/stat").exists() => false,
                // SAFETY: signal 0 only checks that the process exists.
                Err(_) => unsafe { libc::kill(pid, 0) == 0 },
            }
        };
        let t = Instant::now();
        let script = format!("sleep 60 & echo $! > {}; printf ok", pidfile.display());
        let r = run_bounded(sh(&script), Duration::from_secs(20), 1 << 16, 1 << 10)
            .expect("spawned")
            .expect("exited");
        assert_eq!(r.stdout, b"ok");
        assert!(t.elapsed() < Duration::from_secs(5), "{:?}", t.elapsed());
        std::thread::sleep(Duration::from_millis(100));
        assert!(!alive(&pidfile), "the background sleep survived");
        let script = format!("sleep 60 & echo $! > {}; sleep 60", pidfile.display());
        let r = run_bounded(sh(&script), Duration::from_millis(300), 1 << 16, 1 << 10);
        assert_eq!(r.expect("spawned").err(), Some(Stopped::Timeout));
        std::thread::sleep(Duration::from_millis(100));
        assert!(
            !alive(&pidfile),
            "the background sleep survived the time limit"
        );
    }

    #[test]
    fn stdout_within_the_cap_is_kept_whole() {
        let r = run_bounded(sh("printf 'abc'"), Duration::from_secs(20), 3, 10)
            .expect("spawned")
            .expect("exited");
        assert_eq!(r.stdout, b"abc");
    }
}
