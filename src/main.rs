//! `audit`: the command-line front end of extrinsic-audit. Arguments and
//! output live in `cli`; everything else is the library's.

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    cli::main()
}
