//! GitHub workflow commands: each diagnostic becomes an `::error` or
//! `::warning` annotation on its file and line; the rest of the document is
//! printed as plain text (no colour) after the annotations' block.

use super::style::Style;
use super::text;
use crate::diagnostic::{Diagnostic, Severity};
use crate::document::{Block, Document};

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

/// Escape a workflow-command value (`%`, CR, LF; and in properties `:` `,`),
/// after showing control and bidirectional characters as escapes
/// ([`crate::sanitize::visible`]): an ESC or U+202E from a file must not reach
/// the log raw. A message's own line breaks stay (as `%0A`).
pub fn escape(s: &str, property: bool) -> String {
    let mut o = crate::sanitize::visible(s, !property)
        .replace('%', "%25")
        .replace('\r', "%0D")
        .replace('\n', "%0A");
    if property {
        o = o.replace(':', "%3A").replace(',', "%2C");
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_and_bidi_characters_are_shown_not_passed_through() {
        let m = escape("frame \u{1b}[31mred\u{202e} 50%\nnext", false);
        assert_eq!(m, "frame \\x1b[31mred\\u{202e} 50%25%0Anext");
        let p = escape("a\nb:c,d\u{7}", true);
        assert_eq!(p, "a\\nb%3Ac%2Cd\\x07");
    }
}
