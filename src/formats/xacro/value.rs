//! Values of the `${...}` language: the Python types real xacro files compute
//! with (int, float, bool, str, None, list, dict from `load_yaml`), printed
//! as Python's `str()` prints them, so an attribute reads back the same number.

use super::scope;
use super::tree::Elem;
use std::rc::Rc;

/// A property table of values (see `scope`).
pub type Bindings = scope::Bindings<Value>;
/// A chain of property tables.
pub type Scope = scope::Scope<Value>;
/// A property as stored.
pub type Slot = scope::Slot<Value>;

/// A function or module the expressions may name (`pi`, `sin`, `math.radians`,
/// `xacro.load_yaml`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Builtin {
    Func(&'static str),
    Module(&'static str),
}

/// One value. Ints are 64-bit (a Python int beyond that is refused, not
/// rounded); dict keys keep their YAML order.
#[derive(Debug, Clone)]
pub enum Value {
    None,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(Rc<str>),
    List(Rc<Vec<Value>>),
    Dict(Rc<Vec<(Value, Value)>>),
    Builtin(Builtin),
    /// A property namespace (`xacro:include ns="..."`).
    Ns(Scope),
    /// A block parameter or block property (`*name`, `**name`).
    Block(Rc<Elem>),
}

impl Value {
    pub fn str(s: &str) -> Value {
        Value::Str(Rc::from(s))
    }

    /// Python's type name, for messages.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::None => "None",
            Value::Bool(_) => "bool",
            Value::Int(_) => "int",
            Value::Float(_) => "float",
            Value::Str(_) => "str",
            Value::List(_) => "list",
            Value::Dict(_) => "dict",
            Value::Builtin(Builtin::Func(_)) => "function",
            Value::Builtin(Builtin::Module(_)) => "module",
            Value::Ns(_) => "namespace",
            Value::Block(_) => "block",
        }
    }

    /// Python truthiness.
    pub fn truthy(&self) -> bool {
        match self {
            Value::None => false,
            Value::Bool(b) => *b,
            Value::Int(i) => *i != 0,
            Value::Float(f) => *f != 0.0,
            Value::Str(s) => !s.is_empty(),
            Value::List(l) => !l.is_empty(),
            Value::Dict(d) => !d.is_empty(),
            _ => true,
        }
    }

    /// The number as f64 (bool and int included), else `None`.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Value::Bool(b) => Some(f64::from(u8::from(*b))),
            Value::Int(i) => Some(*i as f64),
            Value::Float(f) => Some(*f),
            _ => None,
        }
    }

    /// The integer (bool included), else `None`.
    pub fn as_int(&self) -> Option<i64> {
        match self {
            Value::Bool(b) => Some(i64::from(*b)),
            Value::Int(i) => Some(*i),
            _ => None,
        }
    }

    /// Python `str(value)`.
    pub fn to_py_str(&self) -> String {
        match self {
            Value::Str(s) => s.to_string(),
            other => other.repr(),
        }
    }

    /// Python `repr(value)`.
    pub fn repr(&self) -> String {
        match self {
            Value::None => "None".into(),
            Value::Bool(true) => "True".into(),
            Value::Bool(false) => "False".into(),
            Value::Int(i) => i.to_string(),
            Value::Float(f) => float_repr(*f),
            Value::Str(s) => str_repr(s),
            Value::List(l) => {
                let items: Vec<String> = l.iter().map(Value::repr).collect();
                format!("[{}]", items.join(", "))
            }
            Value::Dict(d) => {
                let items: Vec<String> = d
                    .iter()
                    .map(|(k, v)| format!("{}: {}", k.repr(), v.repr()))
                    .collect();
                format!("{{{}}}", items.join(", "))
            }
            Value::Builtin(Builtin::Func(n)) => format!("<built-in function {n}>"),
            Value::Builtin(Builtin::Module(n)) => format!("<module '{n}'>"),
            Value::Ns(_) => "<namespace>".into(),
            Value::Block(e) => format!("<block <{}>>", e.name),
        }
    }

    /// Python `==`.
    pub fn py_eq(&self, other: &Value) -> bool {
        match (self, other) {
            (Value::None, Value::None) => true,
            (Value::Str(a), Value::Str(b)) => a == b,
            (Value::List(a), Value::List(b)) => {
                a.len() == b.len() && a.iter().zip(b.iter()).all(|(x, y)| x.py_eq(y))
            }
            (Value::Dict(a), Value::Dict(b)) => {
                a.len() == b.len()
                    && a.iter()
                        .all(|(k, v)| b.iter().any(|(k2, v2)| k.py_eq(k2) && v.py_eq(v2)))
            }
            (Value::Int(a), Value::Int(b)) => a == b,
            (a, b) => match (a.as_f64(), b.as_f64()) {
                (Some(x), Some(y)) => x == y,
                _ => false,
            },
        }
    }
}

/// Python's `repr(str)`: single quotes unless the text holds one and no double.
fn str_repr(s: &str) -> String {
    let q = if s.contains('\'') && !s.contains('"') {
        '"'
    } else {
        '\''
    };
    let mut out = String::with_capacity(s.len() + 2);
    out.push(q);
    for c in s.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if c == q => {
                out.push('\\');
                out.push(c);
            }
            c => out.push(c),
        }
    }
    out.push(q);
    out
}

/// Python's `repr(float)`: the shortest digits that read back to the same
/// double, fixed notation for decimal exponents in [-4, 16), else `1e+16`.
pub fn float_repr(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    if x == 0.0 {
        return if x.is_sign_negative() {
            "-0.0".into()
        } else {
            "0.0".into()
        };
    }
    // `{:e}` prints the shortest round-trip digits: "d.ddde-5".
    let sci = format!("{:e}", x.abs());
    let (mant, exp) = sci.split_once('e').unwrap_or((sci.as_str(), "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let digits: String = mant.chars().filter(|c| *c != '.').collect();
    let sign = if x < 0.0 { "-" } else { "" };
    if (-4..16).contains(&exp) {
        let body = if exp >= 0 {
            let int_len = exp as usize + 1;
            if digits.len() <= int_len {
                format!("{digits}{}.0", "0".repeat(int_len - digits.len()))
            } else {
                format!("{}.{}", &digits[..int_len], &digits[int_len..])
            }
        } else {
            format!("0.{}{digits}", "0".repeat((-exp - 1) as usize))
        };
        format!("{sign}{body}")
    } else {
        let m = if digits.len() > 1 {
            format!("{}.{}", &digits[..1], &digits[1..])
        } else {
            digits
        };
        let es = if exp < 0 { '-' } else { '+' };
        format!("{sign}{m}e{es}{:02}", exp.abs())
    }
}

/// Python's `int(text)` for a literal: optional sign and whitespace, decimal
/// digits; `None` when it is not one (or does not fit 64 bits).
pub fn parse_py_int(s: &str) -> Option<i64> {
    let t = s.trim();
    let body = t.strip_prefix(['+', '-']).unwrap_or(t);
    if body.is_empty() || !body.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    t.parse::<i64>().ok()
}

/// Python's `float(text)`: decimal forms, `inf`, `infinity`, `nan` (any case,
/// signed), surrounding whitespace allowed.
pub fn parse_py_float(s: &str) -> Option<f64> {
    let t = s.trim();
    let body = t.strip_prefix(['+', '-']).unwrap_or(t);
    let lower = body.to_ascii_lowercase();
    if matches!(lower.as_str(), "inf" | "infinity" | "nan") {
        return t.to_ascii_lowercase().parse::<f64>().ok();
    }
    let ok = !body.is_empty()
        && body
            .bytes()
            .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-'))
        && body
            .bytes()
            .next()
            .is_some_and(|b| b.is_ascii_digit() || b == b'.');
    if !ok {
        return None;
    }
    t.parse::<f64>().ok()
}

/// A whole decimal integer too large for 64 bits: kept as text, never rounded.
pub fn is_big_int(s: &str) -> bool {
    let t = s.trim();
    let body = t.strip_prefix(['+', '-']).unwrap_or(t);
    !body.is_empty() && body.bytes().all(|b| b.is_ascii_digit()) && t.parse::<i64>().is_err()
}

/// xacro's literal reading of a property or parameter value given as text:
/// `'quoted'` loses its quotes; text with `_` stays text; then int, float,
/// `true`/`True`/`false`/`False`; anything else stays text.
pub fn eval_literal(v: Value) -> Value {
    let Value::Str(s) = &v else {
        return v;
    };
    if s.len() >= 2 && s.starts_with('\'') && s.ends_with('\'') {
        return Value::str(&s[1..s.len() - 1]);
    }
    if s.contains('_') || is_big_int(s) {
        return v;
    }
    if let Some(i) = parse_py_int(s) {
        return Value::Int(i);
    }
    if let Some(f) = parse_py_float(s) {
        return Value::Float(f);
    }
    match &**s {
        "true" | "True" => Value::Bool(true),
        "false" | "False" => Value::Bool(false),
        _ => v,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_print_as_python_does() {
        for (x, s) in [
            (0.1, "0.1"),
            (1.0, "1.0"),
            (123.0, "123.0"),
            (0.30000000000000004, "0.30000000000000004"),
            (1e16, "1e+16"),
            (1.5e-5, "1.5e-05"),
            (0.0001, "0.0001"),
            (-2.5e100, "-2.5e+100"),
            (1234567890123456.0, "1234567890123456.0"),
            (std::f64::consts::PI, "3.141592653589793"),
            (-0.0, "-0.0"),
        ] {
            assert_eq!(float_repr(x), s);
        }
    }

    #[test]
    fn literals_are_read_as_xacro_reads_them() {
        assert!(matches!(eval_literal(Value::str("3")), Value::Int(3)));
        assert!(matches!(eval_literal(Value::str(" -3 ")), Value::Int(-3)));
        assert!(matches!(eval_literal(Value::str("1e-3")), Value::Float(f) if f == 1e-3));
        assert!(matches!(
            eval_literal(Value::str("True")),
            Value::Bool(true)
        ));
        assert!(matches!(eval_literal(Value::str("1_000")), Value::Str(_)));
        assert!(matches!(eval_literal(Value::str("'a b'")), Value::Str(s) if &*s == "a b"));
        assert!(matches!(
            eval_literal(Value::str("99999999999999999999")),
            Value::Str(_)
        ));
        assert!(matches!(eval_literal(Value::str("abc")), Value::Str(_)));
    }
}
