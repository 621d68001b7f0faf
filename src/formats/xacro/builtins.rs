//! The functions and constants `${...}` expressions may call: xacro 2's
//! globals (`pi`, `radians`, `sin`, ..., `min`, `max`, `round`, `int`, ...)
//! and the `math`, `python` and `xacro` namespaces, with CPython's results
//! and domain errors.

use super::ops::{binary, compare, float_pow, overflow};
use super::value::{float_repr, Builtin, Value};
use std::rc::Rc;

/// The names xacro puts in the global scope.
pub(super) fn global(n: &str) -> Option<Value> {
    match n {
        "math" | "xacro" | "python" => Some(Value::Builtin(Builtin::Module(static_name(n)?))),
        "load_yaml" => Some(Value::Builtin(Builtin::Func("load_yaml"))),
        _ => module_member("math", n).or_else(|| {
            // xacro 2 puts only these builtins in the global scope; the others
            // (abs, sum, ...) are under `python.`.
            GLOBAL_PY_FUNCS
                .contains(&n)
                .then(|| module_member("python", n))
                .flatten()
        }),
    }
}

pub(super) fn static_name(n: &str) -> Option<&'static str> {
    ["math", "xacro", "python"].into_iter().find(|m| *m == n)
}

pub(super) const MATH_FUNCS: &[&str] = &[
    "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "asinh", "acosh",
    "atanh", "sqrt", "exp", "log", "log10", "log2", "pow", "fabs", "floor", "ceil", "trunc",
    "radians", "degrees", "hypot", "fmod", "copysign", "isnan", "isinf", "isfinite",
];
pub(super) const GLOBAL_PY_FUNCS: &[&str] = &[
    "min", "max", "round", "int", "float", "str", "bool", "len", "list", "sorted", "range",
];
pub(super) const PY_FUNCS: &[&str] = &[
    "abs", "min", "max", "round", "int", "float", "str", "bool", "len", "list", "sum", "sorted",
    "range",
];

pub(super) fn module_member(m: &str, n: &str) -> Option<Value> {
    let f = |list: &[&'static str]| {
        list.iter()
            .find(|x| **x == n)
            .map(|x| Value::Builtin(Builtin::Func(x)))
    };
    match m {
        "math" => match n {
            "pi" => Some(Value::Float(std::f64::consts::PI)),
            "e" => Some(Value::Float(std::f64::consts::E)),
            "tau" => Some(Value::Float(std::f64::consts::TAU)),
            "inf" => Some(Value::Float(f64::INFINITY)),
            "nan" => Some(Value::Float(f64::NAN)),
            _ => f(MATH_FUNCS),
        },
        "python" => f(PY_FUNCS),
        "xacro" => match n {
            "load_yaml" => Some(Value::Builtin(Builtin::Func("load_yaml"))),
            "arg" => Some(Value::Builtin(Builtin::Func("arg"))),
            _ => None,
        },
        _ => None,
    }
}

pub(super) fn num(v: &Value, what: &str) -> Result<f64, String> {
    v.as_f64()
        .ok_or_else(|| format!("{what}: must be a real number, not {}", v.type_name()))
}

pub(super) fn domain(x: f64, name: &str) -> Result<Value, String> {
    if x.is_nan() {
        Err(format!("math domain error in {name}()"))
    } else {
        Ok(Value::Float(x))
    }
}

pub(super) fn float_to_int(f: f64, what: &str) -> Result<Value, String> {
    if !f.is_finite() {
        return Err(format!(
            "{what}: cannot convert {} to an integer",
            float_repr(f)
        ));
    }
    if f.abs() >= 9.2e18 {
        return Err(overflow());
    }
    Ok(Value::Int(f as i64))
}

pub(super) fn call_builtin(name: &str, a: &[Value]) -> Result<Value, String> {
    let one = |a: &[Value]| -> Result<f64, String> {
        match a {
            [x] => num(x, name),
            _ => Err(format!(
                "{name}() takes exactly one argument ({} given)",
                a.len()
            )),
        }
    };
    let two = |a: &[Value]| -> Result<(f64, f64), String> {
        match a {
            [x, y] => Ok((num(x, name)?, num(y, name)?)),
            _ => Err(format!(
                "{name}() takes exactly two arguments ({} given)",
                a.len()
            )),
        }
    };
    let x_nan = |x: f64, r: f64| {
        if x.is_nan() {
            Ok(Value::Float(r))
        } else {
            domain(r, name)
        }
    };
    match name {
        "sin" => one(a)
            .map(|x| Value::Float(x.sin()))
            .and_then(|v| finite_in(v, a, name)),
        "cos" => one(a)
            .map(|x| Value::Float(x.cos()))
            .and_then(|v| finite_in(v, a, name)),
        "tan" => one(a)
            .map(|x| Value::Float(x.tan()))
            .and_then(|v| finite_in(v, a, name)),
        "asin" => one(a).and_then(|x| x_nan(x, x.asin())),
        "acos" => one(a).and_then(|x| x_nan(x, x.acos())),
        "atan" => one(a).map(|x| Value::Float(x.atan())),
        "atan2" => two(a).map(|(y, x)| Value::Float(y.atan2(x))),
        "sinh" => one(a).map(|x| Value::Float(x.sinh())),
        "cosh" => one(a).map(|x| Value::Float(x.cosh())),
        "tanh" => one(a).map(|x| Value::Float(x.tanh())),
        "asinh" => one(a).map(|x| Value::Float(x.asinh())),
        "acosh" => one(a).and_then(|x| x_nan(x, x.acosh())),
        "atanh" => one(a).and_then(|x| x_nan(x, x.atanh())),
        "sqrt" => one(a).and_then(|x| x_nan(x, x.sqrt())),
        "exp" => one(a).map(|x| Value::Float(x.exp())),
        "log" => match a {
            [x] => log(num(x, name)?),
            [x, b] => {
                let (lx, lb) = (log(num(x, name)?)?, log(num(b, name)?)?);
                let (lx, lb) = (
                    lx.as_f64().unwrap_or(f64::NAN),
                    lb.as_f64().unwrap_or(f64::NAN),
                );
                if lb == 0.0 {
                    Err("float division by zero".into())
                } else {
                    Ok(Value::Float(lx / lb))
                }
            }
            _ => Err("log() takes one or two arguments".into()),
        },
        "log10" => one(a).and_then(|x| {
            if x > 0.0 {
                Ok(Value::Float(x.log10()))
            } else {
                Err("math domain error in log10()".into())
            }
        }),
        "log2" => one(a).and_then(|x| {
            if x > 0.0 {
                Ok(Value::Float(x.log2()))
            } else {
                Err("math domain error in log2()".into())
            }
        }),
        "pow" => two(a).and_then(|(x, y)| float_pow(x, y)),
        "fabs" => one(a).map(|x| Value::Float(x.abs())),
        "floor" => one(a).and_then(|x| int_of_float(a, x.floor(), name)),
        "ceil" => one(a).and_then(|x| int_of_float(a, x.ceil(), name)),
        "trunc" => one(a).and_then(|x| int_of_float(a, x.trunc(), name)),
        "radians" => one(a).map(|x| Value::Float(x * (std::f64::consts::PI / 180.0))),
        "degrees" => one(a).map(|x| Value::Float(x * (180.0 / std::f64::consts::PI))),
        "hypot" => two(a).map(|(x, y)| Value::Float(x.hypot(y))),
        "fmod" => two(a).and_then(|(x, y)| {
            if y == 0.0 {
                Err("math domain error in fmod()".into())
            } else {
                Ok(Value::Float(x % y))
            }
        }),
        "copysign" => two(a).map(|(x, y)| Value::Float(x.copysign(y))),
        "isnan" => one(a).map(|x| Value::Bool(x.is_nan())),
        "isinf" => one(a).map(|x| Value::Bool(x.is_infinite())),
        "isfinite" => one(a).map(|x| Value::Bool(x.is_finite())),
        _ => py_builtin(name, a),
    }
}

/// sin/cos/tan of an infinity is a domain error in Python.
pub(super) fn finite_in(v: Value, a: &[Value], name: &str) -> Result<Value, String> {
    match a.first().and_then(Value::as_f64) {
        Some(x) if x.is_infinite() => Err(format!("math domain error in {name}()")),
        _ => Ok(v),
    }
}

pub(super) fn log(x: f64) -> Result<Value, String> {
    if x > 0.0 || x.is_nan() {
        Ok(Value::Float(x.ln()))
    } else {
        Err("math domain error in log()".into())
    }
}

/// math.floor/ceil/trunc return an int in Python 3 (an int argument unchanged).
pub(super) fn int_of_float(a: &[Value], r: f64, name: &str) -> Result<Value, String> {
    if let Some(Value::Int(i)) = a.first() {
        return Ok(Value::Int(*i));
    }
    float_to_int(r, name)
}

pub(super) fn py_builtin(name: &str, a: &[Value]) -> Result<Value, String> {
    match (name, a) {
        ("abs", [Value::Float(f)]) => Ok(Value::Float(f.abs())),
        ("abs", [v]) => v
            .as_int()
            .and_then(i64::checked_abs)
            .map(Value::Int)
            .ok_or_else(|| format!("bad operand type for abs(): '{}'", v.type_name())),
        ("min" | "max", _) => min_max(name, a),
        ("round", [x]) => {
            if let Some(i) = x.as_int() {
                return Ok(Value::Int(i));
            }
            let f = num(x, "round")?;
            let r = f.round();
            // Python rounds halves to even.
            let r = if (f - f.trunc()).abs() == 0.5 {
                2.0 * (f / 2.0).round()
            } else {
                r
            };
            float_to_int(r, "round")
        }
        ("round", [x, n]) => {
            let f = num(x, "round")?;
            let n = n.as_int().ok_or("round(): ndigits must be an integer")?;
            if let Some(i) = x.as_int() {
                if n >= 0 {
                    return Ok(Value::Int(i));
                }
            }
            if !(0..=17).contains(&n) {
                return Err("round() with this many digits is not supported".into());
            }
            // Correctly rounded decimal text, read back (as CPython does).
            let s = format!("{f:.*}", n as usize);
            s.parse::<f64>()
                .map(Value::Float)
                .map_err(|e| e.to_string())
        }
        ("int", [Value::Str(s)]) => super::value::parse_py_int(s)
            .map(Value::Int)
            .ok_or_else(|| format!("invalid literal for int(): {s:?}")),
        ("int", [Value::Float(f)]) => float_to_int(*f, "int"),
        ("int", [v]) => v
            .as_int()
            .map(Value::Int)
            .ok_or_else(|| format!("int() of a {}", v.type_name())),
        ("float", [Value::Str(s)]) => super::value::parse_py_float(s)
            .map(Value::Float)
            .ok_or_else(|| format!("could not convert string to float: {s:?}")),
        ("float", [v]) => num(v, "float").map(Value::Float),
        ("str", [v]) => Ok(Value::str(&v.to_py_str())),
        ("bool", [v]) => Ok(Value::Bool(v.truthy())),
        ("len", [Value::Str(s)]) => Ok(Value::Int(s.chars().count() as i64)),
        ("len", [Value::List(l)]) => Ok(Value::Int(l.len() as i64)),
        ("len", [Value::Dict(d)]) => Ok(Value::Int(d.len() as i64)),
        ("list", [Value::List(l)]) => Ok(Value::List(l.clone())),
        ("list", [Value::Dict(d)]) => Ok(Value::List(Rc::new(
            d.iter().map(|(k, _)| k.clone()).collect(),
        ))),
        ("sum", [Value::List(l)]) => {
            let mut acc = Value::Int(0);
            for x in l.iter() {
                acc = binary("+", &acc, x)?;
            }
            Ok(acc)
        }
        _ => Err(format!(
            "{name}() with {} argument(s) of type(s) ({}) is not supported",
            a.len(),
            a.iter()
                .map(Value::type_name)
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

pub(super) fn min_max(name: &str, a: &[Value]) -> Result<Value, String> {
    let items: Vec<Value> = match a {
        [Value::List(l)] => l.to_vec(),
        _ => a.to_vec(),
    };
    let mut best: Option<Value> = None;
    for x in items {
        best = Some(match best {
            None => x,
            Some(b) => {
                let better = if name == "min" {
                    compare("<", &x, &b)?
                } else {
                    compare(">", &x, &b)?
                };
                if better {
                    x
                } else {
                    b
                }
            }
        });
    }
    best.ok_or_else(|| format!("{name}() arg is an empty sequence"))
}
