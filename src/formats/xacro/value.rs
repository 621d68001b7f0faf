//! Values of the `${...}` language: the Python types real xacro files compute
//! with (int, float, bool, str, None, list, tuple, dict, range), printed as
//! Python's `str()` and `repr()` print them, so an attribute reads back the
//! same number.
//!
//! Lists and dicts are shared and mutable as in Python (`levels.pop(0)` in a
//! macro empties the list its caller passed); a mutation that would make a
//! container hold itself is refused (`methods`), so values form no cycles.
//! Containers are dropped iteratively (a list nested a million deep frees
//! without recursion); everything that walks a value (printing, `==`,
//! ordering, `in`) counts its depth against `XACRO_MAX_VALUE_DEPTH` and its
//! work against the [`Meter`].

use super::limits::{Meter, VALUE_BYTES};
use super::scope;
use super::tree::Elem;
use crate::tolerances::XACRO_MAX_VALUE_DEPTH;
use std::cell::{Ref, RefCell, RefMut};
use std::rc::Rc;

/// A property table of values (see `scope`).
pub type Bindings = scope::Bindings<Value>;
/// A chain of property tables.
pub type Scope = scope::Scope<Value>;
/// A property as stored.
pub type Slot = scope::Slot<Value>;

/// What evaluation reports: a message (the expander adds the place).
pub type Res<T> = std::result::Result<T, String>;

/// A function, module or type the expressions may name (`pi`, `sin`,
/// `math.radians`, `xacro.load_yaml`, `str`, ...). A type is its constructor
/// (`str`, `int`, ...; [`TYPES`]) or a type that has none (`NoneType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Builtin {
    Func(&'static str),
    Module(&'static str),
    /// A type that is not callable here (`type(None)`, `type(len)`).
    Type(&'static str),
}

/// The builtins that are types (and construct their values).
pub const TYPES: &[&str] = &[
    "bool", "int", "float", "str", "list", "tuple", "dict", "range",
];

/// A list's items (mutable, shared).
#[derive(Debug, Default)]
pub struct List(RefCell<Vec<Value>>);
/// A tuple's items.
#[derive(Debug, Default)]
pub struct Tuple(Vec<Value>);
/// A dict's entries in insertion order (keys compared with `==`, as Python's
/// hash table finds `1`, `1.0` and `True` as one key).
#[derive(Debug, Default)]
pub struct Dict(RefCell<Vec<(Value, Value)>>);

/// One value. Ints are 64-bit (a Python int beyond that is refused, not
/// rounded).
#[derive(Debug, Clone)]
pub enum Value {
    None,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(Rc<str>),
    List(Rc<List>),
    Tuple(Rc<Tuple>),
    Dict(Rc<Dict>),
    /// `range(start, stop, step)`.
    Range(Rc<[i64; 3]>),
    Builtin(Builtin),
    /// A method bound to its object (`s.split`), called later.
    Method(Rc<(Value, &'static str)>),
    /// A property namespace (`xacro:include ns="..."`).
    Ns(Scope),
    /// A block parameter or block property (`*name`, `**name`).
    Block(Rc<Elem>),
}

// The meter charges each item of a list this size (`limits::VALUE_BYTES`).
const _: () = assert!(std::mem::size_of::<Value>() as u64 == VALUE_BYTES);

impl List {
    pub fn items(&self) -> Ref<'_, Vec<Value>> {
        self.0.borrow()
    }
    pub fn items_mut(&self) -> RefMut<'_, Vec<Value>> {
        self.0.borrow_mut()
    }
}

impl Tuple {
    pub fn items(&self) -> &[Value] {
        &self.0
    }
}

impl Dict {
    pub fn items(&self) -> Ref<'_, Vec<(Value, Value)>> {
        self.0.borrow()
    }
    pub fn items_mut(&self) -> RefMut<'_, Vec<(Value, Value)>> {
        self.0.borrow_mut()
    }
}

/// The children of a container that is dropped now (its last reference),
/// moved onto `stack` so that nothing recurses.
fn take_children(v: Value, stack: &mut Vec<Value>) {
    match v {
        Value::List(rc) => {
            if let Ok(mut l) = Rc::try_unwrap(rc) {
                stack.append(l.0.get_mut());
            }
        }
        Value::Tuple(rc) => {
            if let Ok(mut t) = Rc::try_unwrap(rc) {
                stack.append(&mut t.0);
            }
        }
        Value::Dict(rc) => {
            if let Ok(mut d) = Rc::try_unwrap(rc) {
                for (k, v) in d.0.get_mut().drain(..) {
                    stack.push(k);
                    stack.push(v);
                }
            }
        }
        _ => {}
    }
}

fn drop_iteratively(mut stack: Vec<Value>) {
    while let Some(v) = stack.pop() {
        take_children(v, &mut stack);
    }
}

impl Drop for List {
    fn drop(&mut self) {
        drop_iteratively(std::mem::take(self.0.get_mut()));
    }
}

impl Drop for Tuple {
    fn drop(&mut self) {
        drop_iteratively(std::mem::take(&mut self.0));
    }
}

impl Drop for Dict {
    fn drop(&mut self) {
        let mut stack = Vec::new();
        for (k, v) in self.0.get_mut().drain(..) {
            stack.push(k);
            stack.push(v);
        }
        drop_iteratively(stack);
    }
}

/// The error of a value nested too deep to walk.
pub fn too_deep() -> String {
    format!("a value nested deeper than {XACRO_MAX_VALUE_DEPTH} levels (lists in lists)")
}

/// The error of an int result past 64 bits.
pub(super) fn overflow() -> String {
    "integer result beyond 64 bits: not supported".into()
}

/// `int()` of a finite float within 64 bits (`what` names the caller).
pub(super) fn float_to_int(f: f64, what: &str) -> Res<Value> {
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

impl Value {
    pub fn str(s: &str) -> Value {
        Value::Str(Rc::from(s))
    }

    /// A new list (the meter charged by the caller).
    pub fn list(items: Vec<Value>) -> Value {
        Value::List(Rc::new(List(RefCell::new(items))))
    }

    /// A new tuple (the meter charged by the caller).
    pub fn tuple(items: Vec<Value>) -> Value {
        Value::Tuple(Rc::new(Tuple(items)))
    }

    /// A new dict (the meter charged by the caller; keys distinct).
    pub fn dict(items: Vec<(Value, Value)>) -> Value {
        Value::Dict(Rc::new(Dict(RefCell::new(items))))
    }

    /// Python's type name, for messages and `type()`.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::None => "NoneType",
            Value::Bool(_) => "bool",
            Value::Int(_) => "int",
            Value::Float(_) => "float",
            Value::Str(_) => "str",
            Value::List(_) => "list",
            Value::Tuple(_) => "tuple",
            Value::Dict(_) => "dict",
            Value::Range(_) => "range",
            Value::Builtin(Builtin::Func(f)) if TYPES.contains(f) => "type",
            Value::Builtin(Builtin::Type(_)) => "type",
            Value::Builtin(Builtin::Func(_)) | Value::Method(_) => "builtin_function_or_method",
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
            Value::List(l) => !l.items().is_empty(),
            Value::Tuple(t) => !t.items().is_empty(),
            Value::Dict(d) => !d.items().is_empty(),
            Value::Range(r) => range_len(r) > 0,
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

    /// The items of a sequence (list, tuple, range, the characters of a
    /// string, the keys of a dict) as a new vector: what `for x in v`
    /// iterates. The meter is charged per item.
    pub fn iter_items(&self, m: &mut Meter) -> Res<Vec<Value>> {
        let v = match self {
            Value::List(l) => l.items().clone(),
            Value::Tuple(t) => t.items().to_vec(),
            Value::Dict(d) => d.items().iter().map(|(k, _)| k.clone()).collect(),
            Value::Str(s) => {
                m.scan(s.len())?;
                s.chars()
                    .map(|c| Value::str(c.encode_utf8(&mut [0; 4])))
                    .collect()
            }
            Value::Range(r) => {
                let n = range_len(r);
                m.list(usize::try_from(n).unwrap_or(usize::MAX))?;
                (0..n).map(|i| Value::Int(r[0] + i * r[2])).collect()
            }
            other => return Err(format!("'{}' object is not iterable", other.type_name())),
        };
        m.work(v.len() as u64)?;
        Ok(v)
    }

    /// Python `str(value)`, within the meter's limits.
    pub fn to_py_str(&self, m: &mut Meter) -> Res<String> {
        match self {
            Value::Str(s) => Ok(s.to_string()),
            other => other.repr(m),
        }
    }

    /// Python `repr(value)`, within the meter's limits.
    pub fn repr(&self, m: &mut Meter) -> Res<String> {
        let mut out = String::new();
        self.repr_into(&mut out, m, 0)?;
        m.string(out.len())?;
        Ok(out)
    }

    /// A short repr for messages: at most about 200 characters, never
    /// failing (a value too large or deep is cut).
    pub fn show(&self) -> String {
        let mut m = Meter::with_steps(2_000);
        let mut out = String::new();
        match self.repr_into(&mut out, &mut m, 0) {
            Ok(()) if out.len() <= 200 => out,
            _ => {
                let cut: String = out.chars().take(200).collect();
                format!("{cut}...")
            }
        }
    }

    fn repr_into(&self, out: &mut String, m: &mut Meter, depth: usize) -> Res<()> {
        m.step()?;
        if depth > XACRO_MAX_VALUE_DEPTH {
            return Err(too_deep());
        }
        if out.len() > crate::tolerances::XACRO_MAX_STRING_BYTES {
            return m.string(out.len());
        }
        let seq = |out: &mut String, m: &mut Meter, items: &[Value], open, close| -> Res<()> {
            out.push(open);
            for (i, x) in items.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                x.repr_into(out, m, depth + 1)?;
            }
            out.push(close);
            Ok(())
        };
        match self {
            Value::None => out.push_str("None"),
            Value::Bool(true) => out.push_str("True"),
            Value::Bool(false) => out.push_str("False"),
            Value::Int(i) => out.push_str(&i.to_string()),
            Value::Float(f) => out.push_str(&float_repr(*f)),
            Value::Str(s) => {
                m.scan(s.len())?;
                out.push_str(&str_repr(s));
            }
            Value::List(l) => seq(out, m, &l.items(), '[', ']')?,
            Value::Tuple(t) => {
                if let [one] = t.items() {
                    out.push('(');
                    one.repr_into(out, m, depth + 1)?;
                    out.push_str(",)");
                } else {
                    seq(out, m, t.items(), '(', ')')?;
                }
            }
            Value::Dict(d) => {
                out.push('{');
                for (i, (k, v)) in d.items().iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    k.repr_into(out, m, depth + 1)?;
                    out.push_str(": ");
                    v.repr_into(out, m, depth + 1)?;
                }
                out.push('}');
            }
            Value::Range(r) => {
                out.push_str(&if r[2] == 1 {
                    format!("range({}, {})", r[0], r[1])
                } else {
                    format!("range({}, {}, {})", r[0], r[1], r[2])
                });
            }
            Value::Builtin(Builtin::Func(n)) if TYPES.contains(n) => {
                out.push_str(&format!("<class '{n}'>"))
            }
            Value::Builtin(Builtin::Type(n)) => out.push_str(&format!("<class '{n}'>")),
            Value::Builtin(Builtin::Func(n)) => out.push_str(&format!("<built-in function {n}>")),
            Value::Builtin(Builtin::Module(n)) => out.push_str(&format!("<module '{n}'>")),
            Value::Method(b) => out.push_str(&format!(
                "<built-in method {} of {} object>",
                b.1,
                b.0.type_name()
            )),
            Value::Ns(_) => out.push_str("<namespace>"),
            Value::Block(e) => out.push_str(&format!("<block <{}>>", e.name)),
        }
        Ok(())
    }

    /// Python `==`.
    pub fn py_eq(&self, other: &Value, m: &mut Meter) -> Res<bool> {
        eq_at(self, other, m, 0)
    }

    /// Whether the value may be a dict key (Python: hashable).
    pub fn hashable(&self) -> bool {
        match self {
            Value::List(_) | Value::Dict(_) | Value::Ns(_) | Value::Block(_) => false,
            Value::Tuple(t) => t.items().iter().all(Value::hashable),
            _ => true,
        }
    }
}

fn eq_at(a: &Value, b: &Value, m: &mut Meter, depth: usize) -> Res<bool> {
    m.step()?;
    if depth > XACRO_MAX_VALUE_DEPTH {
        return Err(too_deep());
    }
    let seq = |x: &[Value], y: &[Value], m: &mut Meter| -> Res<bool> {
        if x.len() != y.len() {
            return Ok(false);
        }
        for (p, q) in x.iter().zip(y) {
            if !eq_at(p, q, m, depth + 1)? {
                return Ok(false);
            }
        }
        Ok(true)
    };
    Ok(match (a, b) {
        (Value::None, Value::None) => true,
        (Value::Str(x), Value::Str(y)) => {
            m.scan(x.len().min(y.len()))?;
            x == y
        }
        (Value::List(x), Value::List(y)) => Rc::ptr_eq(x, y) || seq(&x.items(), &y.items(), m)?,
        (Value::Tuple(x), Value::Tuple(y)) => seq(x.items(), y.items(), m)?,
        (Value::Range(x), Value::Range(y)) => {
            let (nx, ny) = (range_len(x), range_len(y));
            nx == ny && (nx == 0 || (x[0] == y[0] && (nx == 1 || x[2] == y[2])))
        }
        (Value::Dict(x), Value::Dict(y)) => {
            let (x, y) = (x.items(), y.items());
            if x.len() != y.len() {
                return Ok(false);
            }
            for (k, v) in x.iter() {
                let mut found = false;
                for (k2, v2) in y.iter() {
                    if eq_at(k, k2, m, depth + 1)? {
                        found = eq_at(v, v2, m, depth + 1)?;
                        break;
                    }
                }
                if !found {
                    return Ok(false);
                }
            }
            true
        }
        (Value::Int(x), Value::Int(y)) => x == y,
        (Value::Builtin(x), Value::Builtin(y)) => x == y,
        (x, y) => match (x.as_f64(), y.as_f64()) {
            (Some(p), Some(q)) => {
                // An int and a float are equal when the float is that integer
                // (exactly, as Python compares them).
                match (x.as_int(), y.as_int()) {
                    (Some(i), None) => float_eq_int(q, i),
                    (None, Some(j)) => float_eq_int(p, j),
                    _ => p == q,
                }
            }
            _ => false,
        },
    })
}

/// `f == i` exactly (Python compares an int with a float without rounding
/// the int).
fn float_eq_int(f: f64, i: i64) -> bool {
    f.fract() == 0.0 && f.abs() < 9.3e18 && f as i64 == i && (i as f64) == f
}

/// The number of items of a range.
pub fn range_len(r: &[i64; 3]) -> i64 {
    let (start, stop, step) = (r[0] as i128, r[1] as i128, r[2] as i128);
    let n = if step > 0 && start < stop {
        (stop - start - 1) / step + 1
    } else if step < 0 && start > stop {
        (start - stop - 1) / (-step) + 1
    } else {
        0
    };
    i64::try_from(n).unwrap_or(i64::MAX)
}

/// Python's `repr(str)`: single quotes unless the text holds one and no double.
pub fn str_repr(s: &str) -> String {
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
            c if (c as u32) < 0x20 || c == '\u{7f}' => {
                out.push_str(&format!("\\x{:02x}", c as u32));
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
/// digits (`_` between digits allowed); `None` when it is not one (or does
/// not fit 64 bits).
pub fn parse_py_int(s: &str) -> Option<i64> {
    let t = s.trim();
    let body = t.strip_prefix(['+', '-']).unwrap_or(t);
    if body.is_empty()
        || !body.bytes().all(|b| b.is_ascii_digit() || b == b'_')
        || body.starts_with('_')
        || body.ends_with('_')
        || body.contains("__")
    {
        return None;
    }
    let clean: String = t.chars().filter(|c| *c != '_').collect();
    clean.parse::<i64>().ok()
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

    /// A list nested a million levels deep is dropped without recursion, and
    /// printing it stops at the depth limit with an error.
    #[test]
    fn deep_values_drop_iteratively_and_print_bounded() {
        let mut v = Value::list(Vec::new());
        for _ in 0..1_000_000 {
            v = Value::list(vec![v]);
        }
        let mut m = Meter::new();
        assert_eq!(v.repr(&mut m), Err(too_deep()));
        assert!(v.show().ends_with("..."));
        let mut d = Value::dict(Vec::new());
        for _ in 0..1_000_000 {
            d = Value::tuple(vec![Value::dict(vec![(Value::Int(0), d)])]);
        }
        drop((v, d));
    }
}
