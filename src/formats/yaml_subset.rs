//! A fast reader for the plain YAML most calibration files are written in
//! (a fleet's Autoware files among them): block mappings of plain keys whose
//! values are numbers, plain words, `true`/`false`, `null`, strings in quotes
//! on one line with no escape, nested block mappings or flow lists of those
//! scalars (over several lines too), with `#` comments and blank lines.
//!
//! It builds the tree [`super::yaml::parse_documents`]'s serde-saphyr path
//! builds, positions included, and returns `None` ("not in the subset") for
//! anything else: tabs, CR, non-ASCII outside comments, escapes, anchors, tags, block lists,
//! `---`, empty values, keywords such as `True`, `~` or `nan`, numbers
//! outside `-?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?`. serde-saphyr then
//! reads the text, so every error message and every other document is its
//! own. The tests compare the two readers on the shipped and fixture files,
//! their variants and thousands of one-character edits.

use super::yaml_node::{Node, Value};

/// Deeper mappings are left to serde-saphyr (and its nesting budget).
const MAX_DEPTH: usize = 32;

/// The words serde-saphyr types as something other than a string (or might:
/// `nan`, `inf`), compared ignoring case; `true` and `false` are read here
/// as it reads them, the rest (`True`, `NULL`, ...) left to it. With strict
/// booleans (`yaml::options`) YAML 1.1's `y`, `n`, `yes`, `off` ... are
/// strings (a tf dump's `y:`).
const KEYWORDS: [&str; 6] = ["null", "true", "false", "nan", "inf", "infinity"];

/// One open block mapping: its indent, where its first key is, its entries
/// so far, and the key whose value (a deeper mapping) is being read.
struct Frame {
    indent: usize,
    line: usize,
    column: usize,
    entries: Vec<(Node, Node)>,
    open: Option<Node>,
}

impl Frame {
    fn into_node(self) -> Node {
        Node {
            value: Value::Map(self.entries),
            line: self.line,
            column: self.column,
        }
    }
}

/// The one document of `text`, or `None` when the text is not in the subset.
pub(super) fn parse(text: &str) -> Option<Vec<Node>> {
    // Non-ASCII text may stand in comments only (a token is ASCII), but not
    // the characters YAML 1.1 breaks lines at; no control character but LF.
    let ascii_or_comment = |b: &u8| *b == b'\n' || (0x20..0x7f).contains(b) || *b >= 0x80;
    if !text.as_bytes().iter().all(ascii_or_comment) {
        return None;
    }
    let breaks = ['\u{85}', '\u{2028}', '\u{2029}'];
    if !text.is_ascii() && breaks.iter().any(|c| text.contains(*c)) {
        return None;
    }
    let mut stack: Vec<Frame> = Vec::new();
    let mut lines = text.split('\n').enumerate().map(|(k, l)| (k + 1, l));
    while let Some((no, line)) = lines.next() {
        let indent = indent_of(line);
        if is_blank(&line[indent..]) {
            continue;
        }
        open_level(&mut stack, indent, no)?;
        let (key, value) = entry(line, indent, no, &mut lines)?;
        let top = stack.last_mut()?;
        match value {
            Some(v) => top.entries.push((key, v)),
            None => top.open = Some(key),
        }
    }
    // A key left open has no value (a null): serde-saphyr's to read.
    while let Some(f) = stack.pop() {
        if f.open.is_some() {
            return None;
        }
        let node = f.into_node();
        match stack.last_mut() {
            Some(parent) => parent.entries.push((parent.open.take()?, node)),
            None => return Some(vec![node]),
        }
    }
    None
}

/// Make the mapping a line at `indent` belongs to the top of the stack: a
/// new one under the open key, or the enclosing one it returns to (closing
/// the deeper ones).
fn open_level(stack: &mut Vec<Frame>, indent: usize, line: usize) -> Option<()> {
    let new = |indent| Frame {
        indent,
        line,
        column: indent + 1,
        entries: Vec::new(),
        open: None,
    };
    let Some(top) = stack.last() else {
        // The document's mapping starts at the first column.
        (indent == 0).then(|| stack.push(new(0)))?;
        return Some(());
    };
    if top.open.is_some() {
        if indent <= top.indent || stack.len() >= MAX_DEPTH {
            return None;
        }
        stack.push(new(indent));
        return Some(());
    }
    while stack.last()?.indent > indent {
        let f = stack.pop()?;
        if f.open.is_some() {
            return None;
        }
        let node = f.into_node();
        let parent = stack.last_mut()?;
        let key = parent.open.take()?;
        parent.entries.push((key, node));
    }
    (stack.last()?.indent == indent).then_some(())
}

fn indent_of(line: &str) -> usize {
    line.bytes().take_while(|&b| b == b' ').count()
}

/// Nothing, or a comment, after the indent.
fn is_blank(rest: &str) -> bool {
    rest.is_empty() || rest.starts_with('#')
}

/// `KEY: VALUE` or `KEY:` (a deeper mapping follows) starting at byte
/// `indent` of `line`, the `line_no`-th; a flow list may go on over the
/// next `lines`.
fn entry<'a>(
    line: &'a str,
    indent: usize,
    line_no: usize,
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
) -> Option<(Node, Option<Node>)> {
    let b = line.as_bytes();
    let end = token_end(b, indent);
    let key = match scalar(&line[indent..end])? {
        v @ Value::Str(_) => v,
        _ => return None,
    };
    let key = Node {
        value: key,
        line: line_no,
        column: indent + 1,
    };
    if b.get(end) != Some(&b':') {
        return None;
    }
    let mut i = end + 1;
    if i < b.len() && b[i] != b' ' {
        return None;
    }
    i = skip_spaces(b, i);
    if i == b.len() || b[i] == b'#' {
        return Some((key, None));
    }
    let (value, last, after) = if b[i] == b'[' {
        flow_list(line, i, line_no, indent, lines)?
    } else {
        let (v, after) = item(line, i, line_no)?;
        (v, line, after)
    };
    line_end(last.as_bytes(), after)?;
    Some((key, Some(value)))
}

/// `[a, b, c]` from the `[` at byte `open` of `line`, over as many of the
/// next `lines` as it takes (each indented deeper than the key's `indent`):
/// the list, the line of its `]` and the byte after it.
fn flow_list<'a>(
    mut line: &'a str,
    open: usize,
    line_no: usize,
    indent: usize,
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
) -> Option<(Node, &'a str, usize)> {
    let (mut no, mut i) = (line_no, open + 1);
    let mut items = Vec::new();
    // After `[` or `,`: an item is due (or the `]` of an empty list).
    let mut due = true;
    loop {
        // Blanks, comments and line ends between the tokens.
        loop {
            let b = line.as_bytes();
            i = skip_spaces(b, i);
            if i < b.len() && b[i] != b'#' {
                break;
            }
            if i < b.len() && b[i - 1] != b' ' {
                return None;
            }
            let (n, next) = lines.next()?;
            let k = indent_of(next);
            if k <= indent && !next[k..].is_empty() {
                return None;
            }
            (line, no, i) = (next, n, k);
        }
        match (line.as_bytes()[i], due) {
            (b']', true) if items.is_empty() => break,
            (b']', false) => break,
            (b',', false) => (due, i) = (true, i + 1),
            (_, true) => {
                let (node, e) = item(line, i, no)?;
                items.push(node);
                (due, i) = (false, e);
            }
            _ => return None,
        }
    }
    let node = Node {
        value: Value::Seq(items),
        line: line_no,
        column: open + 1,
    };
    Some((node, line, i + 1))
}

/// A scalar from byte `i`: a quoted string or a token; the node and the byte
/// after it.
fn item(line: &str, i: usize, line_no: usize) -> Option<(Node, usize)> {
    let b = line.as_bytes();
    let (value, end) = match *b.get(i)? {
        q @ (b'"' | b'\'') => {
            // Quoted, on one line, with no escape (`\\`, `''`) to undo.
            let len = b[i + 1..].iter().position(|&c| c == q)?;
            let body = &line[i + 1..i + 1 + len];
            if body.contains('\\') || body.bytes().any(|c| c >= 0x80) {
                return None;
            }
            (Value::Str(body.to_string()), i + len + 2)
        }
        _ => {
            let e = token_end(b, i);
            (scalar(&line[i..e])?, e)
        }
    };
    let node = Node {
        value,
        line: line_no,
        column: i + 1,
    };
    Some((node, end))
}

/// After a value: blanks, then the line's end or a comment.
fn line_end(b: &[u8], i: usize) -> Option<()> {
    if i < b.len() && b[i] != b' ' {
        return None;
    }
    let i = skip_spaces(b, i);
    (i == b.len() || b[i] == b'#').then_some(())
}

fn skip_spaces(b: &[u8], mut i: usize) -> usize {
    while b.get(i) == Some(&b' ') {
        i += 1;
    }
    i
}

/// The end of the run of letters, digits and `_ . / -` from byte `i`.
fn token_end(b: &[u8], mut i: usize) -> usize {
    while i < b.len() && (b[i].is_ascii_alphanumeric() || b"_./-".contains(&b[i])) {
        i += 1;
    }
    i
}

/// A token typed as serde-saphyr types a plain scalar: a number, a word,
/// `true`/`false`, `null`; `None` for the empty token and whatever may be typed
/// otherwise.
fn scalar(t: &str) -> Option<Value> {
    let first = *t.as_bytes().first()?;
    if first.is_ascii_alphabetic() || first == b'_' {
        return match KEYWORDS.iter().find(|k| k.eq_ignore_ascii_case(t)) {
            None => Some(Value::Str(t.to_string())),
            Some(_) if t == "true" => Some(Value::Bool(true)),
            Some(_) if t == "false" => Some(Value::Bool(false)),
            Some(_) if matches!(t, "null" | "Null" | "NULL") => Some(Value::Null),
            Some(_) => None,
        };
    }
    number(t).map(Value::Num)
}

/// `-?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?`, the whole token: an
/// integer read as `i64` (then `f64`), a float by Rust's `f64` parse.
fn number(t: &str) -> Option<f64> {
    let b = t.as_bytes();
    let digits = |mut i: usize| {
        let s = i;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        (i, i - s)
    };
    let mut i = usize::from(b.first() == Some(&b'-'));
    let (e, n) = digits(i);
    if n == 0 || (n > 1 && b[i] == b'0') || n > 18 {
        return None;
    }
    i = e;
    let mut float = false;
    if b.get(i) == Some(&b'.') {
        let (e, n) = digits(i + 1);
        if n == 0 {
            return None;
        }
        (i, float) = (e, true);
    }
    if matches!(b.get(i), Some(b'e' | b'E')) {
        let sign = usize::from(matches!(b.get(i + 1), Some(b'+' | b'-')));
        let (e, n) = digits(i + 1 + sign);
        if n == 0 {
            return None;
        }
        (i, float) = (e, true);
    }
    if i != b.len() {
        return None;
    }
    if float {
        t.parse::<f64>().ok().filter(|x| x.is_finite())
    } else {
        t.parse::<i64>().ok().map(|x| x as f64)
    }
}
