//! Operators of `${...}` expressions with Python's semantics: int/float
//! arithmetic (floor division and modulo follow the divisor's sign, int
//! overflow is an error), string and list concatenation and repetition (capped
//! at the output size), comparisons, `in`, `is`, indexing.

use super::value::Value;
use crate::tolerances::XACRO_MAX_OUTPUT_BYTES;
use std::rc::Rc;

pub(super) fn overflow() -> String {
    "integer result beyond 64 bits: not supported".into()
}

pub(super) fn index(b: &Value, i: &Value) -> Result<Value, String> {
    match b {
        Value::List(l) => {
            let k = seq_index(i, l.len())?;
            Ok(l[k].clone())
        }
        Value::Str(s) => {
            let chars: Vec<char> = s.chars().collect();
            let k = seq_index(i, chars.len())?;
            Ok(Value::str(&chars[k].to_string()))
        }
        Value::Dict(d) => d
            .iter()
            .find(|(k, _)| k.py_eq(i))
            .map(|(_, v)| v.clone())
            .ok_or_else(|| format!("the yaml dictionary has no key {}", i.repr())),
        other => Err(format!(
            "a {} value is not subscriptable",
            other.type_name()
        )),
    }
}

pub(super) fn seq_index(i: &Value, len: usize) -> Result<usize, String> {
    let k = i
        .as_int()
        .ok_or_else(|| format!("indices must be integers, not {}", i.type_name()))?;
    let len_i = len as i64;
    let k2 = if k < 0 { k + len_i } else { k };
    if k2 < 0 || k2 >= len_i {
        return Err(format!("index {k} out of range (length {len})"));
    }
    Ok(k2 as usize)
}

pub(super) fn float_pow(x: f64, y: f64) -> Result<Value, String> {
    if x == 0.0 && y < 0.0 {
        return Err("0.0 cannot be raised to a negative power".into());
    }
    if x < 0.0 && y.fract() != 0.0 && y.is_finite() {
        return Err(
            "a negative number raised to a fractional power (a complex result) is not supported"
                .into(),
        );
    }
    Ok(Value::Float(x.powf(y)))
}

/// Python's float floor division and modulo (signs follow the divisor).
pub(super) fn float_divmod(x: f64, y: f64) -> Result<(f64, f64), String> {
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

pub(super) fn check_len(n: usize) -> Result<(), String> {
    if n > XACRO_MAX_OUTPUT_BYTES {
        return Err(format!(
            "a value of {n} items or bytes: above the {XACRO_MAX_OUTPUT_BYTES}-byte output cap"
        ));
    }
    Ok(())
}

pub(super) fn repeat<T: Clone>(items: &[T], n: i64) -> Result<Vec<T>, String> {
    let n = n.max(0) as usize;
    check_len(items.len().saturating_mul(n))?;
    Ok(items
        .iter()
        .cloned()
        .cycle()
        .take(items.len() * n)
        .collect())
}

pub(super) fn binary(op: &str, l: &Value, r: &Value) -> Result<Value, String> {
    match (op, l, r) {
        ("+", Value::Str(a), Value::Str(b)) => {
            check_len(a.len() + b.len())?;
            Ok(Value::str(&format!("{a}{b}")))
        }
        ("+", Value::List(a), Value::List(b)) => {
            let mut v = a.to_vec();
            v.extend(b.iter().cloned());
            Ok(Value::List(Rc::new(v)))
        }
        ("*", Value::Str(s), n) | ("*", n, Value::Str(s)) if n.as_int().is_some() => {
            let chars: Vec<char> = s.chars().collect();
            let v = repeat(&chars, n.as_int().unwrap_or(0))?;
            Ok(Value::str(&v.into_iter().collect::<String>()))
        }
        ("*", Value::List(l), n) | ("*", n, Value::List(l)) if n.as_int().is_some() => {
            Ok(Value::List(Rc::new(repeat(l, n.as_int().unwrap_or(0))?)))
        }
        _ => match (l.as_int(), r.as_int()) {
            (Some(a), Some(b)) => int_binary(op, a, b),
            _ => match (l.as_f64(), r.as_f64()) {
                (Some(a), Some(b)) => float_binary(op, a, b),
                _ => Err(format!(
                    "unsupported operand types for {op}: '{}' and '{}'",
                    l.type_name(),
                    r.type_name()
                )),
            },
        },
    }
}

pub(super) fn int_binary(op: &str, a: i64, b: i64) -> Result<Value, String> {
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
        _ => return Err(format!("operator {op} is not supported")),
    };
    r.map(Value::Int).ok_or_else(overflow)
}

pub(super) fn float_binary(op: &str, a: f64, b: f64) -> Result<Value, String> {
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

pub(super) fn compare(op: &str, l: &Value, r: &Value) -> Result<bool, String> {
    match op {
        "==" => Ok(l.py_eq(r)),
        "!=" => Ok(!l.py_eq(r)),
        "is" => Ok(same(l, r)),
        "is not" => Ok(!same(l, r)),
        "in" | "not in" => {
            let found = match r {
                Value::Str(s) => match l {
                    Value::Str(x) => s.contains(&**x),
                    _ => {
                        return Err(format!(
                            "'in <string>' requires a string, not {}",
                            l.type_name()
                        ))
                    }
                },
                Value::List(v) => v.iter().any(|x| x.py_eq(l)),
                Value::Dict(d) => d.iter().any(|(k, _)| k.py_eq(l)),
                other => {
                    return Err(format!(
                        "'in' a {} value is not supported",
                        other.type_name()
                    ))
                }
            };
            Ok(found == (op == "in"))
        }
        _ => {
            let ord = match (l, r) {
                (Value::Str(a), Value::Str(b)) => a.cmp(b),
                _ => match (l.as_f64(), r.as_f64()) {
                    (Some(a), Some(b)) => match a.partial_cmp(&b) {
                        Some(o) => o,
                        None => return Ok(false),
                    },
                    _ => {
                        return Err(format!(
                            "'{op}' between '{}' and '{}' is not supported",
                            l.type_name(),
                            r.type_name()
                        ))
                    }
                },
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

/// `is`: identity for the singletons (None, True, False).
pub(super) fn same(l: &Value, r: &Value) -> bool {
    match (l, r) {
        (Value::None, Value::None) => true,
        (Value::Bool(a), Value::Bool(b)) => a == b,
        _ => false,
    }
}
