//! Text from files, made safe to print: escaped so that it shows what it
//! holds and cannot act on a terminal or a log, and shortened so that a message
//! stays readable. A leaf module (imports only `tolerances`): the readers,
//! `diagnostic`, `render` and the CLI use it.
//!
//! [`visible`] shows control characters, line and paragraph separators and
//! bidirectional-text controls as escapes (`\n`, `\r`, `\x1b`, `\u{202e}`);
//! a tab stays a tab. [`guard_line_start`] escapes the first character of a
//! line that a CI log would read as a command (`::` GitHub workflow commands,
//! `##` Azure/legacy ones). [`shorten`] keeps the head and the tail of a long
//! value and says how many characters were cut. JSON never goes through here:
//! it stays exact.

use crate::tolerances::MAX_QUOTED_CHARS;
use std::borrow::Cow;
use std::fmt::Write as _;

/// Whether `c` is shown as an escape: control characters (C0, DEL, C1)
/// except tab, the Unicode line and paragraph separators, and the
/// bidirectional-text controls (embeddings, overrides, isolates, marks).
pub fn needs_escape(c: char) -> bool {
    (c.is_control() && c != '\t')
        || matches!(
            c,
            '\u{2028}' | '\u{2029}' | '\u{061c}' | '\u{200e}' | '\u{200f}'
                | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}'
        )
}

/// `s` with every character [`needs_escape`] picks written as an escape;
/// with `keep_newlines`, `\n` stays a line break (for multi-line blocks whose
/// line breaks are the report's own).
pub fn visible(s: &str, keep_newlines: bool) -> Cow<'_, str> {
    let pick = |c: char| needs_escape(c) && !(keep_newlines && c == '\n');
    if !s.chars().any(pick) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if !pick(c) {
            out.push(c);
            continue;
        }
        match c {
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\0' => out.push_str("\\0"),
            c if (c as u32) < 0x80 => {
                let _ = write!(out, "\\x{:02x}", c as u32);
            }
            c => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
        }
    }
    Cow::Owned(out)
}

/// `line` with its first character escaped when the line (after leading
/// spaces) would start a CI log command: `::` (GitHub) or `##` (Azure, the
/// legacy `##[error]`).
pub fn guard_line_start(line: &str) -> Cow<'_, str> {
    let body = line.trim_start();
    if !(body.starts_with("::") || body.starts_with("##")) {
        return Cow::Borrowed(line);
    }
    let indent = &line[..line.len() - body.len()];
    let first = if body.starts_with(':') {
        "\\x3a"
    } else {
        "\\x23"
    };
    Cow::Owned(format!("{indent}{first}{}", &body[1..]))
}

/// Every line of `text` through [`guard_line_start`].
pub fn guard_lines(text: &str) -> Cow<'_, str> {
    if !text
        .split('\n')
        .any(|l| matches!(guard_line_start(l), Cow::Owned(_)))
    {
        return Cow::Borrowed(text);
    }
    let lines: Vec<Cow<str>> = text.split('\n').map(guard_line_start).collect();
    Cow::Owned(lines.join("\n"))
}

/// A multi-line block for a terminal or a log: [`visible`] keeping its line
/// breaks, then [`guard_lines`].
pub fn block(text: &str) -> String {
    guard_lines(&visible(text, true)).into_owned()
}

/// One line for a terminal or a log: `visible` (a line break in it shown as
/// `\n`), then `guard_line_start`.
pub fn line(text: &str) -> String {
    guard_line_start(&visible(text, false)).into_owned()
}

/// `s` cut to at most `max` characters plus a note: the head and the tail
/// kept, the middle replaced by `...[N characters cut]...`.
pub fn shorten(s: &str, max: usize) -> Cow<'_, str> {
    if s.len() <= max {
        return Cow::Borrowed(s);
    }
    let n = s.chars().count();
    if n <= max {
        return Cow::Borrowed(s);
    }
    let head = max.div_ceil(2);
    let tail = max - head;
    let cut = n - head - tail;
    let h: String = s.chars().take(head).collect();
    let t: String = s.chars().skip(n - tail).collect();
    Cow::Owned(format!("{h}...[{cut} characters cut]...{t}"))
}

/// A value from a file shortened to [`MAX_QUOTED_CHARS`], for a message that
/// quotes it with `{:?}` (which escapes control characters itself).
pub fn clip(s: &str) -> Cow<'_, str> {
    shorten(s, MAX_QUOTED_CHARS)
}

/// A value from a file as a message quotes it: shortened to
/// [`MAX_QUOTED_CHARS`] and made [`visible`] on one line.
pub fn quote(s: &str) -> String {
    visible(&shorten(s, MAX_QUOTED_CHARS), false).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn controls_and_bidi_are_shown() {
        assert_eq!(
            visible("a\nb\x1b[31m\u{202e}c\td", false),
            "a\\nb\\x1b[31m\\u{202e}c\td"
        );
        assert_eq!(visible("a\nb\r", true), "a\nb\\r");
        assert_eq!(visible("\0\u{85}\u{2028}", false), "\\0\\u{85}\\u{2028}");
        assert!(matches!(visible("plain é", false), Cow::Borrowed(_)));
    }

    #[test]
    fn log_commands_cannot_start_a_line() {
        assert_eq!(
            guard_line_start("::error file=x::F"),
            "\\x3a:error file=x::F"
        );
        assert_eq!(guard_line_start("  ##[error]x"), "  \\x23#[error]x");
        assert_eq!(
            guard_lines("ok\n::warning::x\nok"),
            "ok\n\\x3a:warning::x\nok"
        );
        assert_eq!(line("lidar\n::error::X"), "lidar\\n::error::X");
    }

    #[test]
    fn long_values_keep_head_tail_and_the_count_cut() {
        let s = "a".repeat(10) + &"b".repeat(1000) + &"c".repeat(10);
        let q = shorten(&s, 20);
        assert_eq!(
            q,
            format!(
                "{}...[1000 characters cut]...{}",
                "a".repeat(10),
                "c".repeat(10)
            )
        );
        assert_eq!(shorten("short", 20), "short");
    }
}
