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
pub mod graph;
mod markdown;
pub mod numbers;
pub mod plot;
mod sarif;
mod style;
mod text;

pub use document::{Block, Document, Table};
pub use style::Style;

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

/// Render a report in a format; `style` colours terminal text.
pub fn render<R: Report>(report: &R, format: OutputFormat, style: Style) -> Result<String> {
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
        OutputFormat::Table => text::render(&report.document(), style),
        OutputFormat::Markdown => markdown::render(&report.document()),
        OutputFormat::Github => github::render(&report.document()),
        OutputFormat::Csv => csv::render(&report.document()),
        OutputFormat::Sarif => sarif::render(&report.document()),
    })
}
