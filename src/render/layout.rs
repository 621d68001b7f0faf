//! Fitting text to a terminal: which columns a table shows and how wide each
//! is, and word wrapping that never splits a number, a path or a `file:line`.
//!
//! Conventions: widths are display columns (`unicode-width`); a table drawn
//! by comfy-table's condensed preset takes `3 n + 1` columns of borders and
//! padding for `n` columns. A `width` of `None` means the output is not a
//! terminal: every column is shown and nothing is wrapped (the full,
//! machine-friendly table).
//!
//! Three ways to draw a table on a terminal, tried in turn: bordered with its
//! cells wrapped ([`fit`]); borderless, one line per row, for a table that
//! asks for it ([`borderless`], e.g. the survey at 80 columns); and, when a
//! word that must stay whole is wider than its column, one `key: value` line
//! per cell ([`records`]) rather than a line wider than the terminal.

use crate::diagnostic::{Error, Result};
use crate::document::Table;
use unicode_width::UnicodeWidthStr;

/// Narrowest terminal the tables are laid out for (columns): below it the
/// layout of this width is printed and the terminal wraps it.
pub const MIN_TERMINAL_WIDTH: usize = 40;

/// Narrowest a plain word (no digit, no path separator) is cut to when a
/// table column is too narrow for it; numbers and `file:line` are never cut.
pub const SOFT_WORD_MIN_WIDTH: usize = 10;

/// Narrowest a column of a one-line-per-row table (the survey's id) is
/// shortened to, an ellipsis in its middle: below it the table wraps instead.
pub const ELIDE_MIN_WIDTH: usize = 12;

/// Spaces between the columns of a borderless table.
pub const BORDERLESS_GAP: usize = 2;

/// Largest table (cells, the header included) whose column widths are tuned
/// for the fewest lines on a terminal; a bigger one keeps the first share
/// (the tuning tries every move between two columns, per cell).
pub const LAYOUT_REFINE_MAX_CELLS: usize = 400;

/// Cells read, at most, while tuning one table's column widths (every layout
/// tried reads each cell once), after which the best layout found so far is
/// kept (the tuning of a 75-row table of five prose columns takes 0.3 s in a
/// debug build, most of it wrapping every cell at every width once).
pub const LAYOUT_REFINE_BUDGET: usize = 5_000_000;

/// Widest table (columns) whose tuning also tries moving width from one
/// column to two others at once (the cost grows with the cube of the count).
pub const LAYOUT_REFINE_MAX_COLUMNS: usize = 5;

/// A word cut across lines in a table cell costs as much as this many more
/// lines when the column widths are tuned: a whole name (`unnormalized`) is
/// worth a few more lines of wrapped prose beside it.
pub const CUT_WORD_COST: usize = 8;

/// How the terminal output is laid out (`--wide`, `--columns`, the width).
#[derive(Debug, Clone, Default)]
pub struct Layout {
    /// The terminal's width in columns; `None` when not printing to a terminal.
    pub width: Option<usize>,
    /// Show every column of every table (`--wide`), still wrapped to the width.
    pub wide: bool,
    /// Show these columns (`--columns`, matched against the table headers).
    pub columns: Vec<String>,
    /// Paths under this directory are shown relative to it.
    pub cwd: Option<std::path::PathBuf>,
}

impl Layout {
    /// The width, never below [`MIN_TERMINAL_WIDTH`] (a narrower terminal
    /// gets the 80-column layout and wraps it itself).
    pub fn width(&self) -> Option<usize> {
        self.width.map(|w| w.max(MIN_TERMINAL_WIDTH))
    }
}

/// Display width of a string.
pub fn width_of(s: &str) -> usize {
    UnicodeWidthStr::width(s)
}

/// A word that must stay whole: it holds a digit (a number, a vector entry,
/// `file:line`) or a path separator.
fn is_hard(word: &str) -> bool {
    word.chars()
        .any(|c| c.is_ascii_digit() || c == '/' || c == '\\')
}

/// The narrowest a word may be cut to: a plain word to
/// [`SOFT_WORD_MIN_WIDTH`], a hyphenated name (`os1-128-stim300`, not a
/// number such as `1e-05`) after a hyphen, anything else not at all.
fn word_min(word: &str) -> usize {
    let w = width_of(word);
    if !is_hard(word) {
        w.min(SOFT_WORD_MIN_WIDTH)
    } else if hyphen_breakable(word) {
        hyphen_pieces(word).map(width_of).max().unwrap_or(w)
    } else {
        w
    }
}

/// A name with hyphens (`ouster-os1-128-fw2.3`): it starts with a letter
/// (no number, no vector entry `[-1.0,`) and is no path or place.
fn hyphen_breakable(word: &str) -> bool {
    word.contains('-')
        && word.starts_with(|c: char| c.is_alphabetic())
        && !word.contains(['/', '\\', ':'])
        && word.parse::<f64>().is_err()
}

/// `a-b-c` as `a-`, `b-`, `c`.
fn hyphen_pieces(word: &str) -> impl Iterator<Item = &str> {
    word.split_inclusive('-')
}

/// Wrap one paragraph (its own line breaks kept) to `width` at spaces; a word
/// wider than `width` is cut only when it holds no digit and no path separator.
pub fn wrap(text: &str, width: usize) -> Vec<String> {
    let width = width.max(1);
    let mut out = Vec::new();
    for line in text.split('\n') {
        if width_of(line) <= width {
            out.push(line.to_string());
            continue;
        }
        // A line's leading spaces stay, as the indent of its continuation lines.
        let indent_len = line.len() - line.trim_start_matches(' ').len();
        let indent = &line[..indent_len.min(width / 2)];
        let mut cur = indent.to_string();
        for word in line[indent_len..].split(' ').filter(|w| !w.is_empty()) {
            push_word(&mut out, &mut cur, word, width, indent);
        }
        if !cur.trim().is_empty() || out.is_empty() {
            out.push(cur);
        }
    }
    out
}

fn push_word(out: &mut Vec<String>, cur: &mut String, word: &str, width: usize, indent: &str) {
    let sep = usize::from(!cur.trim().is_empty());
    if width_of(cur) + sep + width_of(word) <= width {
        if sep == 1 {
            cur.push(' ');
        }
        cur.push_str(word);
        return;
    }
    if !cur.trim().is_empty() {
        out.push(std::mem::replace(cur, indent.to_string()));
    }
    let room = width.saturating_sub(width_of(indent)).max(1);
    if width_of(word) <= room || (is_hard(word) && !hyphen_breakable(word)) {
        cur.push_str(word);
        return;
    }
    if is_hard(word) {
        // A hyphenated name continues after a hyphen.
        for p in hyphen_pieces(word) {
            if !cur.trim().is_empty() && width_of(cur) + width_of(p) > width {
                out.push(std::mem::replace(cur, indent.to_string()));
            }
            cur.push_str(p);
        }
        return;
    }
    // A long plain word is cut into pieces that fit.
    let mut piece = String::new();
    for c in word.chars() {
        if width_of(&piece) + UnicodeWidthStr::width(c.encode_utf8(&mut [0; 4]) as &str) > room {
            out.push(format!("{indent}{piece}"));
            piece.clear();
        }
        piece.push(c);
    }
    cur.push_str(&piece);
}

/// A table cut to what the layout shows: the columns kept, and every cell
/// wrapped to its column's width.
#[derive(Debug, Clone)]
pub struct Fitted {
    /// Column titles.
    pub header: Vec<String>,
    /// Rows of cells (line breaks where wrapped).
    pub rows: Vec<Vec<String>>,
    /// How many columns are left out (shown with `--wide`).
    pub hidden: usize,
    /// A whole word is wider than the terminal leaves its column: draw the
    /// rows as records ([`records`]); the cells are then unwrapped.
    pub records: bool,
}

/// Which columns `--columns` names in this table (by header, case-insensitive,
/// the unit in parentheses optional); `None` when it names none of them.
fn named_columns(t: &Table, names: &[String]) -> Option<Vec<usize>> {
    let idx: Vec<usize> = (0..t.header.len())
        .filter(|&i| names.iter().any(|n| header_matches(&t.header[i], n)))
        .collect();
    (!idx.is_empty()).then_some(idx)
}

/// A header matches a name given in full or without its `(unit)`.
pub fn header_matches(header: &str, name: &str) -> bool {
    let h = header.trim().to_lowercase();
    let n = name.trim().to_lowercase();
    let bare = h.split(" (").next().unwrap_or(&h).trim().to_string();
    h == n || bare == n || h.replace(' ', "-") == n || bare.replace(' ', "-") == n
}

/// Check `--columns`: every name must be a column of some table.
pub fn check_columns(tables: &[&Table], names: &[String]) -> Result<()> {
    for n in names {
        if !tables
            .iter()
            .any(|t| t.header.iter().any(|h| header_matches(h, n)))
        {
            let mut all: Vec<String> = tables
                .iter()
                .flat_map(|t| t.header.iter().map(|h| h.replace('\n', " ")))
                .collect();
            all.dedup();
            return Err(Error::usage(format!(
                "--columns: expected one of the columns of this report ({}), found `{n}`",
                all.join(", ")
            )));
        }
    }
    Ok(())
}

/// The columns a table shows under a layout.
fn chosen_columns(t: &Table, layout: &Layout, width: Option<usize>) -> Vec<usize> {
    let all: Vec<usize> = (0..t.header.len()).collect();
    if let Some(named) = named_columns(t, &layout.columns) {
        return named;
    }
    let Some(w) = width else { return all };
    if layout.wide || t.compact.is_empty() || natural_width(t, &all) <= w {
        return all;
    }
    t.compact.clone()
}

/// The width of a table with no cell wrapped.
fn natural_width(t: &Table, cols: &[usize]) -> usize {
    cols.iter().map(|&c| column_max(t, c)).sum::<usize>() + 3 * cols.len() + 1
}

fn cells(t: &Table, c: usize) -> impl Iterator<Item = &str> {
    std::iter::once(t.header.get(c).map_or("", String::as_str)).chain(
        t.rows
            .iter()
            .map(move |r| r.get(c).map_or("", String::as_str)),
    )
}

/// A column's natural width: its widest cell line (a header wraps at its
/// words rather than widen the column).
fn column_max(t: &Table, c: usize) -> usize {
    let header = t.header.get(c).map_or("", String::as_str);
    let head = header.split(['\n', ' ']).map(word_min).max().unwrap_or(0);
    t.rows
        .iter()
        .flat_map(|r| r.get(c).map_or("", String::as_str).split('\n'))
        .map(width_of)
        .max()
        .unwrap_or(0)
        .max(head)
}

/// A column's narrowest: no cell word cut below [`word_min`], and no header
/// word cut at all (issue 33: "equivarian / t rule" at 80 columns), except a
/// hyphenated name, after a hyphen.
fn column_min(t: &Table, c: usize) -> usize {
    let header = t.header.get(c).map_or("", String::as_str);
    t.rows
        .iter()
        .map(|r| cell_min(r.get(c).map_or("", String::as_str)))
        .max()
        .unwrap_or(0)
        .max(header_min(header))
        .max(1)
}

/// The narrowest a header cell may be (its words whole, a hyphenated name
/// cut after a hyphen).
fn header_min(header: &str) -> usize {
    header
        .split(['\n', ' '])
        .map(|w| {
            if hyphen_breakable(w) {
                word_min(w)
            } else {
                width_of(w)
            }
        })
        .max()
        .unwrap_or(0)
}

/// The narrowest a body cell may be (no word cut below [`word_min`]).
fn cell_min(cell: &str) -> usize {
    cell.split(['\n', ' ']).map(word_min).max().unwrap_or(0)
}

/// The widest word of a column's cells, uncut.
fn column_longest_word(t: &Table, c: usize) -> usize {
    cells(t, c)
        .flat_map(|s| s.split(['\n', ' ']))
        .map(width_of)
        .max()
        .unwrap_or(0)
}

/// Fit a table to a layout (cells already escaped).
pub fn fit(t: &Table, layout: &Layout) -> Fitted {
    let width = layout.width().filter(|_| t.wrap);
    let mut cols = chosen_columns(t, layout, width);
    let total = t.header.len();
    let widths = match width {
        // Not a terminal: every column; only a bounded column wraps.
        None if t.wrap && !t.bounds.is_empty() => Some(
            cols.iter()
                .map(|&c| {
                    let bound = t.bounds.iter().find(|b| b.0 == c);
                    bound.map_or(usize::MAX, |b| bound_width(b.1).max(column_min(t, c)))
                })
                .collect(),
        ),
        None => None,
        Some(w) => {
            // Narrowest first: drop columns from the right while even their
            // narrowest layout is too wide (never the first; never with --wide).
            let mins = |cols: &[usize]| {
                cols.iter().map(|&c| column_min(t, c)).sum::<usize>() + 3 * cols.len() + 1
            };
            while !layout.wide && cols.len() > 1 && mins(&cols) > w {
                cols.pop();
            }
            (mins(&cols) <= w).then(|| share(t, &cols, w))
        }
    };
    let records = width.is_some() && widths.is_none();
    let pick = |r: &Vec<String>| -> Vec<String> {
        cols.iter()
            .enumerate()
            .map(|(k, &c)| {
                let s = r.get(c).map_or("", String::as_str);
                match &widths {
                    Some(ws) => wrap(s, ws[k]).join("\n"),
                    None => s.to_string(),
                }
            })
            .collect()
    };
    Fitted {
        header: pick(&t.header),
        rows: t.rows.iter().map(pick).collect(),
        hidden: total - cols.len(),
        records,
    }
}

/// A table off a terminal (no width, or a table that does not wrap) written
/// row by row, as [`fit`] then comfy-table's condensed borders draw it:
/// every column (or those `--columns` names), only a bounded column wrapped
/// (at its bound, or its narrowest if wider). The rows are read in passes
/// (the columns' widths and the bounded columns' narrowest; the wrapped
/// widths, only where a bounded column has a line wider than its wrap; then
/// each row written), each cell through `esc` first: a streamed table (issue 29) is
/// never held whole. Returns how many columns are left out; writes no line
/// break after the last line.
pub fn write_unfitted(
    t: &Table,
    layout: &Layout,
    esc: &dyn Fn(&str) -> String,
    out: &mut dyn std::io::Write,
) -> std::io::Result<usize> {
    // The columns shown, by the escaped header (as `fit` matches them).
    let named = Table {
        header: t.header.iter().map(|h| esc(h)).collect(),
        ..Table::default()
    };
    let cols = chosen_columns(&named, layout, None);
    let bounds: Vec<Option<usize>> = cols
        .iter()
        .map(|&c| {
            let b = t.bounds.iter().find(|b| b.0 == c);
            b.filter(|_| t.wrap).map(|b| bound_width(b.1))
        })
        .collect();
    let cell_of = |r: &[String], c: usize| esc(r.get(c).map_or("", String::as_str));
    let widest = |s: &str| s.split('\n').map(width_of).max().unwrap_or(0);
    // Pass 1: each column's widest line unwrapped (comfy-table's width: at
    // least 1), and a bounded column's narrowest.
    let mut natural: Vec<usize> = vec![1; cols.len()];
    let mut mins: Vec<usize> = vec![1; cols.len()];
    let mut measure = |r: &[String], head: bool| {
        for (k, &c) in cols.iter().enumerate() {
            let cell = cell_of(r, c);
            natural[k] = natural[k].max(widest(&cell));
            if bounds[k].is_some() {
                let m = if head {
                    header_min(&cell)
                } else {
                    cell_min(&cell)
                };
                mins[k] = mins[k].max(m);
            }
        }
    };
    measure(&t.header, true);
    t.for_each_row(|r| measure(r, false));
    // A bounded column wraps at its bound, or at its narrowest if wider.
    let wraps: Vec<Option<usize>> = bounds
        .iter()
        .zip(&mins)
        .map(|(b, &m)| b.map(|b| b.max(m)))
        .collect();
    let fitted = |k: usize, s: String| match wraps[k] {
        Some(w) => wrap(&s, w).join("\n"),
        None => s,
    };
    let pick = |r: &[String]| -> Vec<String> {
        cols.iter()
            .enumerate()
            .map(|(k, &c)| fitted(k, cell_of(r, c)))
            .collect()
    };
    let head = pick(&t.header);
    // Where no line is wider than its wrap, wrapping changes nothing: the
    // widths are the natural ones; else a second pass measures the wrapped
    // cells.
    let mut widths = natural.clone();
    if wraps
        .iter()
        .zip(&natural)
        .any(|(w, &n)| w.is_some_and(|w| n > w))
    {
        widths = head.iter().map(|h| widest(h).max(1)).collect();
        t.for_each_row(|r| {
            for (w, cell) in widths.iter_mut().zip(pick(r)) {
                *w = (*w).max(widest(&cell));
            }
        });
    }
    for w in &mut widths {
        *w = (*w).min(usize::from(u16::MAX));
    }
    // Pass 3: the borders and the rows.
    let rule = |left: &str, fill: &str, mid: &str, right: &str| {
        let parts: Vec<String> = widths.iter().map(|&w| fill.repeat(w + 2)).collect();
        format!("{left}{}{right}", parts.join(mid))
    };
    let mut line = String::new();
    let mut write_row = |cells: &[String], out: &mut dyn std::io::Write| {
        let lines: Vec<Vec<&str>> = cells.iter().map(|c| c.split('\n').collect()).collect();
        let depth = lines.iter().map(Vec::len).max().unwrap_or(0);
        for i in 0..depth {
            line.clear();
            line.push('│');
            for (k, (cell, &w)) in lines.iter().zip(&widths).enumerate() {
                if k > 0 {
                    line.push('┆');
                }
                line.push(' ');
                let s = cell.get(i).copied().unwrap_or("");
                line.push_str(s);
                line.push_str(&" ".repeat(w.saturating_sub(width_of(s)) + 1));
            }
            line.push_str("│\n");
            out.write_all(line.as_bytes())?;
        }
        Ok::<(), std::io::Error>(())
    };
    out.write_all(rule("┌", "─", "┬", "┐\n").as_bytes())?;
    write_row(&head, out)?;
    out.write_all(rule("╞", "═", "╪", "╡\n").as_bytes())?;
    t.try_for_each_row(|r| write_row(&pick(r), out))?;
    out.write_all(rule("└", "─", "┴", "┘").as_bytes())?;
    Ok(t.header.len() - cols.len())
}

/// A frame tree (`name  [file:line, ...]` under `├── ` branches) fitted to
/// `width`: a line too wide has its bracket moved to the next line, under
/// the name, the branches continued; the bracket is wrapped at its words.
pub fn fit_tree(text: &str, width: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let tree_chars = |l: &str| {
        l.chars()
            .take_while(|c| matches!(c, '│' | '├' | '└' | '─' | ' '))
            .count()
    };
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let split = line.find("  [").filter(|_| width_of(line) > width);
        let Some(at) = split else {
            out.push(line.to_string());
            continue;
        };
        let (head, tail) = (&line[..at], line[at..].trim_start());
        out.push(head.to_string());
        let depth = tree_chars(head);
        let branch: String = head
            .chars()
            .take(depth)
            .map(|c| match c {
                '├' | '│' => '│',
                _ => ' ',
            })
            .collect();
        // The frame's children hang from its name's first column.
        let kids = lines.get(i + 1).is_some_and(|n| tree_chars(n) > depth);
        let under = format!("{branch}{}", if kids { "│ " } else { "  " });
        // Under the name, or as far left as the bracket's longest word needs.
        let longest = tail.split(' ').map(width_of).max().unwrap_or(0);
        let keep = width_of(&under).min(width.saturating_sub(longest));
        let indent: String = under.chars().take(keep).collect();
        let room = width.saturating_sub(width_of(&indent));
        out.extend(pack(tail, room).into_iter().map(|l| format!("{indent}{l}")));
    }
    let mut s = out.join("\n");
    if text.ends_with('\n') {
        s.push('\n');
    }
    s
}

/// A tree line's tail (its place, then its numbers, two spaces apart) in
/// lines of at most `room` columns: whole parts side by side while they fit,
/// a part that fits no line wrapped by words (a vector is not split across
/// lines unless it alone is wider than the room).
fn pack(tail: &str, room: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut cur = String::new();
    for part in tail.split("  ").map(str::trim).filter(|p| !p.is_empty()) {
        let joined = if cur.is_empty() {
            part.to_string()
        } else {
            format!("{cur}  {part}")
        };
        if width_of(&joined) <= room {
            cur = joined;
            continue;
        }
        if !cur.is_empty() {
            lines.push(std::mem::take(&mut cur));
        }
        let mut wrapped = wrap(part, room);
        cur = wrapped.pop().unwrap_or_default();
        lines.extend(wrapped);
    }
    if !cur.is_empty() {
        lines.push(cur);
    }
    lines
}

/// A fitted table as records, for a terminal `width` wide: per row, one
/// `key: value` line per column (values aligned, wrapped under themselves;
/// under their key, indented, when the keys take half the width), rows
/// apart by a blank line. Only a single word wider than the terminal itself
/// can still exceed it.
pub fn records(f: &Fitted, width: usize) -> Vec<String> {
    let keys: Vec<String> = f
        .header
        .iter()
        .map(|h| format!("{}:", h.replace('\n', " ")))
        .collect();
    let kw = keys.iter().map(|k| width_of(k)).max().unwrap_or(0);
    let under = 2 * (kw + 1) > width;
    let indent = if under { 2 } else { kw + 1 };
    let mut out = Vec::new();
    for (i, row) in f.rows.iter().enumerate() {
        if i > 0 {
            out.push(String::new());
        }
        for (key, cell) in keys.iter().zip(row) {
            let values = wrap(cell, width.saturating_sub(indent));
            let pad = " ".repeat(indent);
            for (j, v) in values.iter().enumerate() {
                let line = match (j, under) {
                    (0, false) => format!("{key:<kw$} {v}"),
                    (0, true) => format!("{key}\n{pad}{v}"),
                    _ => format!("{pad}{v}"),
                };
                out.push(line.trim_end().to_string());
            }
        }
    }
    out
}

/// A one-line-per-row table ([`Table::one_line`]) drawn borderless: the
/// header (wrapped at its words, bottom-aligned), a rule, then one line per
/// row, columns [`BORDERLESS_GAP`] apart; the table's elided column is cut in
/// its middle with an ellipsis to fit, and columns left out from the right
/// on a terminal narrower than the table's compact set. `None`, and the
/// caller draws the bordered table, when not on a terminal, with `--wide`,
/// when the bordered table fits unwrapped, when a cell holds a line break, or
/// when even two columns do not fit (`one_line_cells`).
pub fn borderless(t: &Table, layout: &Layout) -> Option<(Vec<String>, usize)> {
    let elide = t.one_line?;
    let w = layout.width().filter(|_| t.wrap && !layout.wide)?;
    let mut cols = chosen_columns(t, layout, Some(w));
    if natural_width(t, &cols) <= w || t.rows.iter().flatten().any(|c| c.contains('\n')) {
        return None;
    }
    // A terminal narrower than 80: columns go from the right (never the
    // elided one) until the rest fits, unless `--columns` named them.
    let (widths, rows) = loop {
        if let Some(fitted) = one_line_cells(t, &cols, elide, w) {
            break fitted;
        }
        if !layout.columns.is_empty() || cols.len() <= 2 {
            return None;
        }
        let last = cols.len() - 1 - usize::from(cols[cols.len() - 1] == elide);
        cols.remove(last);
    };
    let heads: Vec<Vec<String>> = cols
        .iter()
        .zip(&widths)
        .map(|(&c, &cw)| wrap(&t.header[c], cw))
        .collect();
    let depth = heads.iter().map(Vec::len).max().unwrap_or(1);
    let line = |cells: &[&str]| -> String {
        let padded: Vec<String> = cells
            .iter()
            .zip(&widths)
            .map(|(s, &cw)| format!("{s}{}", " ".repeat(cw.saturating_sub(width_of(s)))))
            .collect();
        padded
            .join(&" ".repeat(BORDERLESS_GAP))
            .trim_end()
            .to_string()
    };
    let mut out = Vec::new();
    for i in 0..depth {
        // Bottom-aligned: a short header sits on the line above the rule.
        let cells: Vec<&str> = heads
            .iter()
            .map(|h| {
                let skip = depth - h.len();
                if i < skip {
                    ""
                } else {
                    h[i - skip].as_str()
                }
            })
            .collect();
        out.push(line(&cells));
    }
    let rules: Vec<String> = widths.iter().map(|&cw| "─".repeat(cw)).collect();
    out.push(line(&rules.iter().map(String::as_str).collect::<Vec<_>>()));
    for r in &rows {
        out.push(line(&r.iter().map(String::as_str).collect::<Vec<_>>()));
    }
    Some((out, t.header.len() - cols.len()))
}

/// The widest word of a header (it wraps at its words).
fn header_word(t: &Table, c: usize) -> usize {
    t.header[c]
        .split(['\n', ' '])
        .map(width_of)
        .max()
        .unwrap_or(0)
}

/// The columns' widths and the rows' cells of a borderless table `w` wide,
/// the `elide` column cut to fit; `None` when it would fall below
/// [`ELIDE_MIN_WIDTH`] or two of its cells would then read the same.
fn one_line_cells(
    t: &Table,
    cols: &[usize],
    elide: usize,
    w: usize,
) -> Option<(Vec<usize>, Vec<Vec<String>>)> {
    let mut widths: Vec<usize> = cols
        .iter()
        .map(|&c| column_max(t, c).max(header_word(t, c)))
        .collect();
    let total = widths.iter().sum::<usize>() + BORDERLESS_GAP * cols.len().saturating_sub(1);
    let mut rows: Vec<Vec<String>> = t
        .rows
        .iter()
        .map(|r| {
            cols.iter()
                .map(|&c| r.get(c).cloned().unwrap_or_default())
                .collect()
        })
        .collect();
    if total > w {
        let k = cols.iter().position(|&c| c == elide)?;
        let room = widths[k].checked_sub(total - w)?;
        if room < ELIDE_MIN_WIDTH.max(header_word(t, elide)) {
            return None;
        }
        widths[k] = room;
        let before: std::collections::HashSet<&String> = rows.iter().map(|r| &r[k]).collect();
        let cut: Vec<String> = rows.iter().map(|r| ellipsize(&r[k], room)).collect();
        let after: std::collections::HashSet<&String> = cut.iter().collect();
        if after.len() < before.len() {
            return None;
        }
        for (r, c) in rows.iter_mut().zip(cut) {
            r[k] = c;
        }
    }
    Some((widths, rows))
}

/// `s` cut to `w` columns by an ellipsis in its middle (ids differ at both
/// ends: `fusionport…-stim300`).
pub fn ellipsize(s: &str, w: usize) -> String {
    if width_of(s) <= w {
        return s.to_string();
    }
    let keep = w.saturating_sub(1);
    let (tail_w, mut head_w) = (keep / 2, keep - keep / 2);
    let mut head = String::new();
    for c in s.chars() {
        let cw = width_of(c.encode_utf8(&mut [0; 4]));
        if cw > head_w {
            break;
        }
        head_w -= cw;
        head.push(c);
    }
    let mut tail: Vec<char> = Vec::new();
    let mut left = tail_w + head_w;
    for c in s.chars().rev() {
        let cw = width_of(c.encode_utf8(&mut [0; 4]));
        if cw > left {
            break;
        }
        left -= cw;
        tail.push(c);
    }
    tail.reverse();
    format!("{head}…{}", tail.into_iter().collect::<String>())
}

/// A `Table::bounds` width counts the cell's padding (one space each side).
fn bound_width(b: u16) -> usize {
    usize::from(b).saturating_sub(2)
}

/// Share `width` among the columns: each gets its narrowest, then the room
/// left goes, a column at a time, to the one furthest from its natural width.
fn share(t: &Table, cols: &[usize], width: usize) -> Vec<usize> {
    let mut w: Vec<usize> = cols.iter().map(|&c| column_min(t, c)).collect();
    // A column's upper bound (`Table::bounds`) caps its natural width.
    let max: Vec<usize> = cols
        .iter()
        .zip(&w)
        .map(|(&c, &lo)| {
            let bound = t.bounds.iter().find(|b| b.0 == c).map(|b| bound_width(b.1));
            column_max(t, c).min(bound.unwrap_or(usize::MAX)).max(lo)
        })
        .collect();
    let frame = 3 * cols.len() + 1;
    if max.iter().sum::<usize>() + frame <= width {
        return max;
    }
    // Whole words where they fit: start each column at its longest word.
    let words: Vec<usize> = cols
        .iter()
        .zip(&max)
        .map(|(&c, &m)| column_longest_word(t, c).min(m))
        .zip(&w)
        .map(|(a, &b)| a.max(b))
        .collect();
    if words.iter().sum::<usize>() + frame <= width {
        w = words;
    }
    let mut room = width.saturating_sub(w.iter().sum::<usize>() + frame);
    while room > 0 {
        let Some(k) = (0..cols.len())
            .filter(|&k| w[k] < max[k])
            .max_by_key(|&k| (max[k] - w[k], usize::MAX - k))
        else {
            break;
        };
        w[k] += 1;
        room -= 1;
    }
    let lo: Vec<usize> = cols.iter().map(|&c| column_min(t, c)).collect();
    if (t.rows.len() + 1) * cols.len() > LAYOUT_REFINE_MAX_CELLS {
        return w;
    }
    fewer_lines(t, cols, w, &lo, &max)
}

/// What a cell costs at width `x`: its lines, and [`CUT_WORD_COST`] more when
/// a word is cut.
fn cost(cell: &str, x: usize) -> usize {
    let cut = cell.split(['\n', ' ']).any(|w| width_of(w) > x);
    wrap(cell, x).len() + if cut { CUT_WORD_COST } else { 0 }
}

/// Move width between columns while the table gets shorter (the header and
/// every row counted by its costliest cell): a row that one line can hold is
/// not wrapped because another column took the room first. Each pass tries
/// every move of `m` columns from one column to another and keeps the best;
/// `lo`/`hi` are the columns' narrowest and widest.
fn fewer_lines(
    t: &Table,
    cols: &[usize],
    mut w: Vec<usize>,
    lo: &[usize],
    hi: &[usize],
) -> Vec<usize> {
    let cell = |r: usize, c: usize| -> &str {
        let row = if r == 0 { &t.header } else { &t.rows[r - 1] };
        row.get(c).map_or("", String::as_str)
    };
    let n_rows = t.rows.len() + 1;
    // lines[k][x - lo[k]][r]: how many lines row r's cell takes at width x.
    let lines: Vec<Vec<Vec<usize>>> = cols
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            (lo[k]..=hi[k].max(lo[k]))
                .map(|x| (0..n_rows).map(|r| cost(cell(r, c), x)).collect())
                .collect()
        })
        .collect();
    let height = |w: &[usize]| -> usize {
        (0..n_rows)
            .map(|r| {
                (0..cols.len())
                    .map(|k| lines[k][w[k] - lo[k]][r])
                    .max()
                    .unwrap_or(1)
            })
            .sum()
    };
    let n = cols.len();
    let mut best = height(&w);
    // Each layout tried reads every cell once; the search stops when the
    // budget is spent, with the best found so far (a big table stays quick).
    let mut budget = LAYOUT_REFINE_BUDGET / (n_rows * n).max(1);
    loop {
        let mut found: Option<(Vec<usize>, usize)> = None;
        let mut try_move = |v: Vec<usize>| {
            if budget == 0 {
                return;
            }
            budget -= 1;
            let h = height(&v);
            if h < found.as_ref().map_or(best, |f| f.1) {
                found = Some((v, h));
            }
        };
        for a in 0..n {
            let spare = w[a].saturating_sub(lo[a]);
            for b in (0..n).filter(|&b| b != a) {
                for m in 1..=spare.min(hi[b].saturating_sub(w[b])) {
                    let mut v = w.clone();
                    v[a] -= m;
                    v[b] += m;
                    try_move(v.clone());
                    // A narrow table: the room may have to go to two columns
                    // at once (a row fits only when both widen).
                    for c in (b + 1..n).filter(|&c| c != a && n <= LAYOUT_REFINE_MAX_COLUMNS) {
                        for k in 1..=(spare - m).min(hi[c].saturating_sub(w[c])) {
                            let mut u = v.clone();
                            u[a] -= k;
                            u[c] += k;
                            try_move(u);
                        }
                    }
                }
            }
        }
        match found {
            Some((v, h)) => (w, best) = (v, h),
            None => return w,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_keeps_numbers_and_places_whole() {
        let s = "see tests/fixtures/urdf/anymal_c.urdf:666:5 for -0.1422 m";
        let lines = wrap(s, 12);
        assert!(lines.contains(&"tests/fixtures/urdf/anymal_c.urdf:666:5".to_string()));
        assert!(lines.iter().any(|l| l.contains("-0.1422")));
        assert!(lines.iter().all(|l| width_of(l) <= 12 || !l.contains(' ')));
        assert_eq!(lines.join(" "), s);
    }

    #[test]
    fn wrap_cuts_only_plain_words() {
        assert_eq!(wrap("abcdefghij", 4), ["abcd", "efgh", "ij"]);
        assert_eq!(wrap("1234567890", 4), ["1234567890"]);
        assert_eq!(wrap("a b\nc", 80), ["a b", "c"]);
        assert_eq!(wrap("ouster-os1-128", 8), ["ouster-", "os1-128"]);
        assert_eq!(wrap("1.5e-05 -0.0403", 4), ["1.5e-05", "-0.0403"]);
        assert_eq!(wrap("[-1.000, 0]", 4), ["[-1.000,", "0]"]);
    }

    #[test]
    fn a_table_fits_and_keeps_its_first_column() {
        let rows = vec![vec![
            "id-1".to_string(),
            "a fairly long sentence that has to wrap over several lines".to_string(),
            "0.1234".to_string(),
        ]];
        let t = Table::new(&["id", "why", "value (m)"], rows);
        let layout = Layout {
            width: Some(40),
            ..Layout::default()
        };
        let f = fit(&t, &layout);
        assert_eq!(f.hidden, 0);
        assert_eq!(f.rows[0][2], "0.1234");
        let widest = |s: &str| s.lines().map(width_of).max().unwrap_or(0);
        let total: usize = (0..3)
            .map(|k| widest(&f.rows[0][k]).max(widest(&f.header[k])))
            .sum();
        assert!(total + 10 <= 40, "{f:?}");
        assert!(f.rows[0][1].lines().count() > 1);
    }

    #[test]
    fn columns_are_matched_without_their_unit() {
        assert!(header_matches("lever arm (m)", "lever arm"));
        assert!(header_matches("lever arm (m)", "lever-arm"));
        assert!(!header_matches("lever arm (m)", "lever"));
    }

    #[test]
    fn ellipsis_cuts_in_the_middle() {
        assert_eq!(
            ellipsize("fusionportable-os1-128-stim300", 18),
            "fusionpor…-stim300"
        );
        assert_eq!(ellipsize("short", 18), "short");
        assert_eq!(width_of(&ellipsize("ab日本語cd日本語ef", 7)), 7);
    }

    fn ids_table(ids: &[&str]) -> Table {
        let rows = ids
            .iter()
            .map(|id| vec![id.to_string(), "0.0430".into(), "[0.9579, 1.044]".into()])
            .collect();
        Table::new(&["id", "lever arm (m)", "band at l = 1"], rows).one_line(0)
    }

    #[test]
    fn a_one_line_table_goes_borderless_and_elides_its_id() {
        let t = ids_table(&["a-very-long-rig-identifier-indeed", "short"]);
        let lay = |w| Layout {
            width: Some(w),
            ..Layout::default()
        };
        // Wide enough for the bordered table: none.
        assert!(borderless(&t, &lay(80)).is_none());
        let (lines, hidden) = borderless(&t, &lay(40)).unwrap();
        assert_eq!(hidden, 0);
        assert_eq!(
            lines,
            [
                "                 lever",
                "                 arm",
                "id               (m)     band at l = 1",
                "───────────────  ──────  ───────────────",
                "a-very-…-indeed  0.0430  [0.9579, 1.044]",
                "short            0.0430  [0.9579, 1.044]",
            ]
        );
        // Two ids that would read the same once cut: the bordered table instead.
        let twins = ids_table(&[
            "a-very-long-rig-identifier-indeed",
            "a-very-long-rig-XXidentifier-indeed",
        ]);
        assert!(borderless(&twins, &lay(40)).is_none());
        // With --wide: the bordered table too.
        assert!(borderless(
            &t,
            &Layout {
                width: Some(40),
                wide: true,
                ..Layout::default()
            }
        )
        .is_none());
    }

    #[test]
    fn an_unbreakable_word_wider_than_its_column_gives_records() {
        let t = Table::new(
            &["id", "file:line"],
            vec![vec![
                "r1".into(),
                "tests/fixtures/urdf/a_rather_long_name.urdf:666:5".into(),
            ]],
        );
        let lay = Layout {
            width: Some(40),
            wide: true,
            ..Layout::default()
        };
        let f = fit(&t, &lay);
        assert!(f.records);
        assert_eq!(
            records(&f, 40),
            [
                "id:        r1",
                "file:line: tests/fixtures/urdf/a_rather_long_name.urdf:666:5"
            ]
        );
        assert!(
            !fit(
                &t,
                &Layout {
                    width: Some(80),
                    ..lay
                }
            )
            .records
        );
    }

    #[test]
    fn a_tree_line_too_wide_puts_its_place_below() {
        let tree = "base\n├── lidar_link  [robot.urdf:10:5]\n│   └── x  [a.urdf:1:1]\n└── imu_link  [robot.urdf:20:5]\n";
        assert_eq!(
            fit_tree(tree, 24),
            "base\n├── lidar_link\n│   │ [robot.urdf:10:5]\n│   └── x  [a.urdf:1:1]\n└── imu_link\n      [robot.urdf:20:5]\n"
        );
        assert_eq!(fit_tree(tree, 80), tree);
    }

    #[test]
    fn a_big_table_of_prose_is_laid_out_within_the_width() {
        // 75 rows of five prose columns (under LAYOUT_REFINE_MAX_CELLS): the
        // tuning's budget bounds the work.
        let prose = "a fairly long sentence of words that has to wrap";
        let rows = (0..75)
            .map(|i| (0..5).map(|k| format!("{i} {k} {prose}")).collect())
            .collect();
        let t = Table::new(&["a", "b", "c", "d", "e"], rows);
        let lay = Layout {
            width: Some(80),
            ..Layout::default()
        };
        let start = std::time::Instant::now();
        let f = fit(&t, &lay);
        eprintln!("laid out in {:?}", start.elapsed());
        assert_eq!(f.hidden, 0);
        let widest = |s: &str| s.lines().map(width_of).max().unwrap_or(0);
        let total: usize = (0..5)
            .map(|k| widest(&f.rows[0][k]).max(widest(&f.header[k])))
            .sum();
        assert!(total + 16 <= 80, "{total}");
    }
}
