//! Evaluate an expression: Python's semantics for the values of
//! [`super::value`] (int/float promotion, floor division and modulo with the
//! divisor's sign, `and`/`or` returning an operand, chained comparisons,
//! negative indices and slices), a closed list of builtins, `math`
//! functions and `str`/`list`/`dict` methods; anything else is an error
//! naming it. Nothing is ever executed. A value the host cannot know
//! ([`Value::Unknown`]) propagates through every operation.

use std::rc::Rc;

use super::budget::{items_fit, str_fits, Budget};
use super::parse::{Expr, ExprKind, FPart};
use super::value::{float_repr, Func, Value};
use crate::diagnostic::{Error, Result};

/// What the evaluator asks of its host: names, and calls of what the host
/// defines (functions of the file, launch actions).
pub trait Host {
    /// The value of a name the evaluator does not bind itself; `None`:
    /// undefined.
    fn name(&mut self, name: &str) -> Option<Value>;
    /// Call a host function (`Func::User`, `Func::Host`).
    fn call(
        &mut self,
        f: &Func,
        args: Vec<Value>,
        kwargs: Vec<(String, Value)>,
        at: &Expr,
    ) -> Result<Value>;
    /// Whether an argument that cannot be evaluated becomes a value known to
    /// be unknown (a launch.py reader keeps the call) instead of an error.
    fn lenient(&self) -> bool {
        false
    }
}

/// An error at `e`.
pub fn fail<T>(e: &Expr, msg: impl Into<String>) -> Result<T> {
    Err(Error::parse(msg.into()).at_line(e.line, Some(e.col)))
}

/// The builtins evaluated (CPython's semantics for these arguments).
pub const BUILTINS: &[&str] = &[
    "abs",
    "bool",
    "dict",
    "enumerate",
    "float",
    "int",
    "len",
    "list",
    "max",
    "min",
    "range",
    "repr",
    "round",
    "str",
    "sum",
    "tuple",
    "zip",
];

/// The `math` names evaluated.
pub const MATH: &[&str] = &[
    "acos", "asin", "atan", "atan2", "ceil", "cos", "cosh", "degrees", "exp", "fabs", "floor",
    "hypot", "log", "log10", "log2", "pow", "radians", "sin", "sinh", "sqrt", "tan", "tanh",
];

/// A `math` constant.
pub fn math_constant(n: &str) -> Option<f64> {
    Some(match n {
        "pi" => std::f64::consts::PI,
        "e" => std::f64::consts::E,
        "tau" => std::f64::consts::TAU,
        "inf" => f64::INFINITY,
        "nan" => f64::NAN,
        _ => return None,
    })
}

/// An evaluator over `host`, with the comprehension variables in scope and
/// the budget every value it creates is charged to.
pub struct Eval<'h> {
    pub host: &'h mut dyn Host,
    scopes: Vec<Vec<(String, Value)>>,
    budget: Rc<Budget>,
}

impl<'h> Eval<'h> {
    /// An evaluator with a budget of its own.
    pub fn new(host: &'h mut dyn Host) -> Self {
        Self::with_budget(host, Rc::default())
    }

    /// An evaluator charging `budget` (shared by a file's expressions).
    pub fn with_budget(host: &'h mut dyn Host, budget: Rc<Budget>) -> Self {
        Eval {
            host,
            scopes: Vec::new(),
            budget,
        }
    }

    /// Evaluate `e`, charging the value to the budget.
    pub fn eval(&mut self, e: &Expr) -> Result<Value> {
        let r = self
            .eval_uncharged(e)
            .and_then(|v| self.budget.charge(&v, e).map(|()| v));
        if let Err(err) = &r {
            self.budget.note(err);
        }
        r
    }

    fn eval_uncharged(&mut self, e: &Expr) -> Result<Value> {
        Ok(match &e.kind {
            ExprKind::Name(n) => self.name(n, e)?,
            ExprKind::Int(i) => Value::Int(*i),
            ExprKind::Float(f) => Value::Float(*f),
            ExprKind::Str(s) => Value::Str(s.clone()),
            ExprKind::FStr(parts) => self.fstring(parts)?,
            ExprKind::List(items) => Value::list(self.all(items)?),
            ExprKind::Tuple(items) => Value::Tuple(self.all(items)?),
            ExprKind::Dict(items) => {
                let mut d: Vec<(Value, Value)> = Vec::new();
                for (k, v) in items {
                    let (k, v) = (self.eval(k)?, self.eval(v)?);
                    match d.iter_mut().find(|(x, _)| equal(x, &k)) {
                        Some(slot) => slot.1 = v,
                        None => d.push((k, v)),
                    }
                }
                Value::Dict(d)
            }
            ExprKind::ListComp {
                elt,
                target,
                iter,
                conds,
            } => self.comprehension(elt, target, iter, conds)?,
            ExprKind::Attr(obj, name) => self.attr(obj, name, e)?,
            ExprKind::Call {
                func,
                args,
                kwargs,
                star,
            } => {
                if *star {
                    return fail(e, "a call with *args or **kwargs is not evaluated");
                }
                let f = self.eval(func)?;
                let mut vals = Vec::new();
                for a in args {
                    vals.push(self.arg(a)?);
                }
                let mut kw = Vec::new();
                for (k, v, _) in kwargs {
                    kw.push((k.clone(), self.arg(v)?));
                }
                self.call(f, vals, kw, e)?
            }
            ExprKind::Index(obj, idx) => {
                let o = self.eval(obj)?;
                if let ExprKind::Slice(a, b, c) = &idx.kind {
                    let mut part = |x: &Option<Box<Expr>>| -> Result<Option<Value>> {
                        x.as_ref().map(|x| self.eval(x)).transpose()
                    };
                    let (a, b, c) = (part(a)?, part(b)?, part(c)?);
                    slice(&o, a, b, c, e)?
                } else {
                    let i = self.eval(idx)?;
                    index(&o, &i, e)?
                }
            }
            ExprKind::Slice(..) => return fail(e, "a slice outside a subscript"),
            ExprKind::Unary(op, x) => unary(op, self.eval(x)?, e)?,
            ExprKind::Binary(op, a, b) => {
                let (a, b) = (self.eval(a)?, self.eval(b)?);
                binary(op, &a, &b, e)?
            }
            ExprKind::Compare(items, ops) => self.compare(items, ops)?,
            ExprKind::And(a, b) => {
                let a = self.eval(a)?;
                match a.truth() {
                    None => a,
                    Some(false) => a,
                    Some(true) => self.eval(b)?,
                }
            }
            ExprKind::Or(a, b) => {
                let a = self.eval(a)?;
                match a.truth() {
                    None => a,
                    Some(true) => a,
                    Some(false) => self.eval(b)?,
                }
            }
            ExprKind::Not(x) => {
                let v = self.eval(x)?;
                match v.truth() {
                    None => v,
                    Some(t) => Value::Bool(!t),
                }
            }
            ExprKind::IfElse { cond, then, other } => {
                let c = self.eval(cond)?;
                match c.truth() {
                    None => c,
                    Some(true) => self.eval(then)?,
                    Some(false) => self.eval(other)?,
                }
            }
            ExprKind::Unsupported(what) => return fail(e, format!("{what} is not evaluated")),
        })
    }

    /// A call's argument: an error is an unknown value for a lenient host.
    fn arg(&mut self, a: &Expr) -> Result<Value> {
        match self.eval(a) {
            Err(err) if self.host.lenient() => Ok(Value::unknown(format!(
                "{} (line {})",
                err.message,
                err.location.line.unwrap_or(a.line)
            ))),
            r => r,
        }
    }

    fn all(&mut self, items: &[Expr]) -> Result<Vec<Value>> {
        items.iter().map(|x| self.eval(x)).collect()
    }

    fn name(&mut self, n: &str, e: &Expr) -> Result<Value> {
        for scope in self.scopes.iter().rev() {
            if let Some((_, v)) = scope.iter().rev().find(|(k, _)| k == n) {
                return Ok(v.clone());
            }
        }
        match n {
            "True" => return Ok(Value::Bool(true)),
            "False" => return Ok(Value::Bool(false)),
            "None" => return Ok(Value::None),
            _ => {}
        }
        match self.host.name(n) {
            Some(v) => Ok(v),
            None => fail(e, format!("name `{n}` is not defined")),
        }
    }

    fn fstring(&mut self, parts: &[FPart]) -> Result<Value> {
        let mut out = String::new();
        for p in parts {
            match p {
                FPart::Text(t) => out.push_str(t),
                FPart::Field { expr, conv, spec } => {
                    let v = self.eval(expr)?;
                    if let Value::Unknown(_) = v {
                        return Ok(v);
                    }
                    let v = match conv {
                        Some('r') => Value::Str(v.try_repr(expr)?),
                        Some('s') | None => v,
                        Some(c) => {
                            return fail(expr, format!("f-string conversion !{c} is not evaluated"))
                        }
                    };
                    out.push_str(&format_spec(&v, spec, expr)?);
                    str_fits(out.len(), "an f-string", expr)?;
                }
            }
        }
        Ok(Value::Str(out))
    }

    fn comprehension(
        &mut self,
        elt: &Expr,
        target: &Expr,
        iter: &Expr,
        conds: &[Expr],
    ) -> Result<Value> {
        let it = self.eval(iter)?;
        if let Value::Unknown(_) = it {
            return Ok(it);
        }
        let items = iterate(&it, iter)?;
        let mut out = Vec::new();
        for x in items {
            let mut scope = Vec::new();
            bind(target, x, &mut scope)?;
            self.scopes.push(scope);
            let mut keep = true;
            for c in conds {
                match self.eval(c)?.truth() {
                    Some(t) => keep &= t,
                    None => {
                        self.scopes.pop();
                        return Ok(Value::unknown(format!(
                            "a comprehension condition at line {} is not known",
                            c.line
                        )));
                    }
                }
            }
            let v = if keep { Some(self.eval(elt)?) } else { None };
            self.scopes.pop();
            out.extend(v);
            items_fit(out.len(), "a list comprehension", elt)?;
        }
        Ok(Value::list(out))
    }

    fn compare(&mut self, items: &[Expr], ops: &[&'static str]) -> Result<Value> {
        let mut left = self.eval(&items[0])?;
        for (op, r) in ops.iter().zip(&items[1..]) {
            let right = self.eval(r)?;
            if let Value::Unknown(_) = left {
                return Ok(left);
            }
            if let Value::Unknown(_) = right {
                return Ok(right);
            }
            if let Some(Value::Record(r)) = [&left, &right]
                .into_iter()
                .find(|v| matches!(v, Value::Record(_)))
            {
                return Ok(Value::unknown(format!(
                    "a comparison with {}(...) (line {}), whose value is known only at launch",
                    r.name, r.line
                )));
            }
            if !compare(op, &left, &right, r)? {
                return Ok(Value::Bool(false));
            }
            left = right;
        }
        Ok(Value::Bool(true))
    }

    fn attr(&mut self, obj: &Expr, name: &str, e: &Expr) -> Result<Value> {
        let o = self.eval(obj)?;
        match &o {
            Value::Unknown(_) => Ok(o),
            Value::Module("math") => {
                if let Some(c) = math_constant(name) {
                    return Ok(Value::Float(c));
                }
                match MATH.iter().find(|m| **m == name) {
                    Some(m) => Ok(Value::Func(Func::Builtin(m))),
                    None => fail(e, format!("math.{name} is not evaluated")),
                }
            }
            Value::Str(_) | Value::List(_) | Value::Dict(_) | Value::Tuple(_) => Ok(Value::Func(
                Func::Method(Box::new(o.clone()), name.to_string()),
            )),
            Value::Record(r) => Ok(Value::unknown(format!(
                "attribute `{name}` of {}(...) at line {}",
                r.name, r.line
            ))),
            // An imported module or class: its attributes are the host's names.
            Value::Func(Func::Host(_)) => Ok(Value::Func(Func::Host(name.to_string()))),
            other => fail(
                e,
                format!(
                    "attribute `{name}` of a {} value is not evaluated",
                    other.type_name()
                ),
            ),
        }
    }

    /// Call `f` with the arguments given.
    pub fn call(
        &mut self,
        f: Value,
        args: Vec<Value>,
        kw: Vec<(String, Value)>,
        e: &Expr,
    ) -> Result<Value> {
        match f {
            Value::Unknown(_) => Ok(f),
            Value::Func(Func::Builtin(name)) => {
                if let Some(u) = args
                    .iter()
                    .chain(kw.iter().map(|(_, v)| v))
                    .find(|v| matches!(v, Value::Unknown(_)))
                {
                    return Ok(u.clone());
                }
                super::builtins::call(name, &args, &kw, e)
            }
            Value::Func(Func::Method(recv, name)) => {
                if let Some(u) = args.iter().find(|v| matches!(v, Value::Unknown(_))) {
                    return Ok(u.clone());
                }
                if let (Value::List(_), "append", [x]) = (&*recv, name.as_str(), &args[..]) {
                    self.budget.fits_in_list(x, "list.append()", e)?;
                }
                super::methods::call(&recv, &name, &args, &kw, e)
            }
            Value::Func(ref h @ (Func::User(_) | Func::Host(_))) => self.host.call(h, args, kw, e),
            other => fail(e, format!("a {} value is not callable", other.type_name())),
        }
    }
}

/// Bind a `for` target (a name or a tuple of names) to `v`.
pub fn bind(target: &Expr, v: Value, scope: &mut Vec<(String, Value)>) -> Result<()> {
    match &target.kind {
        ExprKind::Name(n) => {
            scope.push((n.clone(), v));
            Ok(())
        }
        ExprKind::Tuple(ts) | ExprKind::List(ts) => {
            if let Value::Unknown(_) = v {
                for t in ts {
                    bind(t, v.clone(), scope)?;
                }
                return Ok(());
            }
            let items = v.items().ok_or_else(|| {
                Error::parse(format!(
                    "cannot unpack a {} value into {} names",
                    v.type_name(),
                    ts.len()
                ))
                .at_line(target.line, Some(target.col))
            })?;
            if items.len() != ts.len() {
                return fail(
                    target,
                    format!(
                        "cannot unpack {} values into {} names",
                        items.len(),
                        ts.len()
                    ),
                );
            }
            for (t, x) in ts.iter().zip(items) {
                bind(t, x, scope)?;
            }
            Ok(())
        }
        _ => fail(target, "only names and tuples of names are assigned here"),
    }
}

/// The items a `for` iterates over.
pub fn iterate(v: &Value, at: &Expr) -> Result<Vec<Value>> {
    match v {
        Value::List(_) | Value::Tuple(_) => Ok(v.items().unwrap_or_default()),
        Value::Str(s) => {
            items_fit(s.chars().count(), "iterating a string", at)?;
            Ok(s.chars().map(|c| Value::Str(c.to_string())).collect())
        }
        Value::Dict(d) => Ok(d.iter().map(|(k, _)| k.clone()).collect()),
        other => fail(
            at,
            format!(
                "iteration over a {} value is not evaluated",
                other.type_name()
            ),
        ),
    }
}

/// `==` between two values (numbers across int/float/bool).
pub fn equal(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Str(x), Value::Str(y)) => x == y,
        // The same list, as CPython's identity test first: a list that holds
        // itself compares without recursing forever.
        (Value::List(x), Value::List(y)) if Rc::ptr_eq(x, y) => true,
        (Value::None, Value::None) => true,
        (x, y) if x.as_f64().is_some() && y.as_f64().is_some() => match (x.as_int(), y.as_int()) {
            (Some(i), Some(j)) => i == j,
            _ => x.as_f64() == y.as_f64(),
        },
        (x, y) if x.items().is_some() && y.items().is_some() => {
            let same_kind = matches!(
                (x, y),
                (Value::List(_), Value::List(_)) | (Value::Tuple(_), Value::Tuple(_))
            );
            let (p, q) = (x.items().unwrap_or_default(), y.items().unwrap_or_default());
            same_kind && p.len() == q.len() && p.iter().zip(&q).all(|(a, b)| equal(a, b))
        }
        (Value::Dict(x), Value::Dict(y)) => {
            x.len() == y.len()
                && x.iter()
                    .all(|(k, v)| y.iter().any(|(k2, v2)| equal(k, k2) && equal(v, v2)))
        }
        _ => false,
    }
}

/// Order between two values (`None` when Python would raise TypeError).
fn order(a: &Value, b: &Value) -> Option<std::cmp::Ordering> {
    match (a, b) {
        (Value::Str(x), Value::Str(y)) => Some(x.cmp(y)),
        (x, y) if x.as_f64().is_some() && y.as_f64().is_some() => match (x.as_int(), y.as_int()) {
            (Some(i), Some(j)) => Some(i.cmp(&j)),
            _ => x.as_f64()?.partial_cmp(&y.as_f64()?),
        },
        (x, y) if x.items().is_some() && y.items().is_some() => {
            let (p, q) = (x.items()?, y.items()?);
            for (a, b) in p.iter().zip(&q) {
                if !equal(a, b) {
                    return order(a, b);
                }
            }
            Some(p.len().cmp(&q.len()))
        }
        _ => None,
    }
}

fn compare(op: &str, a: &Value, b: &Value, at: &Expr) -> Result<bool> {
    use std::cmp::Ordering::*;
    Ok(match op {
        "==" => equal(a, b),
        "!=" => !equal(a, b),
        "is" => {
            matches!((a, b), (Value::None, Value::None))
                || matches!((a, b), (Value::Bool(x), Value::Bool(y)) if x == y)
        }
        "is not" => {
            !(matches!((a, b), (Value::None, Value::None))
                || matches!((a, b), (Value::Bool(x), Value::Bool(y)) if x == y))
        }
        "in" | "not in" => {
            let hit = match b {
                Value::Str(s) => match a {
                    Value::Str(x) => s.contains(x.as_str()),
                    _ => {
                        return fail(
                            at,
                            format!(
                                "'in <string>' requires a string as left operand, not {}",
                                a.type_name()
                            ),
                        )
                    }
                },
                Value::Dict(d) => d.iter().any(|(k, _)| equal(k, a)),
                other => iterate(other, at)?.iter().any(|x| equal(x, a)),
            };
            hit == (op == "in")
        }
        _ => {
            let o = order(a, b).ok_or_else(|| {
                Error::parse(format!(
                    "'{op}' not supported between {} and {}",
                    a.type_name(),
                    b.type_name()
                ))
                .at_line(at.line, Some(at.col))
            })?;
            match op {
                "<" => o == Less,
                ">" => o == Greater,
                "<=" => o != Greater,
                _ => o != Less,
            }
        }
    })
}

fn unary(op: &str, v: Value, at: &Expr) -> Result<Value> {
    if let Value::Unknown(_) = v {
        return Ok(v);
    }
    match (op, &v) {
        ("-", Value::Float(f)) => Ok(Value::Float(-f)),
        ("+", Value::Float(_)) => Ok(v),
        ("-", x) if x.as_int().is_some() => x
            .as_int()
            .and_then(i64::checked_neg)
            .map(Value::Int)
            .ok_or_else(|| overflow(at)),
        ("+", x) if x.as_int().is_some() => Ok(Value::Int(x.as_int().unwrap_or(0))),
        ("~", x) if x.as_int().is_some() => Ok(Value::Int(!x.as_int().unwrap_or(0))),
        _ => fail(
            at,
            format!("bad operand type for unary {op}: {}", v.type_name()),
        ),
    }
}

fn overflow(at: &Expr) -> Error {
    Error::parse("integer beyond 64 bits: not evaluated").at_line(at.line, Some(at.col))
}

/// Python's floor modulo for floats.
fn fmod_py(a: f64, b: f64) -> f64 {
    let r = a % b;
    if r != 0.0 && (r < 0.0) != (b < 0.0) {
        r + b
    } else {
        r
    }
}

/// A binary operator.
pub fn binary(op: &str, a: &Value, b: &Value, at: &Expr) -> Result<Value> {
    if let Value::Unknown(_) = a {
        return Ok(a.clone());
    }
    if let Value::Unknown(_) = b {
        return Ok(b.clone());
    }
    match (op, a, b) {
        ("+", Value::Str(x), Value::Str(y)) => {
            str_fits(x.len() + y.len(), "`+`", at)?;
            return Ok(Value::Str(format!("{x}{y}")));
        }
        ("+", Value::List(x), Value::List(y)) => {
            items_fit(x.borrow().len() + y.borrow().len(), "`+`", at)?;
            let mut v = x.borrow().clone();
            v.extend(y.borrow().iter().cloned());
            return Ok(Value::list(v));
        }
        ("+", Value::Tuple(x), Value::Tuple(y)) => {
            items_fit(x.len() + y.len(), "`+`", at)?;
            return Ok(Value::Tuple(x.iter().chain(y).cloned().collect()));
        }
        ("*", Value::Str(s), n) | ("*", n, Value::Str(s)) if n.as_int().is_some() => {
            let k = n.as_int().unwrap_or(0).max(0) as usize;
            str_fits(s.len().saturating_mul(k), "string repetition", at)?;
            return Ok(Value::Str(s.repeat(k)));
        }
        ("%", Value::Str(_), _) => return fail(at, "printf-style `%` formatting is not evaluated"),
        _ => {}
    }
    let (Some(x), Some(y)) = (a.as_f64(), b.as_f64()) else {
        return fail(
            at,
            format!(
                "unsupported operand types for {op}: {} and {}",
                a.type_name(),
                b.type_name()
            ),
        );
    };
    if let (Some(i), Some(j)) = (a.as_int(), b.as_int()) {
        return int_binary(op, i, j, at);
    }
    let zero = || fail(at, "float division by zero");
    Ok(Value::Float(match op {
        "+" => x + y,
        "-" => x - y,
        "*" => x * y,
        "/" if y == 0.0 => return zero(),
        "/" => x / y,
        "//" if y == 0.0 => return zero(),
        "//" => (x / y).floor(),
        "%" if y == 0.0 => return zero(),
        "%" => fmod_py(x, y),
        "**" => x.powf(y),
        _ => return fail(at, format!("unsupported operand types for {op}: float")),
    }))
}

fn int_binary(op: &str, i: i64, j: i64, at: &Expr) -> Result<Value> {
    let ov = || overflow(at);
    let zero = || fail(at, "integer division or modulo by zero");
    Ok(Value::Int(match op {
        "+" => i.checked_add(j).ok_or_else(ov)?,
        "-" => i.checked_sub(j).ok_or_else(ov)?,
        "*" => i.checked_mul(j).ok_or_else(ov)?,
        "/" if j == 0 => return fail(at, "division by zero"),
        "/" => return Ok(Value::Float(i as f64 / j as f64)),
        "//" if j == 0 => return zero(),
        "//" => i
            .checked_div_euclid(j)
            .map(|q| {
                if j < 0 && i.rem_euclid(j) != 0 {
                    q - 1
                } else {
                    q
                }
            })
            .ok_or_else(ov)?,
        "%" if j == 0 => return zero(),
        "%" => {
            let r = i.checked_rem(j).ok_or_else(ov)?;
            if r != 0 && (r < 0) != (j < 0) {
                r + j
            } else {
                r
            }
        }
        "**" if j < 0 => return Ok(Value::Float((i as f64).powf(j as f64))),
        "**" => i
            .checked_pow(u32::try_from(j).map_err(|_| ov())?)
            .ok_or_else(ov)?,
        "&" => i & j,
        "|" => i | j,
        "^" => i ^ j,
        "<<" => i
            .checked_shl(u32::try_from(j).map_err(|_| ov())?)
            .filter(|v| v >> j == i)
            .ok_or_else(ov)?,
        ">>" => i >> j.clamp(0, 63),
        _ => return fail(at, format!("unsupported operand types for {op}: int")),
    }))
}

fn norm_index(i: i64, len: usize) -> Option<usize> {
    let n = len as i64;
    let k = if i < 0 { i + n } else { i };
    (0..n).contains(&k).then_some(k as usize)
}

fn index(o: &Value, i: &Value, at: &Expr) -> Result<Value> {
    if let Value::Unknown(_) = o {
        return Ok(o.clone());
    }
    if let Value::Unknown(_) = i {
        return Ok(i.clone());
    }
    match o {
        Value::Dict(d) => d
            .iter()
            .find(|(k, _)| equal(k, i))
            .map(|(_, v)| v.clone())
            .ok_or_else(|| {
                Error::parse(format!("KeyError: {}", i.repr())).at_line(at.line, Some(at.col))
            }),
        Value::Str(s) => {
            let chars: Vec<char> = s.chars().collect();
            let k = i.as_int().ok_or_else(|| {
                Error::parse("string indices must be integers").at_line(at.line, Some(at.col))
            })?;
            norm_index(k, chars.len())
                .map(|k| Value::Str(chars[k].to_string()))
                .ok_or_else(|| {
                    Error::parse("string index out of range").at_line(at.line, Some(at.col))
                })
        }
        Value::List(_) | Value::Tuple(_) => {
            let items = o.items().unwrap_or_default();
            let k = i.as_int().ok_or_else(|| {
                Error::parse("list indices must be integers").at_line(at.line, Some(at.col))
            })?;
            norm_index(k, items.len())
                .map(|k| items[k].clone())
                .ok_or_else(|| {
                    Error::parse(format!("index {k} out of range")).at_line(at.line, Some(at.col))
                })
        }
        other => fail(
            at,
            format!("a {} value is not subscriptable here", other.type_name()),
        ),
    }
}

/// Python's slice bounds for a sequence of `len`.
fn bounds(a: Option<i64>, b: Option<i64>, step: i64, len: usize) -> Vec<usize> {
    let n = len as i64;
    let clamp = |x: i64, lo: i64, hi: i64| x.clamp(lo, hi);
    let fix = |x: i64| if x < 0 { x + n } else { x };
    let mut out = Vec::new();
    if step > 0 {
        let (mut i, stop) = (
            clamp(fix(a.unwrap_or(0)), 0, n),
            clamp(fix(b.unwrap_or(n)), 0, n),
        );
        while i < stop {
            out.push(i as usize);
            let Some(next) = i.checked_add(step) else {
                break;
            };
            i = next;
        }
    } else {
        let (mut i, stop) = (
            clamp(a.map(fix).unwrap_or(n - 1), -1, n - 1),
            b.map(|x| clamp(fix(x), -1, n - 1)).unwrap_or(-1),
        );
        while i > stop {
            out.push(i as usize);
            let Some(next) = i.checked_add(step) else {
                break;
            };
            i = next;
        }
    }
    out
}

fn slice(
    o: &Value,
    a: Option<Value>,
    b: Option<Value>,
    c: Option<Value>,
    at: &Expr,
) -> Result<Value> {
    let int = |v: Option<Value>| -> Result<Option<i64>> {
        match v {
            None | Some(Value::None) => Ok(None),
            Some(x) => x.as_int().map(Some).ok_or_else(|| {
                Error::parse("slice indices must be integers").at_line(at.line, Some(at.col))
            }),
        }
    };
    let (a, b, step) = (int(a)?, int(b)?, int(c)?.unwrap_or(1));
    if step == 0 {
        return fail(at, "slice step cannot be zero");
    }
    match o {
        Value::Str(s) => {
            let chars: Vec<char> = s.chars().collect();
            Ok(Value::Str(
                bounds(a, b, step, chars.len())
                    .into_iter()
                    .map(|i| chars[i])
                    .collect(),
            ))
        }
        Value::List(_) | Value::Tuple(_) => {
            let items = o.items().unwrap_or_default();
            let picked: Vec<Value> = bounds(a, b, step, items.len())
                .into_iter()
                .map(|i| items[i].clone())
                .collect();
            Ok(if let Value::Tuple(_) = o {
                Value::Tuple(picked)
            } else {
                Value::list(picked)
            })
        }
        Value::Unknown(_) => Ok(o.clone()),
        other => fail(
            at,
            format!("a {} value cannot be sliced", other.type_name()),
        ),
    }
}

/// `format(v, spec)` for the specs launch files use: empty, `d`, `s`, and
/// `[0][width][.precision](f|e|g|%)`.
pub fn format_spec(v: &Value, spec: &str, at: &Expr) -> Result<String> {
    if spec.is_empty() || spec == "s" {
        return v.try_to_str(at);
    }
    if spec == "d" {
        return v.as_int().map(|i| i.to_string()).ok_or_else(|| {
            Error::parse(format!("format 'd' of a {} value", v.type_name()))
                .at_line(at.line, Some(at.col))
        });
    }
    let (body, kind) = spec.split_at(spec.len() - 1);
    let (width, prec) = match body.split_once('.') {
        Some((w, p)) => (w, p.parse::<usize>().ok()),
        None => (body, None),
    };
    let zero = width.starts_with('0');
    let width: usize = if width.is_empty() {
        0
    } else {
        width.parse().map_err(|_| {
            Error::parse(format!("format spec {spec:?} is not evaluated"))
                .at_line(at.line, Some(at.col))
        })?
    };
    let x = v.as_f64().ok_or_else(|| {
        Error::parse(format!("format {spec:?} of a {} value", v.type_name()))
            .at_line(at.line, Some(at.col))
    })?;
    let p = prec.unwrap_or(6);
    str_fits(width.max(p), &format!("format spec {spec:?}"), at)?;
    let s = match kind {
        "f" => format!("{x:.p$}"),
        "%" => format!("{:.p$}%", x * 100.0),
        "e" => {
            let s = format!("{x:.p$e}");
            let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
            let e: i32 = e.parse().unwrap_or(0);
            format!("{m}e{}{:02}", if e < 0 { '-' } else { '+' }, e.abs())
        }
        "g" if prec.is_none() && width == 0 => float_repr(x),
        _ => return fail(at, format!("format spec {spec:?} is not evaluated")),
    };
    let pad = width.saturating_sub(s.chars().count());
    Ok(if zero {
        format!("{}{s}", "0".repeat(pad))
    } else {
        format!("{}{s}", " ".repeat(pad))
    })
}
