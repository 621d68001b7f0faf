//! Mermaid `flowchart LR`: one node per frame (ids `n0`, `n1`, ...), the
//! names in quoted labels with every character outside a small safe set
//! written as a Mermaid entity code (`#35;`), so that no name can close a
//! label, start a link or inject markup.

use super::{label_lines, name, CHAIN_COLOUR};
use crate::report::frames::FramesReport;
use std::collections::HashMap;
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

/// The frame tree as a Mermaid flowchart (left to right).
pub fn mermaid(rep: &FramesReport) -> String {
    let mut out = String::from("flowchart LR\n");
    let ids: HashMap<&str, usize> = rep
        .frames
        .iter()
        .enumerate()
        .map(|(i, f)| (f.name.as_str(), i))
        .collect();
    for (i, f) in rep.frames.iter().enumerate() {
        let _ = writeln!(out, "  n{i}[\"{}\"]", escaped(&name(&f.name)));
    }
    let mut chain_links = Vec::new();
    for (k, e) in rep.edges.iter().enumerate() {
        let (Some(p), Some(c)) = (ids.get(e.parent.as_str()), ids.get(e.child.as_str())) else {
            continue;
        };
        let label: Vec<String> = label_lines(e).iter().map(|l| escaped(l)).collect();
        let _ = writeln!(out, "  n{p} -->|\"{}\"| n{c}", label.join("<br>"));
        if e.on_chain {
            chain_links.push(k.to_string());
        }
    }
    let on: Vec<String> = rep
        .frames
        .iter()
        .enumerate()
        .filter(|(_, f)| f.on_chain)
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
