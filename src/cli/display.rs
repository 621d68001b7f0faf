//! The display options every command takes (`--color`, `--wide`, `--columns`)
//! and what they resolve to: the colour of standard output and standard error,
//! and the layout of terminal tables (the terminal's width, `COLUMNS` first;
//! no width when standard output is not a terminal, so a pipe gets the full
//! machine-friendly table).

use clap::Args;
use extrinsic_audit::internals::render::layout::{wrap, MIN_TERMINAL_WIDTH};
use extrinsic_audit::internals::render::{ColorChoice, Style};
use extrinsic_audit::{Progress, ProgressFactory, RenderOptions};
use std::io::IsTerminal;
use std::sync::OnceLock;

#[derive(Debug, Args, Clone, Default)]
pub struct DisplayArgs {
    /// Colour: auto (on a terminal, unless NO_COLOR is set), always, never
    #[arg(long, value_enum, global = true, default_value_t = ColorChoice::Auto, value_name = "WHEN")]
    pub color: ColorChoice,
    /// Every column of every table (a terminal otherwise shows a compact set
    /// when the full table does not fit its width)
    #[arg(long, global = true)]
    pub wide: bool,
    /// Only these table columns, by header (comma-separated, unit optional:
    /// `id,lever arm,metric`)
    #[arg(long, global = true, value_delimiter = ',', value_name = "LIST")]
    pub columns: Vec<String>,
}

static DISPLAY: OnceLock<DisplayArgs> = OnceLock::new();

/// Record the display options of this run (once, before any output).
pub fn set(args: DisplayArgs) {
    let _ = DISPLAY.set(args);
}

fn args() -> DisplayArgs {
    DISPLAY.get().cloned().unwrap_or_default()
}

/// The style of standard output.
pub fn stdout_style() -> Style {
    Style::chosen(args().color, std::io::stdout().is_terminal())
}

/// The style of standard error.
pub fn stderr_style() -> Style {
    Style::chosen(args().color, std::io::stderr().is_terminal())
}

/// How standard output is written: its colour, and the terminal's width
/// (`COLUMNS` when set to a number, else the terminal's own, else 80), none
/// when not a terminal.
pub fn stdout_options() -> RenderOptions {
    let a = args();
    let mut opts = RenderOptions::default();
    opts.color = stdout_style().color;
    opts.width = std::io::stdout().is_terminal().then(terminal_width);
    opts.wide = a.wide;
    opts.columns = a.columns;
    opts.cwd = std::env::current_dir().ok();
    opts
}

/// How an output file (`--output`) is written: as a pipe gets it, every
/// column and no colour unless `--color always`.
pub fn file_options() -> RenderOptions {
    let a = args();
    let mut opts = RenderOptions::default();
    opts.color = Style::chosen(a.color, false).color;
    opts.wide = a.wide;
    opts.columns = a.columns;
    opts.cwd = std::env::current_dir().ok();
    opts
}

fn terminal_width() -> usize {
    let env = std::env::var("COLUMNS")
        .ok()
        .and_then(|c| c.trim().parse::<usize>().ok())
        .filter(|&c| c > 0);
    env.or_else(|| terminal_size::terminal_size().map(|(w, _)| usize::from(w.0)))
        .unwrap_or(80)
}

/// A line for standard error, wrapped to the terminal (continuation lines
/// indented) when standard error is one.
pub fn stderr_fit(line: &str) -> String {
    if !std::io::stderr().is_terminal() {
        return line.to_string();
    }
    let w = terminal_width().max(MIN_TERMINAL_WIDTH);
    let lines = wrap(line, w);
    match lines.split_first() {
        Some((first, rest)) if !rest.is_empty() => {
            let rest = wrap(&format!("    {}", rest.join(" ")), w);
            format!("{first}\n{}", rest.join("\n"))
        }
        _ => line.to_string(),
    }
}

/// A progress bar on standard error, drawn only when standard error is a
/// terminal (a pipe, a file or CI logs get nothing), and only from `start`,
/// when its length is known: a bar made visible before would first draw a
/// full `0/0` (issue 33).
pub struct TermProgress {
    bar: indicatif::ProgressBar,
    terminal: bool,
}

impl TermProgress {
    pub fn new() -> Self {
        let bar = indicatif::ProgressBar::hidden();
        let style =
            indicatif::ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} ({eta} left)")
                .map(|s| s.progress_chars("=> "));
        if let Ok(style) = style {
            bar.set_style(style);
        }
        TermProgress {
            bar,
            terminal: std::io::stderr().is_terminal(),
        }
    }
}

impl Progress for TermProgress {
    fn start(&self, total: u64, what: &str) {
        self.bar.set_message(what.to_string());
        self.bar.set_length(total);
        if self.terminal {
            self.bar
                .set_draw_target(indicatif::ProgressDrawTarget::stderr());
        }
    }
    fn advance(&self, n: u64) {
        self.bar.inc(n);
    }
    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// A [`TermProgress`] for each piece of work the library reports.
pub struct TermBars;

impl ProgressFactory for TermBars {
    fn progress(&self) -> Box<dyn Progress> {
        Box::new(TermProgress::new())
    }
}
