//! Frame graph with provenance: frames are nodes, edges carry a `Transform`
//! (pose of child in parent) and where it came from.

use crate::error::{Result, Warning};
use crate::formats::{Edge, Loaded};
use crate::se3::Transform;

/// One step of a composed chain: an edge walked down (parent -> child) or up
/// (`inverted`, child -> parent).
#[derive(Debug, Clone, PartialEq)]
pub struct ChainStep {
    pub edge: Edge,
    pub inverted: bool,
}

/// `T_from_to` and the edges used, in order from `from` to `to`.
#[derive(Debug, Clone)]
pub struct Chain {
    pub from: String,
    pub to: String,
    pub transform: Transform,
    pub steps: Vec<ChainStep>,
    /// Warnings raised by the path (joints at default position, ...).
    pub warnings: Vec<Warning>,
}

#[derive(Debug, Clone, Default)]
pub struct FrameGraph {
    edges: Vec<Edge>,
    warnings: Vec<Warning>,
}

impl FrameGraph {
    pub fn new() -> Self {
        Self::default()
    }
    /// Add everything a file yielded.
    pub fn add(&mut self, loaded: Loaded) -> Result<()> {
        self.warnings.extend(loaded.warnings);
        for e in loaded.edges {
            self.add_edge(e)?;
        }
        Ok(())
    }
    pub fn add_edge(&mut self, edge: Edge) -> Result<()> {
        self.edges.push(edge);
        Ok(())
    }
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }
    /// All frame names, sorted.
    pub fn frames(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .edges
            .iter()
            .flat_map(|e| [e.parent.clone(), e.child.clone()])
            .collect();
        v.sort();
        v.dedup();
        v
    }
    /// Compose `T_from_to` along the path through the common ancestor.
    pub fn transform(&self, from: &str, to: &str) -> Result<Chain> {
        let _ = (from, to);
        unimplemented!("graph::transform is being written")
    }
}

impl FrameGraph {
    /// The frame tree as text (like check_urdf).
    pub fn tree(&self) -> String {
        self.frames().join("\n")
    }
}
