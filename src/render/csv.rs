//! CSV (RFC 4180, minimal quoting): the document's data tables, or its display
//! tables when it has none, separated by blank lines.

use crate::document::{Block, Document, Table};

/// Render a document's tables as CSV.
pub fn render(doc: &Document) -> String {
    let tables: Vec<&Table> = doc
        .blocks
        .iter()
        .filter_map(|b| match b {
            Block::Table(t) => Some(t),
            _ => None,
        })
        .collect();
    let data: Vec<&Table> = tables.iter().copied().filter(|t| t.data_only).collect();
    let chosen = if data.is_empty() { tables } else { data };
    chosen
        .iter()
        .map(|t| table(t))
        .collect::<Vec<_>>()
        .join("\n")
}

/// One table as CSV.
pub fn table(t: &Table) -> String {
    let mut s = line(&t.header);
    s.push('\n');
    for r in &t.rows {
        s.push_str(&line(r));
        s.push('\n');
    }
    s
}

/// One CSV record (no line end): cells quoted where they need it. A command
/// that streams its rows (`audit run`) writes them with this.
pub fn line(cells: &[String]) -> String {
    let q = |s: &str| {
        if s.contains([',', '"', '\n', '\r']) {
            format!("\"{}\"", s.replace('"', "\"\""))
        } else {
            s.to_string()
        }
    };
    cells.iter().map(|c| q(c)).collect::<Vec<_>>().join(",")
}
