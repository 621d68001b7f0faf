//! Terminal text: comfy-table tables (no colour inside tables: they are copied
//! into tickets and logs), bold section titles, dim notes.
//!
//! Every piece of text is escaped here, before colour is added (names from
//! files can hold ESC or bidi controls; see [`crate::sanitize`]): blocks keep
//! the report's own line breaks and no line may start a CI log command;
//! diagnostics are one line each.

use super::layout::{self, Layout};
use super::style::Style;
use crate::diagnostic::Diagnostic;
use crate::document::{Block, Document, Graph, Table};
use crate::sanitize::{block, line, visible};

/// Render a document for a terminal (or a log), every column, nothing wrapped.
pub fn render(doc: &Document, st: Style) -> String {
    render_laid(doc, st, &Layout::default())
}

/// Render a document fitted to a layout (the terminal's width, `--wide`,
/// `--columns`): text wrapped at spaces, tables cut to their columns.
pub fn render_laid(doc: &Document, st: Style, lay: &Layout) -> String {
    let mut out = Vec::new();
    write_laid(doc, st, lay, &mut out).expect("a Vec takes every write");
    String::from_utf8(out).expect("the text is UTF-8")
}

/// [`render_laid`] written to `out` as it is made: a streamed table
/// ([`Table::streamed`]) off a terminal is written row by row (issue 29); on
/// a terminal its layout reads every cell, so it is made whole first.
pub fn write_laid(
    doc: &Document,
    st: Style,
    lay: &Layout,
    out: &mut dyn std::io::Write,
) -> std::io::Result<()> {
    let mut s = String::new();
    let para = |t: &str| paragraph(&relative(&block(t), lay), lay);
    for b in &doc.blocks {
        match b {
            Block::Headline { text, good } => {
                let text = &para(text);
                s.push_str(&if *good { st.good(text) } else { st.bad(text) });
                s.push('\n');
            }
            Block::Section(t) => {
                s.push('\n');
                s.push_str(&st.bold(&para(t)));
                s.push('\n');
            }
            Block::Note { text, .. } => {
                s.push_str(&st.dim(&para(text)));
                s.push('\n');
            }
            Block::Text(t) => {
                s.push_str(&para(t));
                s.push('\n');
            }
            Block::Table(t) if !t.data_only && t.stream.is_some() => {
                if lay.width().filter(|_| t.wrap).is_some() {
                    s.push_str(&table_laid(&t.materialized(), st, lay));
                } else {
                    out.write_all(s.as_bytes())?;
                    s.clear();
                    let esc = |c: &str| relative(&visible(c, true), lay);
                    let hidden = layout::write_unfitted(t, lay, &esc, out)?;
                    s.push_str(&hidden_note(hidden, st));
                }
                s.push('\n');
            }
            Block::Table(t) if !t.data_only => {
                s.push_str(&table_laid(t, st, lay));
                s.push('\n');
            }
            Block::Table(_) => {}
            Block::Diagnostics(ds) => {
                for d in ds {
                    let l = relative(&diagnostic_line(d), lay);
                    // On a terminal a long diagnostic continues indented.
                    s.push_str(&paragraph_indented(&l, lay));
                    s.push('\n');
                }
            }
            Block::Graph(g) => {
                s.push_str(&tree(g, lay));
                s.push('\n');
            }
            // A chart is drawn as SVG only (refused before it gets here).
            Block::Plot(_) | Block::Scene(_) => {}
        }
    }
    out.write_all(s.as_bytes())
}

/// A graph as its text tree, fitted to the terminal (a node's place goes
/// under it rather than past the width), then the chain; uncoloured, as is
/// (names cannot hold a line break: refused when loaded; the rest of what
/// could act on a terminal or a CI log is escaped).
fn tree(g: &Graph, lay: &Layout) -> String {
    let mut t = block(&g.text);
    if let Some(w) = lay.width() {
        t = layout::fit_tree(&t, w);
    }
    if let Some(c) = &g.chain {
        let chain = format!("chain: {}", line(&c.join(" -> ")));
        // On a terminal a long chain continues under its first frame.
        match lay.width() {
            Some(w) if layout::width_of(&chain) > w => {
                let lines = layout::wrap(&chain, w);
                let rest = layout::wrap(&lines[1..].join(" "), w.saturating_sub(7).max(1));
                t.push_str(&lines[0]);
                t.push('\n');
                for l in rest.iter().filter(|l| !l.is_empty()) {
                    t.push_str(&format!("       {l}\n"));
                }
            }
            _ => t.push_str(&format!("{chain}\n")),
        }
    }
    t
}

/// Paths under the current directory shown relative to it.
fn relative(s: &str, lay: &Layout) -> String {
    match lay.cwd.as_ref().and_then(|c| c.to_str()) {
        Some(c) if !c.is_empty() && c != "/" => {
            let c = c.trim_end_matches('/');
            s.replace(&format!("{c}/"), "")
        }
        _ => s.to_string(),
    }
}

fn paragraph(t: &str, lay: &Layout) -> String {
    match lay.width() {
        Some(w) => layout::wrap(t, w).join("\n"),
        None => t.to_string(),
    }
}

fn paragraph_indented(t: &str, lay: &Layout) -> String {
    match lay.width() {
        Some(w) if layout::width_of(t) > w => {
            let first = layout::wrap(t, w);
            let rest = first[1..].join(" ");
            let mut out = vec![first[0].clone()];
            out.extend(layout::wrap(&format!("    {rest}"), w));
            out.join("\n")
        }
        _ => t.to_string(),
    }
}

/// A table fitted to a layout; a dim line says how many columns are hidden.
pub fn table_laid(t: &Table, st: Style, lay: &Layout) -> String {
    // Cells keep their own line breaks; inside the borders no cell starts a line.
    let cell = |c: &String| relative(&visible(c, true), lay);
    let escaped = Table {
        header: t.header.iter().map(cell).collect(),
        rows: t
            .rows
            .iter()
            .map(|r| r.iter().map(cell).collect())
            .collect(),
        ..t.clone()
    };
    let (mut s, hidden) = if let Some((lines, hidden)) = layout::borderless(&escaped, lay) {
        (lines.join("\n"), hidden)
    } else {
        let fitted = layout::fit(&escaped, lay);
        let hidden = fitted.hidden;
        match lay.width() {
            Some(w) if fitted.records => (layout::records(&fitted, w).join("\n"), hidden),
            _ => (bordered(fitted), hidden),
        }
    };
    s.push_str(&hidden_note(hidden, st));
    s
}

/// The dim line under a table that says how many columns are hidden (none:
/// empty), with the line break before it.
fn hidden_note(hidden: usize, st: Style) -> String {
    if hidden == 0 {
        return String::new();
    }
    let note = format!(
        "{} more column{} with --wide (or --columns NAME,...)",
        hidden,
        if hidden == 1 { "" } else { "s" }
    );
    format!("\n{}", st.dim(&note))
}

/// A fitted table in comfy-table's condensed borders.
fn bordered(fitted: layout::Fitted) -> String {
    let mut ct = comfy_table::Table::new();
    ct.load_preset(comfy_table::presets::UTF8_FULL_CONDENSED);
    ct.set_content_arrangement(comfy_table::ContentArrangement::Disabled);
    ct.set_header(fitted.header);
    for r in fitted.rows {
        ct.add_row(r);
    }
    ct.to_string()
}

/// `file:line: severity[code]: message`, the place omitted when unknown; one
/// line, escaped ([`crate::sanitize::line`]).
pub fn diagnostic_line(d: &Diagnostic) -> String {
    let kind = d.severity.name();
    let place = match (&d.location.file, d.location.line) {
        (None, _) => String::new(),
        (Some(f), Some(l)) => format!("{}:{l}: ", f.display()),
        (Some(f), None) => format!("{}: ", f.display()),
    };
    line(&format!("{place}{kind}[{}]: {}", d.code, d.message))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::Held;
    use std::sync::Arc;

    fn rows(cells: &[&[&str]]) -> Vec<Vec<String>> {
        cells
            .iter()
            .map(|r| r.iter().map(|c| c.to_string()).collect())
            .collect()
    }

    /// A streamed table off a terminal is written row by row by
    /// `layout::write_unfitted`; the same table held whole is drawn by
    /// comfy-table (the reference): the two texts are the same, for
    /// multi-line, empty, missing, wide and escaped cells, a bounded column
    /// wrapped, no rows at all, and `--columns`.
    #[test]
    fn a_streamed_table_is_drawn_as_comfy_table_draws_it_whole() {
        let header = ["id", "sensor name", "x (m)"];
        let cases = [
            rows(&[
                &["a", "os1", "0.1"],
                &["two\nlines", "", "-"],
                &["日本語", "a rather long sensor name that wraps", "12.5"],
                &["short"],
                &["esc\x1b[31m", "tab\there", "/work/x/y"],
            ]),
            rows(&[]),
            rows(&[&["", "", ""]]),
        ];
        let layouts = [
            Layout::default(),
            Layout {
                columns: vec!["x".into(), "id".into()],
                ..Layout::default()
            },
            Layout {
                cwd: Some("/work".into()),
                ..Layout::default()
            },
        ];
        for r in &cases {
            for bounds in [&[][..], &[(1, 14)][..]] {
                let held = Table::new(&header, r.clone()).bounded(bounds);
                let streamed = Table::streamed(&header, Arc::new(Held(r.clone()))).bounded(bounds);
                for lay in &layouts {
                    let draw = |t: &Table| {
                        let mut d = Document::new();
                        d.text("above").table(t.clone()).text("below");
                        render_laid(&d, Style::plain(), lay)
                    };
                    let want = draw(&held);
                    assert_eq!(draw(&streamed), want, "{r:?} {bounds:?} {lay:?}");
                    assert!(want.contains('┆'), "{want}");
                }
            }
        }
    }
}
