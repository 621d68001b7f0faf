//! A tree of named nodes joined by labelled links, one chain through it
//! highlighted: what the frame-tree pictures (DOT, Mermaid, SVG) and the
//! frame tree's text are drawn from. Nodes are in drawing order, a parent
//! before its children (depth first); a link joins a parent to a child.
//! Names and labels are as the files have them: each renderer escapes them.

/// The tree.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Graph {
    /// The nodes, depth first from the roots.
    pub nodes: Vec<GraphNode>,
    /// The links, each from a parent to a child (indices into `nodes`).
    pub links: Vec<GraphLink>,
    /// The names along the highlighted chain, from its first node to its
    /// last; `None` when no chain is highlighted.
    pub chain: Option<Vec<String>>,
    /// The tree as text, one node a line (what the text formats print).
    pub text: String,
}

/// One node.
#[derive(Debug, Clone, PartialEq)]
pub struct GraphNode {
    /// Its name.
    pub name: String,
    /// Its parent (index into [`Graph::nodes`]); `None` for a root.
    pub parent: Option<usize>,
    /// Links from its root (0 for a root).
    pub depth: usize,
    /// On the highlighted chain.
    pub on_chain: bool,
}

/// One link, parent to child.
#[derive(Debug, Clone, PartialEq)]
pub struct GraphLink {
    /// The parent (index into [`Graph::nodes`]).
    pub from: usize,
    /// The child (index into [`Graph::nodes`]).
    pub to: usize,
    /// The label, one line each (a picture joins them its own way).
    pub label: Vec<String>,
    /// On the highlighted chain.
    pub on_chain: bool,
}

impl Graph {
    /// The link into each node (`None` for a root), indexed like `nodes`.
    pub fn links_into(&self) -> Vec<Option<&GraphLink>> {
        let mut into = vec![None; self.nodes.len()];
        for l in &self.links {
            if let Some(slot) = into.get_mut(l.to) {
                *slot = Some(l);
            }
        }
        into
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_node_has_the_link_into_it() {
        let node = |name: &str, parent| GraphNode {
            name: name.into(),
            parent,
            depth: parent.map_or(0, |_| 1),
            on_chain: false,
        };
        let link = |from, to| GraphLink {
            from,
            to,
            label: vec![],
            on_chain: false,
        };
        let g = Graph {
            nodes: vec![node("a", None), node("b", Some(0)), node("c", Some(0))],
            links: vec![link(0, 2), link(0, 1)],
            ..Graph::default()
        };
        let into: Vec<Option<usize>> = g.links_into().iter().map(|l| l.map(|l| l.to)).collect();
        assert_eq!(into, [None, Some(1), Some(2)]);
    }
}
