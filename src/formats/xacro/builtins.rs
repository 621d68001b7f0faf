//! The functions and constants `${...}` expressions may call, exactly the
//! names Python xacro 2.1.1 exposes (`xacro/__init__.py`,
//! `create_global_symbols`): the globals `list dict map len str float int
//! bool min max round sorted range` and every `math` name; the `python.`
//! namespace (those plus `abs all any divmod enumerate filter isinstance
//! issubclass ord repr reversed sum tuple type zip`); `math.`; `xacro.`
//! (`load_yaml`, `arg`, messages: `eval`). CPython's results and errors.
//!
//! Differences, by name: `python.complex`, `set`, `frozenset`, `hash`,
//! `slice` and `vars` are refused; `map`, `filter`, `zip`, `enumerate` and
//! `reversed` give lists (Python gives one-shot iterators whose printed form
//! holds a memory address); the `math` functions beyond those listed in
//! [`MATH_FUNCS`] are refused.

use super::kwargs::{kwarg, no_kw, only_kw};
use super::limits::Meter;
use super::methods;
use super::ops::{binary, float_pow, order};
use super::subscript::dict_insert;
use super::value::{
    float_to_int, overflow, parse_py_float, parse_py_int, Builtin, Res, Value, TYPES,
};
use std::cmp::Ordering;
use std::rc::Rc;

/// The names xacro puts in the global scope.
pub(super) fn global(n: &str) -> Option<Value> {
    match n {
        "math" | "xacro" | "python" => Some(Value::Builtin(Builtin::Module(static_name(
            &["math", "xacro", "python"],
            n,
        )?))),
        "load_yaml" | "abs_filename" | "dotify" => module_member("xacro", n),
        _ if GLOBAL_PY_FUNCS.contains(&n) => module_member("python", n),
        _ => module_member("math", n),
    }
}

fn static_name(list: &[&'static str], n: &str) -> Option<&'static str> {
    list.iter().copied().find(|m| *m == n)
}

pub(super) const MATH_FUNCS: &[&str] = &[
    "sin",
    "cos",
    "tan",
    "asin",
    "acos",
    "atan",
    "atan2",
    "sinh",
    "cosh",
    "tanh",
    "asinh",
    "acosh",
    "atanh",
    "sqrt",
    "exp",
    "log",
    "log10",
    "log2",
    "pow",
    "fabs",
    "floor",
    "ceil",
    "trunc",
    "radians",
    "degrees",
    "hypot",
    "fmod",
    "copysign",
    "isnan",
    "isinf",
    "isfinite",
    "cbrt",
    "exp2",
    "expm1",
    "log1p",
    "ldexp",
    "frexp",
    "modf",
    "isclose",
    "factorial",
    "gcd",
    "lcm",
    "isqrt",
    "comb",
    "perm",
];
/// The builtins xacro exposes as globals.
const GLOBAL_PY_FUNCS: &[&str] = &[
    "list", "dict", "map", "len", "str", "float", "int", "bool", "min", "max", "round", "sorted",
    "range",
];
/// The `python.` namespace.
const PY_FUNCS: &[&str] = &[
    "list",
    "dict",
    "map",
    "len",
    "str",
    "float",
    "int",
    "bool",
    "min",
    "max",
    "round",
    "abs",
    "all",
    "any",
    "complex",
    "divmod",
    "enumerate",
    "filter",
    "frozenset",
    "hash",
    "isinstance",
    "issubclass",
    "ord",
    "repr",
    "reversed",
    "slice",
    "set",
    "sum",
    "tuple",
    "type",
    "vars",
    "zip",
    "sorted",
    "range",
];
const XACRO_FUNCS: &[&str] = &[
    "load_yaml",
    "abs_filename",
    "dotify",
    "arg",
    "message",
    "warning",
    "error",
    "print_location",
    "fatal",
    "tokenize",
];

pub(super) fn module_member(m: &str, n: &str) -> Option<Value> {
    let f = |list: &[&'static str]| static_name(list, n).map(|x| Value::Builtin(Builtin::Func(x)));
    match m {
        "math" => match n {
            "pi" => Some(Value::Float(std::f64::consts::PI)),
            "e" => Some(Value::Float(std::f64::consts::E)),
            "tau" => Some(Value::Float(std::f64::consts::TAU)),
            "inf" => Some(Value::Float(f64::INFINITY)),
            "nan" => Some(Value::Float(f64::NAN)),
            _ => f(MATH_FUNCS),
        },
        "python" => match n {
            "True" => Some(Value::Bool(true)),
            "False" => Some(Value::Bool(false)),
            _ => f(PY_FUNCS),
        },
        "xacro" => f(XACRO_FUNCS),
        _ => None,
    }
}

/// Call a function value: a builtin or a bound method.
pub(super) fn apply(f: &Value, a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<Value> {
    m.step()?;
    match f {
        Value::Builtin(Builtin::Func(name)) => {
            if XACRO_FUNCS.contains(name) && *name != "dotify" && *name != "tokenize" {
                return Err(format!("xacro.{name} cannot be passed as a function here"));
            }
            call_builtin(name, a, kw, m)
        }
        // `list.sort(key=...)` calls back into `apply`: kept here, not in
        // `methods`, so that the methods never call the builtins.
        Value::Method(b) => match (&b.0, b.1) {
            (Value::List(l), "sort") => {
                if !a.is_empty() {
                    return Err("sort() takes no positional arguments".into());
                }
                let v = sorted(l.items().clone(), kw, m)?;
                *l.items_mut() = v;
                Ok(Value::None)
            }
            _ => methods::call(&b.0, b.1, a, kw, m),
        },
        other => Err(format!("'{}' object is not callable", other.type_name())),
    }
}

pub(super) fn num(v: &Value, what: &str) -> Res<f64> {
    v.as_f64()
        .ok_or_else(|| format!("{what}: must be real number, not {}", v.type_name()))
}

pub(super) fn domain(x: f64, name: &str) -> Res<Value> {
    if x.is_nan() {
        Err(format!("math domain error in {name}()"))
    } else {
        Ok(Value::Float(x))
    }
}

/// A float result that overflowed from a finite input: Python's
/// `OverflowError: math range error`.
fn range_checked(r: f64, x: f64) -> Res<Value> {
    if r.is_infinite() && x.is_finite() {
        Err("math range error".into())
    } else {
        Ok(Value::Float(r))
    }
}

pub(super) fn call_builtin(
    name: &str,
    a: &[Value],
    kw: &[(String, Value)],
    m: &mut Meter,
) -> Res<Value> {
    if name == "isclose" {
        return isclose(a, kw);
    }
    if MATH_FUNCS.contains(&name) {
        no_kw(name, kw)?;
        if matches!(
            name,
            "factorial" | "gcd" | "lcm" | "isqrt" | "comb" | "perm"
        ) {
            return math_int(name, a);
        }
        if matches!(name, "ldexp" | "frexp" | "modf") {
            return math_parts(name, a);
        }
        return math(name, a);
    }
    py_builtin(name, a, kw, m)
}

fn math(name: &str, a: &[Value]) -> Res<Value> {
    let one = |a: &[Value]| -> Res<f64> {
        match a {
            [x] => num(x, name),
            _ => Err(format!(
                "{name}() takes exactly one argument ({} given)",
                a.len()
            )),
        }
    };
    let two = |a: &[Value]| -> Res<(f64, f64)> {
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
    let trig = |f: fn(f64) -> f64| {
        one(a).and_then(|x| {
            if x.is_infinite() {
                Err(format!("math domain error in {name}()"))
            } else {
                Ok(Value::Float(f(x)))
            }
        })
    };
    match name {
        "sin" => trig(f64::sin),
        "cos" => trig(f64::cos),
        "tan" => trig(f64::tan),
        "asin" => one(a).and_then(|x| x_nan(x, x.asin())),
        "acos" => one(a).and_then(|x| x_nan(x, x.acos())),
        "atan" => one(a).map(|x| Value::Float(x.atan())),
        "atan2" => two(a).map(|(y, x)| Value::Float(y.atan2(x))),
        "sinh" => one(a).and_then(|x| range_checked(x.sinh(), x)),
        "cosh" => one(a).and_then(|x| range_checked(x.cosh(), x)),
        "tanh" => one(a).map(|x| Value::Float(x.tanh())),
        "asinh" => one(a).map(|x| Value::Float(x.asinh())),
        "acosh" => one(a).and_then(|x| x_nan(x, x.acosh())),
        "atanh" => one(a).and_then(|x| {
            if x.abs() == 1.0 {
                Err("math domain error in atanh()".into())
            } else {
                x_nan(x, x.atanh())
            }
        }),
        "sqrt" => one(a).and_then(|x| x_nan(x, x.sqrt())),
        "exp" => one(a).and_then(|x| range_checked(x.exp(), x)),
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
        "log10" | "log2" => one(a).and_then(|x| {
            if x > 0.0 || x.is_nan() {
                Ok(Value::Float(if name == "log10" {
                    x.log10()
                } else {
                    x.log2()
                }))
            } else {
                Err(format!("math domain error in {name}()"))
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
            if y == 0.0 || x.is_infinite() {
                Err("math domain error in fmod()".into())
            } else {
                Ok(Value::Float(x % y))
            }
        }),
        "copysign" => two(a).map(|(x, y)| Value::Float(x.copysign(y))),
        "cbrt" => one(a).map(|x| Value::Float(x.cbrt())),
        "exp2" => one(a).and_then(|x| range_checked(x.exp2(), x)),
        "expm1" => one(a).and_then(|x| range_checked(x.exp_m1(), x)),
        "log1p" => one(a).and_then(|x| {
            if x <= -1.0 {
                Err("math domain error in log1p()".into())
            } else {
                Ok(Value::Float(x.ln_1p()))
            }
        }),
        "isnan" => one(a).map(|x| Value::Bool(x.is_nan())),
        "isinf" => one(a).map(|x| Value::Bool(x.is_infinite())),
        _ => one(a).map(|x| Value::Bool(x.is_finite())),
    }
}

/// `math.isclose(a, b, *, rel_tol=1e-09, abs_tol=0.0)`, CPython's test.
fn isclose(a: &[Value], kw: &[(String, Value)]) -> Res<Value> {
    only_kw("isclose", kw, &["rel_tol", "abs_tol"])?;
    let [x, y] = a else {
        return Err(format!(
            "isclose() takes exactly 2 positional arguments ({} given)",
            a.len()
        ));
    };
    let (x, y) = (num(x, "isclose")?, num(y, "isclose")?);
    let rel = kwarg(kw, "rel_tol").map_or(Ok(1e-9), |v| num(v, "isclose"))?;
    let abs = kwarg(kw, "abs_tol").map_or(Ok(0.0), |v| num(v, "isclose"))?;
    if rel < 0.0 || abs < 0.0 {
        return Err("tolerances must be non-negative".into());
    }
    if x == y {
        return Ok(Value::Bool(true));
    }
    if x.is_infinite() || y.is_infinite() {
        return Ok(Value::Bool(false));
    }
    let d = (y - x).abs();
    Ok(Value::Bool(
        d <= (rel * y).abs() || d <= (rel * x).abs() || d <= abs,
    ))
}

/// The integer functions of `math` (64-bit results; beyond is an error).
fn math_int(name: &str, a: &[Value]) -> Res<Value> {
    let ints = a
        .iter()
        .map(|v| match v {
            Value::Float(_) => Err(format!(
                "'float' object cannot be interpreted as an integer ({name})"
            )),
            v => v.as_int().ok_or_else(|| {
                format!(
                    "{name}(): '{}' object cannot be interpreted as an integer",
                    v.type_name()
                )
            }),
        })
        .collect::<Res<Vec<i64>>>()?;
    let gcd = |mut x: i64, mut y: i64| {
        (x, y) = (x.abs(), y.abs());
        while y != 0 {
            (x, y) = (y, x % y);
        }
        x
    };
    let neg = |what: &str| Err(format!("{name}() not defined for negative values ({what})"));
    let prod = |lo: i64, hi: i64| -> Res<i64> {
        (lo..=hi).try_fold(1i64, |acc, k| acc.checked_mul(k).ok_or_else(overflow))
    };
    Ok(Value::Int(match (name, &ints[..]) {
        ("factorial", [n]) if *n < 0 => return neg("n"),
        ("factorial", [n]) => prod(1, *n)?,
        ("gcd", v) => v.iter().fold(0, |g, x| gcd(g, *x)),
        ("lcm", v) => v.iter().try_fold(1i64, |l, x| {
            if *x == 0 || l == 0 {
                return Ok(0);
            }
            (l / gcd(l, *x)).checked_mul(x.abs()).ok_or_else(overflow)
        })?,
        ("isqrt", [n]) if *n < 0 => return neg("n"),
        ("isqrt", [n]) => {
            let mut r = (*n as f64).sqrt() as i64;
            while r.checked_mul(r).is_none_or(|sq| sq > *n) {
                r -= 1;
            }
            while (r + 1).checked_mul(r + 1).is_some_and(|sq| sq <= *n) {
                r += 1;
            }
            r
        }
        ("comb" | "perm", [n, k]) if *n < 0 || *k < 0 => return neg("n, k"),
        ("comb" | "perm", [n, k]) if k > n => 0,
        ("perm", [n]) => prod(1, *n)?,
        ("perm", [n, k]) => prod(n - k + 1, *n)?,
        ("comb", [n, k]) => {
            let k = (*k).min(n - k);
            let mut c: i64 = 1;
            for i in 0..k {
                c = c.checked_mul(n - i).ok_or_else(overflow)? / (i + 1);
            }
            c
        }
        _ => {
            return Err(format!(
                "{name}() takes other arguments ({} given)",
                a.len()
            ))
        }
    }))
}

/// `ldexp`, `frexp`, `modf`.
fn math_parts(name: &str, a: &[Value]) -> Res<Value> {
    match (name, a) {
        ("ldexp", [x, i]) => {
            let (mut x, mut i) = (
                num(x, name)?,
                i.as_int().ok_or("ldexp(): the exponent must be an int")?,
            );
            let start = x;
            while i > 0 {
                let k = i.min(1000);
                x *= 2f64.powi(k as i32);
                i -= k;
            }
            while i < 0 {
                let k = (-i).min(1000);
                x /= 2f64.powi(k as i32);
                i += k;
            }
            range_checked(x, start)
        }
        ("frexp", [x]) => {
            let x = num(x, name)?;
            if x == 0.0 || !x.is_finite() {
                return Ok(Value::tuple(vec![Value::Float(x), Value::Int(0)]));
            }
            let (mut m, mut e) = (x, 0i64);
            while m.abs() >= 1.0 {
                m /= 2.0;
                e += 1;
            }
            while m.abs() < 0.5 {
                m *= 2.0;
                e -= 1;
            }
            Ok(Value::tuple(vec![Value::Float(m), Value::Int(e)]))
        }
        ("modf", [x]) => {
            let x = num(x, name)?;
            let frac = if x.is_infinite() {
                0.0f64.copysign(x)
            } else {
                x.fract()
            };
            Ok(Value::tuple(vec![
                Value::Float(frac),
                Value::Float(x.trunc()),
            ]))
        }
        _ => Err(format!(
            "{name}() takes other arguments ({} given)",
            a.len()
        )),
    }
}

pub(super) fn log(x: f64) -> Res<Value> {
    if x > 0.0 || x.is_nan() {
        Ok(Value::Float(x.ln()))
    } else {
        Err("math domain error in log()".into())
    }
}

/// math.floor/ceil/trunc return an int in Python 3 (an int argument unchanged).
pub(super) fn int_of_float(a: &[Value], r: f64, name: &str) -> Res<Value> {
    if let Some(i) = a.first().and_then(Value::as_int) {
        return Ok(Value::Int(i));
    }
    float_to_int(r, name)
}

/// The items of an iterable argument.
fn iterable(v: &Value, m: &mut Meter) -> Res<Vec<Value>> {
    v.iter_items(m)
}

/// The one argument of `name` (or `default` when none).
fn one_arg<'a>(name: &str, a: &'a [Value], default: Option<&'a Value>) -> Res<Option<&'a Value>> {
    match a {
        [] => Ok(default),
        [x] => Ok(Some(x)),
        _ => Err(format!(
            "{name}() takes at most 1 argument ({} given)",
            a.len()
        )),
    }
}

/// Python's `round`: half to even, `ndigits` through the correctly rounded
/// decimal text (as CPython does).
fn round(a: &[Value], kw: &[(String, Value)]) -> Res<Value> {
    only_kw("round", kw, &["ndigits"])?;
    let (x, n) = match (a, kwarg(kw, "ndigits")) {
        ([x], None) | ([x, Value::None], None) | ([x], Some(Value::None)) => (x, None),
        ([x], Some(n)) | ([x, n], None) => (x, Some(n)),
        _ => return Err("round() takes 1 or 2 arguments".into()),
    };
    let Some(n) = n else {
        if let Some(i) = x.as_int() {
            return Ok(Value::Int(i));
        }
        let f = num(x, "round")?;
        let r = if (f - f.trunc()).abs() == 0.5 {
            2.0 * (f / 2.0).round()
        } else {
            f.round()
        };
        return float_to_int(r, "round");
    };
    let n = n.as_int().ok_or("round(): ndigits must be an integer")?;
    if let Some(i) = x.as_int() {
        if n >= 0 {
            return Ok(Value::Int(i));
        }
        let p = 10i64.checked_pow(u32::try_from(-n).unwrap_or(u32::MAX));
        let Some(p) = p else { return Ok(Value::Int(0)) };
        let (q, r) = (i.div_euclid(p), i.rem_euclid(p));
        let up = r * 2 > p || (r * 2 == p && q % 2 != 0);
        return (q + i64::from(up))
            .checked_mul(p)
            .map(Value::Int)
            .ok_or_else(overflow);
    }
    let f = num(x, "round")?;
    if !(0..=17).contains(&n) {
        return Err(
            "round() of a float with negative or more than 17 digits is not supported".into(),
        );
    }
    if !f.is_finite() {
        return Ok(Value::Float(f));
    }
    format!("{f:.*}", n as usize)
        .parse::<f64>()
        .map(Value::Float)
        .map_err(|e| e.to_string())
}

fn int_of(a: &[Value], kw: &[(String, Value)]) -> Res<Value> {
    only_kw("int", kw, &["base"])?;
    let base = match (a.get(1), kwarg(kw, "base")) {
        (Some(b), None) | (None, Some(b)) => Some(b.as_int().ok_or("int(): base must be an int")?),
        (None, None) => None,
        _ => return Err("int() got multiple values for argument 'base'".into()),
    };
    match (a.first(), base) {
        (None, None) => Ok(Value::Int(0)),
        (Some(Value::Str(s)), None) => parse_py_int(s).map(Value::Int).ok_or_else(|| {
            format!(
                "invalid literal for int() with base 10: {}",
                Value::Str(s.clone()).show()
            )
        }),
        (Some(Value::Str(s)), Some(b)) => int_in_base(s, b),
        (Some(_), Some(_)) => Err("int() can't convert non-string with explicit base".into()),
        (Some(Value::Float(f)), None) => float_to_int(f.trunc(), "int"),
        (Some(v), None) => v.as_int().map(Value::Int).ok_or_else(|| {
            format!(
                "int() argument must be a string or a number, not '{}'",
                v.type_name()
            )
        }),
        (None, Some(_)) => Err("int() missing string argument".into()),
    }
}

fn int_in_base(s: &str, base: i64) -> Res<Value> {
    let t = s.trim();
    let (neg, body) = match t.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, t.strip_prefix('+').unwrap_or(t)),
    };
    let lower = body.to_ascii_lowercase();
    let (base, digits) = match (base, lower.get(..2)) {
        (0 | 16, Some("0x")) => (16, &lower[2..]),
        (0 | 8, Some("0o")) => (8, &lower[2..]),
        (0 | 2, Some("0b")) => (2, &lower[2..]),
        (0, _) => (10, lower.as_str()),
        (b, _) => (b, lower.as_str()),
    };
    let bad = || {
        format!(
            "invalid literal for int() with base {base}: {}",
            Value::str(s).show()
        )
    };
    if !(2..=36).contains(&base) {
        return Err("int() base must be >= 2 and <= 36, or 0".into());
    }
    let clean: String = digits.chars().filter(|c| *c != '_').collect();
    if clean.is_empty() || digits.starts_with('_') {
        return Err(bad());
    }
    let v = i64::from_str_radix(&clean, base as u32).map_err(|_| bad())?;
    Ok(Value::Int(if neg { -v } else { v }))
}

/// `isinstance(x, t)`: whether `x` is of type `t` (or one in a tuple).
fn isinstance(x: &Value, t: &Value) -> Res<bool> {
    match t {
        Value::Tuple(ts) => {
            for t in ts.items() {
                if isinstance(x, t)? {
                    return Ok(true);
                }
            }
            Ok(false)
        }
        Value::Builtin(Builtin::Func(n)) if TYPES.contains(n) => Ok(subclass(x.type_name(), n)),
        Value::Builtin(Builtin::Type(n)) => Ok(x.type_name() == *n),
        other => Err(format!(
            "isinstance() arg 2 must be a type or tuple of types, not {}",
            other.type_name()
        )),
    }
}

/// Whether type `a` is `b` or derives from it (`bool` is an `int`).
fn subclass(a: &str, b: &str) -> bool {
    a == b || (a == "bool" && b == "int")
}

/// `type(x)`: the type value (its constructor where it has one).
fn type_of(x: &Value) -> Value {
    let n = x.type_name();
    match static_name(TYPES, n) {
        Some(t) => Value::Builtin(Builtin::Func(t)),
        None => Value::Builtin(Builtin::Type(n)),
    }
}

/// `min`/`max` over the arguments or one iterable, with `key=`, `default=`.
fn min_max(name: &str, a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<Value> {
    only_kw(name, kw, &["key", "default"])?;
    let items = match a {
        [one] => iterable(one, m)?,
        [] => return Err(format!("{name} expected at least 1 argument, got 0")),
        _ if kwarg(kw, "default").is_some() => {
            return Err(format!(
                "Cannot specify a default for {name}() with multiple positional arguments"
            ))
        }
        _ => a.to_vec(),
    };
    let key = kwarg(kw, "key").filter(|k| !matches!(k, Value::None));
    let mut best: Option<(Value, Value)> = None;
    for x in items {
        let k = match key {
            Some(f) => apply(f, std::slice::from_ref(&x), &[], m)?,
            None => x.clone(),
        };
        best = Some(match best {
            None => (x, k),
            Some((bx, bk)) => {
                let o = order(&k, &bk, m, 0)?;
                let better = if name == "min" {
                    o == Some(Ordering::Less)
                } else {
                    o == Some(Ordering::Greater)
                };
                if better {
                    (x, k)
                } else {
                    (bx, bk)
                }
            }
        });
    }
    match (best, kwarg(kw, "default")) {
        (Some((x, _)), _) => Ok(x),
        (None, Some(d)) => Ok(d.clone()),
        (None, None) => Err(format!("{name}() arg is an empty sequence")),
    }
}

/// `sorted(iterable, key=, reverse=)` and `list.sort`: stable, as CPython.
pub(super) fn sorted(items: Vec<Value>, kw: &[(String, Value)], m: &mut Meter) -> Res<Vec<Value>> {
    only_kw("sort", kw, &["key", "reverse"])?;
    let reverse = kwarg(kw, "reverse").is_some_and(Value::truthy);
    let key = kwarg(kw, "key").filter(|k| !matches!(k, Value::None));
    let mut keyed = Vec::with_capacity(items.len());
    for x in items {
        let k = match key {
            Some(f) => apply(f, std::slice::from_ref(&x), &[], m)?,
            None => x.clone(),
        };
        keyed.push((k, x));
    }
    m.work(keyed.len() as u64 * (64 - (keyed.len() as u64).leading_zeros() as u64))?;
    if reverse {
        keyed.reverse();
    }
    let mut fail: Option<String> = None;
    keyed.sort_by(|(a, _), (b, _)| {
        if fail.is_some() {
            return Ordering::Equal;
        }
        match order(a, b, m, 0) {
            Ok(o) => o.unwrap_or(Ordering::Equal),
            Err(e) => {
                fail = Some(e);
                Ordering::Equal
            }
        }
    });
    if let Some(e) = fail {
        return Err(e);
    }
    if reverse {
        keyed.reverse();
    }
    Ok(keyed.into_iter().map(|(_, x)| x).collect())
}

/// `range(stop)`, `range(start, stop[, step])`.
fn range(a: &[Value]) -> Res<Value> {
    let ints: Vec<i64> = a
        .iter()
        .map(|v| {
            v.as_int().ok_or_else(|| {
                format!(
                    "'{}' object cannot be interpreted as an integer",
                    v.type_name()
                )
            })
        })
        .collect::<Res<_>>()?;
    let r = match ints[..] {
        [stop] => [0, stop, 1],
        [start, stop] => [start, stop, 1],
        [start, stop, step] => [start, stop, step],
        _ => return Err(format!("range expected 1 to 3 arguments, got {}", a.len())),
    };
    if r[2] == 0 {
        return Err("range() arg 3 must not be zero".into());
    }
    Ok(Value::Range(Rc::new(r)))
}

/// `dict(...)`: from a dict or an iterable of pairs, then keywords.
fn dict_of(a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<Value> {
    let mut pairs = Vec::new();
    match a {
        [] => {}
        [Value::Dict(d)] => pairs = d.items().clone(),
        [it] => {
            for (i, p) in iterable(it, m)?.into_iter().enumerate() {
                let kv = iterable(&p, m).map_err(|_| {
                    format!("cannot convert dictionary update sequence element #{i} to a sequence")
                })?;
                let [k, v] = <[Value; 2]>::try_from(kv).map_err(|kv| {
                    format!(
                        "dictionary update sequence element #{i} has length {}; 2 is required",
                        kv.len()
                    )
                })?;
                dict_insert(&mut pairs, k, v, m)?;
            }
        }
        _ => return Err(format!("dict expected at most 1 argument, got {}", a.len())),
    }
    for (k, v) in kw {
        dict_insert(&mut pairs, Value::str(k), v.clone(), m)?;
    }
    m.list(pairs.len())?;
    Ok(Value::dict(pairs))
}

/// `zip(*iterables)` as a list of tuples.
fn zip(a: &[Value], m: &mut Meter) -> Res<Value> {
    let lists = a.iter().map(|x| iterable(x, m)).collect::<Res<Vec<_>>>()?;
    let n = lists.iter().map(Vec::len).min().unwrap_or(0);
    m.list(n)?;
    let out = (0..n)
        .map(|i| Value::tuple(lists.iter().map(|l| l[i].clone()).collect()))
        .collect();
    Ok(Value::list(out))
}

/// `map(f, *iterables)` as a list.
fn map(a: &[Value], m: &mut Meter) -> Res<Value> {
    let [f, its @ ..] = a else {
        return Err("map() must have at least two arguments.".into());
    };
    if its.is_empty() {
        return Err("map() must have at least two arguments.".into());
    }
    let lists = its
        .iter()
        .map(|x| iterable(x, m))
        .collect::<Res<Vec<_>>>()?;
    let n = lists.iter().map(Vec::len).min().unwrap_or(0);
    m.list(n)?;
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let args: Vec<Value> = lists.iter().map(|l| l[i].clone()).collect();
        out.push(apply(f, &args, &[], m)?);
    }
    Ok(Value::list(out))
}

/// `sum(iterable, start=0)`.
fn sum(a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<Value> {
    only_kw("sum", kw, &["start"])?;
    let (it, start) = match (a, kwarg(kw, "start")) {
        ([it], None) => (it, Value::Int(0)),
        ([it], Some(s)) | ([it, s], None) => (it, s.clone()),
        _ => return Err("sum() takes 1 or 2 arguments".into()),
    };
    if matches!(start, Value::Str(_)) {
        return Err("sum() can't sum strings [use ''.join(seq) instead]".into());
    }
    let mut acc = start;
    for x in iterable(it, m)? {
        acc = binary("+", &acc, &x, m)?;
    }
    Ok(acc)
}

/// Builtins refused by name, and why.
fn refused(name: &str) -> Option<&'static str> {
    Some(match name {
        "complex" => "complex numbers are not supported",
        "set" | "frozenset" => "sets are not supported (their order is not Python's)",
        "hash" => "hash() of a string differs between Python runs",
        "slice" => "slice objects are not supported; write x[a:b]",
        "vars" => "vars() is not supported",
        _ => return None,
    })
}

fn py_builtin(name: &str, a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<Value> {
    if let Some(why) = refused(name) {
        return Err(format!("python.{name}: {why}"));
    }
    let kw_ok = matches!(
        name,
        "round" | "int" | "min" | "max" | "sorted" | "dict" | "sum" | "enumerate" | "tokenize"
    );
    if !kw_ok {
        no_kw(name, kw)?;
    }
    match (name, a) {
        ("abs", [Value::Float(f)]) => Ok(Value::Float(f.abs())),
        ("abs", [v]) => v
            .as_int()
            .and_then(i64::checked_abs)
            .map(Value::Int)
            .ok_or_else(|| format!("bad operand type for abs(): '{}'", v.type_name())),
        ("all" | "any", [it]) => {
            let want = name == "any";
            Ok(Value::Bool(
                iterable(it, m)?.iter().any(|x| x.truthy() == want) == want,
            ))
        }
        ("min" | "max", _) => min_max(name, a, kw, m),
        ("round", _) => round(a, kw),
        ("int", _) => int_of(a, kw),
        ("float", _) => match one_arg(name, a, None)? {
            None => Ok(Value::Float(0.0)),
            Some(Value::Str(s)) => parse_py_float(&s.replace('_', ""))
                .filter(|_| !s.contains("__") && !s.trim().starts_with('_'))
                .map(Value::Float)
                .ok_or_else(|| {
                    format!(
                        "could not convert string to float: {}",
                        Value::Str(s.clone()).show()
                    )
                }),
            Some(v) => num(v, "float").map(Value::Float),
        },
        ("str", _) => match one_arg(name, a, None)? {
            None => Ok(Value::str("")),
            Some(v) => v.to_py_str(m).map(|s| Value::str(&s)),
        },
        ("repr", [v]) => v.repr(m).map(|s| Value::str(&s)),
        ("bool", _) => Ok(Value::Bool(
            one_arg(name, a, None)?.is_some_and(Value::truthy),
        )),
        ("len", [v]) => methods::len(v).map(Value::Int),
        ("dict", _) => dict_of(a, kw, m),
        ("range", _) => range(a),
        ("sum", _) => sum(a, kw, m),
        ("divmod", [x, y]) => {
            let q = binary("//", x, y, m)?;
            let r = binary("%", x, y, m)?;
            Ok(Value::tuple(vec![q, r]))
        }
        ("list" | "tuple" | "sorted" | "reversed" | "enumerate" | "filter" | "map" | "zip", _) => {
            sequence(name, a, kw, m)
        }
        ("isinstance", [x, t]) => isinstance(x, t).map(Value::Bool),
        ("issubclass", [c, t]) => match c {
            Value::Builtin(Builtin::Func(n)) if TYPES.contains(n) => {
                let probe = match *n {
                    "bool" => Value::Bool(false),
                    "int" => Value::Int(0),
                    _ => return isinstance(&type_probe(n), t).map(Value::Bool),
                };
                isinstance(&probe, t).map(Value::Bool)
            }
            _ => Err("issubclass() arg 1 must be a class".into()),
        },
        ("type", [x]) => Ok(type_of(x)),
        ("ord", [Value::Str(s)]) => {
            let mut cs = s.chars();
            match (cs.next(), cs.next()) {
                (Some(c), None) => Ok(Value::Int(i64::from(u32::from(c)))),
                _ => Err(format!(
                    "ord() expected a character, but string of length {} found",
                    s.chars().count()
                )),
            }
        }
        ("dotify", [d @ Value::Dict(_)]) => Ok(d.clone()),
        ("tokenize", [Value::Str(s), rest @ ..]) => methods::tokenize(s, rest, kw, m),
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

/// The builtins that make a sequence from iterables.
fn sequence(name: &str, a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<Value> {
    match (name, a) {
        ("list" | "tuple" | "sorted" | "reversed", _) => {
            let items = match one_arg(name, a, None)? {
                None if name != "sorted" && name != "reversed" => Vec::new(),
                None => return Err(format!("{name}() takes exactly one argument (0 given)")),
                Some(v) => iterable(v, m)?,
            };
            m.list(items.len())?;
            Ok(match name {
                "tuple" => Value::tuple(items),
                "sorted" => Value::list(sorted(items, kw, m)?),
                "reversed" => Value::list(items.into_iter().rev().collect()),
                _ => Value::list(items),
            })
        }
        ("enumerate", [it, rest @ ..]) => {
            only_kw(name, kw, &["start"])?;
            let start = match (rest, kwarg(kw, "start")) {
                ([], None) => 0,
                ([s], None) | ([], Some(s)) => {
                    s.as_int().ok_or("enumerate(): start must be an int")?
                }
                _ => return Err("enumerate() takes at most 2 arguments".into()),
            };
            let items = iterable(it, m)?;
            m.list(items.len())?;
            let out = items
                .into_iter()
                .zip(start..)
                .map(|(x, i)| Value::tuple(vec![Value::Int(i), x]))
                .collect();
            Ok(Value::list(out))
        }
        ("filter", [f, it]) => {
            let mut out = Vec::new();
            for x in iterable(it, m)? {
                let keep = match f {
                    Value::None => x.truthy(),
                    f => apply(f, std::slice::from_ref(&x), &[], m)?.truthy(),
                };
                if keep {
                    out.push(x);
                }
            }
            Ok(Value::list(out))
        }
        ("map", _) => map(a, m),
        ("zip", _) => zip(a, m),
        _ => Err(format!(
            "{name}() takes other arguments ({} given)",
            a.len()
        )),
    }
}

/// A value of type `n`, for `issubclass`.
fn type_probe(n: &str) -> Value {
    match n {
        "float" => Value::Float(0.0),
        "str" => Value::str(""),
        "list" => Value::list(Vec::new()),
        "tuple" => Value::tuple(Vec::new()),
        "dict" => Value::dict(Vec::new()),
        _ => Value::Range(Rc::new([0, 0, 1])),
    }
}
