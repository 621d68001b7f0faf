//! Evaluate an expression: Python's semantics for the values of
//! [`super::value`] (int/float promotion, floor division and modulo with the
//! divisor's sign, `and`/`or` returning an operand, chained comparisons,
//! negative indices and slices), a closed list of builtins, `math`
//! functions and `str`/`list`/`dict` methods; anything else is an error
//! naming it. Nothing is ever executed. A value the host cannot know
//! ([`Value::Unknown`]) propagates through every operation.

use std::rc::Rc;

use super::budget::Budget;
use super::caps::{items_fit, str_fits};
use super::ops::{binary, compare, equal, fail, format_spec, index, iterate, slice, unary};
use super::parse::{Expr, ExprKind, FPart};
use super::value::{Func, Value};
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
