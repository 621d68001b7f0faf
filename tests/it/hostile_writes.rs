//! Issue 27, data loss through planted files: nothing a pull request commits
//! (a symlink at a name the writer might use, at the target, or in place of
//! the target's directory; a hard link to an input; a path spelt with `..`)
//! makes a write land outside the declared output or over an input, and no
//! write leaves its temporary behind, an interruption included. Every file
//! the tool writes goes through `pipeline::write_atomic`: `--write-baseline`
//! and `survey --plot` are tested through the binary, the primitive itself
//! through the library.

#![cfg(unix)]

use crate::check_gate::run_in;
use extrinsic_audit::internals::pipeline::write_atomic;
use std::os::unix::fs::symlink;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const CALIBRATION: &str = "calibrations/fastlio-avia.toml";

/// Every entry under `dir` with its bytes (a link as its target's name).
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let m = std::fs::symlink_metadata(&p).unwrap();
        if m.file_type().is_symlink() {
            let to = std::fs::read_link(&p).unwrap();
            out.push((p, to.into_os_string().into_encoded_bytes()));
        } else if m.is_dir() {
            out.extend(snapshot(&p));
        } else {
            out.push((p.clone(), std::fs::read(&p).unwrap()));
        }
    }
    out.sort();
    out
}

/// A tree with `cal/rig.toml` (a calibration), `outside/victim.txt` (a file
/// no command may touch) and an empty `out/`.
fn tree() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().to_path_buf();
    for d in ["cal", "outside", "out"] {
        std::fs::create_dir(root.join(d)).unwrap();
    }
    std::fs::copy(CALIBRATION, root.join("cal/rig.toml")).unwrap();
    std::fs::write(root.join("outside/victim.txt"), "precious").unwrap();
    (dir, root)
}

/// Each `(command line, reason)` in `root`: exit 2 with the reason on
/// standard error, and not a byte or link under `root` changed.
fn refused(root: &Path, cases: &[(&str, &str)]) {
    let before = snapshot(root);
    for (line, why) in cases {
        let args: Vec<&str> = line.split(' ').collect();
        let (code, out, err) = run_in(root, &args);
        assert_eq!(code, 2, "{line}: {out}{err}");
        assert!(err.contains(why), "{line}: {err}");
        assert_eq!(snapshot(root), before, "{line} touched a file");
    }
}

#[test]
fn planted_links_never_steer_a_write() {
    let (_d, root) = tree();
    let victim = root.join("outside/victim.txt");

    // Library: links at the name the writer once used (`.NAME.tmp.PID`) and
    // at the target itself.
    let out = root.join("out");
    let old_name = out.join(format!(".b.json.tmp.{}", std::process::id()));
    symlink(&victim, &old_name).unwrap();
    write_atomic(&out.join("b.json"), b"new").unwrap();
    assert_eq!(std::fs::read_to_string(out.join("b.json")).unwrap(), "new");
    symlink(&victim, out.join("link.json")).unwrap();
    let e = write_atomic(&out.join("link.json"), b"new").unwrap_err();
    assert!(
        e.to_string().contains("link.json") && e.message.contains("symlink"),
        "{e}"
    );
    assert_eq!(std::fs::read_link(out.join("link.json")).unwrap(), victim);
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    assert_eq!(std::fs::read_link(&old_name).unwrap(), victim);

    // The binary: a baseline whose name or directory is a link, a plot
    // whose name or directory is a link. Nothing anywhere changes.
    std::fs::write(
        root.join("outside/B.json"),
        "{\"schema_version\": 1, \"files\": {}}\n",
    )
    .unwrap();
    symlink(root.join("outside/B.json"), root.join("B.json")).unwrap();
    symlink(root.join("outside"), root.join("ci")).unwrap();
    symlink(&victim, root.join("p.svg")).unwrap();
    refused(
        &root,
        &[
            ("check cal --write-baseline B.json", "is a symlink (to "),
            (
                "check cal --write-baseline ci/new.json",
                "ci is a symlink inside the current directory",
            ),
            (
                "check cal --write-baseline ./ci/../ci/B.json",
                "is a symlink inside",
            ),
            ("survey cal --plot p.svg", "is a symlink (to "),
            ("survey cal --plot ci/p.svg", "is a symlink inside"),
        ],
    );
    // A link outside the current directory is the operator's layout: followed.
    let (code, out, err) = run_in(
        &root.join("cal"),
        &["check", ".", "--write-baseline", "../ci/new.json"],
    );
    assert_eq!(code, 0, "{out}{err}");
    assert!(root.join("outside/new.json").is_file());
}

#[test]
fn no_spelling_of_an_input_is_written() {
    let (_d, root) = tree();
    std::fs::hard_link(root.join("cal/rig.toml"), root.join("out/hard.json")).unwrap();
    std::fs::hard_link(root.join("cal/rig.toml"), root.join("out/hard.svg")).unwrap();
    std::fs::copy(CALIBRATION, root.join("cal/odd.svg")).unwrap();
    std::fs::create_dir(root.join("cal/sub")).unwrap();
    refused(
        &root,
        &[
            (
                "check cal --write-baseline cal/../cal/rig.toml",
                "one of the checked calibration files",
            ),
            (
                "check cal --write-baseline ./cal//sub/../rig.toml",
                "one of the checked calibration files",
            ),
            (
                "check cal/rig.toml --write-baseline out/hard.json",
                "one of the checked calibration files",
            ),
            (
                "check cal --write-baseline out/hard.json",
                "one of the checked calibration files",
            ),
            (
                "survey cal/rig.toml --plot out/hard.svg",
                "input of the survey",
            ),
            ("survey cal --plot out/hard.svg", "hard links"),
            (
                "survey cal/odd.svg --plot cal/sub/../odd.svg",
                "input of the survey",
            ),
        ],
    );
}

#[test]
fn new_files_get_the_mode_file_create_gives() {
    use std::os::unix::fs::PermissionsExt;
    let (_d, root) = tree();
    let (code, out, err) = run_in(&root, &["check", "cal", "--write-baseline", "out/B.json"]);
    assert_eq!(code, 0, "{out}{err}");
    std::fs::File::create(root.join("out/plain")).unwrap();
    let mode = |p: &str| {
        std::fs::metadata(root.join(p))
            .unwrap()
            .permissions()
            .mode()
            & 0o777
    };
    assert_eq!(mode("out/B.json"), mode("out/plain"));
}

fn spawn_write(root: &Path) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_audit"))
        .current_dir(root)
        .args(["check", "big", "--write-baseline", "out/B.json"])
        .env("NO_COLOR", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

/// SIGTERM and SIGINT sent the moment the temporary appears (between its
/// creation and the rename): the process dies of the signal, the baseline is
/// the old or the new one, and the temporary is gone. (SIGKILL, which
/// nothing can catch, is `hostile_atomic`'s case.)
#[test]
fn interrupted_writes_leave_no_temporary() {
    use std::os::unix::process::ExitStatusExt;
    let (_d, root) = tree();
    for i in 0..10 {
        let to = root.join(format!("big/c{i}"));
        std::fs::create_dir_all(&to).unwrap();
        for e in std::fs::read_dir("calibrations").unwrap() {
            let p = e.unwrap().path();
            if p.is_file() {
                std::fs::copy(&p, to.join(p.file_name().unwrap())).unwrap();
            }
        }
    }
    let (code, _, err) = run_in(&root, &["check", "cal", "--write-baseline", "out/B.json"]);
    assert!(code <= 1, "{err}");
    let old = std::fs::read(root.join("out/B.json")).unwrap();
    let (mut caught, mut new) = (0, 0);
    for (k, sig) in [libc::SIGTERM, libc::SIGINT]
        .into_iter()
        .cycle()
        .take(10)
        .enumerate()
    {
        let mut child = spawn_write(&root);
        let t = Instant::now();
        let (mut seen, mut exited) = (false, None);
        while t.elapsed() < Duration::from_secs(120) {
            if std::fs::read_dir(root.join("out")).unwrap().count() > 1 {
                seen = true;
                break;
            }
            exited = child.try_wait().unwrap();
            if exited.is_some() {
                break;
            }
            std::hint::spin_loop();
        }
        let status = match exited {
            Some(s) => s,
            None => {
                // SAFETY: kill(2) of our own child, not yet waited for.
                unsafe { libc::kill(child.id() as libc::pid_t, sig) };
                child.wait().unwrap()
            }
        };
        let now = std::fs::read(root.join("out/B.json")).unwrap();
        let left: Vec<_> = std::fs::read_dir(root.join("out"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left, ["B.json"], "round {k}: the temporary was left");
        if now == old {
            assert!(
                seen,
                "round {k}: never saw the temporary, yet no new baseline"
            );
            assert_eq!(status.signal(), Some(sig), "round {k}: {status:?}");
            caught += 1;
        } else {
            serde_json::from_slice::<serde_json::Value>(&now).expect("the new baseline is whole");
            new += 1;
            std::fs::write(root.join("out/B.json"), &old).unwrap();
        }
    }
    eprintln!("10 signals aimed at the write: {caught} landed before the rename, {new} after it");
    assert!(caught > 0, "no signal landed between create and rename");
}
