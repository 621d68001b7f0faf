//! A table of a document, with the hints a terminal layout uses (which
//! columns a narrow terminal keeps, bounds on widths, one line per row).
//!
//! A table's rows are either held as cells ([`Table::rows`]) or made one at
//! a time by a [`RowSource`] ([`Table::streamed`]): a survey of a fleet
//! (issue 29) keeps its rows compact and the renderers write each row as it
//! is made, never holding every cell of a 100,000-row table.

use std::borrow::Cow;
use std::sync::Arc;

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
    /// Rows made on demand, after [`Table::rows`] (which a streamed table
    /// leaves empty): see [`Table::streamed`].
    pub stream: Option<Streamed>,
}

/// Rows made one at a time, in order: what a streamed table holds instead of
/// its cells.
pub trait RowSource: Send + Sync {
    /// How many rows.
    fn len(&self) -> usize;
    /// Whether there are none.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Row `i`'s cells (`i < len()`).
    fn row(&self, i: usize) -> Vec<String>;
}

/// A table's [`RowSource`], shared (a document is cloned cheaply).
#[derive(Clone)]
pub struct Streamed(pub Arc<dyn RowSource>);

impl std::fmt::Debug for Streamed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Streamed({} rows)", self.0.len())
    }
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
    /// A table whose rows `source` makes one at a time (the renderers that
    /// can write a row as it comes never hold them all).
    pub fn streamed(header: &[&str], source: Arc<dyn RowSource>) -> Self {
        Table {
            stream: Some(Streamed(source)),
            ..Table::new(header, Vec::new())
        }
    }
    /// How many rows: those held, then those streamed.
    pub fn row_count(&self) -> usize {
        self.rows.len() + self.stream.as_ref().map_or(0, |s| s.0.len())
    }
    /// Call `f` on every row in order (held rows borrowed, streamed ones made
    /// one at a time); stops at the first error.
    pub fn try_for_each_row<E>(
        &self,
        mut f: impl FnMut(&[String]) -> Result<(), E>,
    ) -> Result<(), E> {
        for r in &self.rows {
            f(r)?;
        }
        if let Some(s) = &self.stream {
            for i in 0..s.0.len() {
                f(&s.0.row(i))?;
            }
        }
        Ok(())
    }
    /// Call `f` on every row in order.
    pub fn for_each_row(&self, mut f: impl FnMut(&[String])) {
        let _ = self.try_for_each_row(|r| {
            f(r);
            Ok::<(), ()>(())
        });
    }
    /// The table with every row held as cells (a streamed one made whole:
    /// for the layouts that need all cells at once, such as a terminal's).
    pub fn materialized(&self) -> Cow<'_, Table> {
        match &self.stream {
            None => Cow::Borrowed(self),
            Some(_) => {
                let mut rows = Vec::with_capacity(self.row_count());
                self.for_each_row(|r| rows.push(r.to_vec()));
                Cow::Owned(Table {
                    rows,
                    stream: None,
                    ..self.clone()
                })
            }
        }
    }
}

/// A number as a data cell: every digit (the shortest text that reads back
/// as the same `f64`, as the JSON writes it), exponent form for the very
/// small and very large; empty when not finite (the JSON writes `null`).
pub fn data_number(x: f64) -> String {
    let a = x.abs();
    if !x.is_finite() {
        String::new()
    } else if x == 0.0 || (1e-4..1e15).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// One column of a data table: its name and how a row's cell is written.
type Column<'a, T> = (String, Box<dyn Fn(&T) -> String + Send + Sync + 'a>);

/// The columns of a report's data table (the one `--format csv` writes),
/// declared once, so that the header exists even without rows. Each kind of
/// column writes its cells one way: numbers by [`data_number`], flags as
/// `true`/`false`, a missing value as an empty cell.
pub struct Columns<'a, T> {
    columns: Vec<Column<'a, T>>,
}

impl<'a, T> Default for Columns<'a, T> {
    fn default() -> Self {
        Columns {
            columns: Vec::new(),
        }
    }
}

impl<'a, T> Columns<'a, T> {
    /// No columns yet.
    pub fn new() -> Self {
        Self::default()
    }
    /// A text column.
    pub fn text(mut self, name: &str, f: impl Fn(&T) -> String + Send + Sync + 'a) -> Self {
        self.columns.push((name.to_string(), Box::new(f)));
        self
    }
    /// A number column (empty where the value is `None`).
    pub fn num<X: Into<Option<f64>>>(
        self,
        name: &str,
        f: impl Fn(&T) -> X + Send + Sync + 'a,
    ) -> Self {
        self.text(name, move |r| {
            f(r).into().map_or(String::new(), data_number)
        })
    }
    /// A count column (empty where the value is `None`).
    pub fn count<X: Into<Option<usize>>>(
        self,
        name: &str,
        f: impl Fn(&T) -> X + Send + Sync + 'a,
    ) -> Self {
        self.text(name, move |r| {
            f(r).into().map_or(String::new(), |n| n.to_string())
        })
    }
    /// A flag column: `true` or `false` (empty where the value is `None`).
    pub fn flag<X: Into<Option<bool>>>(
        self,
        name: &str,
        f: impl Fn(&T) -> X + Send + Sync + 'a,
    ) -> Self {
        self.text(name, move |r| {
            f(r).into().map_or(String::new(), |b| b.to_string())
        })
    }
    /// A vector split into one number column per component: the JSON key
    /// with the component's name put before its unit (`translation_m` and
    /// `x` give `translation_x_m`; `quaternion_xyzw` and `x` give
    /// `quaternion_x`, a key without a unit taking the component last).
    pub fn vector<const N: usize>(
        self,
        key: &str,
        parts: [&str; N],
        f: impl Fn(&T) -> Option<[f64; N]> + Clone + Send + Sync + 'a,
    ) -> Self {
        self.split(key, parts, f, data_number)
    }
    /// A vector of flags split into one flag column per component (named as
    /// [`Columns::vector`] names them).
    pub fn flags<const N: usize>(
        self,
        key: &str,
        parts: [&str; N],
        f: impl Fn(&T) -> Option<[bool; N]> + Clone + Send + Sync + 'a,
    ) -> Self {
        self.split(key, parts, f, |b: bool| b.to_string())
    }
    /// One column per component of `f`'s array, named by [`split_name`],
    /// each cell written by `cell` (empty where `f` gives `None`).
    fn split<V: Copy + Send + Sync + 'a, const N: usize>(
        mut self,
        key: &str,
        parts: [&str; N],
        f: impl Fn(&T) -> Option<[V; N]> + Clone + Send + Sync + 'a,
        cell: fn(V) -> String,
    ) -> Self {
        for (k, part) in parts.iter().enumerate() {
            let g = f.clone();
            self = self.text(&split_name(key, part), move |r| {
                g(r).map_or(String::new(), |v| cell(v[k]))
            });
        }
        self
    }
    /// The column names.
    pub fn header(&self) -> Vec<String> {
        self.columns.iter().map(|(n, _)| n.clone()).collect()
    }
    /// One row's cells.
    pub fn cells(&self, r: &T) -> Vec<String> {
        self.columns.iter().map(|(_, f)| f(r)).collect()
    }
    /// The table over `rows`, marked as the document's data table.
    pub fn table<'r>(&self, rows: impl IntoIterator<Item = &'r T>) -> Table
    where
        T: 'r,
    {
        Table {
            header: self.header(),
            rows: rows.into_iter().map(|r| self.cells(r)).collect(),
            data_only: true,
            ..Table::default()
        }
    }
}

/// Units a column name ends with (the JSON keys' suffixes).
const UNITS: [&str; 7] = ["m_per_rad", "mm", "m", "deg", "rad", "s", "ns"];

/// `key` with `part` put before its unit suffix (`translation_m`, `x` ->
/// `translation_x_m`), or after a key without one (`quaternion_xyzw`: the
/// component letters are the key's own suffix, dropped).
pub fn split_name(key: &str, part: &str) -> String {
    for u in UNITS {
        if let Some(stem) = key.strip_suffix(&format!("_{u}")) {
            return format!("{stem}_{part}_{u}");
        }
    }
    let stem = key.strip_suffix("_xyzw").unwrap_or(key);
    format!("{stem}_{part}")
}

/// Rows handed out one at a time, as a survey's are: the render tests'
/// streamed table.
#[cfg(test)]
pub(crate) struct Held(pub Vec<Vec<String>>);

#[cfg(test)]
impl RowSource for Held {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn row(&self, i: usize) -> Vec<String> {
        self.0[i].clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors_are_split_before_the_unit() {
        assert_eq!(split_name("translation_m", "x"), "translation_x_m");
        assert_eq!(split_name("rpy_rad", "roll"), "rpy_roll_rad");
        assert_eq!(split_name("axis_point_m", "z"), "axis_point_z_m");
        assert_eq!(
            split_name("translation_delta_m", "y"),
            "translation_delta_y_m"
        );
        assert_eq!(split_name("rotation_from_deg", "x"), "rotation_from_x_deg");
        assert_eq!(split_name("quaternion_xyzw", "w"), "quaternion_w");
        assert_eq!(split_name("axis", "x"), "axis_x");
    }

    #[test]
    fn numbers_read_back_as_the_same_f64() {
        for x in [
            0.0,
            -0.0,
            1.5,
            -0.231_4,
            1e-20,
            6.02e23,
            1.0 / 3.0,
            12345.678,
        ] {
            let s = data_number(x);
            assert_eq!(s.parse::<f64>().unwrap(), x, "{s}");
        }
        assert_eq!(data_number(f64::NAN), "");
        assert_eq!(data_number(f64::NEG_INFINITY), "");
        assert_eq!(data_number(1e-20), "1e-20");
    }

    #[test]
    fn columns_give_a_header_without_rows() {
        struct R {
            t: [f64; 3],
            h: Option<f64>,
        }
        let c = Columns::<R>::new()
            .vector("translation_m", ["x", "y", "z"], |r| Some(r.t))
            .num("h_m", |r| r.h);
        let empty = c.table(&[]);
        assert_eq!(
            empty.header,
            [
                "translation_x_m",
                "translation_y_m",
                "translation_z_m",
                "h_m"
            ]
        );
        assert!(empty.data_only && empty.rows.is_empty());
        let t = c.table(&[R {
            t: [1.0, -2.5, 0.0],
            h: None,
        }]);
        assert_eq!(t.rows, [["1", "-2.5", "0", ""]]);
    }
}
