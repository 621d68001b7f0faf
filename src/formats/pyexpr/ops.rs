//! What Python's operators, subscripts, iteration and format specs do to
//! values (CPython's semantics for the values evaluated): the leaf that the
//! evaluator ([`super::eval`]), the builtins and the methods share.

use std::rc::Rc;

use super::caps::{items_fit, str_fits};
use super::parse::Expr;
use super::value::{float_repr, Value};
use crate::diagnostic::{Error, Result};

/// An error at `e`.
pub fn fail<T>(e: &Expr, msg: impl Into<String>) -> Result<T> {
    Err(Error::parse(msg.into()).at_line(e.line, Some(e.col)))
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

pub(super) fn compare(op: &str, a: &Value, b: &Value, at: &Expr) -> Result<bool> {
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

pub(super) fn unary(op: &str, v: Value, at: &Expr) -> Result<Value> {
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

pub(super) fn index(o: &Value, i: &Value, at: &Expr) -> Result<Value> {
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

pub(super) fn slice(
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
