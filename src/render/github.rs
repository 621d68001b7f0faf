//! GitHub workflow commands: each diagnostic becomes an `::error` or
//! `::warning` annotation on its file and line; the rest of the document is
//! printed as plain text (no colour) after the annotations' block.

use super::document::{Block, Document};
use super::{text, Style};
use crate::diagnostic::{Diagnostic, Severity};

/// Render a document for a GitHub Actions log.
pub fn render(doc: &Document) -> String {
    let mut s = String::new();
    let mut rest = Document::new();
    for b in &doc.blocks {
        match b {
            Block::Diagnostics(ds) => {
                for d in ds {
                    s.push_str(&annotation(d));
                }
            }
            other => {
                rest.push(other.clone());
            }
        }
    }
    s.push_str(&text::render(&rest, Style::plain()));
    s
}

/// One workflow command.
pub fn annotation(d: &Diagnostic) -> String {
    let kind = match d.severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
    };
    let mut props = Vec::new();
    if let Some(f) = &d.location.file {
        props.push(format!("file={}", escape(&f.display().to_string(), true)));
    }
    if let Some(l) = d.location.line {
        props.push(format!("line={l}"));
    }
    if let Some(c) = d.location.column {
        props.push(format!("col={c}"));
    }
    props.push(format!("title={}", escape(d.code.name(), true)));
    format!(
        "::{kind} {}::{}\n",
        props.join(","),
        escape(&d.message, false)
    )
}

/// Escape a workflow-command value (`%`, CR, LF; and in properties `:` `,`).
pub fn escape(s: &str, property: bool) -> String {
    let mut o = s
        .replace('%', "%25")
        .replace('\r', "%0D")
        .replace('\n', "%0A");
    if property {
        o = o.replace(':', "%3A").replace(',', "%2C");
    }
    o
}
