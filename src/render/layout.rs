//! Fitting text to a terminal: which columns a table shows and how wide each
//! is, and word wrapping that never splits a number, a path or a `file:line`.
//!
//! Conventions: widths are display columns (`unicode-width`); a table drawn
//! by comfy-table's condensed preset takes `3 n + 1` columns of borders and
//! padding for `n` columns. A `width` of `None` means the output is not a
//! terminal: every column is shown and nothing is wrapped (the full,
//! machine-friendly table).

use super::document::Table;
use crate::diagnostic::{Error, Result};
use crate::tolerances::{MIN_TERMINAL_WIDTH, SOFT_WORD_MIN_WIDTH};
use unicode_width::UnicodeWidthStr;

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

fn column_min(t: &Table, c: usize) -> usize {
    cells(t, c)
        .flat_map(|s| s.split(['\n', ' ']))
        .map(word_min)
        .max()
        .unwrap_or(0)
        .max(1)
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
            Some(share(t, &cols, w))
        }
    };
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
    }
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
    w
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
}
