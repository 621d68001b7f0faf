//! `extrinsic_audit._native`: the library's face for Python, wrapped as thin
//! as it goes. Each function takes the options as keyword arguments already
//! checked for type by the Python layer (`python/extrinsic_audit/`), runs
//! the library with the GIL released (everything but the sub-millisecond
//! calls: `frames`, `transform`), and hands back the report as its JSON (the
//! CLI's `--format json`, byte for byte) with the warnings as tuples; the
//! Python layer turns those into typed reports, `warnings.warn` calls and
//! `AuditError` exceptions (`diag`).

mod cli;
mod detector;
mod diag;
mod files;
mod robot;
mod run;

use pyo3::prelude::*;

/// The native module: two classes (`Robot`, `Run`) and the functions of the
/// face.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<robot::PyRobot>()?;
    m.add_class::<run::PyRun>()?;
    m.add_function(wrap_pyfunction!(robot::load, m)?)?;
    m.add_function(wrap_pyfunction!(files::check, m)?)?;
    m.add_function(wrap_pyfunction!(files::diff, m)?)?;
    m.add_function(wrap_pyfunction!(files::survey, m)?)?;
    m.add_function(wrap_pyfunction!(detector::degeneracy, m)?)?;
    m.add_function(wrap_pyfunction!(detector::degeneracy_scan, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(cli::cli_main, m)?)?;
    Ok(())
}
