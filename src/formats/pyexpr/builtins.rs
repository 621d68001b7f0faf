//! The builtins and `math` functions the evaluator implements
//! ([`super::eval::BUILTINS`], [`super::eval::MATH`]), with CPython's
//! results: `round` half to even (exact decimal rounding, as Rust's
//! formatting does), `int()` truncating, `float()`/`int()` of text as Python
//! parses it, `math.floor`/`ceil` returning ints.

use super::caps::items_fit;
use super::ops::{equal, fail, iterate};
use super::parse::Expr;
use super::value::Value;
use crate::diagnostic::Result;

fn num(v: &Value, f: &str, at: &Expr) -> Result<f64> {
    v.as_f64().map_or_else(
        || {
            fail(
                at,
                format!("{f}() of a {} value is not evaluated", v.type_name()),
            )
        },
        Ok,
    )
}

fn arity(
    name: &str,
    args: &[Value],
    kw: &[(String, Value)],
    lo: usize,
    hi: usize,
    at: &Expr,
) -> Result<()> {
    if !kw.is_empty() {
        return fail(
            at,
            format!("{name}() with keyword arguments is not evaluated"),
        );
    }
    if args.len() < lo || args.len() > hi {
        return fail(
            at,
            format!(
                "{name}() takes {lo} to {hi} arguments, {} given",
                args.len()
            ),
        );
    }
    Ok(())
}

/// `int(text)`: optional sign, digits, `_` between digits, blanks around.
fn parse_int(s: &str) -> Option<i64> {
    let t = s.trim();
    let body = t.strip_prefix(['+', '-']).unwrap_or(t);
    if body.is_empty() || body.starts_with('_') || body.ends_with('_') || body.contains("__") {
        return None;
    }
    t.replace('_', "").parse().ok()
}

/// `float(text)`: Python's float syntax, `inf`/`nan` in any case.
fn parse_float(s: &str) -> Option<f64> {
    let t = s.trim();
    let l = t.to_ascii_lowercase();
    let body = l.strip_prefix(['+', '-']).unwrap_or(&l);
    if matches!(body, "inf" | "infinity" | "nan") {
        return l.parse().ok().or(Some(if l.starts_with('-') {
            f64::NEG_INFINITY
        } else {
            f64::INFINITY
        }));
    }
    if t.is_empty()
        || !t
            .chars()
            .all(|c| c.is_ascii_digit() || "+-.eE_".contains(c))
    {
        return None;
    }
    t.replace('_', "").parse().ok()
}

fn to_int(v: &Value, at: &Expr) -> Result<Value> {
    match v {
        Value::Float(f) if f.is_finite() && f.abs() < 9.2e18 => Ok(Value::Int(f.trunc() as i64)),
        Value::Float(_) => fail(at, "int() of a float beyond 64 bits"),
        Value::Str(s) => parse_int(s).map(Value::Int).map_or_else(
            || {
                fail(
                    at,
                    format!("invalid literal for int() with base 10: {}", v.repr()),
                )
            },
            Ok,
        ),
        x => x.as_int().map(Value::Int).map_or_else(
            || fail(at, format!("int() of a {} value", x.type_name())),
            Ok,
        ),
    }
}

fn to_float(v: &Value, at: &Expr) -> Result<Value> {
    match v {
        Value::Str(s) => parse_float(s).map(Value::Float).map_or_else(
            || {
                fail(
                    at,
                    format!("could not convert string to float: {}", v.repr()),
                )
            },
            Ok,
        ),
        x => x.as_f64().map(Value::Float).map_or_else(
            || fail(at, format!("float() of a {} value", x.type_name())),
            Ok,
        ),
    }
}

fn round(args: &[Value], at: &Expr) -> Result<Value> {
    let x = &args[0];
    let nd = match args.get(1) {
        None | Some(Value::None) => None,
        Some(n) => Some(
            n.as_int()
                .map_or_else(|| fail(at, "round() digits must be an integer"), Ok)?,
        ),
    };
    if let (Some(i), _) = (x.as_int(), &nd) {
        if nd.is_none_or(|n| n >= 0) {
            return Ok(Value::Int(i));
        }
    }
    let f = num(x, "round", at)?;
    match nd {
        None => {
            let r = f.round_ties_even();
            if !r.is_finite() || r.abs() >= 9.2e18 {
                return fail(at, "round() of a float beyond 64 bits");
            }
            Ok(Value::Int(r as i64))
        }
        Some(n) if (0..=300).contains(&n) => {
            // Rust's fixed formatting rounds the exact binary value half to
            // even, as CPython's round does.
            let s = format!("{f:.*}", n as usize);
            Ok(Value::Float(s.parse().unwrap_or(f)))
        }
        Some(_) => fail(at, "round() with negative or huge digits is not evaluated"),
    }
}

/// `sum(items, start)`: numbers by `+`; lists or tuples joined in one pass
/// (adding them pairwise would copy the total once per item).
fn sum(start: Value, items: Vec<Value>, at: &Expr) -> Result<Value> {
    let joined = match &start {
        Value::List(_) | Value::Tuple(_) => start.items(),
        _ => None,
    };
    let Some(mut out) = joined else {
        let mut acc = start;
        for v in items {
            acc = super::ops::binary("+", &acc, &v, at)?;
        }
        return Ok(acc);
    };
    for v in items {
        if std::mem::discriminant(&v) != std::mem::discriminant(&start) {
            return fail(
                at,
                format!(
                    "sum() of a {} into a {} is not evaluated",
                    v.type_name(),
                    start.type_name()
                ),
            );
        }
        let more = v.items().unwrap_or_default();
        items_fit(out.len() + more.len(), "sum()", at)?;
        out.extend(more);
    }
    Ok(match start {
        Value::Tuple(_) => Value::Tuple(out),
        _ => Value::list(out),
    })
}

fn min_max(name: &str, args: &[Value], at: &Expr) -> Result<Value> {
    let items = if args.len() == 1 {
        iterate(&args[0], at)?
    } else {
        args.to_vec()
    };
    let mut best: Option<Value> = None;
    for v in items {
        let better = match &best {
            None => true,
            Some(b) => {
                let (x, y) = (v.as_f64(), b.as_f64());
                match (x, y, &v, b) {
                    (Some(x), Some(y), _, _) => {
                        if name == "min" {
                            x < y
                        } else {
                            x > y
                        }
                    }
                    (_, _, Value::Str(p), Value::Str(q)) => {
                        if name == "min" {
                            p < q
                        } else {
                            p > q
                        }
                    }
                    _ => return fail(at, format!("{name}() of mixed types is not evaluated")),
                }
            }
        };
        if better {
            best = Some(v);
        }
    }
    best.map_or_else(
        || fail(at, format!("{name}() arg is an empty sequence")),
        Ok,
    )
}

/// Call builtin or `math` function `name`.
pub fn call(name: &str, args: &[Value], kw: &[(String, Value)], at: &Expr) -> Result<Value> {
    let a0 = args.first();
    match name {
        "abs" => {
            arity(name, args, kw, 1, 1, at)?;
            match &args[0] {
                Value::Float(f) => Ok(Value::Float(f.abs())),
                x => x
                    .as_int()
                    .and_then(i64::checked_abs)
                    .map(Value::Int)
                    .map_or_else(
                        || fail(at, format!("abs() of a {} value", x.type_name())),
                        Ok,
                    ),
            }
        }
        "bool" => {
            arity(name, args, kw, 0, 1, at)?;
            Ok(a0.map_or(Some(false), Value::truth).map_or_else(
                || Value::unknown("the truth of a launch object"),
                Value::Bool,
            ))
        }
        "int" => {
            arity(name, args, kw, 0, 1, at)?;
            a0.map_or(Ok(Value::Int(0)), |v| to_int(v, at))
        }
        "float" => {
            arity(name, args, kw, 0, 1, at)?;
            a0.map_or(Ok(Value::Float(0.0)), |v| to_float(v, at))
        }
        "str" => {
            arity(name, args, kw, 0, 1, at)?;
            Ok(Value::Str(
                a0.map(|v| v.try_to_str(at))
                    .transpose()?
                    .unwrap_or_default(),
            ))
        }
        "repr" => {
            arity(name, args, kw, 1, 1, at)?;
            Ok(Value::Str(args[0].try_repr(at)?))
        }
        "len" => {
            arity(name, args, kw, 1, 1, at)?;
            let n = match &args[0] {
                Value::Str(s) => s.chars().count(),
                Value::Dict(d) => d.len(),
                v => v.items().map_or_else(
                    || fail(at, format!("len() of a {} value", v.type_name())),
                    |i| Ok(i.len()),
                )?,
            };
            Ok(Value::Int(n as i64))
        }
        _ => sequences(name, args, kw, at),
    }
}

/// The builtins over sequences, then `math`.
fn sequences(name: &str, args: &[Value], kw: &[(String, Value)], at: &Expr) -> Result<Value> {
    let a0 = args.first();
    match name {
        "list" | "tuple" => {
            arity(name, args, kw, 0, 1, at)?;
            let items = a0.map_or(Ok(Vec::new()), |v| iterate(v, at))?;
            Ok(if name == "list" {
                Value::list(items)
            } else {
                Value::Tuple(items)
            })
        }
        "dict" => {
            if !args.is_empty() {
                return fail(at, "dict() of positional arguments is not evaluated");
            }
            Ok(Value::Dict(
                kw.iter()
                    .map(|(k, v)| (Value::Str(k.clone()), v.clone()))
                    .collect(),
            ))
        }
        "min" | "max" => {
            arity(name, args, kw, 1, usize::MAX, at)?;
            min_max(name, args, at)
        }
        "sum" => {
            arity(name, args, kw, 1, 2, at)?;
            let start = args.get(1).cloned().unwrap_or(Value::Int(0));
            sum(start, iterate(&args[0], at)?, at)
        }
        "range" => {
            arity(name, args, kw, 1, 3, at)?;
            let n: Vec<i64> = args
                .iter()
                .map(|v| {
                    v.as_int()
                        .map_or_else(|| fail(at, "range() of a non-integer"), Ok)
                })
                .collect::<Result<_>>()?;
            let (start, stop, step) = match n.as_slice() {
                [s] => (0, *s, 1),
                [a, b] => (*a, *b, 1),
                [a, b, c] => (*a, *b, *c),
                _ => (0, 0, 1),
            };
            if step == 0 {
                return fail(at, "range() arg 3 must not be zero");
            }
            // In i128: `stop - start` and `-step` overflow i64 at its ends.
            let (a, b, c) = (i128::from(start), i128::from(stop), i128::from(step));
            let span = if c > 0 { b - a } else { a - b };
            let count = ((span.max(0) + c.abs() - 1) / c.abs()) as i64;
            items_fit(count as usize, "range()", at)?;
            Ok(Value::list(
                (0..count).map(|k| Value::Int(start + k * step)).collect(),
            ))
        }
        "round" => {
            arity(name, args, kw, 1, 2, at)?;
            round(args, at)
        }
        "enumerate" => {
            arity(name, args, kw, 1, 2, at)?;
            let start = args.get(1).and_then(Value::as_int).unwrap_or(0);
            let items = iterate(&args[0], at)?;
            Ok(Value::list(
                items
                    .into_iter()
                    .zip(start..)
                    .map(|(v, i)| Value::Tuple(vec![Value::Int(i), v]))
                    .collect(),
            ))
        }
        "zip" => {
            arity(name, args, kw, 1, usize::MAX, at)?;
            let lists: Vec<Vec<Value>> =
                args.iter().map(|a| iterate(a, at)).collect::<Result<_>>()?;
            let n = lists.iter().map(Vec::len).min().unwrap_or(0);
            Ok(Value::list(
                (0..n)
                    .map(|i| Value::Tuple(lists.iter().map(|l| l[i].clone()).collect()))
                    .collect(),
            ))
        }
        _ => math(name, args, kw, at),
    }
}

fn math(name: &str, args: &[Value], kw: &[(String, Value)], at: &Expr) -> Result<Value> {
    let two = matches!(name, "atan2" | "hypot" | "pow");
    let hi = if two || name == "log" { 2 } else { 1 };
    arity(name, args, kw, if two { 2 } else { 1 }, hi, at)?;
    let x = num(&args[0], name, at)?;
    let y = args.get(1).map(|v| num(v, name, at)).transpose()?;
    let domain = |ok: bool, v: f64| {
        if ok {
            Ok(Value::Float(v))
        } else {
            fail(at, "math domain error")
        }
    };
    match name {
        "floor" | "ceil" => {
            let r = if name == "floor" { x.floor() } else { x.ceil() };
            if !r.is_finite() || r.abs() >= 9.2e18 {
                return fail(at, format!("math.{name}() of a value beyond 64 bits"));
            }
            Ok(Value::Int(r as i64))
        }
        "sqrt" => domain(x >= 0.0, x.sqrt()),
        "log" => match y {
            None => domain(x > 0.0, x.ln()),
            Some(b) => domain(x > 0.0 && b > 0.0 && b != 1.0, x.ln() / b.ln()),
        },
        "log10" => domain(x > 0.0, x.log10()),
        "log2" => domain(x > 0.0, x.log2()),
        "acos" => domain((-1.0..=1.0).contains(&x), x.acos()),
        "asin" => domain((-1.0..=1.0).contains(&x), x.asin()),
        _ => Ok(Value::Float(match name {
            "atan" => x.atan(),
            "atan2" => x.atan2(y.unwrap_or(1.0)),
            "cos" => x.cos(),
            "cosh" => x.cosh(),
            "degrees" => x.to_degrees(),
            "exp" => x.exp(),
            "fabs" => x.abs(),
            "hypot" => x.hypot(y.unwrap_or(0.0)),
            "pow" => x.powf(y.unwrap_or(1.0)),
            "radians" => x.to_radians(),
            "sin" => x.sin(),
            "sinh" => x.sinh(),
            "tan" => x.tan(),
            "tanh" => x.tanh(),
            _ => return fail(at, format!("{name}() is not evaluated")),
        })),
    }
}

/// Whether `a` holds `b` (for `list.index`/`count`).
pub fn position(items: &[Value], v: &Value) -> Option<usize> {
    items.iter().position(|x| equal(x, v))
}
