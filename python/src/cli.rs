//! The `audit` command of the wheel: the binary's own command line
//! (../src/main.rs and ../src/cli/, compiled here as they are there), run on
//! the arguments the console script passes (`sys.argv`).

#[allow(dead_code)]
#[path = "../../src/main.rs"]
mod audit_main;

use pyo3::prelude::*;

/// Run `audit` on `argv` (the program's name first); returns the exit code.
/// The GIL is released: the command may run long and prints by itself.
#[pyfunction(name = "_cli_main")]
pub fn cli_main(py: Python<'_>, argv: Vec<std::ffi::OsString>) -> u8 {
    py.detach(|| audit_main::main_with(argv))
}
