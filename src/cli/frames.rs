//! `audit FILE... --frames [--from A --to B] --format text|json|dot|mermaid|svg`:
//! the frame tree as text, JSON or a picture, the chain highlighted when asked.

use super::write_output;
use clap::ValueEnum;
use extrinsic_audit::diagnostic::{Code, Error, Result};
use extrinsic_audit::pipeline::Loaded;
use extrinsic_audit::render::{graph, OutputFormat};
use extrinsic_audit::report::frames::frames_report;
use extrinsic_audit::sanitize;
use std::io::Write;

/// `--format` of the rig report: the report formats, and the pictures of
/// `--frames`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum AuditFormat {
    /// Tables for a terminal (the default; `text` is the same).
    #[default]
    #[value(alias = "text")]
    Table,
    /// GitHub-flavoured markdown (with --frames: a Mermaid block).
    Markdown,
    /// The report as JSON (schemas in docs/schemas).
    Json,
    /// GitHub workflow commands for the diagnostics, then the text.
    Github,
    /// The data tables as CSV.
    Csv,
    /// SARIF 2.1.0 for GitHub code scanning (the diagnostics only).
    Sarif,
    /// With --frames: a Graphviz DOT digraph.
    Dot,
    /// With --frames: a Mermaid flowchart.
    Mermaid,
    /// With --frames: an SVG picture (drawn by audit, no Graphviz needed).
    Svg,
}

impl AuditFormat {
    /// The report format, or an error for a picture format without --frames.
    pub fn report_format(self) -> Result<OutputFormat> {
        Ok(match self {
            AuditFormat::Table => OutputFormat::Table,
            AuditFormat::Markdown => OutputFormat::Markdown,
            AuditFormat::Json => OutputFormat::Json,
            AuditFormat::Github => OutputFormat::Github,
            AuditFormat::Csv => OutputFormat::Csv,
            AuditFormat::Sarif => OutputFormat::Sarif,
            AuditFormat::Dot | AuditFormat::Mermaid | AuditFormat::Svg => {
                return Err(Error::usage(format!(
                    "--format {}: expected --frames with a picture format (the rig report takes text, markdown, json, github, csv or sarif)",
                    self.name()
                )))
            }
        })
    }

    fn name(self) -> String {
        self.to_possible_value()
            .map(|v| v.get_name().to_string())
            .unwrap_or_default()
    }
}

/// Print the frame tree of `loaded` in `format`, the `from` -> `to` chain
/// marked when both are given.
pub fn run(
    loaded: &Loaded,
    from: Option<&str>,
    to: Option<&str>,
    format: AuditFormat,
    out: &mut dyn Write,
) -> Result<i32> {
    let chain = match (from, to) {
        (Some(f), Some(t)) => Some(loaded.graph.transform(f, t)?),
        (None, None) => None,
        _ => {
            return Err(Error::usage(
                "--frames: give both --from and --to to highlight a chain, or neither",
            ))
        }
    };
    let rep = frames_report(&loaded.graph, chain.as_ref());
    let text = match format {
        // Names cannot hold a line break (refused when loaded); the rest of
        // what could act on a terminal or a CI log is escaped.
        AuditFormat::Table => {
            let mut t = sanitize::block(&rep.tree_text);
            // On a terminal a frame's place goes under it rather than past the width.
            if let Some(w) = super::display::stdout_layout().width() {
                t = extrinsic_audit::render::layout::fit_tree(&t, w);
            }
            if let Some(c) = &rep.chain {
                t.push_str(&format!(
                    "chain: {}\n",
                    sanitize::line(&c.path.join(" -> "))
                ));
            }
            t + "\n"
        }
        AuditFormat::Json => serde_json::to_string_pretty(&rep).map_err(|e| {
            Error::new(
                Code::Io,
                format!("cannot serialise the frames as JSON: {e}"),
            )
        })?,
        AuditFormat::Dot => graph::dot(&rep),
        AuditFormat::Mermaid => graph::mermaid(&rep),
        AuditFormat::Markdown => format!("```mermaid\n{}```\n", graph::mermaid(&rep)),
        AuditFormat::Svg => graph::svg(&rep),
        AuditFormat::Github | AuditFormat::Csv | AuditFormat::Sarif => {
            return Err(Error::usage(format!(
                "--frames --format {}: expected text, json, dot, mermaid, svg or markdown",
                format.name()
            )))
        }
    };
    let text = if text.ends_with('\n') {
        text
    } else {
        text + "\n"
    };
    write_output(out, &text)?;
    Ok(0)
}
