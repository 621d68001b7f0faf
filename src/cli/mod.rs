//! The commands' arguments and the output. Each command module parses its
//! arguments, calls the library, and renders the typed report it gets back
//! with `extrinsic_audit::render` (through [`emit`]); the flags several
//! commands share are declared once, in `args`. The command tree and the
//! dispatch are in `main.rs`.

pub mod args;
pub mod audit;
pub mod check;
pub mod detector;
pub mod diff;
pub mod display;
mod frames;
pub mod survey;

use extrinsic_audit::internals::sanitize;
use extrinsic_audit::{render, Code, Error, OutputFormat, Report, Result, Warning};
use std::io::Write;

/// Render `report` in `format` to `out` (colour for tables on a terminal).
pub fn emit<R: Report>(report: &R, format: OutputFormat, out: &mut dyn Write) -> Result<()> {
    emit_warned(report, &[], format, out)
}

/// [`emit`], the JSON carrying `warnings` (already printed on stderr). Every
/// report, the frame tree included, reaches standard output here.
pub fn emit_warned<R: Report>(
    report: &R,
    warnings: &[Warning],
    format: OutputFormat,
    out: &mut dyn Write,
) -> Result<()> {
    let mut opts = display::stdout_options();
    opts.color &= format == OutputFormat::Table;
    opts.warnings = warnings.to_vec();
    write_output(out, &render(report, format, &opts)?)
}

/// `--strict`: warnings (already printed) stop the command, an error naming
/// their codes.
pub fn deny_warnings(strict: bool, warnings: &[Warning]) -> Result<()> {
    if !strict || warnings.is_empty() {
        return Ok(());
    }
    let mut codes: Vec<&str> = warnings.iter().map(|w| w.code.name()).collect();
    codes.sort_unstable();
    codes.dedup();
    Err(Error::new(
        Code::WarningsDenied,
        format!(
            "--strict: expected no warnings, found {} ({})",
            warnings.len(),
            codes.join(", ")
        ),
    ))
}

/// Write `text` to standard output. A closed pipe (`audit ... | head -1`) ends
/// the process quietly with status 0, as `head` asked for no more.
fn write_output(out: &mut dyn Write, text: &str) -> Result<()> {
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => Err(Error::new(Code::Io, format!("cannot write output: {e}"))),
    }
}

/// One line to standard error; a closed standard error is ignored (the
/// process must not panic, as `eprintln!` does).
fn to_stderr(line: &str) {
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}

/// Print warnings to stderr, one per line, with their names (escaped: a
/// warning quotes names from files).
pub fn print_warnings(warnings: &[Warning]) {
    let st = display::stderr_style();
    for w in warnings {
        let text = display::stderr_fit(&sanitize::line(&w.to_string()));
        match text.split_once(": ") {
            Some((head, rest)) => to_stderr(&format!("{}: {rest}", st.bad(head))),
            None => to_stderr(&st.bad(&text)),
        }
    }
}

/// Notes (a redundant edge that agrees, the path a chain used) to stderr.
pub fn print_notes(notes: &[String]) {
    for n in notes {
        to_stderr(&format!("note: {}", sanitize::line(n)));
    }
}

/// An error that stopped a command, on standard error: `error: ...`, escaped
/// (messages quote names from files) and wrapped to the terminal.
pub fn print_error(e: &Error) {
    let msg = sanitize::line(&e.to_string());
    let line = display::stderr_fit(&format!("error: {msg}"));
    let rest = line.strip_prefix("error:").unwrap_or(&line);
    to_stderr(&format!(
        "{}:{rest}",
        display::stderr_style().error("error")
    ));
}
