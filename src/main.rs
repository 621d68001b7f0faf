//! `audit`: thin front end; everything lives in the library (`extrinsic_audit::cli`).

use std::process::ExitCode;

fn main() -> ExitCode {
    extrinsic_audit::cli::main()
}
