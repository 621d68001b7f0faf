//! Helpers shared by the test modules.

#![allow(dead_code)] // each module uses some of the helpers

pub mod hostile;
pub mod schema;

/// The `audit` binary with `NO_COLOR` set: the one command builder of the suite.
pub fn audit() -> assert_cmd::Command {
    let mut c = assert_cmd::Command::cargo_bin("audit").expect("binary");
    c.env("NO_COLOR", "1");
    c
}

/// Run `audit ARGS`: (exit code, stdout, stderr).
pub fn run_cli(args: &[&str]) -> (i32, String, String) {
    let out = audit().args(args).output().expect("run");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
