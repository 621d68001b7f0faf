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
pub mod run;
pub mod spread;
pub mod survey;

use args::OutputArgs;
use extrinsic_audit::internals::pipeline;
use extrinsic_audit::internals::sanitize;
use extrinsic_audit::{
    render_bytes, render_to, Code, Error, OutputFormat, Report, Result, Warning,
};
use std::io::{IsTerminal, Write};
use std::path::PathBuf;

/// Render `report` as `output` asks (`--format`, `--output`) to `out` or
/// the output file; `inputs` are the files the command read (never written
/// over).
pub fn emit<R: Report>(
    report: &R,
    output: &OutputArgs,
    inputs: &[PathBuf],
    out: &mut dyn Write,
) -> Result<()> {
    emit_warned(report, &[], output, inputs, out)
}

/// [`emit`], the JSON carrying `warnings` (already printed on stderr). Every
/// report, the frame tree included, reaches standard output or its
/// `--output` file here: a file through the atomic writer, after the check
/// that it is none of `inputs`; a binary format never to a terminal.
pub fn emit_warned<R: Report>(
    report: &R,
    warnings: &[Warning],
    output: &OutputArgs,
    inputs: &[PathBuf],
    out: &mut dyn Write,
) -> Result<()> {
    let format = output.format;
    if let Some(path) = &output.output {
        pipeline::check_output_target("--output", "command", path, inputs)?;
        let mut opts = display::file_options();
        opts.warnings = warnings.to_vec();
        let bytes = render_bytes(report, format, &opts)?;
        return pipeline::write_atomic(path, &bytes);
    }
    if format.is_binary() && std::io::stdout().is_terminal() {
        return Err(Error::usage(format!(
            "--format {} is binary: refusing to write it to a terminal; give --output FILE.{0} or redirect standard output",
            format.name()
        )));
    }
    let mut opts = display::stdout_options();
    opts.color &= format == OutputFormat::Table;
    opts.warnings = warnings.to_vec();
    let mut pipe = Pipe { out, closed: false };
    let written = render_to(report, format, &opts, &mut pipe).and_then(|()| {
        pipe.flush()
            .map_err(|e| Error::new(Code::Io, format!("cannot write output: {e}")))
    });
    if pipe.closed {
        // `audit ... | head -1`: the reader asked for no more; status 0.
        std::process::exit(0);
    }
    written
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

/// Check `--output` before a command does its work (the write checks again).
pub fn check_output(output: &OutputArgs, inputs: &[PathBuf]) -> Result<()> {
    match &output.output {
        Some(path) => pipeline::check_output_target("--output", "command", path, inputs),
        None => Ok(()),
    }
}

/// Standard output as the renderers write it, noting a closed pipe.
struct Pipe<'a> {
    out: &'a mut dyn Write,
    closed: bool,
}

impl Write for Pipe<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let r = self.out.write(buf);
        self.closed |= matches!(&r, Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe);
        r
    }
    fn flush(&mut self) -> std::io::Result<()> {
        let r = self.out.flush();
        self.closed |= matches!(&r, Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe);
        r
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
        to_stderr(&display::stderr_fit(&format!(
            "note: {}",
            sanitize::line(n)
        )));
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
