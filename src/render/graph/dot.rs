//! Graphviz DOT: `digraph frames`, one node per frame (ids `n0`, `n1`, ...,
//! the names only in quoted labels), one edge per frame edge.

use super::{label_lines, name, CHAIN_COLOUR};
use crate::report::frames::FramesReport;
use std::collections::HashMap;
use std::fmt::Write as _;

/// A DOT double-quoted string's body: `\` and `"` escaped, so that a name can
/// neither end the string nor start a label escape (`\N`, `\G`, `\l`, ...).
fn quoted(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '"' => out.push_str("\\\""),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The frame tree as a DOT digraph (left to right).
pub fn dot(rep: &FramesReport) -> String {
    let mut out = String::from(
        "digraph frames {\n  rankdir=LR;\n  node [shape=box, fontname=\"monospace\", fontsize=10];\n  edge [fontname=\"monospace\", fontsize=8];\n",
    );
    let ids: HashMap<&str, usize> = rep
        .frames
        .iter()
        .enumerate()
        .map(|(i, f)| (f.name.as_str(), i))
        .collect();
    for (i, f) in rep.frames.iter().enumerate() {
        let hl = if f.on_chain {
            format!(", color=\"{CHAIN_COLOUR}\", fontcolor=\"{CHAIN_COLOUR}\", penwidth=2")
        } else {
            String::new()
        };
        let _ = writeln!(out, "  n{i} [label={}{hl}];", quoted(&name(&f.name)));
    }
    for e in &rep.edges {
        let (Some(p), Some(c)) = (ids.get(e.parent.as_str()), ids.get(e.child.as_str())) else {
            continue;
        };
        // Each line escaped, then joined with DOT's own `\n` line break.
        let label: Vec<String> = label_lines(e)
            .iter()
            .map(|l| {
                let q = quoted(l);
                q[1..q.len() - 1].to_string()
            })
            .collect();
        let hl = if e.on_chain {
            format!(", color=\"{CHAIN_COLOUR}\", fontcolor=\"{CHAIN_COLOUR}\", penwidth=2")
        } else {
            String::new()
        };
        let _ = writeln!(out, "  n{p} -> n{c} [label=\"{}\"{hl}];", label.join("\\n"));
    }
    out.push_str("}\n");
    out
}

#[cfg(test)]
mod tests {
    use super::quoted;

    #[test]
    fn quotes_and_backslashes_cannot_escape_the_string() {
        assert_eq!(quoted(r#"a"b\N"#), r#""a\"b\\N""#);
    }
}
