//! Rendering: the one output path. Every report reaches a format through
//! [`render`]: JSON is the report itself, serialised in the one envelope
//! (`json.rs`); every other format draws the report's [`Document`]
//! ([`draw`]): text, markdown, GitHub workflow commands, CSV and SARIF
//! from its blocks, and the pictures from its picture block: DOT, Mermaid
//! and SVG from a graph (`graph/`), SVG from a plot (`plot.rs`); MCAP
//! from its 3D scene block (`mcap/`, binary, through [`render_bytes`]). A
//! format that cannot draw a document (a picture of a report without one, SARIF
//! without findings, CSV of a picture) is a usage error naming the formats
//! that can, never other output.
//!
//! This module imports the document layer and never `report`: a renderer
//! knows blocks, not report types.

mod csv;
mod github;
mod graph;
mod json;
mod labels;
pub mod layout;
mod markdown;
pub mod mcap;
mod plot;
mod sarif;
mod style;
mod text;

pub use csv::line as csv_line;
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
    /// GitHub-flavoured markdown (pull requests, job summaries; a Mermaid
    /// frame tree).
    Markdown,
    /// The report as JSON (schemas in docs/schemas).
    Json,
    /// GitHub workflow commands for the diagnostics, then the text.
    Github,
    /// The report's data table as CSV: one tidy table, a row per
    /// observation, a number per cell (README "CSV").
    Csv,
    /// SARIF 2.1.0 for GitHub code scanning (the diagnostics only).
    Sarif,
    /// The frame tree (--frames) as a Graphviz DOT digraph.
    Dot,
    /// The frame tree (--frames) as a Mermaid flowchart.
    Mermaid,
    /// The frame tree (--frames) as SVG (drawn by audit, no Graphviz needed).
    Svg,
    /// The 3D scene as MCAP for Foxglove (rig, frame tree, degeneracy; binary:
    /// with --output FILE.mcap or to a pipe).
    Mcap,
}

/// What a format needs of a document to draw it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Needs {
    /// Any report (JSON: the report itself, not its document).
    Report,
    /// Any document but a chart (a graph is written as its text form).
    NoChart,
    /// A document without a picture.
    NoPicture,
    /// A data table (CSV: the one tidy table a report declares).
    Data,
    /// Findings (a diagnostics block).
    Findings,
    /// A graph.
    Graph,
    /// A graph or a chart.
    Picture,
    /// A 3D scene.
    Scene,
}

/// What the picture formats do.
const FRAME_TREE: &str = "draws the frame tree (`audit FILE... --frames`)";

impl OutputFormat {
    /// The format's row: its name in messages (`text` for the table, its
    /// alias), what it does and what it expected (for a refusal), and what it
    /// needs of a document.
    fn spec(self) -> (&'static str, &'static str, &'static str, Needs) {
        match self {
            OutputFormat::Table => (
                "text",
                "writes a report as text",
                "a report",
                Needs::NoChart,
            ),
            OutputFormat::Markdown => (
                "markdown",
                "writes a report as text",
                "a report",
                Needs::NoChart,
            ),
            OutputFormat::Json => ("json", "is the report itself", "a report", Needs::Report),
            OutputFormat::Github => (
                "github",
                "annotates a report's findings for GitHub",
                "a report",
                Needs::NoPicture,
            ),
            OutputFormat::Csv => (
                "csv",
                "writes a report's data table (one row per observation)",
                "a data table",
                Needs::Data,
            ),
            OutputFormat::Sarif => (
                "sarif",
                "lists the findings of `audit check`",
                "findings",
                Needs::Findings,
            ),
            OutputFormat::Dot => ("dot", FRAME_TREE, "a picture", Needs::Graph),
            OutputFormat::Mermaid => ("mermaid", FRAME_TREE, "a picture", Needs::Graph),
            OutputFormat::Svg => ("svg", FRAME_TREE, "a picture", Needs::Picture),
            OutputFormat::Mcap => (
                "mcap",
                "writes a 3D scene for Foxglove (a rig, the frame tree, `audit degeneracy`)",
                "a scene",
                Needs::Scene,
            ),
        }
    }

    /// The name `--format` takes (`text` for the table, its alias).
    pub fn name(self) -> &'static str {
        let (name, ..) = self.spec();
        name
    }

    /// Whether this format can draw `doc` (JSON: any report, from the report
    /// itself). A graph is drawn by the picture formats and written as text;
    /// a chart only as SVG.
    pub fn draws(self, doc: &Document) -> bool {
        let (.., needs) = self.spec();
        let picture = picture(doc);
        match needs {
            Needs::Report => true,
            Needs::NoChart => !matches!(picture, Some(Block::Plot(_))),
            Needs::NoPicture => picture.is_none(),
            Needs::Data => doc
                .blocks
                .iter()
                .any(|b| matches!(b, Block::Table(t) if t.data_only)),
            Needs::Findings => doc
                .blocks
                .iter()
                .any(|b| matches!(b, Block::Diagnostics(_))),
            Needs::Graph => matches!(picture, Some(Block::Graph(_))),
            Needs::Picture => picture.is_some(),
            Needs::Scene => scene(doc).is_some(),
        }
    }

    /// Whether the format is binary (never written to a terminal).
    pub fn is_binary(self) -> bool {
        self == OutputFormat::Mcap
    }

    /// Every format, in the order `--help` lists them.
    fn all() -> &'static [OutputFormat] {
        <OutputFormat as clap::ValueEnum>::value_variants()
    }
}

/// The document's picture: its first graph or plot block.
fn picture(doc: &Document) -> Option<&Block> {
    doc.blocks
        .iter()
        .find(|b| matches!(b, Block::Graph(_) | Block::Plot(_)))
}

/// The document's 3D scene: its first scene block.
fn scene(doc: &Document) -> Option<&crate::document::Scene> {
    doc.blocks.iter().find_map(|b| match b {
        Block::Scene(s) => Some(s),
        _ => None,
    })
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
        _ => draw(&report.document(), format, style, layout),
    }
}

/// [`render`] as bytes, for every format: the binary ones (MCAP) written
/// whole, the others as their UTF-8 text.
pub fn render_bytes<R: Report>(
    report: &R,
    warnings: &[Warning],
    format: OutputFormat,
    style: Style,
    layout: &Layout,
) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    render_to(report, warnings, format, style, layout, &mut out)?;
    Ok(out)
}

/// [`render`] written to `out`, for every format; JSON is written as it is
/// serialised (a survey of a fleet is never held as text), MCAP as its
/// binary file.
pub fn render_to<R: Report>(
    report: &R,
    warnings: &[Warning],
    format: OutputFormat,
    style: Style,
    layout: &Layout,
    out: &mut dyn std::io::Write,
) -> Result<()> {
    match format {
        OutputFormat::Json => json::write(report, warnings, out),
        OutputFormat::Mcap => {
            let doc = report.document();
            let bytes = match scene(&doc) {
                Some(s) => mcap::write(s)?,
                None => return Err(refusal(format, &doc)),
            };
            out.write_all(&bytes).map_err(cannot)
        }
        _ => {
            let mut w = std::io::BufWriter::new(out);
            draw_to(&report.document(), format, style, layout, &mut w)?;
            std::io::Write::flush(&mut w).map_err(cannot)
        }
    }
}

/// Draw a document in a text format (every format but JSON, which is the
/// report itself, and MCAP, which is binary: `render_to`): the text
/// formats from its blocks, the pictures from its picture.
pub fn draw(doc: &Document, format: OutputFormat, style: Style, layout: &Layout) -> Result<String> {
    let mut out = Vec::new();
    draw_to(doc, format, style, layout, &mut out)?;
    String::from_utf8(out).map_err(cannot)
}

/// [`draw`] written to `out`: text, markdown and CSV as they are made (a
/// streamed table a row at a time, issue 29), the other formats whole.
pub fn draw_to(
    doc: &Document,
    format: OutputFormat,
    style: Style,
    layout: &Layout,
    out: &mut dyn std::io::Write,
) -> Result<()> {
    let picture = picture(doc);
    let graph = || match picture {
        Some(Block::Graph(g)) => Ok(g),
        _ => Err(refusal(format, doc)),
    };
    if !format.draws(doc) {
        return Err(refusal(format, doc));
    }
    let text = match format {
        OutputFormat::Table => {
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
            return text::write_laid(doc, style, layout, out).map_err(cannot);
        }
        OutputFormat::Markdown => return markdown::write(doc, out).map_err(cannot),
        OutputFormat::Json => return Err(refusal(format, doc)),
        OutputFormat::Mcap => {
            return Err(Error::usage(
                "--format mcap is binary: it is rendered as bytes (render_bytes)",
            ))
        }
        OutputFormat::Github => github::render(doc),
        OutputFormat::Csv => return csv::write(doc, out).map_err(cannot),
        OutputFormat::Sarif => sarif::render(doc),
        OutputFormat::Dot => graph::dot(graph()?),
        OutputFormat::Mermaid => graph::mermaid(graph()?),
        OutputFormat::Svg => match picture {
            Some(Block::Plot(p)) => plot::svg(p)?,
            _ => graph::svg(graph()?),
        },
    };
    out.write_all(text.as_bytes()).map_err(cannot)
}

/// The one error for output that cannot be written (an I/O error, or text
/// that is not UTF-8).
fn cannot(e: impl std::fmt::Display) -> Error {
    Error::new(
        crate::diagnostic::Code::Io,
        format!("cannot write output: {e}"),
    )
}

/// A format that cannot draw `doc`: a usage error saying what the format is
/// for, what it found instead, and which formats draw this document.
fn refusal(format: OutputFormat, doc: &Document) -> Error {
    let found = match picture(doc) {
        Some(Block::Graph(_)) => "a picture (the frame tree)",
        Some(_) => "a chart (drawn as SVG only)",
        None => "a report without one",
    };
    let (name, does, expected, _) = format.spec();
    let takes: Vec<&str> = OutputFormat::all()
        .iter()
        .filter(|f| f.draws(doc))
        .map(|f| f.name())
        .collect();
    Error::usage(format!(
        "--format {name} {does}; expected {expected}, found {found}: this report takes {}",
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
    use crate::document::{Graph, Plot, Scene};

    fn of(block: Block) -> Document {
        let mut d = Document::new();
        d.text("a paragraph").push(block);
        d
    }

    /// Which format draws which kind of document: a data table (every report
    /// but the frame tree and the survey plot), findings (the check), a graph (the frame tree), a plot (the
    /// survey plot).
    #[test]
    fn each_format_draws_the_documents_it_can() {
        let docs = [
            of(Block::Table(Table {
                data_only: true,
                ..Table::new(&["a"], vec![])
            })),
            of(Block::Diagnostics(vec![])),
            of(Block::Graph(Graph::default())),
            of(Block::Plot(Plot {
                size_px: (10, 10),
                panels: vec![],
                rows: 1,
            })),
            of(Block::Scene(Scene::default())),
        ];
        let takes = |d: &Document| -> String {
            let t: Vec<&str> = OutputFormat::all()
                .iter()
                .filter(|f| f.draws(d))
                .map(|f| f.name())
                .collect();
            t.join(" ")
        };
        assert_eq!(takes(&docs[0]), "text markdown json github csv");
        // CSV is a data table's: findings alone have none.
        assert_eq!(takes(&docs[1]), "text markdown json github sarif");
        assert_eq!(takes(&docs[2]), "text markdown json dot mermaid svg");
        assert_eq!(takes(&docs[3]), "json svg");
        // A scene goes with the text formats, and is drawn only as MCAP.
        assert_eq!(takes(&docs[4]), "text markdown json github mcap");
        assert!(draw(
            &docs[4],
            OutputFormat::Mcap,
            Style::plain(),
            &Layout::default()
        )
        .is_err());
        let e = draw(
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
        assert!(draw(
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
