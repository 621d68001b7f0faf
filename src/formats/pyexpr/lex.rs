//! Python's tokens, as far as launch files use them: names, numbers, strings
//! (prefixes r, b, u, f; triple quotes; escapes), operators, and for whole
//! files NEWLINE / INDENT / DEDENT with brackets and `\` joining lines.

use crate::diagnostic::{Error, Result};

/// One token.
#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    Name(String),
    Int(i64),
    Float(f64),
    /// A string literal: its value, whether it is an f-string (the value is
    /// then the raw text between the quotes) and its first line.
    Str {
        value: String,
        fstring: bool,
    },
    Op(&'static str),
    Newline,
    Indent,
    Dedent,
    End,
}

/// A token with its 1-based line and column.
#[derive(Debug, Clone)]
pub struct Token {
    pub tok: Tok,
    pub line: usize,
    pub col: usize,
}

const OPS: &[&str] = &[
    "**=", "//=", ">>=", "<<=", "...", "->", ":=", "**", "//", "<<", ">>", "<=", ">=", "==", "!=",
    "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "@=", "(", ")", "[", "]", "{", "}", ",", ":",
    ".", ";", "+", "-", "*", "/", "%", "<", ">", "=", "&", "|", "^", "~", "@",
];

/// A lexer error at `line`, `col`.
pub fn err(line: usize, col: usize, msg: impl Into<String>) -> Error {
    Error::parse(msg.into()).at_line(line, Some(col))
}

struct Lexer<'a> {
    s: &'a [u8],
    text: &'a str,
    i: usize,
    line: usize,
    line_start: usize,
    depth: usize,
    out: Vec<Token>,
}

impl Lexer<'_> {
    fn col(&self) -> usize {
        self.text[self.line_start..self.i].chars().count() + 1
    }
    fn push(&mut self, tok: Tok, line: usize, col: usize) {
        self.out.push(Token { tok, line, col });
    }
    fn newline(&mut self) {
        self.i += 1;
        self.line += 1;
        self.line_start = self.i;
    }
}

/// The tokens of `text`. `file`: a whole module (NEWLINE, INDENT and DEDENT
/// tokens); else one expression (newlines are blanks). `line0` is the line
/// the text starts on (for messages).
pub fn tokens(text: &str, file: bool, line0: usize) -> Result<Vec<Token>> {
    let mut lx = Lexer {
        s: text.as_bytes(),
        text,
        i: 0,
        line: line0,
        line_start: 0,
        depth: 0,
        out: Vec::new(),
    };
    let mut indents = vec![0usize];
    let mut at_line_start = true;
    while lx.i < lx.s.len() {
        // A line inside brackets continues the logical line.
        at_line_start &= lx.depth == 0;
        if file && at_line_start {
            at_line_start = false;
            let mut width = 0;
            while lx.i < lx.s.len() && matches!(lx.s[lx.i], b' ' | b'\t' | b'\x0c') {
                width += if lx.s[lx.i] == b'\t' {
                    8 - width % 8
                } else {
                    1
                };
                lx.i += 1;
            }
            // Blank and comment-only lines do not change the indentation.
            if lx.i >= lx.s.len() || matches!(lx.s[lx.i], b'\n' | b'#' | b'\r') {
                skip_to_eol(&mut lx);
                if lx.i < lx.s.len() {
                    lx.newline();
                }
                at_line_start = true;
                continue;
            }
            let (line, col) = (lx.line, lx.col());
            if width > *indents.last().unwrap_or(&0) {
                indents.push(width);
                lx.push(Tok::Indent, line, col);
            } else {
                while width < *indents.last().unwrap_or(&0) {
                    indents.pop();
                    lx.push(Tok::Dedent, line, col);
                }
                if width != *indents.last().unwrap_or(&0) {
                    return Err(err(
                        line,
                        col,
                        "unindent does not match any outer indentation level",
                    ));
                }
            }
        }
        let c = lx.s[lx.i];
        match c {
            b'\n' => {
                if file
                    && lx.depth == 0
                    && !matches!(lx.out.last().map(|t| &t.tok), Some(Tok::Newline) | None)
                {
                    let (l, c) = (lx.line, lx.col());
                    lx.push(Tok::Newline, l, c);
                }
                lx.newline();
                at_line_start = true;
            }
            b' ' | b'\t' | b'\r' | b'\x0c' => lx.i += 1,
            b'#' => skip_to_eol(&mut lx),
            b'\\' if lx.s.get(lx.i + 1) == Some(&b'\n') => {
                lx.i += 1;
                lx.newline();
            }
            b'\\' if lx.s.get(lx.i + 1) == Some(&b'\r') && lx.s.get(lx.i + 2) == Some(&b'\n') => {
                lx.i += 2;
                lx.newline();
            }
            b'0'..=b'9' => number(&mut lx)?,
            b'.' if lx.s.get(lx.i + 1).is_some_and(u8::is_ascii_digit) => number(&mut lx)?,
            b'"' | b'\'' => string(&mut lx, String::new())?,
            c if c == b'_' || c.is_ascii_alphabetic() || c >= 0x80 => name_or_prefixed(&mut lx)?,
            _ => op(&mut lx)?,
        }
    }
    let (l, c) = (lx.line, lx.col());
    if file {
        if !matches!(lx.out.last().map(|t| &t.tok), Some(Tok::Newline) | None) {
            lx.push(Tok::Newline, l, c);
        }
        for _ in 1..indents.len() {
            lx.push(Tok::Dedent, l, c);
        }
    }
    lx.push(Tok::End, l, c);
    Ok(lx.out)
}

fn skip_to_eol(lx: &mut Lexer) {
    while lx.i < lx.s.len() && lx.s[lx.i] != b'\n' {
        lx.i += 1;
    }
}

fn op(lx: &mut Lexer) -> Result<()> {
    let (line, col) = (lx.line, lx.col());
    let rest = &lx.text[lx.i..];
    let Some(o) = OPS.iter().find(|o| rest.starts_with(**o)) else {
        let ch = rest.chars().next().unwrap_or(' ');
        return Err(err(line, col, format!("unexpected character {ch:?}")));
    };
    match *o {
        "(" | "[" | "{" => lx.depth += 1,
        ")" | "]" | "}" => lx.depth = lx.depth.saturating_sub(1),
        _ => {}
    }
    lx.i += o.len();
    lx.push(Tok::Op(o), line, col);
    Ok(())
}

fn name_or_prefixed(lx: &mut Lexer) -> Result<()> {
    let (line, col) = (lx.line, lx.col());
    let start = lx.i;
    while lx.i < lx.s.len() {
        let ch = lx.text[lx.i..].chars().next().unwrap_or(' ');
        if ch == '_' || ch.is_alphanumeric() {
            lx.i += ch.len_utf8();
        } else {
            break;
        }
    }
    let word = &lx.text[start..lx.i];
    if word.is_empty() {
        // A non-ASCII character that is no letter (`€`, U+FFFD): Python's
        // "invalid character". Without this the lexer stood still on it,
        // pushing empty names until memory ran out (found by fuzzing xacro,
        // whose expression lexer had the same fault).
        let ch = lx.text[lx.i..].chars().next().unwrap_or('?');
        return Err(err(
            line,
            col,
            format!("invalid character {ch:?} (U+{:04X})", ch as u32),
        ));
    }
    let is_prefix = word.len() <= 2 && word.chars().all(|c| "rRbBuUfF".contains(c));
    if is_prefix && lx.i < lx.s.len() && matches!(lx.s[lx.i], b'"' | b'\'') {
        return string(lx, word.to_ascii_lowercase());
    }
    lx.push(Tok::Name(word.to_string()), line, col);
    Ok(())
}

fn number(lx: &mut Lexer) -> Result<()> {
    let (line, col) = (lx.line, lx.col());
    let start = lx.i;
    let s = lx.s;
    let hex = s[lx.i] == b'0'
        && matches!(
            s.get(lx.i + 1),
            Some(b'x' | b'X' | b'o' | b'O' | b'b' | b'B')
        );
    if hex {
        lx.i += 2;
        while lx.i < s.len() && (s[lx.i].is_ascii_alphanumeric() || s[lx.i] == b'_') {
            lx.i += 1;
        }
        let t = lx.text[start..lx.i].replace('_', "");
        let radix = match t.as_bytes()[1] | 0x20 {
            b'x' => 16,
            b'o' => 8,
            _ => 2,
        };
        let v = i64::from_str_radix(&t[2..], radix)
            .map_err(|_| err(line, col, format!("integer {t}: not a 64-bit integer")))?;
        lx.push(Tok::Int(v), line, col);
        return Ok(());
    }
    let mut float = false;
    while lx.i < s.len() {
        let c = s[lx.i];
        if c.is_ascii_digit() || c == b'_' {
            lx.i += 1;
        } else if c == b'.' && !float {
            float = true;
            lx.i += 1;
        } else if (c == b'e' || c == b'E') && lx.i > start {
            float = true;
            lx.i += 1;
            if lx.i < s.len() && matches!(s[lx.i], b'+' | b'-') {
                lx.i += 1;
            }
        } else {
            break;
        }
    }
    if lx.i < s.len() && matches!(s[lx.i], b'j' | b'J') {
        return Err(err(line, col, "complex numbers are not evaluated"));
    }
    let t = lx.text[start..lx.i].replace('_', "");
    let tok = if float {
        Tok::Float(
            t.parse()
                .map_err(|_| err(line, col, format!("malformed number {t}")))?,
        )
    } else {
        Tok::Int(t.parse().map_err(|_| {
            err(
                line,
                col,
                format!("integer {t}: beyond 64 bits, not evaluated"),
            )
        })?)
    };
    lx.push(tok, line, col);
    Ok(())
}

fn string(lx: &mut Lexer, prefix: String) -> Result<()> {
    let (line, col) = (lx.line, lx.col());
    let (raw, fstring) = (prefix.contains('r'), prefix.contains('f'));
    let q = lx.s[lx.i];
    let triple = lx.s[lx.i..].starts_with(&[q, q, q]);
    lx.i += if triple { 3 } else { 1 };
    let mut value = String::new();
    loop {
        if lx.i >= lx.s.len() {
            return Err(err(line, col, "string literal never closed"));
        }
        let c = lx.s[lx.i];
        if c == q && (!triple || lx.s[lx.i..].starts_with(&[q, q, q])) {
            lx.i += if triple { 3 } else { 1 };
            break;
        }
        if c == b'\n' {
            if !triple {
                return Err(err(line, col, "string literal never closed on its line"));
            }
            value.push('\n');
            lx.newline();
            continue;
        }
        if c == b'\\' && lx.i + 1 < lx.s.len() {
            let n = lx.s[lx.i + 1];
            if raw || fstring {
                // Raw strings keep the backslash; f-string escapes are decoded
                // in their literal parts (see `fstring_parts`).
                value.push('\\');
                lx.i += 1;
                if n == b'\n' {
                    value.push('\n');
                    lx.newline();
                    continue;
                }
                let ch = lx.text[lx.i..].chars().next().unwrap_or(' ');
                value.push(ch);
                lx.i += ch.len_utf8();
                continue;
            }
            if !n.is_ascii() {
                // An unknown escape of a character beyond ASCII: kept as
                // written, the whole character (Python keeps `\é` as is;
                // stepping two bytes would land inside it: fuzz finding 16).
                value.push('\\');
                lx.i += 1;
                let ch = lx.text[lx.i..].chars().next().unwrap_or(' ');
                value.push(ch);
                lx.i += ch.len_utf8();
                continue;
            }
            lx.i += 2;
            match n {
                b'\n' => {
                    lx.line += 1;
                    lx.line_start = lx.i;
                }
                _ => escape(n, lx, &mut value).map_err(|m| err(line, col, m))?,
            }
            continue;
        }
        let ch = lx.text[lx.i..].chars().next().unwrap_or(' ');
        value.push(ch);
        lx.i += ch.len_utf8();
    }
    lx.push(Tok::Str { value, fstring }, line, col);
    Ok(())
}

/// The escape `\n` (its letter `n` just read) appended to `out`.
fn escape(n: u8, lx: &mut Lexer, out: &mut String) -> std::result::Result<(), String> {
    let simple = match n {
        b'n' => Some('\n'),
        b't' => Some('\t'),
        b'r' => Some('\r'),
        b'\\' => Some('\\'),
        b'\'' => Some('\''),
        b'"' => Some('"'),
        b'a' => Some('\x07'),
        b'b' => Some('\x08'),
        b'f' => Some('\x0c'),
        b'v' => Some('\x0b'),
        _ => None,
    };
    if let Some(c) = simple {
        out.push(c);
        return Ok(());
    }
    if (b'0'..=b'7').contains(&n) {
        // Octal: up to three digits, the first just read (`\012` is a line
        // feed, `\0` a NUL), as Python reads them.
        let more = lx.s[lx.i..]
            .iter()
            .take(2)
            .take_while(|b| (b'0'..=b'7').contains(b))
            .count();
        let digits = &lx.text[lx.i - 1..lx.i + more];
        let v =
            u32::from_str_radix(digits, 8).map_err(|_| format!("malformed escape \\{digits}"))?;
        out.push(char::from_u32(v).ok_or("escape beyond Unicode")?);
        lx.i += more;
        return Ok(());
    }
    if n == b'N' {
        return Err("\\N{...} escapes are not supported".into());
    }
    let hex = match n {
        b'x' => 2,
        b'u' => 4,
        b'U' => 8,
        _ => {
            // Python keeps an unknown escape as written.
            out.push('\\');
            out.push(n as char);
            return Ok(());
        }
    };
    let digits = lx
        .text
        .get(lx.i..lx.i + hex)
        .filter(|d| d.bytes().all(|b| b.is_ascii_hexdigit()))
        .ok_or("truncated \\x / \\u escape")?;
    let v = u32::from_str_radix(digits, 16)
        .map_err(|_| format!("malformed escape \\{}{digits}", n as char))?;
    out.push(char::from_u32(v).ok_or("escape beyond Unicode")?);
    lx.i += hex;
    Ok(())
}
