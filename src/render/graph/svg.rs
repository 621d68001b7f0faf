//! SVG drawn here, no Graphviz: a layered tree read left to right, one node
//! (frame) a row in depth-first order (parents above their children),
//! indented by depth, each node's box joined to its parent's by an elbow and
//! followed by the label of the link into it. Text is monospace, so widths are estimated from the
//! character count. Levels deeper than [`TREE_MAX_INDENT`] are not indented
//! further, so the picture stays linear in the number of frames.

use super::shared::{shown, CHAIN_COLOUR};
use crate::document::{Graph, GraphLink};
use crate::tolerances::TREE_MAX_INDENT;
use std::fmt::Write as _;

const ROW: f64 = 24.0;
const INDENT: f64 = 18.0;
const MARGIN: f64 = 12.0;
const BOX_H: f64 = 18.0;
/// Estimated advance of one character at the 12 px and 10 px monospace sizes.
const CHAR_W: f64 = 7.3;
const LABEL_CHAR_W: f64 = 6.1;

/// Text for XML character data and attribute values: `& < > " '` as entities
/// (after [`shown`] made control characters, which XML 1.0 cannot
/// carry at all, visible escapes).
fn xml(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// Where a frame's box sits.
struct Slot {
    x: f64,
    y: f64,
    w: f64,
}

fn slots(g: &Graph) -> Vec<Slot> {
    g.nodes
        .iter()
        .enumerate()
        .map(|(i, n)| Slot {
            x: MARGIN + INDENT * n.depth.min(TREE_MAX_INDENT) as f64,
            y: MARGIN + ROW * (i + 1) as f64,
            w: shown(&n.name).chars().count() as f64 * CHAR_W + 10.0,
        })
        .collect()
}

/// A link's label on one line.
fn label(l: &GraphLink) -> String {
    shown(&l.label.join("  "))
}

/// The line above the tree: the counts, and the chain drawn in red.
fn title(g: &Graph) -> String {
    let counts = format!("{} frames, {} edges", g.nodes.len(), g.links.len());
    match g.chain.as_deref() {
        Some(path @ [first, ..]) => {
            let last = &path[path.len() - 1];
            format!("{counts}; chain {} -> {} in red", shown(first), shown(last))
        }
        _ => counts,
    }
}

/// The graph as a standalone SVG document.
pub fn svg(g: &Graph) -> String {
    let slots = slots(g);
    let into = g.links_into();
    let title = title(g);
    let mut width = MARGIN * 2.0 + title.chars().count() as f64 * CHAR_W;
    let mut body = String::new();
    // Chain elbows drawn last, over the grey ones sharing their vertical.
    let mut chain_paths = String::new();
    for (i, f) in g.nodes.iter().enumerate() {
        let s = &slots[i];
        let colour = if f.on_chain { CHAIN_COLOUR } else { "#34495e" };
        let stroke = if f.on_chain { 2.5 } else { 1.0 };
        let edge = into[i];
        if let Some(ps) = f.parent.and_then(|p| slots.get(p)) {
            let on = edge.is_some_and(|e| e.on_chain);
            let ec = if on { CHAIN_COLOUR } else { "#95a5a6" };
            let _ = writeln!(
                if on { &mut chain_paths } else { &mut body },
                r#"<path d="M{:.1} {:.1} V{:.1} H{:.1}" fill="none" stroke="{ec}" stroke-width="{stroke}"/>"#,
                ps.x + 6.0,
                ps.y + BOX_H,
                s.y + BOX_H / 2.0,
                s.x
            );
        }
        let _ = writeln!(
            body,
            r#"<g class="frame"><rect x="{:.1}" y="{:.1}" width="{:.1}" height="{BOX_H}" rx="3" fill="white" stroke="{colour}" stroke-width="{stroke}"/><text x="{:.1}" y="{:.1}" font-size="12" fill="{colour}">{}</text></g>"#,
            s.x,
            s.y,
            s.w,
            s.x + 5.0,
            s.y + 13.0,
            xml(&shown(&f.name))
        );
        let mut right = s.x + s.w;
        if let Some(e) = edge {
            let l = label(e);
            let lc = if e.on_chain { CHAIN_COLOUR } else { "#7f8c8d" };
            let _ = writeln!(
                body,
                r#"<text class="edge" x="{:.1}" y="{:.1}" font-size="10" fill="{lc}">{}</text>"#,
                right + 8.0,
                s.y + 13.0,
                xml(&l)
            );
            right += 8.0 + l.chars().count() as f64 * LABEL_CHAR_W;
        }
        width = width.max(right + MARGIN);
    }
    body.push_str(&chain_paths);
    let height = MARGIN * 2.0 + ROW * (g.nodes.len() + 1) as f64;
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\" font-family=\"DejaVu Sans Mono, Menlo, Consolas, monospace\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"{MARGIN}\" y=\"{:.1}\" font-size=\"12\" fill=\"#2c3e50\">{}</text>\n{body}</svg>\n",
        MARGIN + 13.0,
        xml(&title)
    )
}

#[cfg(test)]
mod tests {
    use super::xml;

    #[test]
    fn markup_is_escaped() {
        assert_eq!(
            xml("<a href='x'>&\"</a>"),
            "&lt;a href=&apos;x&apos;&gt;&amp;&quot;&lt;/a&gt;"
        );
    }
}
