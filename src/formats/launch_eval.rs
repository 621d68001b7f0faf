//! `$(eval ...)` in launch files, evaluated statically by the Python
//! expression reader (`pyexpr`): never executed, no environment, no package
//! lookups.
//!
//! ROS 1 (roslaunch, ROS Noetic; ros/ros_comm @
//! 845f74602c7464e08ef5ac6fd9e26c97d0fe42c9
//! `tools/roslaunch/src/roslaunch/substitution_args.py`):
//! - `:376-378`: evaluated only when the whole attribute value starts with
//!   `$(eval ` and ends with `)`; anywhere else `eval` is an unknown
//!   substitution command (`:395-401`) and roslaunch fails: refused here;
//! - `:345-347`: any `__` is refused; the value is `str()` of the result
//!   (`True` -> `True`, `0.1*3` -> `0.30000000000000004`);
//! - `:302-333`: names are looked up in `true`/`false`/`True`/`False`,
//!   `arg()`, `anon()`, `dirname()`, `env()`, `optenv()`, `find()` and every
//!   name of `math`, then as launch args converted by
//!   `loader.py:58-88` `convert_value(value, 'auto')` (a float when the text
//!   holds `.`, an int when it parses and holds no `_`, `True`/`False` for
//!   `true`/`false` in any case, else the text); then, because the
//!   `__builtins__` key sits in the locals mapping and `eval(s, {}, ...)`
//!   fills the empty globals with the real builtins, Python's builtins
//!   (`abs`, `round`, `len` ... work in Noetic).
//!   `env`, `optenv`, `find`, `anon` and `dirname` depend on the machine
//!   that launches: refused, naming the `--arg` to pass instead.
//!
//! ROS 2 (ros2/launch @ 06dc66b437f9908798a5da81dcec1b1646e94ee0
//! `launch/launch/substitutions/python_expression.py`): `$(eval ...)` is a
//! substitution like any other, anywhere in a value; the substitutions inside
//! it (`$(var x)`) are performed as text first, then the text is evaluated
//! with `math`'s names (and the module `math`) and the builtins; bare names
//! are not launch args.

use super::pyexpr::eval::{math_constant, BUILTINS, MATH};
use super::pyexpr::{expression, Eval, Expr, Func, Host, Value};
use crate::diagnostic::{Error, Location, Result};
use crate::sanitize::quote;

/// roslaunch's `convert_value(value, 'auto')`.
pub(crate) fn convert_auto(v: &str) -> Value {
    if v.contains('.') {
        if let Ok(f) = python_float(v) {
            return Value::Float(f);
        }
    } else if !v.contains('_') {
        if let Ok(i) = v.trim().parse::<i64>() {
            return Value::Int(i);
        }
    }
    match v.to_ascii_lowercase().as_str() {
        "true" => Value::Bool(true),
        "false" => Value::Bool(false),
        _ => Value::Str(v.to_string()),
    }
}

/// Python's `float(text)` for the texts launch args hold.
fn python_float(v: &str) -> std::result::Result<f64, ()> {
    let t = v.trim();
    if t.is_empty() || !t.chars().all(|c| c.is_ascii_digit() || "+-.eE".contains(c)) {
        return Err(());
    }
    t.parse().map_err(|_| ())
}

/// The names common to both dialects: `math` and the builtins.
fn common_name(n: &str) -> Option<Value> {
    if let Some(c) = math_constant(n) {
        return Some(Value::Float(c));
    }
    MATH.iter()
        .chain(BUILTINS)
        .find(|m| **m == n)
        .map(|m| Value::Func(Func::Builtin(m)))
}

/// The launch args as `$(eval ...)` reads them (`launch_subst::LaunchArgs`,
/// whose substitutions call this evaluator in turn).
pub(crate) trait ArgSource {
    /// Whether the file declares arg `name` or `--arg` gives it.
    fn declares(&self, name: &str) -> bool;
    /// The value of arg `name`, its own substitutions resolved (`depth`:
    /// the nesting so far, capped by the resolver).
    fn arg_value(&self, name: &str, loc: &Location, depth: usize) -> Result<String>;
}

struct Ros1<'a> {
    args: &'a dyn ArgSource,
    loc: &'a Location,
    depth: usize,
}

impl Ros1<'_> {
    fn arg(&self, name: &str) -> Value {
        match self.args.arg_value(name, self.loc, self.depth) {
            Ok(v) => convert_auto(&v),
            Err(e) => Value::unknown(e.message),
        }
    }
}

impl Host for Ros1<'_> {
    fn name(&mut self, n: &str) -> Option<Value> {
        match n {
            "true" | "True" => return Some(Value::Bool(true)),
            "false" | "False" => return Some(Value::Bool(false)),
            "arg" | "anon" | "dirname" | "env" | "optenv" | "find" => {
                return Some(Value::Func(Func::Host(n.into())))
            }
            _ => {}
        }
        if let Some(v) = math_constant(n).map(Value::Float) {
            return Some(v);
        }
        if let Some(m) = MATH.iter().find(|m| **m == n) {
            return Some(Value::Func(Func::Builtin(m)));
        }
        if self.args.declares(n) {
            return Some(self.arg(n));
        }
        common_name(n)
    }

    fn call(
        &mut self,
        f: &Func,
        args: Vec<Value>,
        _: Vec<(String, Value)>,
        at: &Expr,
    ) -> Result<Value> {
        match (f, args.as_slice()) {
            (Func::Host(h), [Value::Str(name)]) if h == "arg" => Ok(self.arg(name)),
            (Func::Host(h), _) if h == "arg" => super::pyexpr::ops::fail(at, "arg() takes one string, the arg's name"),
            (Func::Host(h), _) => super::pyexpr::ops::fail(at, format!("{h}() depends on the machine that launches (environment, packages): not evaluated; pass the value with --arg NAME=VALUE")),
            _ => super::pyexpr::ops::fail(at, "a call of a function the launch file does not define"),
        }
    }
}

struct Ros2;

impl Host for Ros2 {
    fn name(&mut self, n: &str) -> Option<Value> {
        if n == "math" {
            return Some(Value::Module("math"));
        }
        common_name(n)
    }
    fn call(
        &mut self,
        _: &Func,
        _: Vec<Value>,
        _: Vec<(String, Value)>,
        at: &Expr,
    ) -> Result<Value> {
        super::pyexpr::ops::fail(at, "a call of a function ROS 2's $(eval) does not define")
    }
}

/// Evaluate `text` over `host`: `str()` of the result, errors located at
/// `loc` and naming the expression.
fn run(text: &str, host: &mut dyn Host, loc: &Location) -> Result<String> {
    let located = |m: String| Error::parse(format!("$(eval {}): {m}", quote(text))).at(loc);
    if text.contains("__") {
        return Err(located(
            "may not contain double underscore expressions (roslaunch refuses them)".into(),
        ));
    }
    let e = expression(text, 1).map_err(|e| located(e.message))?;
    match Eval::new(host).eval(&e).map_err(|e| located(e.message))? {
        Value::Unknown(why) => Err(located(why.to_string())),
        v => Ok(v.to_str()),
    }
}

/// ROS 1: the text inside `$(eval ...)` (the whole attribute value).
pub(crate) fn eval_ros1(
    text: &str,
    args: &dyn ArgSource,
    loc: &Location,
    depth: usize,
) -> Result<String> {
    run(text, &mut Ros1 { args, loc, depth }, loc)
}

/// ROS 2: the text inside `$(eval ...)`, its substitutions already performed.
pub(crate) fn eval_ros2(text: &str, loc: &Location) -> Result<String> {
    run(text, &mut Ros2, loc)
}

/// The end (index of the closing `)`) of a `$(` opened at `open` (the index
/// of `$`), parentheses nested and quotes skipped.
pub(crate) fn closing(s: &str, open: usize) -> Option<usize> {
    let b = s.as_bytes();
    let (mut depth, mut quote) = (0usize, None::<u8>);
    for (i, &c) in b.iter().enumerate().skip(open + 1) {
        match (quote, c) {
            (Some(q), _) if c == q => quote = None,
            (Some(_), _) => {}
            (None, b'\'' | b'"') => quote = Some(c),
            (None, b'(') => depth += 1,
            (None, b')') if depth == 1 => return Some(i),
            (None, b')') => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Constructs the reader refuses by name although CPython evaluates them.
    const REFUSED: &[&str] = &["'%d' % 3"];

    #[test]
    fn expressions_match_cpython() {
        let tsv = include_str!("../../tests/fixtures/formats/launch_py/expressions.tsv");
        let loc = Location::file(std::path::Path::new("x.launch"));
        let mut n = 0;
        for line in tsv.lines().filter(|l| !l.starts_with('#')) {
            let (expr, want) = line.split_once('\t').expect("expression TAB value");
            let got = eval_ros2(expr, &loc);
            match (want, &got) {
                ("error", Err(_)) => {}
                (_, Err(e)) if REFUSED.contains(&expr) => {
                    assert!(e.message.contains("not evaluated"), "{expr}: {e}")
                }
                (w, Ok(g)) => assert_eq!(g, w, "{expr}"),
                (w, Err(e)) => panic!("{expr}: expected {w}, refused: {e}"),
            }
            n += 1;
        }
        assert!(n > 80, "{n} expressions");
    }

    #[test]
    fn convert_auto_is_roslaunch_convert_value() {
        assert!(matches!(convert_auto("0.3"), Value::Float(x) if x == 0.3));
        assert!(matches!(convert_auto("90"), Value::Int(90)));
        assert!(matches!(convert_auto("1_000"), Value::Str(_)));
        assert!(matches!(convert_auto("TRUE"), Value::Bool(true)));
        assert!(matches!(convert_auto("jackal"), Value::Str(_)));
    }
}
