//! Rendering: every report becomes a [`Document`] of blocks (headline, sections,
//! tables, text, diagnostics), and one renderer per output format turns a
//! document into text. JSON is the report itself, serialised.
//!
//! Adding an output format: a variant of [`OutputFormat`], its file in this
//! directory with `fn render(&Document, Style) -> String`, and one arm in
//! [`render`].

mod csv;
mod document;
mod github;
pub mod layout;
mod markdown;
pub mod numbers;
mod sarif;
mod style;
mod text;

pub use document::{Block, Document, Table};
pub use layout::Layout;
pub use style::{ColorChoice, Style};

use crate::diagnostic::{Code, Error, Result};
use serde::Serialize;

/// The output formats every command takes (`--format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum OutputFormat {
    /// Tables for a terminal (the default; `text` is the same).
    #[default]
    #[value(alias = "text")]
    Table,
    /// GitHub-flavoured markdown (pull-request comments, job summaries).
    Markdown,
    /// The report as JSON (schemas in docs/schemas).
    Json,
    /// GitHub workflow commands for the diagnostics, then the text.
    Github,
    /// The data tables as CSV.
    Csv,
    /// SARIF 2.1.0 for GitHub code scanning (the diagnostics only).
    Sarif,
}

/// A typed report: serialised for JSON, laid out as a document for the rest.
pub trait Report: Serialize {
    /// The report laid out for people.
    fn document(&self) -> Document;
}

/// Render a report in a format; `style` colours terminal text. Tables have
/// every column and no wrapping (see [`render_laid`] for a terminal).
pub fn render<R: Report>(report: &R, format: OutputFormat, style: Style) -> Result<String> {
    render_laid(report, format, style, &Layout::default())
}

/// Render a report in a format, terminal text fitted to `layout`
/// (`--columns` naming no column of the report is a usage error).
pub fn render_laid<R: Report>(
    report: &R,
    format: OutputFormat,
    style: Style,
    layout: &Layout,
) -> Result<String> {
    Ok(match format {
        OutputFormat::Json => {
            let mut s = serde_json::to_string_pretty(report).map_err(|e| {
                Error::new(
                    Code::Io,
                    format!("cannot serialise the report as JSON: {e}"),
                )
            })?;
            s.push('\n');
            s
        }
        OutputFormat::Table => {
            let doc = report.document();
            if !layout.columns.is_empty() {
                let tables: Vec<&Table> = doc
                    .blocks
                    .iter()
                    .filter_map(|b| match b {
                        Block::Table(t) if !t.data_only => Some(t),
                        _ => None,
                    })
                    .collect();
                layout::check_columns(&tables, &layout.columns)?;
            }
            text::render_laid(&doc, style, layout)
        }
        OutputFormat::Markdown => markdown::render(&report.document()),
        OutputFormat::Github => github::render(&report.document()),
        OutputFormat::Csv => csv::render(&report.document()),
        OutputFormat::Sarif => sarif::render(&report.document()),
    })
}
