//! The methods of `str`, `list` and `dict` the evaluator implements, with
//! CPython's semantics (`strip(chars)` strips a *set* of characters,
//! `split()` without a separator splits on runs of blanks, `format` fills
//! `{}`, `{0}` and `{name}` fields). Any other method is refused by name.

use super::builtins::position;
use super::caps::{items_fit, str_fits};
use super::ops::{fail, format_spec, iterate};
use super::parse::Expr;
use super::value::Value;
use crate::diagnostic::Result;

/// The `str` methods evaluated.
pub const STR_METHODS: &[&str] = &[
    "capitalize",
    "count",
    "endswith",
    "find",
    "format",
    "isalnum",
    "isalpha",
    "isdigit",
    "isspace",
    "join",
    "lower",
    "lstrip",
    "replace",
    "rfind",
    "rsplit",
    "rstrip",
    "split",
    "startswith",
    "strip",
    "title",
    "upper",
    "zfill",
];

fn text<'a>(v: &'a Value, what: &str, at: &Expr) -> Result<&'a str> {
    match v {
        Value::Str(s) => Ok(s),
        other => fail(
            at,
            format!(
                "{what}: expected a string, found a {} value",
                other.type_name()
            ),
        ),
    }
}

fn opt_text<'a>(args: &'a [Value], i: usize, what: &str, at: &Expr) -> Result<Option<&'a str>> {
    match args.get(i) {
        None | Some(Value::None) => Ok(None),
        Some(v) => text(v, what, at).map(Some),
    }
}

/// Call method `name` of `recv`.
pub fn call(
    recv: &Value,
    name: &str,
    args: &[Value],
    kw: &[(String, Value)],
    at: &Expr,
) -> Result<Value> {
    match recv {
        Value::Str(s) => str_method(s, name, args, kw, at),
        Value::List(l) => list_method(l, name, args, at),
        Value::Dict(d) => match (name, args) {
            ("get", [k]) | ("get", [k, _]) => Ok(d
                .iter()
                .find(|(x, _)| super::ops::equal(x, k))
                .map(|(_, v)| v.clone())
                .unwrap_or_else(|| args.get(1).cloned().unwrap_or(Value::None))),
            ("keys", []) => Ok(Value::list(d.iter().map(|(k, _)| k.clone()).collect())),
            ("values", []) => Ok(Value::list(d.iter().map(|(_, v)| v.clone()).collect())),
            ("items", []) => Ok(Value::list(
                d.iter()
                    .map(|(k, v)| Value::Tuple(vec![k.clone(), v.clone()]))
                    .collect(),
            )),
            _ => fail(at, format!("dict.{name}() is not evaluated")),
        },
        Value::Tuple(t) => match (name, args) {
            ("index", [v]) => position(t, v)
                .map(|i| Value::Int(i as i64))
                .map_or_else(|| fail(at, "tuple.index(x): x not in tuple"), Ok),
            ("count", [v]) => Ok(Value::Int(
                t.iter().filter(|x| super::ops::equal(x, v)).count() as i64,
            )),
            _ => fail(at, format!("tuple.{name}() is not evaluated")),
        },
        other => fail(
            at,
            format!(
                "method {name}() of a {} value is not evaluated",
                other.type_name()
            ),
        ),
    }
}

fn list_method(
    l: &std::rc::Rc<super::value::ListCell>,
    name: &str,
    args: &[Value],
    at: &Expr,
) -> Result<Value> {
    match (name, args) {
        ("append", [v]) => {
            items_fit(l.borrow().len() + 1, "list.append()", at)?;
            l.borrow_mut().push(v.clone());
            Ok(Value::None)
        }
        ("extend", [v]) => {
            let items = iterate(v, at)?;
            items_fit(l.borrow().len() + items.len(), "list.extend()", at)?;
            l.borrow_mut().extend(items);
            Ok(Value::None)
        }
        ("pop", []) => l
            .borrow_mut()
            .pop()
            .map_or_else(|| fail(at, "pop from empty list"), Ok),
        ("pop", [i]) => {
            let mut v = l.borrow_mut();
            let n = v.len() as i64;
            let k = i
                .as_int()
                .map(|k| if k < 0 { k + n } else { k })
                .filter(|k| (0..n).contains(k));
            match k {
                Some(k) => Ok(v.remove(k as usize)),
                None => fail(at, "pop index out of range"),
            }
        }
        ("index", [v]) => position(&l.borrow(), v)
            .map(|i| Value::Int(i as i64))
            .map_or_else(|| fail(at, "list.index(x): x not in list"), Ok),
        ("count", [v]) => Ok(Value::Int(
            l.borrow()
                .iter()
                .filter(|x| super::ops::equal(x, v))
                .count() as i64,
        )),
        _ => fail(at, format!("list.{name}() is not evaluated")),
    }
}

/// `strip`-family: the set of characters (blanks when `None`).
fn strip<'a>(s: &'a str, chars: Option<&str>, left: bool, right: bool) -> &'a str {
    let set = |c: char| chars.map_or(c.is_whitespace(), |cs| cs.contains(c));
    let s = if left { s.trim_start_matches(set) } else { s };
    if right {
        s.trim_end_matches(set)
    } else {
        s
    }
}

fn split(s: &str, sep: Option<&str>, max: i64, right: bool, at: &Expr) -> Result<Value> {
    let max = if max < 0 { usize::MAX } else { max as usize };
    let parts: Vec<String> = match sep {
        Some("") => return fail(at, "empty separator"),
        Some(sep) if right => {
            let mut v: Vec<String> = s
                .rsplitn(max.saturating_add(1), sep)
                .map(String::from)
                .collect();
            v.reverse();
            v
        }
        Some(sep) => s
            .splitn(max.saturating_add(1), sep)
            .map(String::from)
            .collect(),
        None => {
            // Runs of blanks; at most `max` splits, the rest kept (stripped
            // on the split side).
            let words: Vec<&str> = s.split_whitespace().collect();
            if words.len() <= max.saturating_add(1) {
                words.into_iter().map(String::from).collect()
            } else if right {
                let mut rest = s.trim_end();
                let mut tail = Vec::new();
                for _ in 0..max {
                    let cut = rest.rfind(char::is_whitespace).unwrap_or(0);
                    tail.push(rest[cut..].trim().to_string());
                    rest = rest[..cut].trim_end();
                }
                tail.push(rest.trim_start().to_string());
                tail.reverse();
                tail
            } else {
                let mut rest = s.trim_start();
                let mut head = Vec::new();
                for _ in 0..max {
                    let cut = rest.find(char::is_whitespace).unwrap_or(rest.len());
                    head.push(rest[..cut].to_string());
                    rest = rest[cut..].trim_start();
                }
                head.push(rest.to_string());
                head
            }
        }
    };
    items_fit(parts.len(), "str.split()", at)?;
    Ok(Value::list(parts.into_iter().map(Value::Str).collect()))
}

fn affix(s: &str, arg: &Value, start: bool, at: &Expr) -> Result<Value> {
    let test = |p: &str| {
        if start {
            s.starts_with(p)
        } else {
            s.ends_with(p)
        }
    };
    match arg {
        Value::Str(p) => Ok(Value::Bool(test(p))),
        Value::Tuple(ps) => {
            let mut hit = false;
            for p in ps {
                hit |= test(text(p, "startswith/endswith", at)?);
            }
            Ok(Value::Bool(hit))
        }
        other => fail(
            at,
            format!("startswith/endswith of a {} value", other.type_name()),
        ),
    }
}

fn str_method(
    s: &str,
    name: &str,
    args: &[Value],
    kw: &[(String, Value)],
    at: &Expr,
) -> Result<Value> {
    if !STR_METHODS.contains(&name) {
        return fail(
            at,
            format!(
                "str.{name}() is not evaluated (evaluated: {})",
                STR_METHODS.join(", ")
            ),
        );
    }
    if name == "format" {
        return format(s, args, kw, at);
    }
    if !kw.is_empty() && !matches!(name, "split" | "rsplit") {
        return fail(
            at,
            format!("str.{name}() with keyword arguments is not evaluated"),
        );
    }
    let int = |i: usize, def: i64| args.get(i).map_or(Some(def), Value::as_int);
    let str_out = |x: String| Ok(Value::Str(x));
    match name {
        "lower" => str_out(s.to_lowercase()),
        "upper" => str_out(s.to_uppercase()),
        "strip" | "lstrip" | "rstrip" => {
            let chars = opt_text(args, 0, name, at)?;
            str_out(strip(s, chars, name != "rstrip", name != "lstrip").to_string())
        }
        "split" | "rsplit" => {
            let sep = match kw.iter().find(|(k, _)| k == "sep").map(|(_, v)| v) {
                Some(Value::None) | None => opt_text(args, 0, name, at)?,
                Some(v) => Some(text(v, name, at)?),
            };
            let max = kw
                .iter()
                .find(|(k, _)| k == "maxsplit")
                .map(|(_, v)| v.as_int())
                .unwrap_or(int(1, -1))
                .unwrap_or(-1);
            split(s, sep, max, name == "rsplit", at)
        }
        "replace" => {
            let (old, new) = (
                text(&args[0], name, at)?,
                text(args.get(1).unwrap_or(&Value::None), name, at)?,
            );
            let count = int(2, -1).unwrap_or(-1);
            let limit = usize::try_from(count).unwrap_or(usize::MAX);
            let hits = if old.is_empty() {
                s.chars().count() + 1
            } else {
                s.matches(old).count()
            }
            .min(limit);
            str_fits(
                (s.len() - hits * old.len()).saturating_add(hits.saturating_mul(new.len())),
                "str.replace()",
                at,
            )?;
            if count < 0 {
                str_out(s.replace(old, new))
            } else {
                str_out(s.replacen(old, new, count as usize))
            }
        }
        "startswith" | "endswith" => affix(
            s,
            args.first().unwrap_or(&Value::None),
            name == "startswith",
            at,
        ),
        "join" => {
            let mut parts = Vec::new();
            for v in iterate(args.first().unwrap_or(&Value::None), at)? {
                parts.push(text(&v, "join: sequence item", at)?.to_string());
            }
            let bytes = parts.iter().map(String::len).sum::<usize>()
                + s.len().saturating_mul(parts.len().saturating_sub(1));
            str_fits(bytes, "str.join()", at)?;
            str_out(parts.join(s))
        }
        "find" | "rfind" => {
            let sub = text(args.first().unwrap_or(&Value::None), name, at)?;
            let hit = if name == "find" {
                s.find(sub)
            } else {
                s.rfind(sub)
            };
            Ok(Value::Int(
                hit.map_or(-1, |b| s[..b].chars().count() as i64),
            ))
        }
        "count" => Ok(Value::Int(
            s.matches(text(args.first().unwrap_or(&Value::None), name, at)?)
                .count() as i64,
        )),
        _ => str_case(s, name, args, at),
    }
}

/// The case, padding and class methods of `str`.
fn str_case(s: &str, name: &str, args: &[Value], at: &Expr) -> Result<Value> {
    let int = |i: usize, def: i64| args.get(i).map_or(Some(def), Value::as_int);
    let str_out = |x: String| Ok(Value::Str(x));
    match name {
        "capitalize" => {
            let mut c = s.chars();
            str_out(
                c.next()
                    .map(|f| {
                        f.to_uppercase()
                            .chain(c.flat_map(char::to_lowercase))
                            .collect()
                    })
                    .unwrap_or_default(),
            )
        }
        "title" => {
            let mut out = String::new();
            let mut prev = false;
            for c in s.chars() {
                if c.is_alphabetic() {
                    out.extend(if prev {
                        c.to_lowercase().collect::<Vec<_>>()
                    } else {
                        c.to_uppercase().collect()
                    });
                    prev = true;
                } else {
                    out.push(c);
                    prev = false;
                }
            }
            str_out(out)
        }
        "zfill" => {
            let w = int(0, 0).unwrap_or(0).max(0) as usize;
            str_fits(w.max(s.len()), "str.zfill()", at)?;
            let n = s.chars().count();
            let (sign, rest) = if s.starts_with(['+', '-']) {
                s.split_at(1)
            } else {
                ("", s)
            };
            str_out(format!("{sign}{}{rest}", "0".repeat(w.saturating_sub(n))))
        }
        _ => {
            let all = |f: fn(char) -> bool| Ok(Value::Bool(!s.is_empty() && s.chars().all(f)));
            match name {
                "isdigit" => all(|c| c.is_ascii_digit()),
                "isalpha" => all(char::is_alphabetic),
                "isalnum" => all(char::is_alphanumeric),
                _ => all(char::is_whitespace),
            }
        }
    }
}

/// `str.format`: `{}`, `{0}`, `{name}`, each with an optional `:spec`.
fn format(s: &str, args: &[Value], kw: &[(String, Value)], at: &Expr) -> Result<Value> {
    let mut out = String::new();
    let mut auto = 0usize;
    let mut it = s.chars().peekable();
    while let Some(c) = it.next() {
        match c {
            '{' if it.peek() == Some(&'{') => {
                it.next();
                out.push('{');
            }
            '}' if it.peek() == Some(&'}') => {
                it.next();
                out.push('}');
            }
            '{' => {
                let mut field = String::new();
                for d in it.by_ref() {
                    if d == '}' {
                        break;
                    }
                    field.push(d);
                }
                let (key, spec) = field.split_once(':').unwrap_or((&field, ""));
                let v = if key.is_empty() {
                    auto += 1;
                    args.get(auto - 1)
                } else if let Ok(i) = key.parse::<usize>() {
                    args.get(i)
                } else {
                    kw.iter().find(|(k, _)| k == key).map(|(_, v)| v)
                };
                let v = v.ok_or_else(|| {
                    crate::diagnostic::Error::parse(format!(
                        "str.format: no value for field {{{key}}}"
                    ))
                    .at_line(at.line, Some(at.col))
                })?;
                out.push_str(&format_spec(v, spec, at)?);
                str_fits(out.len(), "str.format()", at)?;
            }
            c => out.push(c),
        }
    }
    Ok(Value::Str(out))
}
