//! Rendering: the one output path. Every report reaches a format through
//! [`render`]: JSON is the report itself, serialised in the one envelope
//! (`json.rs`); every other format draws the report's
//! [`Document`](crate::document::Document) ([`document`]): text, markdown,
//! GitHub workflow commands, CSV and SARIF from its blocks, and the pictures
//! from its picture block: DOT, Mermaid and SVG from a graph (`graph/`), SVG
//! from a plot (`plot.rs`). A format that cannot draw a document (a picture
//! of a report without one, SARIF without findings, CSV of a picture) is a
//! usage error naming the formats that can, never other output.
//!
//! This module imports the document layer and never `report`: a renderer
//! knows blocks, not report types.

mod csv;
mod github;
mod graph;
mod json;
pub mod layout;
mod markdown;
mod plot;
mod sarif;
mod style;
mod text;

pub use layout::Layout;
pub use style::{ColorChoice, Style};

use crate::diagnostic::{Error, Result, Warning};
use crate::document::{Block, Document, Report, Table};

/// The output formats every command takes (`--format`); a report refuses
/// those it cannot be drawn in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum OutputFormat {
    /// Tables for a terminal (the default; `text` is the same).
    #[default]
    #[value(alias = "text")]
    Table,
    /// GitHub-flavoured markdown (pull-request comments, job summaries; the
    /// frame tree as a Mermaid block).
    Markdown,
    /// The report as JSON (schemas in docs/schemas).
    Json,
    /// GitHub workflow commands for the diagnostics, then the text.
    Github,
    /// The data tables as CSV.
    Csv,
    /// SARIF 2.1.0 for GitHub code scanning (the diagnostics only).
    Sarif,
    /// The frame tree (--frames) as a Graphviz DOT digraph.
    Dot,
    /// The frame tree (--frames) as a Mermaid flowchart.
    Mermaid,
    /// The frame tree (--frames) as an SVG picture (drawn by audit, no
    /// Graphviz needed).
    Svg,
}

impl OutputFormat {
    /// Every format, in the order `--help` lists them.
    pub const ALL: [OutputFormat; 9] = [
        OutputFormat::Table,
        OutputFormat::Markdown,
        OutputFormat::Json,
        OutputFormat::Github,
        OutputFormat::Csv,
        OutputFormat::Sarif,
        OutputFormat::Dot,
        OutputFormat::Mermaid,
        OutputFormat::Svg,
    ];

    /// The name `--format` takes (`text` for the table, its alias).
    pub fn name(self) -> &'static str {
        match self {
            OutputFormat::Table => "text",
            OutputFormat::Markdown => "markdown",
            OutputFormat::Json => "json",
            OutputFormat::Github => "github",
            OutputFormat::Csv => "csv",
            OutputFormat::Sarif => "sarif",
            OutputFormat::Dot => "dot",
            OutputFormat::Mermaid => "mermaid",
            OutputFormat::Svg => "svg",
        }
    }

    /// Whether this format can draw `doc` (JSON: any report, from the report
    /// itself). A picture is drawn by the picture formats and written as
    /// text; a chart only as SVG.
    pub fn draws(self, doc: &Document) -> bool {
        let picture = picture(doc);
        match self {
            OutputFormat::Json => true,
            OutputFormat::Table | OutputFormat::Markdown => {
                !matches!(picture, Some(Block::Plot(_)))
            }
            OutputFormat::Github | OutputFormat::Csv => picture.is_none(),
            OutputFormat::Sarif => doc
                .blocks
                .iter()
                .any(|b| matches!(b, Block::Diagnostics(_))),
            OutputFormat::Dot | OutputFormat::Mermaid => {
                matches!(picture, Some(Block::Graph(_)))
            }
            OutputFormat::Svg => picture.is_some(),
        }
    }
}

/// The document's picture: its first graph or plot block.
fn picture(doc: &Document) -> Option<&Block> {
    doc.blocks
        .iter()
        .find(|b| matches!(b, Block::Graph(_) | Block::Plot(_)))
}

/// Render a report in a format: JSON carrying `warnings` (already printed on
/// standard error), the other formats drawn from its document; `style`
/// colours terminal text, `layout` fits it to the terminal (`--columns`
/// naming no column of the report is a usage error).
pub fn render<R: Report>(
    report: &R,
    warnings: &[Warning],
    format: OutputFormat,
    style: Style,
    layout: &Layout,
) -> Result<String> {
    match format {
        OutputFormat::Json => json::render(report, warnings),
        _ => document(&report.document(), format, style, layout),
    }
}

/// Draw a document in a format (every format but JSON, which is the report
/// itself): the text formats from its blocks, the pictures from its picture.
pub fn document(
    doc: &Document,
    format: OutputFormat,
    style: Style,
    layout: &Layout,
) -> Result<String> {
    if format == OutputFormat::Json || !format.draws(doc) {
        return Err(refusal(format, doc));
    }
    let picture = picture(doc);
    Ok(match (format, picture) {
        (OutputFormat::Table, _) => {
            // A picture has no columns: --columns applies to the tables.
            if !layout.columns.is_empty() && picture.is_none() {
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
            text::render_laid(doc, style, layout)
        }
        (OutputFormat::Markdown, _) => markdown::render(doc),
        (OutputFormat::Github, _) => github::render(doc),
        (OutputFormat::Csv, _) => csv::render(doc),
        (OutputFormat::Sarif, _) => sarif::render(doc),
        (OutputFormat::Dot, Some(Block::Graph(g))) => graph::dot(g),
        (OutputFormat::Mermaid, Some(Block::Graph(g))) => graph::mermaid(g),
        (OutputFormat::Svg, Some(Block::Graph(g))) => graph::svg(g),
        (OutputFormat::Svg, Some(Block::Plot(p))) => plot::svg(p)?,
        _ => return Err(refusal(format, doc)),
    })
}

/// A format that cannot draw `doc`: a usage error saying what the format is
/// for, what it found instead, and which formats draw this document.
fn refusal(format: OutputFormat, doc: &Document) -> Error {
    let picture = picture(doc);
    let found = match picture {
        Some(Block::Graph(_)) => "a picture (the frame tree)",
        Some(_) => "a chart (drawn as SVG only)",
        None => "a report without one",
    };
    let (does, expected) = match format {
        OutputFormat::Table | OutputFormat::Markdown => ("writes a report as text", "a report"),
        OutputFormat::Json => ("is the report itself", "a report"),
        OutputFormat::Github => ("annotates a report's findings for GitHub", "a report"),
        OutputFormat::Csv => ("writes a report's tables", "tables"),
        OutputFormat::Sarif => ("lists the findings of `audit check`", "findings"),
        OutputFormat::Dot | OutputFormat::Mermaid | OutputFormat::Svg => (
            "draws the frame tree (`audit FILE... --frames`)",
            "a picture",
        ),
    };
    let takes: Vec<&str> = OutputFormat::ALL
        .into_iter()
        .filter(|f| f.draws(doc))
        .map(OutputFormat::name)
        .collect();
    Error::usage(format!(
        "--format {} {does}; expected {expected}, found {found}: this report takes {}",
        format.name(),
        one_of(&takes)
    ))
}

/// `a, b or c`.
fn one_of(names: &[&str]) -> String {
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        Some((last, _)) => last.to_string(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::{Graph, Plot};

    fn of(block: Block) -> Document {
        let mut d = Document::new();
        d.text("a paragraph").push(block);
        d
    }

    /// Which format draws which kind of document: tables (every report but
    /// two), findings (the check), a graph (the frame tree), a plot (the
    /// survey plot).
    #[test]
    fn each_format_draws_the_documents_it_can() {
        let docs = [
            of(Block::Table(Table::new(&["a"], vec![]))),
            of(Block::Diagnostics(vec![])),
            of(Block::Graph(Graph::default())),
            of(Block::Plot(Plot {
                size_px: (10, 10),
                panels: vec![],
            })),
        ];
        let takes = |d: &Document| -> String {
            let t: Vec<&str> = OutputFormat::ALL
                .into_iter()
                .filter(|f| f.draws(d))
                .map(OutputFormat::name)
                .collect();
            t.join(" ")
        };
        assert_eq!(takes(&docs[0]), "text markdown json github csv");
        assert_eq!(takes(&docs[1]), "text markdown json github csv sarif");
        assert_eq!(takes(&docs[2]), "text markdown json dot mermaid svg");
        assert_eq!(takes(&docs[3]), "json svg");
        let e = document(
            &docs[0],
            OutputFormat::Dot,
            Style::plain(),
            &Layout::default(),
        );
        let msg = e.unwrap_err().to_string();
        assert!(
            msg.ends_with("this report takes text, markdown, json, github or csv"),
            "{msg}"
        );
        // JSON is the report itself: a bare document has none.
        assert!(document(
            &docs[2],
            OutputFormat::Json,
            Style::plain(),
            &Layout::default()
        )
        .is_err());
    }

    #[test]
    fn lists_read_as_prose() {
        assert_eq!(one_of(&["a", "b", "c"]), "a, b or c");
        assert_eq!(one_of(&["a"]), "a");
    }
}
