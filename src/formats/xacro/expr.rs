//! The `${...}` language: the Python expressions xacro files use, parsed
//! into nodes that know their depth.
//!
//! Supported: int (decimal, `0x`, `0o`, `0b`), float and string literals
//! (`'...'`, `"..."`, triple-quoted, `r''`/`u''` prefixes, every Python
//! escape but `\N{...}`), `True`/`False`/`None`, names, `+ - * / // % **`,
//! `& | ^ << >> ~`, unary `- + not`, comparisons (chained, `in`, `not in`,
//! `is`), `and`/`or`, `a if c else b`, list, tuple and dict literals,
//! `x[i]`, slices `x[a:b:c]`, `x.attr`, calls with keyword arguments. Refused
//! by name: lambda, comprehensions, f-strings, bytes, sets, `*`/`**`
//! unpacking, `:=`, and statements.
//!
//! Depth: a chain of one operator (`a + b - c`, `a and b and c`,
//! `x[0][1].y`) is one node with its operands side by side, evaluated left
//! to right as Python does; real nesting (parentheses, unary operators,
//! `**`, conditionals, calls, subscripts, nested literals) adds a level,
//! refused beyond `XACRO_MAX_EXPR_DEPTH`, so parsing, evaluating and
//! dropping a node never recurse further.

use super::value::{float_repr, Value};
use crate::tolerances::XACRO_MAX_EXPR_DEPTH;

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Tok {
    Int(i64),
    Float(f64),
    Str(String),
    Name(String),
    Op(&'static str),
}

const OPS: &[&str] = &[
    "**", "//", "==", "!=", "<=", ">=", "<<", ">>", ":=", "->", "+", "-", "*", "/", "%", "<", ">",
    "(", ")", "[", "]", ",", ".", ":", "{", "}", "=", "&", "|", "^", "~", "@", ";",
];

pub(super) fn lex(src: &str) -> Result<Vec<Tok>, String> {
    let b = src.as_bytes();
    let mut i = 0;
    let mut out = Vec::new();
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
        } else if c == b'\\' && b.get(i + 1) == Some(&b'\n') {
            i += 2;
        } else if c.is_ascii_digit() || (c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let (t, n) = number(&src[i..])?;
            out.push(t);
            i += n;
        } else if c == b'\'' || c == b'"' {
            let (s, n) = string(&src[i..], false)?;
            out.push(Tok::Str(s));
            i += n;
        } else if c.is_ascii_alphabetic() || c == b'_' || c >= 0x80 {
            let n = src[i..]
                .find(|ch: char| !(ch.is_alphanumeric() || ch == '_'))
                .unwrap_or(src.len() - i);
            if n == 0 {
                // A non-ASCII character that is no letter (`€`, U+FFFD):
                // Python's "invalid character" (it looped here, pushing
                // empty names until memory ran out: found by fuzzing).
                let ch = src[i..].chars().next().unwrap_or('?');
                return Err(format!("unexpected character {ch:?}"));
            }
            let word = &src[i..i + n];
            if matches!(b.get(i + n), Some(b'\'' | b'"')) {
                if let Some(raw) = prefix(word)? {
                    let (s, m) = string(&src[i + n..], raw)?;
                    out.push(Tok::Str(s));
                    i += n + m;
                    continue;
                }
            }
            out.push(Tok::Name(word.to_string()));
            i += n;
        } else if let Some(op) = OPS.iter().find(|op| src[i..].starts_with(**op)) {
            match *op {
                ":=" => return Err("assignment expressions (:=) are not supported".into()),
                "@" | ";" | "->" => {
                    return Err(format!("'{op}' is not supported in xacro expressions"))
                }
                _ => {}
            }
            out.push(Tok::Op(op));
            i += op.len();
        } else {
            let ch = src[i..].chars().next().unwrap_or('?');
            return Err(format!("unexpected character {ch:?}"));
        }
    }
    Ok(out)
}

/// A string prefix: `Some(raw)` for `r`, `u` (and `R`, `U`); f-strings and
/// bytes are refused; `None`: not a prefix (a name before a string).
fn prefix(word: &str) -> Result<Option<bool>, String> {
    Ok(match word.to_ascii_lowercase().as_str() {
        "r" => Some(true),
        "u" => Some(false),
        "f" | "fr" | "rf" => return Err("f-strings are not supported; use str.format".into()),
        "b" | "br" | "rb" => return Err("bytes literals are not supported".into()),
        _ => None,
    })
}

fn number(s: &str) -> Result<(Tok, usize), String> {
    let b = s.as_bytes();
    if b[0] == b'0' && matches!(b.get(1), Some(b'x' | b'X' | b'o' | b'O' | b'b' | b'B')) {
        let radix = match b[1] | 0x20 {
            b'x' => 16,
            b'o' => 8,
            _ => 2,
        };
        let n = 2 + s[2..]
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(s.len() - 2);
        let digits: String = s[2..n].chars().filter(|c| *c != '_').collect();
        return i64::from_str_radix(&digits, radix)
            .map(|v| (Tok::Int(v), n))
            .map_err(|_| format!("invalid or too large integer literal {:?}", &s[..n]));
    }
    let mut n = 0;
    let mut float = false;
    while n < b.len() && (b[n].is_ascii_digit() || b[n] == b'_') {
        n += 1;
    }
    if n < b.len() && b[n] == b'.' {
        float = true;
        n += 1;
        while n < b.len() && (b[n].is_ascii_digit() || b[n] == b'_') {
            n += 1;
        }
    }
    if n < b.len() && (b[n] == b'e' || b[n] == b'E') {
        let mut m = n + 1;
        if m < b.len() && (b[m] == b'+' || b[m] == b'-') {
            m += 1;
        }
        if m < b.len() && b[m].is_ascii_digit() {
            float = true;
            n = m;
            while n < b.len() && (b[n].is_ascii_digit() || b[n] == b'_') {
                n += 1;
            }
        }
    }
    if n < b.len() && (b[n] == b'j' || b[n] == b'J') {
        return Err("complex literals are not supported".into());
    }
    let text: String = s[..n].chars().filter(|c| *c != '_').collect();
    if float {
        text.parse::<f64>()
            .map(|f| (Tok::Float(f), n))
            .map_err(|_| format!("bad number {text:?}"))
    } else if text.len() > 1 && text.starts_with('0') && text.bytes().any(|d| d != b'0') {
        Err(format!(
            "leading zeros in decimal integer literals are not permitted: {text}"
        ))
    } else {
        text.parse::<i64>()
            .map(|v| (Tok::Int(v), n))
            .map_err(|_| format!("integer literal {text} does not fit 64 bits"))
    }
}

/// A string literal at the start of `s` (single, double or triple quoted):
/// its value and length.
fn string(s: &str, raw: bool) -> Result<(String, usize), String> {
    let q = s.as_bytes()[0] as char;
    let triple: String = std::iter::repeat_n(q, 3).collect();
    let (close, start) = if s.starts_with(&triple) {
        (triple.as_str(), 3)
    } else {
        (&s[..1], 1)
    };
    let mut out = String::new();
    let mut i = start;
    while i < s.len() {
        let rest = &s[i..];
        if rest.starts_with(close) {
            return Ok((out, i + close.len()));
        }
        let c = rest.chars().next().unwrap_or(' ');
        if c == '\n' && close.len() == 1 {
            break;
        }
        if c == '\\' && !raw {
            let (piece, n) = escape(&rest[1..])?;
            out.push_str(&piece);
            i += 1 + n;
        } else if c == '\\' {
            // Raw: the backslash stays, and protects the next character.
            let next = rest[1..].chars().next().map_or(0, char::len_utf8);
            out.push_str(&rest[..1 + next]);
            i += 1 + next;
        } else {
            out.push(c);
            i += c.len_utf8();
        }
    }
    Err("string literal is not closed".into())
}

/// One escape after a backslash: its text and the bytes it took.
fn escape(s: &str) -> Result<(String, usize), String> {
    let Some(c) = s.chars().next() else {
        return Err("string literal is not closed".into());
    };
    let simple = match c {
        '\n' => Some(""),
        '\\' => Some("\\"),
        '\'' => Some("'"),
        '"' => Some("\""),
        'a' => Some("\u{7}"),
        'b' => Some("\u{8}"),
        'f' => Some("\u{c}"),
        'n' => Some("\n"),
        'r' => Some("\r"),
        't' => Some("\t"),
        'v' => Some("\u{b}"),
        _ => None,
    };
    if let Some(t) = simple {
        return Ok((t.to_string(), 1));
    }
    let code = |digits: &str, radix: u32, what: &str| -> Result<String, String> {
        u32::from_str_radix(digits, radix)
            .ok()
            .and_then(char::from_u32)
            .map(String::from)
            .ok_or_else(|| format!("invalid {what} escape \\{c}{digits}"))
    };
    match c {
        '0'..='7' => {
            let n = s
                .bytes()
                .take(3)
                .take_while(|b| (b'0'..=b'7').contains(b))
                .count();
            Ok((code(&s[..n], 8, "octal")?, n))
        }
        'x' | 'u' | 'U' => {
            let n = match c {
                'x' => 2,
                'u' => 4,
                _ => 8,
            };
            let digits = s
                .get(1..1 + n)
                .filter(|d| d.bytes().all(|b| b.is_ascii_hexdigit()));
            let digits = digits.ok_or_else(|| format!("truncated \\{c} escape"))?;
            Ok((code(digits, 16, "unicode")?, 1 + n))
        }
        'N' => Err("\\N{...} escapes are not supported".into()),
        other => Ok((format!("\\{other}"), other.len_utf8())),
    }
}

/// A parsed expression and the depth of its tree.
#[derive(Debug)]
pub(super) struct Node {
    pub kind: Kind,
    pub depth: usize,
}

#[derive(Debug)]
pub(super) enum Kind {
    Lit(Value),
    Name(String),
    /// A base and its trailers, applied left to right.
    Postfix(Box<Node>, Vec<Trailer>),
    /// `-x`, `+x`, `~x`, `not x`.
    Unary(&'static str, Box<Node>),
    /// Operands of one precedence level, combined left to right.
    Chain(Box<Node>, Vec<(&'static str, Node)>),
    /// `a ** b` (right-associative).
    Pow(Box<Node>, Box<Node>),
    Cmp(Box<Node>, Vec<(&'static str, Node)>),
    And(Vec<Node>),
    Or(Vec<Node>),
    /// (condition, then, else).
    IfElse(Box<Node>, Box<Node>, Box<Node>),
    List(Vec<Node>),
    Tuple(Vec<Node>),
    Dict(Vec<(Node, Node)>),
}

#[derive(Debug)]
pub(super) enum Trailer {
    Attr(String),
    Index(Node),
    Slice(Box<[Option<Node>; 3]>),
    Call(Vec<Node>, Vec<(String, Node)>),
}

/// The depth of a tree made of these children.
fn depth_of<'a>(children: impl IntoIterator<Item = &'a Node>) -> usize {
    1 + children.into_iter().map(|n| n.depth).max().unwrap_or(0)
}

fn trailer_children(t: &Trailer) -> Vec<&Node> {
    match t {
        Trailer::Attr(_) => Vec::new(),
        Trailer::Index(n) => vec![n],
        Trailer::Slice(parts) => parts.iter().flatten().collect(),
        Trailer::Call(a, kw) => a.iter().chain(kw.iter().map(|(_, n)| n)).collect(),
    }
}

fn children(k: &Kind) -> Vec<&Node> {
    match k {
        Kind::Lit(_) | Kind::Name(_) => Vec::new(),
        Kind::Postfix(b, ts) => std::iter::once(&**b)
            .chain(ts.iter().flat_map(trailer_children))
            .collect(),
        Kind::Unary(_, x) => vec![x],
        Kind::Chain(f, rest) | Kind::Cmp(f, rest) => std::iter::once(&**f)
            .chain(rest.iter().map(|(_, n)| n))
            .collect(),
        Kind::Pow(a, b) => vec![a, b],
        Kind::And(v) | Kind::Or(v) | Kind::List(v) | Kind::Tuple(v) => v.iter().collect(),
        Kind::IfElse(c, a, b) => vec![c, a, b],
        Kind::Dict(v) => v.iter().flat_map(|(k, x)| [k, x]).collect(),
    }
}

pub(super) struct Parser {
    toks: Vec<Tok>,
    pos: usize,
    depth: usize,
}

const KEYWORDS_REFUSED: &[&str] = &[
    "lambda", "for", "yield", "await", "import", "del", "global", "with", "def", "class", "assert",
    "async", "from", "pass", "return", "raise", "try", "while", "nonlocal", "except", "finally",
    "elif", "break", "continue", "as",
];

/// Python keywords the expressions use (never an attribute name).
const PY_KEYWORDS: &[&str] = &[
    "True", "False", "None", "and", "or", "not", "in", "is", "if", "else",
];

fn too_deep() -> String {
    format!("expression nested deeper than {XACRO_MAX_EXPR_DEPTH} levels")
}

impl Parser {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos)
    }
    fn is_op(&self, op: &str) -> bool {
        matches!(self.peek(), Some(Tok::Op(o)) if *o == op)
    }
    fn is_kw(&self, kw: &str) -> bool {
        matches!(self.peek(), Some(Tok::Name(n)) if n == kw)
    }
    fn eat_op(&mut self, op: &str) -> bool {
        let y = self.is_op(op);
        if y {
            self.pos += 1;
        }
        y
    }
    fn eat_kw(&mut self, kw: &str) -> bool {
        let y = self.is_kw(kw);
        if y {
            self.pos += 1;
        }
        y
    }
    fn expect_op(&mut self, op: &str) -> Result<(), String> {
        if self.eat_op(op) {
            Ok(())
        } else {
            Err(format!("expected '{op}', found {}", self.describe()))
        }
    }
    fn describe(&self) -> String {
        match self.peek() {
            None => "the end of the expression".into(),
            Some(Tok::Op(o)) => format!("'{o}'"),
            Some(Tok::Name(n)) => format!("'{n}'"),
            Some(Tok::Int(i)) => format!("'{i}'"),
            Some(Tok::Float(f)) => format!("'{}'", float_repr(*f)),
            Some(Tok::Str(s)) => format!("{s:?}"),
        }
    }

    /// A node of `kind`, refused when it nests too deep.
    fn node(&self, kind: Kind) -> Result<Node, String> {
        let depth = depth_of(children(&kind));
        if depth > XACRO_MAX_EXPR_DEPTH {
            return Err(too_deep());
        }
        Ok(Node { kind, depth })
    }

    /// Run `f` one parser level deeper (the recursion of the parser itself).
    fn nested<T>(&mut self, f: impl FnOnce(&mut Self) -> Result<T, String>) -> Result<T, String> {
        self.depth += 1;
        if self.depth > XACRO_MAX_EXPR_DEPTH {
            return Err(too_deep());
        }
        let r = f(self);
        self.depth -= 1;
        r
    }

    pub(super) fn expr(&mut self) -> Result<Node, String> {
        self.nested(|p| {
            if p.is_kw("lambda") {
                return Err("lambda is not supported".into());
            }
            let body = p.or()?;
            if !p.eat_kw("if") {
                return Ok(body);
            }
            let cond = p.or()?;
            if !p.eat_kw("else") {
                return Err(format!(
                    "conditional expression: expected 'else', found {}",
                    p.describe()
                ));
            }
            let other = p.expr()?;
            p.node(Kind::IfElse(
                Box::new(cond),
                Box::new(body),
                Box::new(other),
            ))
        })
    }

    /// `a or b or ...` / `a and b and ...`: one node each.
    fn logic(
        &mut self,
        kw: &str,
        next: fn(&mut Self) -> Result<Node, String>,
    ) -> Result<Node, String> {
        let first = next(self)?;
        if !self.is_kw(kw) {
            return Ok(first);
        }
        let mut v = vec![first];
        while self.eat_kw(kw) {
            v.push(next(self)?);
        }
        self.node(if kw == "or" {
            Kind::Or(v)
        } else {
            Kind::And(v)
        })
    }
    fn or(&mut self) -> Result<Node, String> {
        self.logic("or", Self::and)
    }
    fn and(&mut self) -> Result<Node, String> {
        self.logic("and", Self::not)
    }
    fn not(&mut self) -> Result<Node, String> {
        if self.eat_kw("not") {
            return self.nested(|p| {
                let x = p.not()?;
                p.node(Kind::Unary("not", Box::new(x)))
            });
        }
        self.cmp()
    }
    fn cmp_op(&mut self) -> Option<&'static str> {
        for op in ["==", "!=", "<=", ">=", "<", ">"] {
            if self.eat_op(op) {
                return Some(op);
            }
        }
        if self.eat_kw("in") {
            return Some("in");
        }
        if self.is_kw("not")
            && matches!(self.toks.get(self.pos + 1), Some(Tok::Name(n)) if n == "in")
        {
            self.pos += 2;
            return Some("not in");
        }
        if self.eat_kw("is") {
            return Some(if self.eat_kw("not") { "is not" } else { "is" });
        }
        None
    }
    fn cmp(&mut self) -> Result<Node, String> {
        let first = self.bor()?;
        let mut rest = Vec::new();
        while let Some(op) = self.cmp_op() {
            rest.push((op, self.bor()?));
        }
        if rest.is_empty() {
            return Ok(first);
        }
        self.node(Kind::Cmp(Box::new(first), rest))
    }

    /// One left-associative level: operands joined by `ops`, one node.
    fn chain(
        &mut self,
        ops: &[&'static str],
        next: fn(&mut Self) -> Result<Node, String>,
    ) -> Result<Node, String> {
        let first = next(self)?;
        let mut rest = Vec::new();
        while let Some(op) = ops.iter().copied().find(|op| self.is_op(op)) {
            self.pos += 1;
            rest.push((op, next(self)?));
        }
        if rest.is_empty() {
            return Ok(first);
        }
        self.node(Kind::Chain(Box::new(first), rest))
    }
    fn bor(&mut self) -> Result<Node, String> {
        self.chain(&["|"], Self::bxor)
    }
    fn bxor(&mut self) -> Result<Node, String> {
        self.chain(&["^"], Self::band)
    }
    fn band(&mut self) -> Result<Node, String> {
        self.chain(&["&"], Self::shift)
    }
    fn shift(&mut self) -> Result<Node, String> {
        self.chain(&["<<", ">>"], Self::arith)
    }
    fn arith(&mut self) -> Result<Node, String> {
        self.chain(&["+", "-"], Self::term)
    }
    fn term(&mut self) -> Result<Node, String> {
        self.chain(&["*", "//", "/", "%"], Self::unary)
    }
    fn unary(&mut self) -> Result<Node, String> {
        let op = ["-", "+", "~"].into_iter().find(|op| self.is_op(op));
        let Some(op) = op else {
            return self.power();
        };
        self.pos += 1;
        self.nested(|p| {
            let x = p.unary()?;
            p.node(Kind::Unary(op, Box::new(x)))
        })
    }
    fn power(&mut self) -> Result<Node, String> {
        let base = self.postfix()?;
        if !self.eat_op("**") {
            return Ok(base);
        }
        let exp = self.nested(Self::unary)?;
        self.node(Kind::Pow(Box::new(base), Box::new(exp)))
    }
    fn postfix(&mut self) -> Result<Node, String> {
        let base = self.atom()?;
        let mut trailers = Vec::new();
        loop {
            if self.eat_op(".") {
                match self.peek().cloned() {
                    Some(Tok::Name(n))
                        if KEYWORDS_REFUSED.contains(&n.as_str())
                            || PY_KEYWORDS.contains(&n.as_str()) =>
                    {
                        return Err(format!("invalid syntax: '.{n}' ({n} is a keyword)"));
                    }
                    Some(Tok::Name(n)) => {
                        self.pos += 1;
                        trailers.push(Trailer::Attr(n));
                    }
                    _ => {
                        return Err(format!(
                            "expected a name after '.', found {}",
                            self.describe()
                        ))
                    }
                }
            } else if self.eat_op("[") {
                trailers.push(self.nested(Self::subscript)?);
            } else if self.eat_op("(") {
                let (args, kwargs) = self.nested(Self::call_args)?;
                trailers.push(Trailer::Call(args, kwargs));
            } else if trailers.is_empty() {
                return Ok(base);
            } else {
                return self.node(Kind::Postfix(Box::new(base), trailers));
            }
        }
    }
    /// After `[`: an index or a slice, through `]`.
    fn subscript(&mut self) -> Result<Trailer, String> {
        let mut parts: [Option<Node>; 3] = [None, None, None];
        let mut colons = 0;
        loop {
            if self.eat_op("]") {
                break;
            }
            if self.eat_op(":") {
                colons += 1;
                if colons > 2 {
                    return Err("a slice takes at most three parts".into());
                }
                continue;
            }
            if parts[colons].is_some() {
                return Err(format!("expected ']' or ':', found {}", self.describe()));
            }
            parts[colons] = Some(self.expr()?);
            if self.is_op(",") {
                return Err("subscripts with several indices (x[a, b]) are not supported".into());
            }
        }
        if colons == 0 {
            return match parts {
                [Some(i), None, None] => Ok(Trailer::Index(i)),
                _ => Err("expected an index inside '[]'".into()),
            };
        }
        Ok(Trailer::Slice(Box::new(parts)))
    }
    /// After `(`: positional then keyword arguments, through `)`.
    #[allow(clippy::type_complexity)]
    fn call_args(&mut self) -> Result<(Vec<Node>, Vec<(String, Node)>), String> {
        let (mut args, mut kwargs) = (Vec::new(), Vec::<(String, Node)>::new());
        while !self.eat_op(")") {
            if self.is_op("*") || self.is_op("**") {
                return Err("argument unpacking (*args, **kwargs) is not supported".into());
            }
            let kw = match (self.peek(), self.toks.get(self.pos + 1)) {
                (Some(Tok::Name(n)), Some(Tok::Op("="))) => Some(n.clone()),
                _ => None,
            };
            if let Some(name) = kw {
                self.pos += 2;
                if kwargs.iter().any(|(k, _)| *k == name) {
                    return Err(format!("keyword argument repeated: {name}"));
                }
                kwargs.push((name, self.expr()?));
            } else if !kwargs.is_empty() {
                return Err("positional argument follows keyword argument".into());
            } else {
                args.push(self.expr()?);
            }
            if self.is_kw("for") {
                return Err("comprehensions are not supported".into());
            }
            if !self.eat_op(",") {
                self.expect_op(")")?;
                break;
            }
        }
        Ok((args, kwargs))
    }
    /// Comma-separated expressions up to `close`; (items, a comma was seen).
    fn items(&mut self, close: &str) -> Result<(Vec<Node>, bool), String> {
        let (mut v, mut comma) = (Vec::new(), false);
        while !self.eat_op(close) {
            if self.is_op("*") {
                return Err("unpacking (*x) is not supported".into());
            }
            v.push(self.expr()?);
            if self.is_kw("for") {
                return Err("comprehensions are not supported".into());
            }
            if matches!(self.peek(), Some(Tok::Op("="))) {
                return Err("unexpected '=' (keyword arguments go inside a call)".into());
            }
            if !self.eat_op(",") {
                self.expect_op(close)?;
                break;
            }
            comma = true;
        }
        Ok((v, comma))
    }
    /// After `{`: a dict literal (sets are refused).
    fn dict(&mut self) -> Result<Node, String> {
        let mut v = Vec::new();
        while !self.eat_op("}") {
            if self.is_op("**") {
                return Err("dict unpacking (**d) is not supported".into());
            }
            let k = self.expr()?;
            if !self.eat_op(":") {
                return Err("set literals are not supported (only dicts: {key: value})".into());
            }
            let x = self.expr()?;
            if self.is_kw("for") {
                return Err("comprehensions are not supported".into());
            }
            v.push((k, x));
            if !self.eat_op(",") {
                self.expect_op("}")?;
                break;
            }
        }
        self.node(Kind::Dict(v))
    }
    fn atom(&mut self) -> Result<Node, String> {
        let Some(t) = self.peek().cloned() else {
            return Err("expected a value, found the end of the expression".into());
        };
        self.pos += 1;
        let lit = |v| {
            Ok(Node {
                kind: Kind::Lit(v),
                depth: 1,
            })
        };
        match t {
            Tok::Int(i) => lit(Value::Int(i)),
            Tok::Float(f) => lit(Value::Float(f)),
            Tok::Str(mut s) => {
                // Adjacent literals concatenate, as in Python.
                while let Some(Tok::Str(more)) = self.peek().cloned() {
                    self.pos += 1;
                    s.push_str(&more);
                }
                lit(Value::str(&s))
            }
            Tok::Name(n) => match n.as_str() {
                "True" => lit(Value::Bool(true)),
                "False" => lit(Value::Bool(false)),
                "None" => lit(Value::None),
                k if KEYWORDS_REFUSED.contains(&k) => {
                    Err(format!("'{k}' is not supported in xacro expressions"))
                }
                _ => Ok(Node {
                    kind: Kind::Name(n),
                    depth: 1,
                }),
            },
            Tok::Op("(") => {
                let (mut items, comma) = self.nested(|p| p.items(")"))?;
                // A single item is grouping; several (or `(x,)`) a tuple.
                if items.len() == 1 && !comma {
                    Ok(items.remove(0))
                } else {
                    self.node(Kind::Tuple(items))
                }
            }
            Tok::Op("[") => {
                let (items, _) = self.nested(|p| p.items("]"))?;
                self.node(Kind::List(items))
            }
            Tok::Op("{") => self.nested(Self::dict),
            _ => {
                self.pos -= 1;
                Err(format!("expected a value, found {}", self.describe()))
            }
        }
    }
}

/// Parse one expression (the text between `${` and `}`).
pub(super) fn parse(src: &str) -> Result<Node, String> {
    let toks = lex(src.trim())?;
    let mut p = Parser {
        toks,
        pos: 0,
        depth: 0,
    };
    let e = p.expr()?;
    if p.pos < p.toks.len() {
        let what = p.describe();
        if p.is_kw("for") {
            return Err("comprehensions are not supported".into());
        }
        return Err(format!("unexpected {what} after a complete expression"));
    }
    Ok(e)
}
