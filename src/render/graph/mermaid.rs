//! Mermaid `flowchart LR`: one node per node (ids `n0`, `n1`, ...), the
//! names in quoted labels with every character outside a small safe set
//! written as a Mermaid entity code (`#35;`), so that no name can close a
//! label, start a link or inject markup.

use super::shared::{shown, CHAIN_COLOUR};
use crate::document::Graph;
use std::fmt::Write as _;

/// `s` with every character but ASCII letters, digits, space and `_.,:/[]-`
/// as `#N;` (decimal code point).
fn escaped(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        if c.is_ascii_alphanumeric() || " _.,:/[]-".contains(c) {
            out.push(c);
        } else {
            let _ = write!(out, "#{};", c as u32);
        }
    }
    out
}

/// The graph as a Mermaid flowchart (left to right).
pub fn mermaid(g: &Graph) -> String {
    let mut out = String::from("flowchart LR\n");
    for (i, n) in g.nodes.iter().enumerate() {
        let _ = writeln!(out, "  n{i}[\"{}\"]", escaped(&shown(&n.name)));
    }
    let mut chain_links = Vec::new();
    for (k, l) in g.links.iter().enumerate() {
        let label: Vec<String> = l.label.iter().map(|s| escaped(&shown(s))).collect();
        let _ = writeln!(
            out,
            "  n{} -->|\"{}\"| n{}",
            l.from,
            label.join("<br>"),
            l.to
        );
        if l.on_chain {
            chain_links.push(k.to_string());
        }
    }
    let on: Vec<String> = g
        .nodes
        .iter()
        .enumerate()
        .filter(|(_, n)| n.on_chain)
        .map(|(i, _)| format!("n{i}"))
        .collect();
    if !on.is_empty() {
        let _ = writeln!(
            out,
            "  classDef chain stroke:{CHAIN_COLOUR},stroke-width:3px,color:{CHAIN_COLOUR}\n  class {} chain",
            on.join(",")
        );
    }
    if !chain_links.is_empty() {
        let _ = writeln!(
            out,
            "  linkStyle {} stroke:{CHAIN_COLOUR},stroke-width:3px",
            chain_links.join(",")
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::escaped;

    #[test]
    fn markup_and_quotes_become_entity_codes() {
        assert_eq!(escaped("a\"]-->x<b>#"), "a#34;]--#62;x#60;b#62;#35;");
    }
}
