//! A fast reader of the plain TOML the rig files are written in (issue 29:
//! lexing and building the `toml` crate's document was a third of checking
//! a rig file). It reads the subset only, and says `None` on anything else,
//! valid TOML or not: the `toml` crate then reads the file, and words every
//! error. So it never decides that a file is wrong, and what it accepts it
//! must read exactly as the `toml` crate does (`rig_toml`'s tests compare the
//! two on every shipped rig file and on variants of them).
//!
//! The subset: `#` comments; the headers `[rig]`, `[rig.source]`,
//! `[[transform]]` and `[[include]]` written exactly so; bare keys; basic
//! strings on one line with the escapes `\" \\ \b \t \n \f \r`; `true` and
//! `false`; decimal numbers (`-0.5`, `1e-3`, `3`: no `_`, no `inf`, `nan`,
//! hexadecimal or leading zeros); arrays of these over any lines, with
//! comments and a trailing comma. No control character but tab outside line
//! ends (LF or CRLF). Not in it: quoted or dotted keys, literal and
//! multi-line strings, inline tables, dates, other headers; a duplicate key
//! is not either (the `toml` crate refuses it).

use std::borrow::Cow;
use std::ops::Range;

/// Which table a header opens (`Root`: the keys before any header).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Header {
    Root,
    Rig,
    RigSource,
    Transform,
    Include,
}

/// A value of the subset; a number with the span of its digits.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Value<'a> {
    Str(Cow<'a, str>),
    Bool(bool),
    Num(f64, Range<usize>),
    Array(Vec<Value<'a>>),
}

/// One table: its header's span (empty for the root), its keys in order.
#[derive(Debug)]
pub(crate) struct Table<'a> {
    pub(crate) header: Header,
    pub(crate) span: Range<usize>,
    pub(crate) entries: Vec<(&'a str, Value<'a>)>,
}

/// Arrays nest at most this deep (a rig's matrices: two).
const MAX_DEPTH: usize = 3;

const HEADERS: [(&str, Header); 4] = [
    ("[[transform]]", Header::Transform),
    ("[[include]]", Header::Include),
    ("[rig.source]", Header::RigSource),
    ("[rig]", Header::Rig),
];

/// The tables of `text` in order, the root first; `None` when the text
/// leaves the subset (see the module doc).
pub(crate) fn parse(text: &str) -> Option<Vec<Table<'_>>> {
    let mut c = Cur {
        s: text,
        b: text.as_bytes(),
        i: 0,
    };
    let mut tables = vec![Table {
        header: Header::Root,
        span: 0..0,
        entries: Vec::new(),
    }];
    loop {
        c.blank();
        let Some(&ch) = c.b.get(c.i) else {
            return Some(tables);
        };
        match ch {
            b'#' | b'\r' | b'\n' => c.line_end()?,
            b'[' => {
                let rest = &c.s[c.i..];
                let (h, kind) = HEADERS.iter().find(|(h, _)| rest.starts_with(h))?;
                let start = c.i;
                c.i += h.len();
                c.line_end()?;
                tables.push(Table {
                    header: *kind,
                    span: start..start + h.len(),
                    entries: Vec::with_capacity(16),
                });
            }
            _ => {
                let key = c.key()?;
                c.blank();
                c.eat(b'=')?;
                c.blank();
                let v = c.value(0)?;
                c.line_end()?;
                let t = tables.last_mut()?;
                if t.entries.iter().any(|(k, _)| *k == key) {
                    return None;
                }
                t.entries.push((key, v));
            }
        }
    }
}

/// Whether `b` holds a control character TOML refuses in a string or a
/// comment (all but tab).
fn has_control(b: &[u8]) -> bool {
    // Eight bytes at a time: a word with no byte below 0x20 and none equal
    // to 0x7f holds none (the usual one: strings and comments are a rig
    // file's longest runs, issue 29); a word that may hold one, a tab
    // among them, is looked at byte by byte.
    const ONES: u64 = 0x0101_0101_0101_0101;
    const HIGH: u64 = 0x8080_8080_8080_8080;
    let below = |x: u64, n: u64| x.wrapping_sub(ONES * n) & !x & HIGH != 0;
    let mut words = b.chunks_exact(8);
    for w in &mut words {
        let x = u64::from_le_bytes(w.try_into().unwrap_or([0; 8]));
        if (below(x, 0x20) || below(x ^ (ONES * 0x7f), 1)) && has_control_bytes(w) {
            return true;
        }
    }
    has_control_bytes(words.remainder())
}

fn has_control_bytes(b: &[u8]) -> bool {
    b.iter().any(|&c| (c < 0x20 && c != b'\t') || c == 0x7f)
}

struct Cur<'a> {
    s: &'a str,
    b: &'a [u8],
    i: usize,
}

impl<'a> Cur<'a> {
    fn peek(&self) -> Option<u8> {
        self.b.get(self.i).copied()
    }

    fn eat(&mut self, ch: u8) -> Option<()> {
        (self.peek() == Some(ch)).then(|| self.i += 1)
    }

    /// Spaces and tabs.
    fn blank(&mut self) {
        while matches!(self.peek(), Some(b' ' | b'\t')) {
            self.i += 1;
        }
    }

    /// The end of a line: a comment, then LF, CRLF or the end of the text.
    fn line_end(&mut self) -> Option<()> {
        self.blank();
        if self.peek() == Some(b'#') {
            let rest = &self.b[self.i..];
            let end = memchr::memchr2(b'\n', b'\r', rest).unwrap_or(rest.len());
            if has_control(&rest[..end]) {
                return None;
            }
            self.i += end;
        }
        match self.peek() {
            None => Some(()),
            Some(b'\n') => {
                self.i += 1;
                Some(())
            }
            Some(b'\r') if self.b.get(self.i + 1) == Some(&b'\n') => {
                self.i += 2;
                Some(())
            }
            _ => None,
        }
    }

    /// Blanks, line ends and comments (between an array's values).
    fn space(&mut self) -> Option<()> {
        loop {
            self.blank();
            match self.peek() {
                Some(b'#' | b'\n' | b'\r') => self.line_end()?,
                _ => return Some(()),
            }
        }
    }

    fn key(&mut self) -> Option<&'a str> {
        let start = self.i;
        while matches!(
            self.peek(),
            Some(b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'_' | b'-')
        ) {
            self.i += 1;
        }
        (self.i > start).then(|| &self.s[start..self.i])
    }

    fn value(&mut self, depth: usize) -> Option<Value<'a>> {
        match self.peek()? {
            b'"' => self.string().map(Value::Str),
            b'[' if depth < MAX_DEPTH => self.array(depth + 1),
            b't' | b'f' => {
                let rest = &self.s[self.i..];
                let (word, v) = if rest.starts_with("true") {
                    ("true", true)
                } else if rest.starts_with("false") {
                    ("false", false)
                } else {
                    return None;
                };
                self.i += word.len();
                self.delimited()?;
                Some(Value::Bool(v))
            }
            b'0'..=b'9' | b'+' | b'-' => self.number(),
            _ => None,
        }
    }

    /// What may follow a scalar: a blank, a comma, a closing bracket, a
    /// comment, a line end or the end of the text.
    fn delimited(&self) -> Option<()> {
        match self.peek() {
            None | Some(b' ' | b'\t' | b',' | b']' | b'#' | b'\r' | b'\n') => Some(()),
            _ => None,
        }
    }

    fn digits(&mut self) -> usize {
        let start = self.i;
        while matches!(self.peek(), Some(b'0'..=b'9')) {
            self.i += 1;
        }
        self.i - start
    }

    /// `[+-]? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?`: an
    /// integer (read as `i64`, then `f64`, as serde reads one into an `f64`)
    /// or a float (Rust's `f64` parse of the digits, as the `toml` crate's).
    fn number(&mut self) -> Option<Value<'a>> {
        let start = self.i;
        if matches!(self.peek(), Some(b'+' | b'-')) {
            self.i += 1;
        }
        let int_start = self.i;
        let n = self.digits();
        if n == 0 || (n > 1 && self.b[int_start] == b'0') {
            return None;
        }
        let mut float = false;
        if self.peek() == Some(b'.') {
            self.i += 1;
            if self.digits() == 0 {
                return None;
            }
            float = true;
        }
        if matches!(self.peek(), Some(b'e' | b'E')) {
            self.i += 1;
            if matches!(self.peek(), Some(b'+' | b'-')) {
                self.i += 1;
            }
            if self.digits() == 0 {
                return None;
            }
            float = true;
        }
        self.delimited()?;
        let lit = &self.s[start..self.i];
        let x = if float {
            lit.parse::<f64>().ok().filter(|x| x.is_finite())?
        } else {
            lit.parse::<i64>().ok()? as f64
        };
        Some(Value::Num(x, start..self.i))
    }

    /// A basic string on one line (borrowed when it holds no escape).
    fn string(&mut self) -> Option<Cow<'a, str>> {
        self.eat(b'"')?;
        let mut owned: Option<String> = None;
        let mut run = self.i;
        loop {
            // Up to the next quote or backslash: plain text, if it holds no
            // control character (a line end among them).
            let k = memchr::memchr2(b'"', b'\\', &self.b[self.i..])?;
            if has_control(&self.b[self.i..self.i + k]) {
                return None;
            }
            self.i += k;
            if self.b[self.i] == b'"' {
                let tail = &self.s[run..self.i];
                self.i += 1;
                self.delimited()?;
                return Some(match owned {
                    None => Cow::Borrowed(tail),
                    Some(mut o) => {
                        o.push_str(tail);
                        Cow::Owned(o)
                    }
                });
            }
            // A backslash.
            let esc = match self.b.get(self.i + 1)? {
                b'"' => '"',
                b'\\' => '\\',
                b'b' => '\u{8}',
                b't' => '\t',
                b'n' => '\n',
                b'f' => '\u{c}',
                b'r' => '\r',
                _ => return None,
            };
            let o = owned.get_or_insert_with(String::new);
            o.push_str(&self.s[run..self.i]);
            o.push(esc);
            self.i += 2;
            run = self.i;
        }
    }

    fn array(&mut self, depth: usize) -> Option<Value<'a>> {
        self.eat(b'[')?;
        let mut items = Vec::with_capacity(4);
        loop {
            self.space()?;
            if self.eat(b']').is_some() {
                break;
            }
            items.push(self.value(depth)?);
            self.space()?;
            if self.eat(b',').is_none() {
                self.eat(b']')?;
                break;
            }
        }
        self.delimited()?;
        Some(Value::Array(items))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_word_at_a_time_control_test_agrees_with_the_byte_one() {
        // Every byte value at every place of runs of 1 to 19 bytes (words
        // and a remainder), amid text, tabs or high bytes.
        for fill in [b'a', b'\t', 0xc3, 0x7e, 0x20] {
            for len in 1..20 {
                for at in 0..len {
                    for c in 0..=255u8 {
                        let mut b = vec![fill; len];
                        b[at] = c;
                        assert_eq!(has_control(&b), has_control_bytes(&b), "{b:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_subset_reads_values_and_spans() {
        let t = "# c\n[rig]\nid = \"a\\\"b\" # x\nok = true\r\n[[transform]]\nt = [1, -0.5,\n  2e-3, # c\n]\n";
        let tables = parse(t).expect("in the subset");
        assert_eq!(tables.len(), 3);
        assert_eq!(tables[1].header, Header::Rig);
        assert_eq!(&t[tables[1].span.clone()], "[rig]");
        assert_eq!(tables[1].entries[0], ("id", Value::Str("a\"b".into())));
        assert_eq!(tables[1].entries[1], ("ok", Value::Bool(true)));
        let Value::Array(xs) = &tables[2].entries[0].1 else {
            panic!("an array");
        };
        let nums: Vec<(f64, &str)> = xs
            .iter()
            .map(|v| match v {
                Value::Num(x, s) => (*x, &t[s.clone()]),
                _ => panic!("a number"),
            })
            .collect();
        assert_eq!(nums, vec![(1.0, "1"), (-0.5, "-0.5"), (2e-3, "2e-3")]);
    }

    #[test]
    fn anything_else_is_left_to_the_toml_crate() {
        for t in [
            "a = 01\n",
            "a = 1_000\n",
            "a = inf\n",
            "a = 1.\n",
            "a = .5\n",
            "a = 1979-05-27\n",
            "a = 'lit'\n",
            "a = \"\"\"m\"\"\"\n",
            "a = \"\\u0041\"\n",
            "a = {b = 1}\n",
            "\"q\" = 1\n",
            "a.b = 1\n",
            "a = 1\na = 2\n",
            "[other]\n",
            "[ rig ]\n",
            "a = 1 b = 2\n",
            "a = \"x\ty\u{1}\"\n",
            "a = 1\rb = 2\n",
            "a = [[[[1]]]]\n",
            "a = [1 2]\n",
            "a = true1\n",
        ] {
            assert!(parse(t).is_none(), "{t:?}");
        }
        assert!(parse("a = \"x\ty\"\nb = [\n]\n").is_some());
    }
}
