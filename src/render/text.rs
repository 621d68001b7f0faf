//! Terminal text: comfy-table tables (no colour inside tables: they are copied
//! into tickets and logs), bold section titles, dim notes.
//!
//! Every piece of text is escaped here, before colour is added (names from
//! files can hold ESC or bidi controls; see [`crate::sanitize`]): blocks keep
//! the report's own line breaks and no line may start a CI log command;
//! diagnostics are one line each.

use super::document::{Block, Document, Table};
use super::Style;
use crate::diagnostic::{Diagnostic, Severity};
use crate::sanitize::{block, line, visible};

/// Render a document for a terminal (or a log).
pub fn render(doc: &Document, st: Style) -> String {
    let mut s = String::new();
    for b in &doc.blocks {
        match b {
            Block::Headline { text, good } => {
                let text = &block(text);
                s.push_str(&if *good { st.good(text) } else { st.bad(text) });
                s.push('\n');
            }
            Block::Section(t) => {
                s.push('\n');
                s.push_str(&st.bold(&block(t)));
                s.push('\n');
            }
            Block::Note { text, .. } => {
                s.push_str(&st.dim(&block(text)));
                s.push('\n');
            }
            Block::Text(t) => {
                s.push_str(&block(t));
                s.push('\n');
            }
            Block::Table(t) if !t.data_only => {
                s.push_str(&table(t));
                s.push('\n');
            }
            Block::Table(_) => {}
            Block::Diagnostics(ds) => {
                for d in ds {
                    s.push_str(&diagnostic_line(d));
                    s.push('\n');
                }
            }
        }
    }
    s
}

/// A table through comfy-table.
pub fn table(t: &Table) -> String {
    let mut ct = comfy_table::Table::new();
    ct.load_preset(comfy_table::presets::UTF8_FULL_CONDENSED);
    if t.wrap {
        ct.set_content_arrangement(comfy_table::ContentArrangement::Dynamic);
    }
    // Cells keep their own line breaks; inside the borders no cell starts a line.
    let cell = |c: &String| visible(c, true).into_owned();
    ct.set_header(t.header.iter().map(cell));
    for r in &t.rows {
        ct.add_row(r.iter().map(cell));
    }
    for &(i, w) in &t.bounds {
        if let Some(c) = ct.column_mut(i) {
            c.set_constraint(comfy_table::ColumnConstraint::UpperBoundary(
                comfy_table::Width::Fixed(w),
            ));
        }
    }
    ct.to_string()
}

/// `file:line: severity[code]: message`, the place omitted when unknown; one
/// line, escaped ([`crate::sanitize::line`]).
pub fn diagnostic_line(d: &Diagnostic) -> String {
    let kind = match d.severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
    };
    let place = match (&d.location.file, d.location.line) {
        (None, _) => String::new(),
        (Some(f), Some(l)) => format!("{}:{l}: ", f.display()),
        (Some(f), None) => format!("{}: ", f.display()),
    };
    line(&format!("{place}{kind}[{}]: {}", d.code, d.message))
}
