//! Python values as the evaluator computes them: `None`, `bool`, `int`
//! (64-bit; beyond is refused), `float`, `str`, `list` (shared and mutable,
//! as Python's), `tuple`, `dict`, and what the host defines (a call of a
//! launch action, a value that cannot be known). `str()` and `repr()` follow
//! CPython's (floats printed with the shortest repr, `1e-05`, `1e+16`).

use std::cell::RefCell;
use std::rc::Rc;

use super::caps::str_fits;
use super::parse::Expr;
use crate::diagnostic::Result;
use crate::tolerances::MAX_PY_STR_BYTES;

/// A Python value.
#[derive(Debug, Clone)]
pub enum Value {
    None,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    List(Rc<ListCell>),
    Tuple(Vec<Value>),
    Dict(Vec<(Value, Value)>),
    /// A builtin function, a module attribute function or a method bound to
    /// its receiver.
    Func(Func),
    /// A module (`math`).
    Module(&'static str),
    /// A call the host keeps as data (a launch action such as `Node(...)`):
    /// its callee's name, arguments and line.
    Record(Rc<Record>),
    /// A value the reader cannot know, with why (and where it came from).
    Unknown(Rc<String>),
}

/// A list's items, shared and mutable. Dropped without recursion: a list
/// can be made deep by appending into a list other lists already hold (a
/// loop `t.append(c); t = c` makes a chain 10^5 deep while every value it
/// evaluates is one level deep), and the recursive drop of such a chain
/// overflowed the stack.
#[derive(Debug, Default)]
pub struct ListCell(RefCell<Vec<Value>>);

impl std::ops::Deref for ListCell {
    type Target = RefCell<Vec<Value>>;
    fn deref(&self) -> &Self::Target {
        &self.0
    }
}

impl Drop for ListCell {
    fn drop(&mut self) {
        // The containers dropped with this list (their last reference) give
        // their items to `stack` instead of dropping them inside their own
        // drop: the depth of a value never reaches the call stack.
        let mut stack = std::mem::take(self.0.get_mut());
        while let Some(v) = stack.pop() {
            match v {
                Value::List(rc) => {
                    if let Ok(mut l) = Rc::try_unwrap(rc) {
                        stack.append(l.0.get_mut());
                    }
                }
                Value::Tuple(mut t) => stack.append(&mut t),
                Value::Dict(d) => {
                    for (k, v) in d {
                        stack.push(k);
                        stack.push(v);
                    }
                }
                Value::Func(Func::Method(recv, _)) => stack.push(*recv),
                _ => {}
            }
        }
    }
}

/// A callable.
#[derive(Debug, Clone)]
pub enum Func {
    /// A builtin or `math` function, by name.
    Builtin(&'static str),
    /// A method of `recv` (`'a b'.split`).
    Method(Box<Value>, String),
    /// A function the file defines, by name (the host runs it).
    User(String),
    /// A callee the host knows by name (`Node`, `LaunchConfiguration`).
    Host(String),
}

/// A call kept as data.
#[derive(Debug)]
pub struct Record {
    pub name: String,
    pub args: Vec<Value>,
    pub kwargs: Vec<(String, Value)>,
    /// Where each keyword argument's name is (line, column).
    pub kwpos: Vec<(String, (usize, usize))>,
    pub line: usize,
    pub col: usize,
}

impl Record {
    /// Keyword argument `k`.
    pub fn kw(&self, k: &str) -> Option<&Value> {
        self.kwargs.iter().find(|(n, _)| n == k).map(|(_, v)| v)
    }

    /// Where keyword argument `k` is written.
    pub fn kw_at(&self, k: &str) -> Option<(usize, usize)> {
        self.kwpos.iter().find(|(n, _)| n == k).map(|(_, p)| *p)
    }
}

impl Value {
    pub fn list(v: Vec<Value>) -> Value {
        Value::List(Rc::new(ListCell(RefCell::new(v))))
    }

    pub fn unknown(why: impl Into<String>) -> Value {
        Value::Unknown(Rc::new(why.into()))
    }

    /// The Python type name, for messages.
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
            Value::Func(_) => "function",
            Value::Module(_) => "module",
            Value::Record(_) => "launch object",
            Value::Unknown(_) => "unknown value",
        }
    }

    /// The items of a list or tuple (a copy).
    pub fn items(&self) -> Option<Vec<Value>> {
        match self {
            Value::List(l) => Some(l.borrow().clone()),
            Value::Tuple(t) => Some(t.clone()),
            _ => None,
        }
    }

    /// The number, for arithmetic (`bool` counts as `int`).
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Value::Bool(b) => Some(f64::from(u8::from(*b))),
            Value::Int(i) => Some(*i as f64),
            Value::Float(f) => Some(*f),
            _ => None,
        }
    }

    /// The integer of an `int` or `bool`.
    pub fn as_int(&self) -> Option<i64> {
        match self {
            Value::Bool(b) => Some(i64::from(*b)),
            Value::Int(i) => Some(*i),
            _ => None,
        }
    }

    /// Python's truth value; `None` for values whose truth is not known.
    pub fn truth(&self) -> Option<bool> {
        Some(match self {
            Value::None => false,
            Value::Bool(b) => *b,
            Value::Int(i) => *i != 0,
            Value::Float(f) => *f != 0.0,
            Value::Str(s) => !s.is_empty(),
            Value::List(l) => !l.borrow().is_empty(),
            Value::Tuple(t) => !t.is_empty(),
            Value::Dict(d) => !d.is_empty(),
            Value::Func(_) | Value::Module(_) => true,
            Value::Record(_) | Value::Unknown(_) => return None,
        })
    }

    /// `str(v)`.
    pub fn to_str(&self) -> String {
        match self {
            Value::Str(s) => s.clone(),
            other => other.repr(),
        }
    }

    /// `str(v)` as a value: refused past the string cap.
    pub fn try_to_str(&self, at: &Expr) -> Result<String> {
        match self {
            Value::Str(s) => Ok(s.clone()),
            other => other.try_repr(at),
        }
    }

    /// `repr(v)` for a message: past the string cap, cut and ended `...`.
    pub fn repr(&self) -> String {
        let mut out = String::new();
        self.repr_into(&mut out, &mut Vec::new());
        if out.len() > MAX_PY_STR_BYTES {
            let mut cut = MAX_PY_STR_BYTES;
            while !out.is_char_boundary(cut) {
                cut -= 1;
            }
            out.truncate(cut);
            out.push_str("...");
        }
        out
    }

    /// `repr(v)` as a value: refused past the string cap.
    pub fn try_repr(&self, at: &Expr) -> Result<String> {
        let mut out = String::new();
        self.repr_into(&mut out, &mut Vec::new());
        str_fits(out.len(), "repr()/str()", at)?;
        Ok(out)
    }

    /// Append `repr(v)` to `out`, stopping once it passes the string cap; a
    /// list inside itself is `[...]`, as CPython prints it (`open`: the lists
    /// being printed).
    fn repr_into(&self, out: &mut String, open: &mut Vec<*const ListCell>) {
        if out.len() > MAX_PY_STR_BYTES {
            return;
        }
        let seq = |out: &mut String, v: &[Value], open: &mut Vec<_>| {
            for (i, x) in v.iter().enumerate() {
                if out.len() > MAX_PY_STR_BYTES {
                    return;
                }
                if i > 0 {
                    out.push_str(", ");
                }
                x.repr_into(out, open);
            }
        };
        match self {
            Value::None => out.push_str("None"),
            Value::Bool(b) => out.push_str(if *b { "True" } else { "False" }),
            Value::Int(i) => out.push_str(&i.to_string()),
            Value::Float(f) => out.push_str(&float_repr(*f)),
            Value::Str(s) => out.push_str(&str_repr(s)),
            Value::List(l) => {
                let p = Rc::as_ptr(l);
                if open.contains(&p) {
                    out.push_str("[...]");
                    return;
                }
                open.push(p);
                out.push('[');
                seq(out, &l.borrow(), open);
                out.push(']');
                open.pop();
            }
            Value::Tuple(t) => {
                out.push('(');
                seq(out, t, open);
                out.push_str(if t.len() == 1 { ",)" } else { ")" });
            }
            Value::Dict(d) => {
                out.push('{');
                for (i, (k, v)) in d.iter().enumerate() {
                    if out.len() > MAX_PY_STR_BYTES {
                        return;
                    }
                    if i > 0 {
                        out.push_str(", ");
                    }
                    k.repr_into(out, open);
                    out.push_str(": ");
                    v.repr_into(out, open);
                }
                out.push('}');
            }
            Value::Func(f) => out.push_str(&match f {
                Func::Builtin(n) => format!("<built-in function {n}>"),
                Func::Method(recv, n) => {
                    format!("<built-in method {n} of {} object>", recv.type_name())
                }
                Func::User(n) | Func::Host(n) => format!("<function {n}>"),
            }),
            Value::Module(m) => out.push_str(&format!("<module '{m}'>")),
            Value::Record(r) => out.push_str(&format!("{}(...)", r.name)),
            Value::Unknown(w) => out.push_str(&format!("<unknown: {w}>")),
        }
    }
}

/// CPython's `repr(str)`: single quotes unless the text holds one and no
/// double quote.
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
            c if (c as u32) < 0x20 || c as u32 == 0x7f => {
                out.push_str(&format!("\\x{:02x}", c as u32))
            }
            c => out.push(c),
        }
    }
    out.push(q);
    out
}

/// CPython's `repr(float)`: the shortest digits that round-trip, in fixed
/// notation when the exponent is in [-4, 16), else `d.ddde+XX`.
pub fn float_repr(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    let sci = format!("{x:e}");
    let (mant, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let neg = mant.starts_with('-');
    let digits: String = mant.chars().filter(char::is_ascii_digit).collect();
    let sign = if neg { "-" } else { "" };
    if (-4..16).contains(&exp) {
        let point = exp + 1;
        let body = if point <= 0 {
            format!("0.{}{}", "0".repeat((-point) as usize), digits)
        } else if (point as usize) >= digits.len() {
            format!("{}{}.0", digits, "0".repeat(point as usize - digits.len()))
        } else {
            format!(
                "{}.{}",
                &digits[..point as usize],
                &digits[point as usize..]
            )
        };
        return format!("{sign}{body}");
    }
    let m = if digits.len() > 1 {
        format!("{}.{}", &digits[..1], &digits[1..])
    } else {
        digits
    };
    format!(
        "{sign}{m}e{}{:02}",
        if exp < 0 { '-' } else { '+' },
        exp.abs()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_print_as_cpython_repr() {
        // Values from CPython 3.11's repr().
        for (x, want) in [
            (0.1 * 3.0, "0.30000000000000004"),
            (1e-5, "1e-05"),
            (1e16, "1e+16"),
            (123456789012345678.0, "1.2345678901234568e+17"),
            (0.0001, "0.0001"),
            (2.0, "2.0"),
            (-0.0, "-0.0"),
            (1e15, "1000000000000000.0"),
            (std::f64::consts::FRAC_PI_2, "1.5707963267948966"),
        ] {
            assert_eq!(float_repr(x), want);
        }
    }

    #[test]
    fn strings_repr_as_cpython() {
        assert_eq!(str_repr("a'b"), "\"a'b\"");
        assert_eq!(str_repr("a\"b'c"), "'a\"b\\'c'");
        assert_eq!(Value::Tuple(vec![Value::Int(1)]).repr(), "(1,)");
    }

    /// A list nested a million levels deep (lists, tuples and dicts in
    /// turn), dropped on a thread with a 256 KiB stack: the recursive drop
    /// overflowed it; the list's drop now walks without recursion.
    #[test]
    fn a_deep_value_drops_without_recursion() {
        std::thread::Builder::new()
            .stack_size(256 << 10)
            .spawn(|| {
                let mut v = Value::list(Vec::new());
                for i in 0..1_000_000 {
                    v = match i % 3 {
                        0 => Value::list(vec![v]),
                        1 => Value::Tuple(vec![Value::list(vec![v])]),
                        _ => Value::Dict(vec![(Value::Int(1), Value::list(vec![v]))]),
                    };
                }
                drop(v);
            })
            .unwrap()
            .join()
            .unwrap();
    }

    #[test]
    fn a_list_holding_itself_reprs_as_cpython() {
        // CPython 3.11: l = [1]; l.append(l); l.append((l,)); repr(l)
        let l = Value::list(vec![Value::Int(1)]);
        let Value::List(cell) = &l else {
            unreachable!()
        };
        cell.borrow_mut().push(l.clone());
        cell.borrow_mut().push(Value::Tuple(vec![l.clone()]));
        assert_eq!(l.repr(), "[1, [...], ([...],)]");
        // Break the cycle so the test does not leak it.
        cell.borrow_mut().clear();
    }
}
