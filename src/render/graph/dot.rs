//! Graphviz DOT: `digraph frames`, one node per node of the graph (ids `n0`,
//! `n1`, ..., the names only in quoted labels), one edge per link.

use super::shared::{shown, CHAIN_COLOUR};
use crate::document::Graph;
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

/// The graph as a DOT digraph (left to right).
pub fn dot(g: &Graph) -> String {
    let mut out = String::from(
        "digraph frames {\n  rankdir=LR;\n  node [shape=box, fontname=\"monospace\", fontsize=10];\n  edge [fontname=\"monospace\", fontsize=8];\n",
    );
    let hl = |on: bool| {
        if on {
            format!(", color=\"{CHAIN_COLOUR}\", fontcolor=\"{CHAIN_COLOUR}\", penwidth=2")
        } else {
            String::new()
        }
    };
    for (i, n) in g.nodes.iter().enumerate() {
        let _ = writeln!(
            out,
            "  n{i} [label={}{}];",
            quoted(&shown(&n.name)),
            hl(n.on_chain)
        );
    }
    for l in &g.links {
        // Each line escaped, then joined with DOT's own `\n` line break.
        let label: Vec<String> = l
            .label
            .iter()
            .map(|line| {
                let q = quoted(&shown(line));
                q[1..q.len() - 1].to_string()
            })
            .collect();
        let _ = writeln!(
            out,
            "  n{} -> n{} [label=\"{}\"{}];",
            l.from,
            l.to,
            label.join("\\n"),
            hl(l.on_chain)
        );
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
