//! CSV (RFC 4180, minimal quoting): the report's one data table, tidy (issue
//! 33): a header row, one observation per row, one variable per column, one
//! number per cell (a vector is split into one column per component), units
//! in the column names, never a display string (`[x, y, z]`, `1.2 mm`) nor a
//! second table. Numbers carry every digit (the shortest text that reads
//! back as the same `f64`, as the JSON prints it), flags are `true`/`false`,
//! an empty cell is the JSON's `null` (or a key it leaves out). A report
//! without a data table (the frame tree, a picture) is refused.
//!
//! Columns are named as the JSON's keys (one name per concept): a vector's
//! component goes before the unit (`translation_m` -> `translation_x_m`,
//! `rpy_rad` -> `rpy_roll_rad`, `quaternion_xyzw` -> `quaternion_x`), six
//! eigenvalues (ascending) are `eigenvalues_1` .. `_6`, a footprint's six
//! twist axes `_rx` .. `_tz`, a band's edges `_low`, `_high`; a nested key
//! takes its parent's name where it alone is ambiguous (`screw_kind`), and
//! a value per characteristic length `l` is suffixed `_l{l}` (`band_l1_low`).
//! The row, per command (`src/report/data.rs` builds the tables, the
//! survey's and the spread's in their own modules):
//!
//! | command | one row per | JSON rows |
//! |---|---|---|
//! | `audit FILE... --from A --to B` | the chain (one row) | the report |
//! | `audit survey` | rig | `rigs[i]`, plus `placeholder`, `duplicate_of` |
//! | `audit check` | finding | `findings[i]` |
//! | `audit diff` | edge of either file | `edges[i]` |
//! | `audit spread` | calibration | `calibrations[i]` |
//! | `audit degeneracy` (a scan or a pair) | family | `families[i]` |
//! | `audit simulate` | family (frame A `_from`, B `_to`) | `families[i]` |
//! | `audit sweep` | family | `families[i]` |
//! | `audit tunnel` | frame (`on_axis`, `shifted`) | those objects |
//! | `audit calibrate-threshold` | (family, configuration) | `configurations[j]` |
//! | `audit run` | scan or pair, streamed | the JSON lines (`report::run`) |
//!
//! The frame tree (`--frames`) is a picture: it has no CSV.
//!
//! Formula injection (OWASP, "CSV Injection", owasp.org/www-community/attacks/CSV_Injection):
//! a spreadsheet reads a cell that begins with `=`, `+`, `-`, `@`, a tab, a
//! carriage return or a line feed as a formula, and a frame name is whatever
//! a file holds. Such a cell is written as OWASP's sanitisation says: a single
//! quote prepended (the spreadsheet shows the text), the cell wrapped in
//! double quotes, every double quote doubled (`=1+2";=1+2` becomes
//! `"'=1+2"";=1+2"`). One exception, ours (OWASP's page names none; the same
//! carve-out as WooCommerce's exporter, PR 53022, and csv-stringify, PR 510):
//! a cell that is a plain decimal number ([`is_number`]: `-0.3640`, `+1`,
//! `-1.5e-7`) stays as it is, so that pandas and a spreadsheet read a
//! negative number as a number; such a cell holds no operator, name or call,
//! so nothing in it can be evaluated. `-inf` and `-1,5` are not plain decimal
//! numbers and are escaped. Cells holding a separator (`,`, or `;` for a
//! spreadsheet in a locale that splits on it), a quote, a tab or a line break
//! are quoted, so that no part of a cell can begin a cell of its own.

use crate::document::{Block, Document, Table};

/// Render a document's data table as CSV: the one table a report marks
/// `data_only` (a document that has none is refused before this, by
/// `OutputFormat::draws`; a second one would be a second table in the file,
/// and is a bug of the report, caught by `tests/it/csv_tidy.rs`).
/// Written to `out` a row at a time (a streamed table is never held whole,
/// issue 29).
pub fn write(doc: &Document, out: &mut dyn std::io::Write) -> std::io::Result<()> {
    match doc.blocks.iter().find_map(|b| match b {
        Block::Table(t) if t.data_only => Some(t),
        _ => None,
    }) {
        Some(t) => table(t, out),
        None => Ok(()),
    }
}

/// One table as CSV, a record per line.
pub fn table(t: &Table, out: &mut dyn std::io::Write) -> std::io::Result<()> {
    let mut s = line(&t.header);
    s.push('\n');
    out.write_all(s.as_bytes())?;
    t.try_for_each_row(|r| {
        s.clear();
        s.push_str(&line(r));
        s.push('\n');
        out.write_all(s.as_bytes())
    })
}

/// One CSV record (no line end), each cell through `cell`. A command that
/// streams its rows (`audit run`) writes them with this.
pub fn line(cells: &[String]) -> String {
    cells.iter().map(|c| cell(c)).collect::<Vec<_>>().join(",")
}

/// First characters that make a spreadsheet read a cell as a formula (OWASP).
const FORMULA_STARTS: [char; 7] = ['=', '+', '-', '@', '\t', '\r', '\n'];

/// One cell: escaped when a spreadsheet would read it as a formula (and it
/// is not a plain number), quoted when it holds a separator, quote or line
/// break, as it is otherwise.
pub fn cell(s: &str) -> String {
    let quoted = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
    if s.starts_with(FORMULA_STARTS) && !is_number(s) {
        quoted(&format!("'{s}"))
    } else if s.contains([',', ';', '"', '\t', '\n', '\r']) {
        quoted(s)
    } else {
        s.to_string()
    }
}

/// A plain decimal number: an optional sign, digits with at most one decimal
/// point (at least one digit), an optional exponent `e`/`E` with an optional
/// sign and at least one digit; nothing else (no space, no `inf`, no `,`).
pub fn is_number(s: &str) -> bool {
    let b = s.as_bytes();
    let mut i = usize::from(b.first().is_some_and(|c| matches!(c, b'+' | b'-')));
    let digits = |i: &mut usize| {
        let start = *i;
        while b.get(*i).is_some_and(u8::is_ascii_digit) {
            *i += 1;
        }
        *i - start
    };
    let mut n = digits(&mut i);
    if b.get(i) == Some(&b'.') {
        i += 1;
        n += digits(&mut i);
    }
    if n == 0 {
        return false;
    }
    if b.get(i).is_some_and(|c| matches!(c, b'e' | b'E')) {
        i += 1;
        i += usize::from(b.get(i).is_some_and(|c| matches!(c, b'+' | b'-')));
        if digits(&mut i) == 0 {
            return false;
        }
    }
    i == b.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_plain_decimal_literals_only() {
        for n in ["0", "-0.3640", "+1", "-1.5e-7", "2E+10", ".5", "-5.", "12"] {
            assert!(is_number(n), "{n}");
        }
        for t in [
            "", "-", "+.", "-e5", "1e", "-1e+", "-inf", "-1,5", "-1 ", " 1", "-1+2", "1.2.3",
            "-0x10",
        ] {
            assert!(!is_number(t), "{t:?}");
        }
    }

    #[test]
    fn formulas_are_escaped_as_owasp_says() {
        // OWASP's two examples.
        assert_eq!(cell("=1+2\";=1+2"), "\"'=1+2\"\";=1+2\"");
        assert_eq!(cell("=1+2'\" ;,=1+2"), "\"'=1+2'\"\" ;,=1+2\"");
        assert_eq!(
            cell("-2+3+cmd|' /C calc'!A0"),
            "\"'-2+3+cmd|' /C calc'!A0\""
        );
        assert_eq!(cell("@SUM(1+1)"), "\"'@SUM(1+1)\"");
        assert_eq!(cell("\tx"), "\"'\tx\"");
        assert_eq!(cell("-0.3640"), "-0.3640");
        assert_eq!(cell("a;b"), "\"a;b\"");
        assert_eq!(cell("lidar"), "lidar");
    }
}
