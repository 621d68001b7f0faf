//! GitHub-flavoured markdown: `###` sections, pipe tables with `|` escaped, a
//! blank line before every paragraph so that none is read as a table row.

use super::document::{Block, Document, Table};
use crate::diagnostic::{Diagnostic, Severity};

/// Render a document as markdown.
pub fn render(doc: &Document) -> String {
    let mut s = String::new();
    for b in &doc.blocks {
        match b {
            Block::Headline { text, .. } => {
                s.push_str(&format!("**{text}**\n"));
            }
            Block::Section(t) => s.push_str(&format!("\n### {t}\n\n")),
            Block::Note { markdown, .. } => {
                if let Some(m) = markdown {
                    s.push_str(m);
                    s.push_str("\n\n");
                }
            }
            Block::Text(t) => {
                paragraph_break(&mut s);
                let lines: Vec<String> = t.lines().map(escape_line_start).collect();
                s.push_str(&lines.join("  \n"));
                s.push('\n');
            }
            Block::Table(t) if !t.data_only => s.push_str(&table(t)),
            Block::Table(_) => {}
            Block::Diagnostics(ds) if !ds.is_empty() => {
                paragraph_break(&mut s);
                s.push_str(&diagnostics_table(ds));
            }
            Block::Diagnostics(_) => {}
        }
    }
    s
}

/// A line that would start a list item is escaped.
fn escape_line_start(l: &str) -> String {
    match l.strip_prefix("* ") {
        Some(rest) => format!("\\* {rest}"),
        None => l.to_string(),
    }
}

fn paragraph_break(s: &mut String) {
    if !s.is_empty() && !s.ends_with("\n\n") {
        s.push('\n');
    }
}

/// A pipe table, cells escaped for `|`.
pub fn table(t: &Table) -> String {
    let esc = |s: &str| s.replace('|', "\\|").replace('\n', "<br>");
    let mut s = String::new();
    s.push_str(&format!(
        "| {} |\n",
        t.header
            .iter()
            .map(|h| esc(h))
            .collect::<Vec<_>>()
            .join(" | ")
    ));
    s.push_str(&format!(
        "|{}|\n",
        t.header.iter().map(|_| "---").collect::<Vec<_>>().join("|")
    ));
    for r in &t.rows {
        s.push_str(&format!(
            "| {} |\n",
            r.iter().map(|c| esc(c)).collect::<Vec<_>>().join(" | ")
        ));
    }
    s
}

/// Diagnostics as a table (a job summary): severity, code, place, message.
fn diagnostics_table(ds: &[Diagnostic]) -> String {
    let rows = ds
        .iter()
        .map(|d| {
            let sev = match d.severity {
                Severity::Error => "**error**",
                Severity::Warning => "warning",
            };
            let place = if d.location.is_empty() {
                String::new()
            } else {
                format!("`{}`", d.location.to_string().replace('`', "'"))
            };
            vec![
                sev.to_string(),
                format!("`{}`", d.code),
                place,
                d.message.clone(),
            ]
        })
        .collect();
    table(&Table::new(&["severity", "code", "where", "message"], rows))
}
