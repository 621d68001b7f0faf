//! Terminal styling: colour only on a terminal and never when `NO_COLOR` is set.

use std::io::IsTerminal;

/// `--color`: when to colour terminal output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum ColorChoice {
    /// On a terminal, unless `NO_COLOR` is set.
    #[default]
    Auto,
    /// Always (also into a pipe or a file).
    Always,
    /// Never.
    Never,
}

/// Whether to colour, and the ANSI sequences for the few styles used.
#[derive(Debug, Clone, Copy)]
pub struct Style {
    /// Colour on.
    pub color: bool,
}

impl Style {
    fn detect(is_tty: bool) -> Self {
        let no_color = std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty());
        Style {
            color: is_tty && !no_color,
        }
    }
    /// For standard output.
    pub fn stdout() -> Self {
        Self::detect(std::io::stdout().is_terminal())
    }
    /// For standard error.
    pub fn stderr() -> Self {
        Self::detect(std::io::stderr().is_terminal())
    }
    /// Colour as `--color` asks: `always` and `never` override the terminal
    /// and `NO_COLOR`; `auto` colours a terminal unless `NO_COLOR` is set.
    pub fn chosen(choice: ColorChoice, is_tty: bool) -> Self {
        match choice {
            ColorChoice::Always => Style { color: true },
            ColorChoice::Never => Style { color: false },
            ColorChoice::Auto => Self::detect(is_tty),
        }
    }
    /// No colour.
    pub fn plain() -> Self {
        Style { color: false }
    }
    fn paint(&self, code: &str, s: &str) -> String {
        if self.color {
            format!("\x1b[{code}m{s}\x1b[0m")
        } else {
            s.to_string()
        }
    }
    /// Bold (section titles).
    pub fn bold(&self, s: &str) -> String {
        self.paint("1", s)
    }
    /// Good news (green).
    pub fn good(&self, s: &str) -> String {
        self.paint("1;32", s)
    }
    /// A caution (yellow).
    pub fn bad(&self, s: &str) -> String {
        self.paint("1;33", s)
    }
    /// An error (red).
    pub fn error(&self, s: &str) -> String {
        self.paint("1;31", s)
    }
    /// Dim (conventions, notes).
    pub fn dim(&self, s: &str) -> String {
        self.paint("2", s)
    }
}
