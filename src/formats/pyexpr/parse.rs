//! Python expressions and statements into a small AST, by recursive descent
//! over [`super::lex`]'s tokens, precedence as in Python's grammar. Only
//! what launch files need is kept; everything else a statement holds is
//! parsed as far as it can be and otherwise kept as [`Stmt::Other`] with its
//! line (the evaluator refuses it only when a value it needs comes from
//! there).

use super::lex::{err, tokens, Tok, Token};
use crate::diagnostic::{Code, Error, Result};
use crate::tolerances::MAX_YAML_DEPTH;

/// An expression with its line and column.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub line: usize,
    pub col: usize,
}

/// One part of an f-string: literal text or `{expr!conv:spec}`.
#[derive(Debug, Clone, PartialEq)]
pub enum FPart {
    Text(String),
    Field {
        expr: Expr,
        conv: Option<char>,
        spec: String,
    },
}

#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    Name(String),
    Int(i64),
    Float(f64),
    Str(String),
    FStr(Vec<FPart>),
    List(Vec<Expr>),
    Tuple(Vec<Expr>),
    Dict(Vec<(Expr, Expr)>),
    /// `[elt for target in iter if cond ...]` (one `for` clause).
    ListComp {
        elt: Box<Expr>,
        target: Box<Expr>,
        iter: Box<Expr>,
        conds: Vec<Expr>,
    },
    Attr(Box<Expr>, String),
    /// A call; each keyword argument with the line and column of its name.
    Call {
        func: Box<Expr>,
        args: Vec<Expr>,
        kwargs: Vec<(String, Expr, (usize, usize))>,
        star: bool,
    },
    Index(Box<Expr>, Box<Expr>),
    Slice(Option<Box<Expr>>, Option<Box<Expr>>, Option<Box<Expr>>),
    Unary(&'static str, Box<Expr>),
    Binary(&'static str, Box<Expr>, Box<Expr>),
    /// `a < b < c`: the operands and the operators between them.
    Compare(Vec<Expr>, Vec<&'static str>),
    And(Box<Expr>, Box<Expr>),
    Or(Box<Expr>, Box<Expr>),
    Not(Box<Expr>),
    IfElse {
        cond: Box<Expr>,
        then: Box<Expr>,
        other: Box<Expr>,
    },
    /// Syntax the evaluator does not implement (lambda, generator, set,
    /// starred, walrus...): what it is, for the message.
    Unsupported(&'static str),
}

/// A statement.
#[derive(Debug, Clone, PartialEq)]
pub enum Stmt {
    Expr(Expr),
    Assign {
        targets: Vec<Expr>,
        value: Expr,
        line: usize,
    },
    AugAssign {
        target: Expr,
        op: &'static str,
        value: Expr,
        line: usize,
    },
    Def {
        name: String,
        params: Vec<(String, Option<Expr>)>,
        body: Vec<Stmt>,
        line: usize,
    },
    Return(Option<Expr>, usize),
    For {
        target: Expr,
        iter: Expr,
        body: Vec<Stmt>,
        orelse: Vec<Stmt>,
        line: usize,
    },
    If {
        cond: Expr,
        body: Vec<Stmt>,
        orelse: Vec<Stmt>,
        line: usize,
    },
    /// `with`, `try`, `while`, `class`: their blocks, run in an order the
    /// reader cannot know (what, line).
    Block {
        what: &'static str,
        body: Vec<Stmt>,
        line: usize,
    },
    /// `import a.b`, `from m import x as y`: the names bound (`*` for a star
    /// import).
    Import(Vec<String>, usize),
    /// `pass`, `global`, ... or a statement this parser does not read (what,
    /// line); names it binds are unknown.
    Other(String, usize),
}

struct P {
    t: Vec<Token>,
    i: usize,
    depth: usize,
}

/// Parse one expression (the whole text).
pub fn expression(text: &str, line0: usize) -> Result<Expr> {
    let mut p = P {
        t: tokens(text, false, line0)?,
        i: 0,
        depth: 0,
    };
    let e = p.test_list()?;
    p.expect_end()?;
    Ok(e)
}

/// Parse a module.
pub fn module(text: &str) -> Result<Vec<Stmt>> {
    let mut p = P {
        t: tokens(text, true, 1)?,
        i: 0,
        depth: 0,
    };
    let mut out = Vec::new();
    while !p.at_end() {
        out.push(p.next_statement()?);
    }
    Ok(out)
}

impl P {
    fn peek(&self) -> &Tok {
        &self.t[self.i.min(self.t.len() - 1)].tok
    }
    fn pos(&self) -> (usize, usize) {
        let t = &self.t[self.i.min(self.t.len() - 1)];
        (t.line, t.col)
    }
    fn at_end(&self) -> bool {
        matches!(self.peek(), Tok::End)
    }
    fn is_op(&self, o: &str) -> bool {
        matches!(self.peek(), Tok::Op(x) if *x == o)
    }
    fn is_name(&self, n: &str) -> bool {
        matches!(self.peek(), Tok::Name(x) if x == n)
    }
    fn eat_op(&mut self, o: &str) -> bool {
        let hit = self.is_op(o);
        if hit {
            self.i += 1;
        }
        hit
    }
    fn eat_name(&mut self, n: &str) -> bool {
        let hit = self.is_name(n);
        if hit {
            self.i += 1;
        }
        hit
    }
    fn fail<T>(&self, msg: impl Into<String>) -> Result<T> {
        let (l, c) = self.pos();
        Err(err(l, c, msg))
    }
    fn expect_op(&mut self, o: &str) -> Result<()> {
        if self.eat_op(o) {
            return Ok(());
        }
        self.fail(format!("expected `{o}`, found {}", describe(self.peek())))
    }
    fn expect_end(&self) -> Result<()> {
        if self.at_end() {
            return Ok(());
        }
        self.fail(format!(
            "expected the end of the expression, found {}",
            describe(self.peek())
        ))
    }
    fn mk(&self, kind: ExprKind, (line, col): (usize, usize)) -> Expr {
        Expr { kind, line, col }
    }
    fn deeper(&mut self) -> Result<()> {
        self.depth += 1;
        if self.depth > MAX_YAML_DEPTH {
            // A limit, not a syntax error: never kept as an unparsed
            // statement (a 10^5-deep literal is refused by name).
            let (l, c) = self.pos();
            return Err(
                Error::limit(format!("expression nested more than {MAX_YAML_DEPTH} deep"))
                    .at_line(l, Some(c)),
            );
        }
        Ok(())
    }

    /// `a, b` (a tuple) or one test.
    fn test_list(&mut self) -> Result<Expr> {
        let at = self.pos();
        let first = self.test()?;
        if !self.is_op(",") {
            return Ok(first);
        }
        let mut items = vec![first];
        while self.eat_op(",") {
            if self.ends_expr() {
                break;
            }
            items.push(self.test()?);
        }
        Ok(self.mk(ExprKind::Tuple(items), at))
    }

    fn ends_expr(&self) -> bool {
        matches!(self.peek(), Tok::End | Tok::Newline)
            || [")", "]", "}", "=", ":"].iter().any(|o| self.is_op(o))
    }

    fn test(&mut self) -> Result<Expr> {
        self.deeper()?;
        let at = self.pos();
        let r = if self.eat_name("lambda") {
            while !self.is_op(":") && !self.at_end() {
                self.i += 1;
            }
            self.expect_op(":")?;
            self.test()?;
            Ok(self.mk(ExprKind::Unsupported("a lambda"), at))
        } else {
            let e = self.or_test()?;
            if self.eat_name("if") {
                let cond = self.or_test()?;
                if !self.eat_name("else") {
                    return self.fail("expected `else` in a conditional expression");
                }
                let other = self.test()?;
                Ok(self.mk(
                    ExprKind::IfElse {
                        cond: cond.into(),
                        then: e.into(),
                        other: other.into(),
                    },
                    at,
                ))
            } else if self.is_op(":=") {
                self.i += 1;
                self.test()?;
                Ok(self.mk(ExprKind::Unsupported("an assignment expression (:=)"), at))
            } else {
                Ok(e)
            }
        };
        self.depth -= 1;
        r
    }

    fn or_test(&mut self) -> Result<Expr> {
        let at = self.pos();
        let mut e = self.and_test()?;
        while self.eat_name("or") {
            let r = self.and_test()?;
            e = self.mk(ExprKind::Or(e.into(), r.into()), at);
        }
        Ok(e)
    }

    fn and_test(&mut self) -> Result<Expr> {
        let at = self.pos();
        let mut e = self.not_test()?;
        while self.eat_name("and") {
            let r = self.not_test()?;
            e = self.mk(ExprKind::And(e.into(), r.into()), at);
        }
        Ok(e)
    }

    fn not_test(&mut self) -> Result<Expr> {
        let at = self.pos();
        if self.eat_name("not") {
            self.deeper()?;
            let e = self.not_test()?;
            self.depth -= 1;
            return Ok(self.mk(ExprKind::Not(e.into()), at));
        }
        self.comparison()
    }

    fn comp_op(&mut self) -> Option<&'static str> {
        for o in ["<", ">", "==", ">=", "<=", "!="] {
            if self.eat_op(o) {
                return Some(o);
            }
        }
        if self.eat_name("in") {
            return Some("in");
        }
        if self.is_name("not")
            && matches!(self.t.get(self.i + 1).map(|t| &t.tok), Some(Tok::Name(n)) if n == "in")
        {
            self.i += 2;
            return Some("not in");
        }
        if self.eat_name("is") {
            return Some(if self.eat_name("not") { "is not" } else { "is" });
        }
        None
    }

    fn comparison(&mut self) -> Result<Expr> {
        let at = self.pos();
        let first = self.binary(0)?;
        let mut ops = Vec::new();
        let mut items = vec![first];
        while let Some(o) = self.comp_op() {
            ops.push(o);
            items.push(self.binary(0)?);
        }
        if ops.is_empty() {
            return Ok(items
                .pop()
                .unwrap_or_else(|| self.mk(ExprKind::Unsupported("nothing"), at)));
        }
        Ok(self.mk(ExprKind::Compare(items, ops), at))
    }

    /// Binary operators by level: | ^ & << >> + - * / // % @.
    fn binary(&mut self, level: usize) -> Result<Expr> {
        const LEVELS: &[&[&str]] = &[
            &["|"],
            &["^"],
            &["&"],
            &["<<", ">>"],
            &["+", "-"],
            &["*", "/", "//", "%", "@"],
        ];
        if level == LEVELS.len() {
            return self.unary();
        }
        let at = self.pos();
        let mut e = self.binary(level + 1)?;
        while let Some(o) = LEVELS[level].iter().find(|o| self.is_op(o)).copied() {
            self.i += 1;
            let r = self.binary(level + 1)?;
            e = self.mk(ExprKind::Binary(o, e.into(), r.into()), at);
        }
        Ok(e)
    }

    fn unary(&mut self) -> Result<Expr> {
        let at = self.pos();
        for o in ["-", "+", "~"] {
            if self.eat_op(o) {
                self.deeper()?;
                let e = self.unary()?;
                self.depth -= 1;
                return Ok(self.mk(ExprKind::Unary(o, e.into()), at));
            }
        }
        self.power()
    }

    fn power(&mut self) -> Result<Expr> {
        let at = self.pos();
        if self.eat_name("await") {
            self.primary()?;
            return Ok(self.mk(ExprKind::Unsupported("await"), at));
        }
        let base = self.primary()?;
        if self.eat_op("**") {
            let exp = self.unary()?;
            return Ok(self.mk(ExprKind::Binary("**", base.into(), exp.into()), at));
        }
        Ok(base)
    }

    fn primary(&mut self) -> Result<Expr> {
        let at = self.pos();
        let mut e = self.atom()?;
        loop {
            if self.eat_op(".") {
                let Tok::Name(n) = self.peek().clone() else {
                    return self.fail("expected a name after `.`");
                };
                self.i += 1;
                e = self.mk(ExprKind::Attr(e.into(), n), at);
            } else if self.eat_op("(") {
                e = self.call(e, at)?;
            } else if self.eat_op("[") {
                let idx = self.subscript()?;
                self.expect_op("]")?;
                e = self.mk(ExprKind::Index(e.into(), idx.into()), at);
            } else {
                return Ok(e);
            }
        }
    }

    fn call(&mut self, func: Expr, at: (usize, usize)) -> Result<Expr> {
        let (mut args, mut kwargs, mut star) = (Vec::new(), Vec::new(), false);
        while !self.eat_op(")") {
            if self.eat_op("**") || self.eat_op("*") {
                star = true;
                self.test()?;
            } else if let (Tok::Name(n), Some(Tok::Op("="))) =
                (self.peek().clone(), self.t.get(self.i + 1).map(|t| &t.tok))
            {
                let at = self.pos();
                self.i += 2;
                kwargs.push((n, self.test()?, at));
            } else {
                let a = self.test()?;
                if self.is_name("for") {
                    self.comp_tail(a)?;
                    args.push(self.mk(ExprKind::Unsupported("a generator expression"), at));
                } else {
                    args.push(a);
                }
            }
            if !self.eat_op(",") {
                self.expect_op(")")?;
                break;
            }
        }
        Ok(self.mk(
            ExprKind::Call {
                func: func.into(),
                args,
                kwargs,
                star,
            },
            at,
        ))
    }

    fn subscript(&mut self) -> Result<Expr> {
        let at = self.pos();
        let part = |p: &mut P| -> Result<Option<Box<Expr>>> {
            if p.is_op(":") || p.is_op("]") || p.is_op(",") {
                Ok(None)
            } else {
                Ok(Some(p.test()?.into()))
            }
        };
        let a = part(self)?;
        if !self.eat_op(":") {
            let Some(a) = a else {
                return self.fail("expected a subscript");
            };
            if self.is_op(",") {
                return self.fail("multi-dimensional subscripts are not evaluated");
            }
            return Ok(*a);
        }
        let b = part(self)?;
        let c = if self.eat_op(":") { part(self)? } else { None };
        Ok(self.mk(ExprKind::Slice(a, b, c), at))
    }

    /// `for target in iter [if cond]...` after a comprehension's element.
    fn comp_tail(&mut self, elt: Expr) -> Result<ExprKind> {
        let mut first: Option<(Expr, Expr)> = None;
        let mut conds = Vec::new();
        let mut many = false;
        while self.eat_name("for") {
            let target = self.target_list()?;
            if !self.eat_name("in") {
                return self.fail("expected `in` in a comprehension");
            }
            let iter = self.or_test()?;
            if first.is_some() {
                many = true;
            } else {
                first = Some((target, iter));
            }
            while self.eat_name("if") {
                conds.push(self.or_test()?);
            }
        }
        let (target, iter) = first.ok_or_else(|| err(elt.line, elt.col, "expected `for`"))?;
        if many {
            return Ok(ExprKind::Unsupported(
                "a comprehension with several `for` clauses",
            ));
        }
        Ok(ExprKind::ListComp {
            elt: elt.into(),
            target: target.into(),
            iter: iter.into(),
            conds,
        })
    }

    fn target_list(&mut self) -> Result<Expr> {
        let at = self.pos();
        let first = self.binary(0)?;
        if !self.is_op(",") {
            return Ok(first);
        }
        let mut items = vec![first];
        while self.eat_op(",") {
            if self.is_name("in") || self.is_op("=") {
                break;
            }
            items.push(self.binary(0)?);
        }
        Ok(self.mk(ExprKind::Tuple(items), at))
    }

    fn atom(&mut self) -> Result<Expr> {
        let at = self.pos();
        let tok = self.peek().clone();
        self.i += 1;
        let kind = match tok {
            Tok::Name(n) => match n.as_str() {
                "True" | "False" | "None" => ExprKind::Name(n),
                "yield" => return self.fail("yield is not evaluated"),
                _ => ExprKind::Name(n),
            },
            Tok::Int(v) => ExprKind::Int(v),
            Tok::Float(v) => ExprKind::Float(v),
            Tok::Str { value, fstring } => return self.strings(value, fstring, at),
            Tok::Op("(") => return self.paren(at),
            Tok::Op("[") => return self.list(at),
            Tok::Op("{") => return self.dict(at),
            Tok::Op("...") => ExprKind::Unsupported("Ellipsis"),
            other => {
                self.i -= 1;
                return self.fail(format!(
                    "expected an expression, found {}",
                    describe(&other)
                ));
            }
        };
        Ok(self.mk(kind, at))
    }

    /// Adjacent string literals concatenate (f-strings included).
    fn strings(&mut self, first: String, fstring: bool, at: (usize, usize)) -> Result<Expr> {
        let mut parts = Vec::new();
        let mut any_f = fstring;
        push_literal(&mut parts, first, fstring, at)?;
        while let Tok::Str { value, fstring } = self.peek().clone() {
            let here = self.pos();
            self.i += 1;
            any_f |= fstring;
            push_literal(&mut parts, value, fstring, here)?;
        }
        if !any_f {
            let s: String = parts
                .into_iter()
                .map(|p| {
                    if let FPart::Text(t) = p {
                        t
                    } else {
                        String::new()
                    }
                })
                .collect();
            return Ok(self.mk(ExprKind::Str(s), at));
        }
        Ok(self.mk(ExprKind::FStr(parts), at))
    }

    fn paren(&mut self, at: (usize, usize)) -> Result<Expr> {
        if self.eat_op(")") {
            return Ok(self.mk(ExprKind::Tuple(Vec::new()), at));
        }
        let first = self.test()?;
        if self.is_name("for") {
            self.comp_tail(first)?;
            self.expect_op(")")?;
            return Ok(self.mk(ExprKind::Unsupported("a generator expression"), at));
        }
        if self.eat_op(")") {
            return Ok(first);
        }
        let mut items = vec![first];
        while self.eat_op(",") {
            if self.is_op(")") {
                break;
            }
            items.push(self.test()?);
        }
        self.expect_op(")")?;
        Ok(self.mk(ExprKind::Tuple(items), at))
    }

    fn list(&mut self, at: (usize, usize)) -> Result<Expr> {
        let mut items = Vec::new();
        while !self.eat_op("]") {
            if self.eat_op("*") {
                self.test()?;
                items.push(self.mk(ExprKind::Unsupported("a starred element"), at));
            } else {
                let e = self.test()?;
                if self.is_name("for") && items.is_empty() {
                    let kind = self.comp_tail(e)?;
                    self.expect_op("]")?;
                    return Ok(self.mk(kind, at));
                }
                items.push(e);
            }
            if !self.eat_op(",") {
                self.expect_op("]")?;
                break;
            }
        }
        Ok(self.mk(ExprKind::List(items), at))
    }

    fn dict(&mut self, at: (usize, usize)) -> Result<Expr> {
        let mut items = Vec::new();
        let mut set = false;
        while !self.eat_op("}") {
            if self.eat_op("**") {
                self.test()?;
                set = true;
            } else {
                let k = self.test()?;
                if self.eat_op(":") {
                    let v = self.test()?;
                    if self.is_name("for") {
                        self.comp_tail(v)?;
                        set = true;
                    } else {
                        items.push((k, v));
                    }
                } else {
                    if self.is_name("for") {
                        self.comp_tail(k)?;
                    }
                    set = true;
                }
            }
            if !self.eat_op(",") {
                self.expect_op("}")?;
                break;
            }
        }
        if set {
            return Ok(self.mk(
                ExprKind::Unsupported("a set, dict unpacking or comprehension"),
                at,
            ));
        }
        Ok(self.mk(ExprKind::Dict(items), at))
    }
}

/// An f-string's text into literal parts and `{...}` fields (`{{`, `}}` are
/// braces); a plain string is one literal part.
fn push_literal(
    parts: &mut Vec<FPart>,
    s: String,
    fstring: bool,
    at: (usize, usize),
) -> Result<()> {
    if !fstring {
        parts.push(FPart::Text(s));
        return Ok(());
    }
    let mut text = String::new();
    let mut it = s.char_indices().peekable();
    while let Some((i, c)) = it.next() {
        match c {
            '{' if it.peek().map(|p| p.1) == Some('{') => {
                it.next();
                text.push('{');
            }
            '}' if it.peek().map(|p| p.1) == Some('}') => {
                it.next();
                text.push('}');
            }
            '{' => {
                parts.push(FPart::Text(unescape(&std::mem::take(&mut text))));
                let (end, field) = fstring_field(&s, i + 1, at)?;
                parts.push(field);
                while it.peek().is_some_and(|p| p.0 < end) {
                    it.next();
                }
            }
            '}' => return Err(err(at.0, at.1, "f-string: single `}` is not allowed")),
            c => text.push(c),
        }
    }
    parts.push(FPart::Text(unescape(&text)));
    Ok(())
}

/// The field starting after `{` at `start`: (index after its `}`, field).
fn fstring_field(s: &str, start: usize, at: (usize, usize)) -> Result<(usize, FPart)> {
    let b = s.as_bytes();
    let (mut depth, mut i, mut quote) = (0usize, start, None::<u8>);
    let mut colon = None;
    let mut bang = None;
    while i < b.len() {
        let c = b[i];
        match (quote, c) {
            (Some(q), _) if c == q => quote = None,
            (Some(_), _) => {}
            (None, b'\'' | b'"') => quote = Some(c),
            (None, b'(' | b'[' | b'{') => depth += 1,
            (None, b')' | b']') => depth = depth.saturating_sub(1),
            (None, b'}') if depth > 0 => depth -= 1,
            (None, b'}') => break,
            (None, b'!') if depth == 0 && colon.is_none() && b.get(i + 1) != Some(&b'=') => {
                bang = Some(i)
            }
            (None, b':') if depth == 0 && colon.is_none() => colon = Some(i),
            _ => {}
        }
        i += 1;
    }
    if i >= b.len() {
        return Err(err(at.0, at.1, "f-string: expected `}`"));
    }
    let expr_end = bang.or(colon).unwrap_or(i);
    let conv = bang.and_then(|p| s[p + 1..].chars().next());
    let spec = colon.map(|p| s[p + 1..i].to_string()).unwrap_or_default();
    let src = &s[start..expr_end];
    if src.trim().ends_with('=') {
        return Err(err(
            at.0,
            at.1,
            "f-string `{x=}` debugging fields are not evaluated",
        ));
    }
    let expr = expression(src, at.0)?;
    Ok((i + 1, FPart::Field { expr, conv, spec }))
}

/// The simple escapes of an f-string's literal text.
fn unescape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut it = s.chars();
    while let Some(c) = it.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match it.next() {
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('\\') => out.push('\\'),
            Some('\'') => out.push('\''),
            Some('"') => out.push('"'),
            Some(o) => {
                out.push('\\');
                out.push(o);
            }
            None => out.push('\\'),
        }
    }
    out
}

pub(crate) fn describe(t: &Tok) -> String {
    match t {
        Tok::Name(n) => format!("`{n}`"),
        Tok::Int(v) => format!("the number {v}"),
        Tok::Float(v) => format!("the number {v}"),
        Tok::Str { .. } => "a string".into(),
        Tok::Op(o) => format!("`{o}`"),
        Tok::Newline => "the end of the line".into(),
        Tok::Indent => "an indented block".into(),
        Tok::Dedent => "the end of a block".into(),
        Tok::End => "the end".into(),
    }
}

/// Statements.
impl P {
    /// A statement that consumes at least one token: a statement loop
    /// that stood still would push statements until memory ran out.
    fn next_statement(&mut self) -> Result<Stmt> {
        let start = self.i;
        if matches!(self.peek(), Tok::Indent) {
            return self.fail("unexpected indent (an indented line that opens no block)");
        }
        let s = self.statement()?;
        if self.i == start {
            return self.fail(format!(
                "expected a statement, found {}",
                describe(self.peek())
            ));
        }
        Ok(s)
    }

    fn statement(&mut self) -> Result<Stmt> {
        let (line, _) = self.pos();
        while self.eat_op("@") {
            self.test()?;
            self.eat_newline();
        }
        let Tok::Name(kw) = self.peek().clone() else {
            return self.simple_line(line);
        };
        match kw.as_str() {
            "def" => self.def(line),
            "for" => {
                self.i += 1;
                let target = self.target_list()?;
                if !self.eat_name("in") {
                    return self.fail("expected `in` after the `for` target");
                }
                let iter = self.test_list()?;
                let body = self.block()?;
                let orelse = if self.eat_name("else") {
                    self.block()?
                } else {
                    Vec::new()
                };
                Ok(Stmt::For {
                    target,
                    iter,
                    body,
                    orelse,
                    line,
                })
            }
            "if" => self.if_stmt(line),
            "while" | "with" | "class" | "try" | "async" => self.compound(line, kw),
            _ => self.simple_line(line),
        }
    }

    fn def(&mut self, line: usize) -> Result<Stmt> {
        self.i += 1;
        let Tok::Name(name) = self.peek().clone() else {
            return self.fail("expected a function name");
        };
        self.i += 1;
        self.expect_op("(")?;
        let mut params = Vec::new();
        while !self.eat_op(")") {
            if self.eat_op("*") || self.eat_op("**") || self.eat_op("/") {
                if let Tok::Name(n) = self.peek().clone() {
                    self.i += 1;
                    params.push((format!("*{n}"), None));
                }
            } else {
                let Tok::Name(n) = self.peek().clone() else {
                    return self.fail("expected a parameter name");
                };
                self.i += 1;
                if self.eat_op(":") {
                    self.test()?;
                }
                let default = if self.eat_op("=") {
                    Some(self.test()?)
                } else {
                    None
                };
                params.push((n, default));
            }
            if !self.eat_op(",") {
                self.expect_op(")")?;
                break;
            }
        }
        if self.eat_op("->") {
            self.test()?;
        }
        let body = self.block()?;
        Ok(Stmt::Def {
            name,
            params,
            body,
            line,
        })
    }

    fn if_stmt(&mut self, line: usize) -> Result<Stmt> {
        self.i += 1;
        let cond = self.test()?;
        let body = self.block()?;
        let orelse = if self.is_name("elif") {
            let (l, _) = self.pos();
            vec![self.if_stmt(l)?]
        } else if self.eat_name("else") {
            self.block()?
        } else {
            Vec::new()
        };
        Ok(Stmt::If {
            cond,
            body,
            orelse,
            line,
        })
    }

    /// `while`, `with`, `class`, `try` (with its `except`/`else`/`finally`):
    /// the header skipped, the blocks kept.
    fn compound(&mut self, line: usize, kw: String) -> Result<Stmt> {
        let what = match kw.as_str() {
            "while" => "a `while` loop",
            "with" => "a `with` block",
            "class" => "a class",
            "try" => "a `try` block",
            _ => "an `async` statement",
        };
        let mut body = Vec::new();
        loop {
            self.skip_header()?;
            body.extend(self.block()?);
            let more = ["except", "else", "finally"]
                .iter()
                .any(|k| self.is_name(k));
            if !(kw == "try" && more) {
                break;
            }
        }
        Ok(Stmt::Block { what, body, line })
    }

    /// Tokens up to the `:` that opens a block (brackets are balanced by the
    /// lexer's line joining).
    fn skip_header(&mut self) -> Result<()> {
        let mut depth = 0usize;
        loop {
            match self.peek() {
                Tok::Op("(" | "[" | "{") => depth += 1,
                Tok::Op(")" | "]" | "}") => depth = depth.saturating_sub(1),
                Tok::Op(":") if depth == 0 => return Ok(()),
                Tok::Newline | Tok::End => return self.fail("expected `:` opening a block"),
                _ => {}
            }
            self.i += 1;
        }
    }

    /// `:` then an indented block, or statements on the same line.
    fn block(&mut self) -> Result<Vec<Stmt>> {
        self.expect_op(":")?;
        let mut out = Vec::new();
        if !self.eat_newline() {
            let (line, _) = self.pos();
            out.push(self.simple_line(line)?);
            return Ok(out);
        }
        if !matches!(self.peek(), Tok::Indent) {
            return self.fail("expected an indented block");
        }
        self.i += 1;
        self.deeper()?;
        while !matches!(self.peek(), Tok::Dedent | Tok::End) {
            out.push(self.next_statement()?);
        }
        self.depth -= 1;
        if matches!(self.peek(), Tok::Dedent) {
            self.i += 1;
        }
        Ok(out)
    }

    fn eat_newline(&mut self) -> bool {
        let hit = matches!(self.peek(), Tok::Newline);
        if hit {
            self.i += 1;
        }
        hit
    }

    /// One simple statement line (`a; b` keeps the first, the rest as
    /// `Other`); a line that does not parse is kept as `Other` with why.
    fn simple_line(&mut self, line: usize) -> Result<Stmt> {
        let start = self.i;
        let s = match self.simple() {
            Ok(s) if matches!(self.peek(), Tok::Newline | Tok::End) || self.is_op(";") => s,
            Ok(_) => Stmt::Other(
                format!(
                    "a statement this reader does not parse ({})",
                    describe(self.peek())
                ),
                line,
            ),
            Err(e) if e.code == Code::Limit => return Err(e),
            Err(e) => Stmt::Other(
                format!("a statement this reader does not parse: {}", e.message),
                line,
            ),
        };
        if matches!(s, Stmt::Other(..)) {
            self.i = start;
        }
        // To the end of the logical line.
        while !matches!(self.peek(), Tok::Newline | Tok::End) {
            if matches!(self.peek(), Tok::Indent | Tok::Dedent) {
                break;
            }
            self.i += 1;
        }
        self.eat_newline();
        Ok(s)
    }

    /// The names an import binds.
    fn import(&mut self, line: usize) -> Result<Stmt> {
        let from = self.is_name("from");
        self.i += 1;
        if from {
            while !self.is_name("import") {
                if matches!(self.peek(), Tok::Newline | Tok::End) {
                    return self.fail("expected `import` in a `from` statement");
                }
                self.i += 1;
            }
            self.i += 1;
        }
        let mut names = Vec::new();
        let paren = self.eat_op("(");
        loop {
            if self.eat_op("*") {
                names.push("*".to_string());
            } else {
                let mut dotted = Vec::new();
                while let Tok::Name(n) = self.peek().clone() {
                    self.i += 1;
                    dotted.push(n);
                    if !self.eat_op(".") {
                        break;
                    }
                }
                let Some(first) = dotted.first().cloned() else {
                    return self.fail("expected a name to import");
                };
                let bound = if self.eat_name("as") {
                    let Tok::Name(a) = self.peek().clone() else {
                        return self.fail("expected a name after `as`");
                    };
                    self.i += 1;
                    a
                } else if from {
                    dotted.last().cloned().unwrap_or(first)
                } else {
                    first
                };
                names.push(bound);
            }
            if !self.eat_op(",") || (paren && self.is_op(")")) {
                break;
            }
        }
        if paren {
            self.expect_op(")")?;
        }
        Ok(Stmt::Import(names, line))
    }

    fn simple(&mut self) -> Result<Stmt> {
        let (line, _) = self.pos();
        if let Tok::Name(kw) = self.peek().clone() {
            match kw.as_str() {
                "return" => {
                    self.i += 1;
                    let v = if matches!(self.peek(), Tok::Newline | Tok::End) || self.is_op(";") {
                        None
                    } else {
                        Some(self.test_list()?)
                    };
                    return Ok(Stmt::Return(v, line));
                }
                "import" | "from" => return self.import(line),
                "pass" | "global" | "nonlocal" | "del" | "assert" | "raise" | "break"
                | "continue" => {
                    while !matches!(self.peek(), Tok::Newline | Tok::End) && !self.is_op(";") {
                        self.i += 1;
                    }
                    return Ok(Stmt::Other(format!("`{kw}`"), line));
                }
                _ => {}
            }
        }
        let first = self.test_list()?;
        if self.is_op("=") {
            let mut targets = vec![first];
            let mut value;
            loop {
                self.expect_op("=")?;
                value = self.test_list()?;
                if !self.is_op("=") {
                    break;
                }
                targets.push(value.clone());
            }
            return Ok(Stmt::Assign {
                targets,
                value,
                line,
            });
        }
        if self.eat_op(":") {
            self.test()?;
            if self.eat_op("=") {
                let value = self.test_list()?;
                return Ok(Stmt::Assign {
                    targets: vec![first],
                    value,
                    line,
                });
            }
            return Ok(Stmt::Other("an annotation".into(), line));
        }
        for op in [
            "+=", "-=", "*=", "/=", "//=", "%=", "**=", "|=", "&=", "^=", ">>=", "<<=", "@=",
        ] {
            if self.eat_op(op) {
                let value = self.test_list()?;
                return Ok(Stmt::AugAssign {
                    target: first,
                    op: &op[..op.len() - 1],
                    value,
                    line,
                });
            }
        }
        Ok(Stmt::Expr(first))
    }
}
