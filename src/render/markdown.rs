//! GitHub-flavoured markdown: `###` sections, pipe tables with `|` escaped, a
//! blank line before every paragraph so that none is read as a table row.
//! Text from the report is escaped (control characters shown, `|` and `<`
//! escaped, no line starting a list, heading, quote or CI log command);
//! the notes' own markdown is kept (only control characters escaped). A
//! graph is a Mermaid code block (GitHub draws it).

use super::graph;
use crate::diagnostic::{Diagnostic, Severity};
use crate::document::{Block, Document, Table};

/// Render a document as markdown, written to `out`: a streamed table ([`Table::streamed`]) a row
/// at a time (issue 29), the rest as it is made.
pub fn write(doc: &Document, out: &mut dyn std::io::Write) -> std::io::Result<()> {
    let mut s = String::new();
    // The head of `s` already written (after a streamed table).
    let mut flushed = 0;
    for b in &doc.blocks {
        match b {
            Block::Headline { text, .. } => {
                s.push_str(&format!("**{}**\n", inline(text)));
            }
            Block::Section(t) => {
                paragraph_break(&mut s);
                s.push_str(&format!("### {}\n\n", inline(t)));
            }
            Block::Note { markdown, .. } => {
                if let Some(m) = markdown {
                    // The note's own markdown, but it may quote names: `<`
                    // outside code spans is escaped (GitHub drops raw tags).
                    paragraph_break(&mut s);
                    s.push_str(&escape_tags(&crate::sanitize::block(m)));
                    s.push_str("\n\n");
                }
            }
            Block::Text(t) => {
                paragraph_break(&mut s);
                let lines: Vec<String> = t.lines().map(|l| escape_line_start(&inline(l))).collect();
                s.push_str(&lines.join("  \n"));
                s.push('\n');
            }
            Block::Table(t) if !t.data_only && t.stream.is_some() => {
                paragraph_break(&mut s);
                out.write_all(&s.as_bytes()[flushed..])?;
                write_table(t, out)?;
                // A blank line: the next line must not read as a table row.
                out.write_all(b"\n")?;
                // What is written ends with the rows' `|\n` and that blank
                // line: kept, for `paragraph_break`, and not written again.
                s = "|\n\n".to_string();
                flushed = s.len();
            }
            Block::Table(t) if !t.data_only => {
                paragraph_break(&mut s);
                s.push_str(&table(t));
                // A blank line: the next line must not read as a table row.
                s.push('\n');
            }
            Block::Table(_) => {}
            Block::Diagnostics(ds) if !ds.is_empty() => {
                paragraph_break(&mut s);
                s.push_str(&diagnostics_table(ds));
            }
            Block::Diagnostics(_) => {}
            Block::Graph(g) => {
                paragraph_break(&mut s);
                s.push_str("```mermaid\n");
                s.push_str(&graph::mermaid(g));
                s.push_str("```\n");
            }
            // A chart is drawn as SVG only (refused before it gets here).
            Block::Plot(_) | Block::Scene(_) => {}
        }
    }
    out.write_all(&s.as_bytes()[flushed..])
}

/// A line that would start a list item, a heading or a quote is escaped (and
/// a CI log command, [`crate::sanitize::guard_line_start`]).
fn escape_line_start(l: &str) -> String {
    if ["* ", "- ", "+ ", "#", ">"]
        .iter()
        .any(|p| l.starts_with(p))
    {
        return format!("\\{l}");
    }
    crate::sanitize::guard_line_start(l).into_owned()
}

/// Text on one line of markdown: escaped ([`crate::sanitize::visible`]), and
/// `|` and `<` escaped so that it cannot break a table or open HTML.
fn inline(s: &str) -> String {
    crate::sanitize::visible(s, false)
        .replace('|', "\\|")
        .replace('<', "&lt;")
}

/// `<` outside code spans as `&lt;` (inside a code span GitHub shows it as is).
fn escape_tags(m: &str) -> String {
    m.split('`')
        .enumerate()
        .map(|(i, part)| {
            if i % 2 == 0 {
                part.replace('<', "&lt;")
            } else {
                part.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("`")
}

fn paragraph_break(s: &mut String) {
    if !s.is_empty() && !s.ends_with("\n\n") {
        s.push('\n');
    }
}

/// A pipe table, cells escaped for `|` and `<` (a cell's line breaks become `<br>`).
pub fn table(t: &Table) -> String {
    let mut out = Vec::new();
    write_table(t, &mut out).expect("a Vec takes every write");
    String::from_utf8(out).expect("the markdown is UTF-8")
}

/// [`table`] written to `out`, a row at a time.
fn write_table(t: &Table, out: &mut dyn std::io::Write) -> std::io::Result<()> {
    let esc = |s: &str| {
        crate::sanitize::visible(s, true)
            .replace('|', "\\|")
            .replace('<', "&lt;")
            .replace('\n', "<br>")
    };
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
    out.write_all(s.as_bytes())?;
    t.try_for_each_row(|r| {
        s.clear();
        s.push_str(&format!(
            "| {} |\n",
            r.iter().map(|c| esc(c)).collect::<Vec<_>>().join(" | ")
        ));
        out.write_all(s.as_bytes())
    })
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::Held;
    use std::sync::Arc;

    /// Two streamed tables written a row at a time read as the same tables
    /// held whole, the blank lines between blocks included (an empty
    /// paragraph after a table among them).
    #[test]
    fn streamed_tables_are_written_as_held_ones() {
        let r = vec![
            vec!["a|b".to_string(), "<x>".into()],
            vec!["two\nlines".into(), String::new()],
        ];
        let doc = |t: &dyn Fn() -> Table| {
            let mut d = Document::new();
            d.text("above").table(t()).text("").table(t()).text("below");
            let mut out = Vec::new();
            write(&d, &mut out).unwrap();
            String::from_utf8(out).unwrap()
        };
        let held = doc(&|| Table::new(&["id", "x"], r.clone()));
        let streamed = doc(&|| Table::streamed(&["id", "x"], Arc::new(Held(r.clone()))));
        assert_eq!(streamed, held);
        assert!(held.contains("| a\\|b | &lt;x> |\n"), "{held}");
    }
}
