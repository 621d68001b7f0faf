//! Operators of `${...}` expressions with Python's semantics: int/float
//! arithmetic (floor division and modulo follow the divisor's sign, int
//! overflow is an error, a float result out of range is Python's
//! `OverflowError`), bitwise operators on ints, string, list and tuple
//! concatenation and repetition (each result within the meter's caps),
//! `str % args`, comparisons (exact between ints and floats, lexicographic
//! between sequences), `in`, `is` (subscripts and slices: `subscript`).

use super::format::percent;
use super::limits::Meter;
use super::subscript::dict_get;
use super::value::{overflow, range_len, too_deep, Res, Value};
use crate::tolerances::XACRO_MAX_VALUE_DEPTH;
use std::cmp::Ordering;

pub(super) fn float_pow(x: f64, y: f64) -> Res<Value> {
    if x == 0.0 && y < 0.0 {
        return Err("0.0 cannot be raised to a negative power".into());
    }
    if x < 0.0 && y.fract() != 0.0 && y.is_finite() {
        return Err(
            "a negative number raised to a fractional power (a complex result) is not supported"
                .into(),
        );
    }
    let r = x.powf(y);
    if r.is_infinite() && x.is_finite() && y.is_finite() {
        return Err("(34, 'Numerical result out of range')".into());
    }
    Ok(Value::Float(r))
}

/// Python's float floor division and modulo (signs follow the divisor).
pub(super) fn float_divmod(x: f64, y: f64) -> Res<(f64, f64)> {
    if y == 0.0 {
        return Err("float division by zero".into());
    }
    let mut m = x % y;
    let mut div = (x - m) / y;
    if m != 0.0 {
        if (y < 0.0) != (m < 0.0) {
            m += y;
            div -= 1.0;
        }
    } else {
        m = 0.0f64.copysign(y);
    }
    let fl = if div != 0.0 {
        let mut f = div.floor();
        if div - f > 0.5 {
            f += 1.0;
        }
        f
    } else {
        0.0f64.copysign(x / y)
    };
    Ok((fl, m))
}

/// `items * n`, within the list cap.
fn repeat(items: &[Value], n: i64, m: &mut Meter) -> Res<Vec<Value>> {
    let n = n.max(0) as usize;
    m.list(items.len().saturating_mul(n))?;
    Ok(items
        .iter()
        .cloned()
        .cycle()
        .take(items.len() * n)
        .collect())
}

/// A sequence operand of `+` and `*`: a copy of its items.
fn items_of(v: &Value) -> Option<Vec<Value>> {
    match v {
        Value::List(l) => Some(l.items().clone()),
        Value::Tuple(t) => Some(t.items().to_vec()),
        _ => None,
    }
}

fn same_kind(items: Vec<Value>, like: &Value) -> Value {
    if matches!(like, Value::Tuple(_)) {
        Value::tuple(items)
    } else {
        Value::list(items)
    }
}

pub(super) fn binary(op: &str, l: &Value, r: &Value, m: &mut Meter) -> Res<Value> {
    m.step()?;
    match (op, l, r) {
        ("+", Value::Str(a), Value::Str(b)) => {
            m.string(a.len() + b.len())?;
            Ok(Value::str(&format!("{a}{b}")))
        }
        ("+", Value::List(_), Value::List(_)) | ("+", Value::Tuple(_), Value::Tuple(_)) => {
            let (mut a, b) = (
                items_of(l).unwrap_or_default(),
                items_of(r).unwrap_or_default(),
            );
            m.list(a.len() + b.len())?;
            a.extend(b);
            Ok(same_kind(a, l))
        }
        ("*", Value::Str(s), n) | ("*", n, Value::Str(s)) if n.as_int().is_some() => {
            let k = n.as_int().unwrap_or(0).max(0) as usize;
            m.string(s.len().saturating_mul(k))?;
            Ok(Value::str(&s.repeat(k)))
        }
        ("*", seq @ (Value::List(_) | Value::Tuple(_)), n)
        | ("*", n, seq @ (Value::List(_) | Value::Tuple(_)))
            if n.as_int().is_some() =>
        {
            let items = items_of(seq).unwrap_or_default();
            let v = repeat(&items, n.as_int().unwrap_or(0), m)?;
            Ok(same_kind(v, seq))
        }
        ("%", Value::Str(f), args) => percent(f, args, m).map(|s| Value::str(&s)),
        ("&" | "|" | "^", Value::Bool(a), Value::Bool(b)) => Ok(Value::Bool(match op {
            "&" => a & b,
            "|" => a | b,
            _ => a ^ b,
        })),
        _ => match (l.as_int(), r.as_int()) {
            (Some(a), Some(b)) => int_binary(op, a, b),
            _ => match (l.as_f64(), r.as_f64()) {
                (Some(a), Some(b)) if !matches!(op, "&" | "|" | "^" | "<<" | ">>") => {
                    float_binary(op, a, b)
                }
                _ => Err(format!(
                    "unsupported operand type(s) for {op}: '{}' and '{}'",
                    l.type_name(),
                    r.type_name()
                )),
            },
        },
    }
}

pub(super) fn int_binary(op: &str, a: i64, b: i64) -> Res<Value> {
    let r = match op {
        "+" => a.checked_add(b),
        "-" => a.checked_sub(b),
        "*" => a.checked_mul(b),
        "/" => {
            if b == 0 {
                return Err("division by zero".into());
            }
            return Ok(Value::Float(a as f64 / b as f64));
        }
        "//" | "%" => {
            if b == 0 {
                return Err("integer division or modulo by zero".into());
            }
            let (q, m) = (a.checked_div_euclid(b), a.checked_rem_euclid(b));
            let (Some(mut q), Some(mut m)) = (q, m) else {
                return Err(overflow());
            };
            // Euclid keeps m >= 0; Python's sign follows the divisor.
            if b < 0 && m != 0 {
                m += b;
                q -= 1;
            }
            return Ok(Value::Int(if op == "//" { q } else { m }));
        }
        "**" => {
            if b < 0 {
                return float_pow(a as f64, b as f64);
            }
            u32::try_from(b).ok().and_then(|e| a.checked_pow(e))
        }
        "&" => Some(a & b),
        "|" => Some(a | b),
        "^" => Some(a ^ b),
        "<<" | ">>" => {
            if b < 0 {
                return Err("negative shift count".into());
            }
            if op == ">>" {
                Some(if b >= 64 {
                    if a < 0 {
                        -1
                    } else {
                        0
                    }
                } else {
                    a >> b
                })
            } else if a == 0 {
                Some(0)
            } else {
                u32::try_from(b)
                    .ok()
                    .filter(|&s| s < 63)
                    .and_then(|s| a.checked_mul(1i64 << s))
            }
        }
        _ => return Err(format!("operator {op} is not supported")),
    };
    r.map(Value::Int).ok_or_else(overflow)
}

pub(super) fn float_binary(op: &str, a: f64, b: f64) -> Res<Value> {
    match op {
        "+" => Ok(Value::Float(a + b)),
        "-" => Ok(Value::Float(a - b)),
        "*" => Ok(Value::Float(a * b)),
        "/" => {
            if b == 0.0 {
                Err("float division by zero".into())
            } else {
                Ok(Value::Float(a / b))
            }
        }
        "//" => float_divmod(a, b).map(|(q, _)| Value::Float(q)),
        "%" => float_divmod(a, b).map(|(_, m)| Value::Float(m)),
        "**" => float_pow(a, b),
        _ => Err(format!("operator {op} is not supported")),
    }
}

/// `int <=> float` exactly (`None`: the float is NaN).
fn cmp_int_float(i: i64, f: f64) -> Option<Ordering> {
    if f.is_nan() {
        return None;
    }
    if f >= 9.3e18 {
        return Some(Ordering::Less);
    }
    if f <= -9.3e18 {
        return Some(Ordering::Greater);
    }
    let fl = f.floor();
    let k = fl as i64;
    Some(match i.cmp(&k) {
        Ordering::Equal if f > fl => Ordering::Less,
        o => o,
    })
}

/// The order of two values (`None`: unordered, a NaN), or Python's
/// `TypeError` for types that have no order between them.
pub(super) fn order(l: &Value, r: &Value, m: &mut Meter, depth: usize) -> Res<Option<Ordering>> {
    m.step()?;
    if depth > XACRO_MAX_VALUE_DEPTH {
        return Err(too_deep());
    }
    let seq = |a: &[Value], b: &[Value], m: &mut Meter| -> Res<Option<Ordering>> {
        for (x, y) in a.iter().zip(b) {
            if !x.py_eq(y, m)? {
                return order(x, y, m, depth + 1);
            }
        }
        Ok(Some(a.len().cmp(&b.len())))
    };
    Ok(match (l, r) {
        (Value::Str(a), Value::Str(b)) => {
            m.scan(a.len().min(b.len()))?;
            Some(a.cmp(b))
        }
        (Value::List(a), Value::List(b)) => seq(&a.items(), &b.items(), m)?,
        (Value::Tuple(a), Value::Tuple(b)) => seq(a.items(), b.items(), m)?,
        _ => match (l.as_int(), r.as_int(), l.as_f64(), r.as_f64()) {
            (Some(a), Some(b), _, _) => Some(a.cmp(&b)),
            (Some(a), None, _, Some(b)) => cmp_int_float(a, b),
            (None, Some(b), Some(a), _) => cmp_int_float(b, a).map(Ordering::reverse),
            (_, _, Some(a), Some(b)) => a.partial_cmp(&b),
            _ => {
                return Err(format!(
                    "'<' not supported between instances of '{}' and '{}'",
                    l.type_name(),
                    r.type_name()
                ))
            }
        },
    })
}

/// `needle in hay`.
pub(super) fn contains(hay: &Value, needle: &Value, m: &mut Meter) -> Res<bool> {
    m.step()?;
    let any = |items: &[Value], m: &mut Meter| -> Res<bool> {
        for x in items {
            if x.py_eq(needle, m)? {
                return Ok(true);
            }
        }
        Ok(false)
    };
    match hay {
        Value::Str(s) => match needle {
            Value::Str(x) => {
                m.scan(s.len())?;
                Ok(s.contains(&**x))
            }
            _ => Err(format!(
                "'in <string>' requires string as left operand, not {}",
                needle.type_name()
            )),
        },
        Value::List(v) => any(&v.items(), m),
        Value::Tuple(v) => any(v.items(), m),
        Value::Dict(d) => Ok(dict_get(d, needle, m)?.is_some()),
        Value::Range(r) => Ok(match needle.as_int() {
            Some(k) => {
                let n = range_len(r);
                let off = (k as i128 - r[0] as i128) / r[2] as i128;
                (k as i128 - r[0] as i128) % r[2] as i128 == 0 && (0..n as i128).contains(&off)
            }
            None => match needle.as_f64() {
                Some(f) if f.fract() == 0.0 && f.abs() < 9.2e18 => {
                    contains(hay, &Value::Int(f as i64), m)?
                }
                _ => false,
            },
        }),
        other => Err(format!(
            "argument of type '{}' is not iterable",
            other.type_name()
        )),
    }
}

pub(super) fn compare(op: &str, l: &Value, r: &Value, m: &mut Meter) -> Res<bool> {
    match op {
        "==" => l.py_eq(r, m),
        "!=" => l.py_eq(r, m).map(|e| !e),
        "is" | "is not" => same(l, r).map(|s| s == (op == "is")),
        "in" => contains(r, l, m),
        "not in" => contains(r, l, m).map(|c| !c),
        _ => {
            let Some(ord) = order(l, r, m, 0)? else {
                return Ok(false);
            };
            Ok(match op {
                "<" => ord.is_lt(),
                "<=" => ord.is_le(),
                ">" => ord.is_gt(),
                _ => ord.is_ge(),
            })
        }
    }
}

/// `is`: identity of the singletons (None, True, False) and of containers;
/// for numbers and strings Python's answer depends on object caching, so it
/// is refused rather than guessed.
pub(super) fn same(l: &Value, r: &Value) -> Res<bool> {
    use std::rc::Rc;
    Ok(match (l, r) {
        (Value::None, Value::None) => true,
        (Value::Bool(a), Value::Bool(b)) => a == b,
        (Value::List(a), Value::List(b)) => Rc::ptr_eq(a, b),
        (Value::Tuple(a), Value::Tuple(b)) => Rc::ptr_eq(a, b),
        (Value::Dict(a), Value::Dict(b)) => Rc::ptr_eq(a, b),
        (Value::Builtin(a), Value::Builtin(b)) => a == b,
        (Value::None | Value::Bool(_), _) | (_, Value::None | Value::Bool(_)) => false,
        (a, b) if std::mem::discriminant(a) != std::mem::discriminant(b) => false,
        (a, _) => {
            return Err(format!(
                "'is' between two {} values: Python's answer depends on object identity; use ==",
                a.type_name()
            ))
        }
    })
}
