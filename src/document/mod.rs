//! The document layer: what a report says, without how a format draws it.
//! Below both `crate::report` (which builds documents) and
//! `crate::render` (which draws them); it imports neither.
//!
//! A [`Report`] is a typed, `Serialize` value (its JSON, with
//! [`SCHEMA_VERSION`]) that lays itself out as a [`Document`]: blocks in
//! reading order (headline, sections, notes, text, [`Table`]s, diagnostics)
//! and, for the pictures, a [`Graph`] (the frame tree) or a [`Plot`] (the
//! survey plot), and for the 3D formats a [`Scene`] (frames, shapes and point
//! clouds; the text formats skip it). Every number a person reads is
//! formatted by `numbers` (inside the crate).
//! Text in a document is as the report has it (names from files included):
//! each renderer escapes it for its own format.
//!
//! On the face as `extrinsic_audit::document`: the types below, which a
//! program reads from [`Report::document`] (to draw a report its own way) or
//! builds; the number formatting and the scene's helpers stay inside the
//! crate.

pub(crate) mod graph;
pub(crate) mod numbers;
pub(crate) mod plot;
pub(crate) mod scene;
mod table;

pub use graph::{Graph, GraphLink, GraphNode};
pub use plot::{Axis, Colour, Corner, Mark, Panel, Plot, Point, Series};
pub use scene::{Entity, Paint, PointCloud, Scene, SceneTransform, Shape};
#[cfg(test)]
pub(crate) use table::Held;
pub(crate) use table::{data_number, Columns};
pub use table::{RowSource, Streamed, Table};

use crate::diagnostic::Diagnostic;
use serde::Serialize;

/// The JSON schema version of every report (the check report has its own,
/// 2, in its `schema_version` field).
pub const SCHEMA_VERSION: u32 = 1;

/// A typed report: serialised for JSON, laid out as a `Document` for the
/// other formats.
pub trait Report: Serialize {
    /// The report laid out for people (and for the pictures).
    fn document(&self) -> Document;
}

/// A report laid out as blocks, in reading order.
#[derive(Debug, Clone, Default)]
pub struct Document {
    /// The blocks.
    pub blocks: Vec<Block>,
}

/// One block of a document.
#[derive(Debug, Clone)]
pub enum Block {
    /// The one-line answer that opens a report; `good` picks its colour.
    Headline {
        /// The sentence.
        text: String,
        /// Whether the news is good (green) or a caution (yellow).
        good: bool,
    },
    /// A section title.
    Section(String),
    /// A line that explains a convention: dim on a terminal; markdown has its
    /// own wording (with code spans), or omits it when `markdown` is `None`.
    Note {
        /// Terminal text.
        text: String,
        /// Markdown text.
        markdown: Option<String>,
    },
    /// A paragraph (one or more lines).
    Text(String),
    /// A table.
    Table(Table),
    /// Diagnostics (errors, warnings, findings), one per line.
    Diagnostics(Vec<Diagnostic>),
    /// A tree of named nodes joined by labelled links (the frame tree): the
    /// text formats write its text form, the picture formats draw it.
    Graph(Graph),
    /// A chart (the survey plot), drawn only as SVG.
    Plot(Plot),
    /// A 3D scene (the rig, the frame tree, a scan), drawn only by the 3D
    /// formats (MCAP); the others skip it.
    Scene(Scene),
}

impl Document {
    /// An empty document.
    pub fn new() -> Self {
        Self::default()
    }
    /// Append a block.
    pub fn push(&mut self, b: Block) -> &mut Self {
        self.blocks.push(b);
        self
    }
    /// Append a section title.
    pub fn section(&mut self, title: impl Into<String>) -> &mut Self {
        self.push(Block::Section(title.into()))
    }
    /// Append a paragraph.
    pub fn text(&mut self, text: impl Into<String>) -> &mut Self {
        self.push(Block::Text(text.into()))
    }
    /// Append a table.
    pub fn table(&mut self, t: Table) -> &mut Self {
        self.push(Block::Table(t))
    }
}
