//! The document model the renderers share: what a report says, without how a
//! format draws it.

use crate::diagnostic::Diagnostic;

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
}

/// A table with a header row.
#[derive(Debug, Clone, Default)]
pub struct Table {
    /// Column titles.
    pub header: Vec<String>,
    /// Rows of cells (cells may hold several lines).
    pub rows: Vec<Vec<String>>,
    /// Wrap to the terminal width (`true`) or keep every cell on its lines.
    pub wrap: bool,
    /// Upper bounds on some columns' widths (column index, characters).
    pub bounds: Vec<(usize, u16)>,
    /// A machine table: rendered only as CSV (the display tables are skipped
    /// there when the document has one).
    pub data_only: bool,
    /// The columns a narrow terminal shows by default (empty: all); `--wide`
    /// shows the rest, piped output always has every column.
    pub compact: Vec<usize>,
    /// One line per row on a terminal: where the bordered table would wrap a
    /// cell, it is drawn borderless (columns two spaces apart, a rule under
    /// the header) with this column shortened by an ellipsis if need be.
    pub one_line: Option<usize>,
}

impl Table {
    /// A table that wraps to the terminal.
    pub fn new(header: &[&str], rows: Vec<Vec<String>>) -> Self {
        Table {
            header: header.iter().map(|s| s.to_string()).collect(),
            rows,
            wrap: true,
            ..Table::default()
        }
    }
    /// A table whose cells never wrap.
    pub fn unwrapped(header: &[&str], rows: Vec<Vec<String>>) -> Self {
        Table {
            wrap: false,
            ..Table::new(header, rows)
        }
    }
    /// With upper bounds on some columns' widths.
    pub fn bounded(mut self, bounds: &[(usize, u16)]) -> Self {
        self.bounds = bounds.to_vec();
        self
    }
    /// With the columns a narrow terminal shows by default.
    pub fn compact(mut self, columns: &[usize]) -> Self {
        self.compact = columns.to_vec();
        self
    }
    /// One line per row on a terminal, `elide` shortened if need be.
    pub fn one_line(mut self, elide: usize) -> Self {
        self.one_line = Some(elide);
        self
    }
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
