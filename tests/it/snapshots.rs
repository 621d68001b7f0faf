//! Snapshots (insta) of every command's text on pseudo-terminals of 80 and
//! 120 columns (`--color never`) and of its markdown (which does not depend
//! on the width). The snapshots live in tests/it/snapshots/; after an
//! intended change of the output, review them with
//! `INSTA_UPDATE=always cargo test --test it snapshots` and `git diff`.
//! Deterministic: paths are relative to the repository, no timings.

use crate::common::run_cli;
use crate::widths::{have_pty, pty_run, pty_run_stdout, COMMANDS};

#[test]
fn text_at_80_and_120_columns() {
    if !have_pty() {
        eprintln!("skipped: no `script` for a pseudo-terminal");
        return;
    }
    for cols in [80, 120] {
        for (name, args) in COMMANDS {
            let args = [args, &["--color", "never"]].concat();
            // The progress bar (drawn in time) is left out of the snapshot.
            let out = if ["calibrate-threshold", "check", "run"].contains(&name) {
                pty_run_stdout(cols, &args)
            } else {
                pty_run(cols, &args)
            };
            insta::assert_snapshot!(format!("{name}_text_{cols}"), out);
        }
    }
}

#[test]
fn markdown() {
    for (name, args) in COMMANDS {
        let args = [args, &["--format", "markdown"]].concat();
        let (code, out, err) = run_cli(&args);
        let shown = format!("exit {code}\n--- stdout\n{out}--- stderr\n{err}");
        insta::assert_snapshot!(format!("{name}_markdown"), shown);
    }
}
