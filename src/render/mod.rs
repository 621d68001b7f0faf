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
pub mod layout;
mod markdown;
pub mod numbers;
pub mod plot;
mod sarif;
mod style;
mod text;

pub use document::{Block, Document, Table};
pub use layout::Layout;
pub use style::{ColorChoice, Style};

use crate::diagnostic::{Code, Error, Result, Warning};
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

/// The report as JSON, with `schema_version` first and a `warnings` array
/// last when the report has none of its own (every command's JSON carries
/// both): the warnings are given as their one-line text.
pub fn json<R: Serialize>(report: &R, warnings: &[Warning]) -> Result<String> {
    let err = |e: serde_json::Error| {
        Error::new(
            Code::Io,
            format!("cannot serialise the report as JSON: {e}"),
        )
    };
    let value = serde_json::to_value(report).map_err(err)?;
    let has = |k: &str| value.as_object().is_some_and(|o| o.contains_key(k));
    let lines: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    let envelope = Envelope {
        schema_version: (!has("schema_version")).then_some(crate::report::SCHEMA_VERSION),
        report,
        warnings: (!has("warnings")).then_some(&lines),
    };
    let mut s = if value.is_object() {
        serde_json::to_string_pretty(&envelope)
    } else {
        serde_json::to_string_pretty(report)
    }
    .map_err(err)?;
    s.push('\n');
    Ok(s)
}

#[derive(Serialize)]
struct Envelope<'a, R: Serialize> {
    #[serde(skip_serializing_if = "Option::is_none")]
    schema_version: Option<u32>,
    #[serde(flatten)]
    report: &'a R,
    #[serde(skip_serializing_if = "Option::is_none")]
    warnings: Option<&'a Vec<String>>,
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
        OutputFormat::Json => json(report, &[])?,
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
        OutputFormat::Sarif => {
            let doc = report.document();
            if !doc
                .blocks
                .iter()
                .any(|b| matches!(b, Block::Diagnostics(_)))
            {
                return Err(Error::usage(
                    "--format sarif lists the findings of `audit check`; expected a check, found a report without findings (use --format json)",
                ));
            }
            sarif::render(&doc)
        }
    })
}
