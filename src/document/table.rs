//! A table of a document, with the hints a terminal layout uses (which
//! columns a narrow terminal keeps, bounds on widths, one line per row).

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
