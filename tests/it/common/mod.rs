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
