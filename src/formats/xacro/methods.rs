//! Methods of `${...}` values, with CPython 3's semantics: every `str`
//! method (a closed list, [`STR_METHODS`]: each implemented or refused by
//! name), the `list`, `tuple`, `dict` and `range` methods, `int.bit_length`
//! and `float.is_integer`; and attribute access on a dict (`d.key`, as
//! Python xacro's `load_yaml` dicts allow; a method name wins, as in Python).
//!
//! Text: indices count code points; whitespace is Python's (`str.isspace`:
//! Unicode White_Space plus U+001C..U+001F); `upper`/`lower` use Unicode's
//! full case mappings as Python does. The methods whose Unicode rules are
//! not reproduced here (`title`, `capitalize`, `swapcase`, `casefold` and
//! the `is...` predicates but `isspace`/`isascii`) are exact on ASCII text
//! and refused on other text. `keys()`, `values()`, `items()` give lists
//! (Python gives views, printed `dict_keys([...])`).
//!
//! Lists and dicts are mutated in place (`pop`, `append`, `update`, ...),
//! shared as Python shares them; a mutation that would put a container
//! inside itself is refused, so values stay acyclic (see `value`).

use super::format::str_format;
use super::kwargs::only_kw;
use super::limits::Meter;
use super::subscript::{dict_get, dict_insert, seq_index, slice_indices};
use super::value::{range_len, too_deep, Builtin, Res, Value};
use crate::tolerances::XACRO_MAX_VALUE_DEPTH;
use std::rc::Rc;

/// Every method of Python 3's `str`.
pub(super) const STR_METHODS: &[&str] = &[
    "capitalize",
    "casefold",
    "center",
    "count",
    "encode",
    "endswith",
    "expandtabs",
    "find",
    "format",
    "format_map",
    "index",
    "isalnum",
    "isalpha",
    "isascii",
    "isdecimal",
    "isdigit",
    "isidentifier",
    "islower",
    "isnumeric",
    "isprintable",
    "isspace",
    "istitle",
    "isupper",
    "join",
    "ljust",
    "lower",
    "lstrip",
    "maketrans",
    "partition",
    "removeprefix",
    "removesuffix",
    "replace",
    "rfind",
    "rindex",
    "rjust",
    "rpartition",
    "rsplit",
    "rstrip",
    "split",
    "splitlines",
    "startswith",
    "strip",
    "swapcase",
    "title",
    "translate",
    "upper",
    "zfill",
];
const LIST_METHODS: &[&str] = &[
    "append", "clear", "copy", "count", "extend", "index", "insert", "pop", "remove", "reverse",
    "sort",
];
const TUPLE_METHODS: &[&str] = &["count", "index"];
const DICT_METHODS: &[&str] = &[
    "clear",
    "copy",
    "fromkeys",
    "get",
    "items",
    "keys",
    "pop",
    "popitem",
    "setdefault",
    "update",
    "values",
];
const RANGE_METHODS: &[&str] = &["count", "index"];

fn find_name(list: &[&'static str], n: &str) -> Option<&'static str> {
    list.iter().copied().find(|x| *x == n)
}

/// `v.name`: a bound method, a dict's key, a range's `start`/`stop`/`step`.
pub(super) fn attr(v: &Value, name: &str, m: &mut Meter) -> Res<Value> {
    let methods: &[&'static str] = match v {
        Value::Str(_) => STR_METHODS,
        Value::List(_) => LIST_METHODS,
        Value::Tuple(_) => TUPLE_METHODS,
        Value::Dict(_) => DICT_METHODS,
        Value::Range(_) => RANGE_METHODS,
        Value::Int(_) | Value::Bool(_) => &["bit_length"],
        Value::Float(_) => &["is_integer"],
        _ => &[],
    };
    if let Some(n) = find_name(methods, name) {
        return Ok(Value::Method(Rc::new((v.clone(), n))));
    }
    if let Value::Builtin(Builtin::Func(t)) = v {
        // `str.upper`: the method unbound, its object the first argument.
        let of_type: &[&'static str] = match *t {
            "str" => STR_METHODS,
            "list" => LIST_METHODS,
            "tuple" => TUPLE_METHODS,
            "dict" => DICT_METHODS,
            _ => &[],
        };
        if let Some(n) =
            find_name(of_type, name).filter(|n| !matches!(*n, "fromkeys" | "maketrans"))
        {
            return Ok(Value::Method(Rc::new((v.clone(), n))));
        }
    }
    match (v, name) {
        (Value::Int(i), "real" | "numerator") => Ok(Value::Int(*i)),
        (Value::Bool(b), "real" | "numerator") => Ok(Value::Int(i64::from(*b))),
        (Value::Int(_) | Value::Bool(_), "imag") => Ok(Value::Int(0)),
        (Value::Int(_) | Value::Bool(_), "denominator") => Ok(Value::Int(1)),
        (Value::Float(f), "real") => Ok(Value::Float(*f)),
        (Value::Float(_), "imag") => Ok(Value::Float(0.0)),
        (Value::Dict(d), _) => dict_get(d, &Value::str(name), m)?
            .ok_or_else(|| format!("The yaml dictionary has no key '{name}'")),
        (Value::Range(r), "start") => Ok(Value::Int(r[0])),
        (Value::Range(r), "stop") => Ok(Value::Int(r[1])),
        (Value::Range(r), "step") => Ok(Value::Int(r[2])),
        _ => Err(format!(
            "'{}' object has no attribute '{name}' (or it is not supported)",
            v.type_name()
        )),
    }
}

/// `len(v)`.
pub(super) fn len(v: &Value) -> Res<i64> {
    Ok(match v {
        Value::Str(s) => s.chars().count() as i64,
        Value::List(l) => l.items().len() as i64,
        Value::Tuple(t) => t.items().len() as i64,
        Value::Dict(d) => d.items().len() as i64,
        Value::Range(r) => range_len(r),
        other => {
            return Err(format!(
                "object of type '{}' has no len()",
                other.type_name()
            ))
        }
    })
}

/// Call method `name` of `obj`.
pub(super) fn call(
    obj: &Value,
    name: &str,
    a: &[Value],
    kw: &[(String, Value)],
    m: &mut Meter,
) -> Res<Value> {
    m.step()?;
    match obj {
        Value::Builtin(Builtin::Func(t)) => {
            let Some((me, rest)) = a.split_first() else {
                return Err(format!("unbound method {t}.{name}() needs an argument"));
            };
            if me.type_name() != *t {
                return Err(format!(
                    "descriptor '{name}' for '{t}' objects doesn't apply to a '{}' object",
                    me.type_name()
                ));
            }
            call(me, name, rest, kw, m)
        }
        Value::Str(s) => str_method(s, name, a, kw, m),
        Value::List(_) => list_method(obj, name, a, kw, m),
        Value::Dict(_) => dict_method(obj, name, a, kw, m),
        Value::Tuple(t) => seq_method(t.items(), name, a, kw, m),
        Value::Range(_) => seq_method(&obj.iter_items(m)?, name, a, kw, m),
        Value::Int(_) | Value::Bool(_) => {
            no_args(name, a, kw)?;
            let i = obj.as_int().unwrap_or(0);
            Ok(Value::Int(i64::from(64 - i.unsigned_abs().leading_zeros())))
        }
        Value::Float(f) => {
            no_args(name, a, kw)?;
            Ok(Value::Bool(f.is_finite() && f.fract() == 0.0))
        }
        other => Err(format!(
            "'{}' object has no method {name}",
            other.type_name()
        )),
    }
}

fn no_args(name: &str, a: &[Value], kw: &[(String, Value)]) -> Res<()> {
    if a.is_empty() && kw.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{name}() takes no arguments ({} given)",
            a.len() + kw.len()
        ))
    }
}

/// Positional arguments `min..=max`, keywords refused.
fn arity<'a>(
    name: &str,
    a: &'a [Value],
    kw: &[(String, Value)],
    min: usize,
    max: usize,
) -> Res<&'a [Value]> {
    if let Some((k, _)) = kw.first() {
        return Err(format!("{name}() takes no keyword arguments (got '{k}')"));
    }
    if a.len() < min || a.len() > max {
        return Err(format!(
            "{name}() takes {} argument(s) ({} given)",
            if min == max {
                min.to_string()
            } else {
                format!("{min} to {max}")
            },
            a.len()
        ));
    }
    Ok(a)
}

fn str_arg<'a>(name: &str, v: &'a Value) -> Res<&'a str> {
    match v {
        Value::Str(s) => Ok(s),
        other => Err(format!(
            "{name}() argument must be str, not {}",
            other.type_name()
        )),
    }
}

fn int_arg(name: &str, v: &Value) -> Res<i64> {
    v.as_int().ok_or_else(|| {
        format!(
            "{name}(): '{}' object cannot be interpreted as an integer",
            v.type_name()
        )
    })
}

/// Python's `str.isspace` for one character.
pub(super) fn py_space(c: char) -> bool {
    c.is_whitespace() || ('\u{1c}'..='\u{1f}').contains(&c)
}

/// The byte range of characters `[a, b)` of `s` (Python's `start`/`end`
/// arguments: negative from the end, clamped), with the character index of
/// its start; `None` when `a` is past the end.
fn char_window(
    s: &str,
    a: Option<&Value>,
    b: Option<&Value>,
) -> Res<Option<(usize, usize, usize)>> {
    let n = s.chars().count() as i64;
    let get = |v: Option<&Value>| -> Res<Option<i64>> {
        match v {
            None | Some(Value::None) => Ok(None),
            Some(x) => x
                .as_int()
                .map(Some)
                .ok_or_else(|| "slice indices must be integers or None".into()),
        }
    };
    let (start, end, _) = slice_indices(n, get(a)?, get(b)?, None)?;
    if get(a)?.is_some_and(|x| x > n) {
        return Ok(None);
    }
    let byte = |k: i64| s.char_indices().nth(k as usize).map_or(s.len(), |(i, _)| i);
    let (lo, hi) = (byte(start), byte(end.max(start)));
    Ok(Some((lo, hi, start as usize)))
}

/// `find`/`rfind`/`index`/`rindex`/`count`/`startswith`/`endswith`.
fn search(s: &str, name: &str, a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<Value> {
    let a = arity(name, a, kw, 1, 3)?;
    m.scan(s.len())?;
    let window = char_window(s, a.get(1), a.get(2))?;
    if matches!(name, "startswith" | "endswith") {
        let subs: Vec<Value> = match &a[0] {
            Value::Tuple(t) => t.items().to_vec(),
            v => vec![v.clone()],
        };
        let Some((lo, hi, _)) = window else {
            return Ok(Value::Bool(false));
        };
        let part = &s[lo..hi];
        for sub in &subs {
            let sub = str_arg(name, sub)?;
            if (name == "startswith" && part.starts_with(sub))
                || (name == "endswith" && part.ends_with(sub))
            {
                return Ok(Value::Bool(true));
            }
        }
        return Ok(Value::Bool(false));
    }
    let sub = str_arg(name, &a[0])?;
    let Some((lo, hi, c0)) = window else {
        return match name {
            "count" => Ok(Value::Int(0)),
            "index" | "rindex" => Err("substring not found".into()),
            _ => Ok(Value::Int(-1)),
        };
    };
    let part = &s[lo..hi];
    if name == "count" {
        let n = if sub.is_empty() {
            part.chars().count() + 1
        } else {
            part.matches(sub).count()
        };
        return Ok(Value::Int(n as i64));
    }
    let at = if name.starts_with('r') {
        part.rfind(sub)
    } else {
        part.find(sub)
    };
    match at {
        Some(b) => Ok(Value::Int((c0 + part[..b].chars().count()) as i64)),
        None if name.ends_with("index") => Err("substring not found".into()),
        None => Ok(Value::Int(-1)),
    }
}

/// `split`/`rsplit` (`sep=None`, `maxsplit=-1`).
fn split(
    s: &str,
    name: &str,
    a: &[Value],
    kw: &[(String, Value)],
    m: &mut Meter,
) -> Res<Vec<String>> {
    only_kw(name, kw, &["sep", "maxsplit"])?;
    if a.len() > 2 {
        return Err(format!(
            "{name}() takes at most 2 arguments ({} given)",
            a.len()
        ));
    }
    let get = |i: usize, k: &str| {
        a.get(i)
            .or_else(|| kw.iter().find(|(n, _)| n == k).map(|(_, v)| v))
    };
    let sep = match get(0, "sep") {
        None | Some(Value::None) => None,
        Some(v) => Some(str_arg(name, v)?),
    };
    let max = match get(1, "maxsplit") {
        None => -1,
        Some(v) => int_arg(name, v)?,
    };
    let max = if max < 0 { usize::MAX } else { max as usize };
    m.scan(s.len())?;
    let right = name == "rsplit";
    let out: Vec<String> = match sep {
        Some("") => return Err("empty separator".into()),
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
        None => split_whitespace(s, max, right),
    };
    m.list(out.len())?;
    m.string(s.len())?;
    Ok(out)
}

/// `str.split()` without a separator: runs of whitespace, at most `max`
/// splits (from the right for `rsplit`), the rest keeping its inner spaces.
fn split_whitespace(s: &str, max: usize, right: bool) -> Vec<String> {
    let chars: Vec<char> = if right {
        s.chars().rev().collect()
    } else {
        s.chars().collect()
    };
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        while i < chars.len() && py_space(chars[i]) {
            i += 1;
        }
        if i == chars.len() {
            break;
        }
        if out.len() == max {
            // The rest whole, its trailing whitespace kept (CPython).
            out.push(chars[i..].iter().collect());
            break;
        }
        let start = i;
        while i < chars.len() && !py_space(chars[i]) {
            i += 1;
        }
        out.push(chars[start..i].iter().collect());
    }
    if right {
        out.reverse();
        for w in &mut out {
            *w = w.chars().rev().collect();
        }
    }
    out
}

/// `strip`/`lstrip`/`rstrip` (`chars=None`: whitespace; else a set of
/// characters, not a suffix: `'rail_link'.rstrip('_link')` is `'ra'`).
fn strip<'a>(s: &'a str, name: &str, a: &[Value], kw: &[(String, Value)]) -> Res<&'a str> {
    let a = arity(name, a, kw, 0, 1)?;
    let set: Option<Vec<char>> = match a.first() {
        None | Some(Value::None) => None,
        Some(v) => Some(str_arg(name, v)?.chars().collect()),
    };
    let hit = |c: char| match &set {
        None => py_space(c),
        Some(cs) => cs.contains(&c),
    };
    Ok(match name {
        "lstrip" => s.trim_start_matches(hit),
        "rstrip" => s.trim_end_matches(hit),
        _ => s.trim_matches(hit),
    })
}

fn pad(s: &str, name: &str, a: &[Value], m: &mut Meter) -> Res<String> {
    let a = arity(name, a, &[], 1, 2)?;
    let width = int_arg(name, &a[0])?.max(0) as usize;
    let fill = match a.get(1) {
        None => ' ',
        Some(v) => {
            let f = str_arg(name, v)?;
            let mut cs = f.chars();
            match (cs.next(), cs.next()) {
                (Some(c), None) => c,
                _ => return Err("The fill character must be exactly one character long".into()),
            }
        }
    };
    let n = s.chars().count();
    if width <= n {
        return Ok(s.to_string());
    }
    m.string(width * fill.len_utf8().max(1))?;
    let marg = width - n;
    let left = match name {
        "ljust" => 0,
        "rjust" => marg,
        _ => marg / 2 + (marg & width & 1),
    };
    let f = |k: usize| fill.to_string().repeat(k);
    Ok(format!("{}{s}{}", f(left), f(marg - left)))
}

fn zfill(s: &str, a: &[Value], m: &mut Meter) -> Res<String> {
    let a = arity("zfill", a, &[], 1, 1)?;
    let width = int_arg("zfill", &a[0])?.max(0) as usize;
    let n = s.chars().count();
    if width <= n {
        return Ok(s.to_string());
    }
    m.string(width)?;
    let zeros = "0".repeat(width - n);
    Ok(match s.strip_prefix(['+', '-']) {
        Some(rest) => format!("{}{zeros}{rest}", &s[..1]),
        None => format!("{zeros}{s}"),
    })
}

fn replace(s: &str, a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<String> {
    let a = arity("replace", a, kw, 2, 3)?;
    let (old, new) = (str_arg("replace", &a[0])?, str_arg("replace", &a[1])?);
    let count = match a.get(2) {
        None => -1,
        Some(v) => int_arg("replace", v)?,
    };
    let max = if count < 0 {
        usize::MAX
    } else {
        count as usize
    };
    m.scan(s.len())?;
    let hits = if old.is_empty() {
        s.chars().count() + 1
    } else {
        s.matches(old).count()
    };
    let k = hits.min(max);
    m.string((s.len() + k * new.len()).saturating_sub(k * old.len()))?;
    if old.is_empty() {
        let mut out = String::new();
        let mut done = 0;
        for c in s.chars() {
            if done < k {
                out.push_str(new);
                done += 1;
            }
            out.push(c);
        }
        if done < k {
            out.push_str(new);
        }
        return Ok(out);
    }
    Ok(s.replacen(old, new, k))
}

/// `splitlines(keepends=False)`: Python's line boundaries.
fn splitlines(s: &str, a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<Vec<String>> {
    only_kw("splitlines", kw, &["keepends"])?;
    let keep = a
        .first()
        .or_else(|| kw.first().map(|(_, v)| v))
        .is_some_and(Value::truthy);
    m.scan(s.len())?;
    let is_break = |c: char| {
        matches!(
            c,
            '\n' | '\r'
                | '\u{b}'
                | '\u{c}'
                | '\u{1c}'
                | '\u{1d}'
                | '\u{1e}'
                | '\u{85}'
                | '\u{2028}'
                | '\u{2029}'
        )
    };
    let mut out = Vec::new();
    let mut line = String::new();
    let mut it = s.chars().peekable();
    while let Some(c) = it.next() {
        if !is_break(c) {
            line.push(c);
            continue;
        }
        let mut end = c.to_string();
        if c == '\r' && it.peek() == Some(&'\n') {
            it.next();
            end.push('\n');
        }
        if keep {
            line.push_str(&end);
        }
        out.push(std::mem::take(&mut line));
    }
    if !line.is_empty() {
        out.push(line);
    }
    m.list(out.len())?;
    Ok(out)
}

fn expandtabs(s: &str, a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<String> {
    only_kw("expandtabs", kw, &["tabsize"])?;
    let size = match a.first().or_else(|| kw.first().map(|(_, v)| v)) {
        None => 8,
        Some(v) => int_arg("expandtabs", v)?.max(0) as usize,
    };
    let mut out = String::new();
    let mut col = 0;
    for c in s.chars() {
        match c {
            '\t' if size > 0 => {
                let n = size - col % size;
                m.string(out.len() + n)?;
                out.push_str(&" ".repeat(n));
                col += n;
            }
            '\t' => {}
            '\n' | '\r' => {
                out.push(c);
                col = 0;
            }
            c => {
                out.push(c);
                col += 1;
            }
        }
    }
    m.string(out.len())?;
    Ok(out)
}

/// The ASCII-only case and class methods (refused on other text).
fn ascii_method(s: &str, name: &str) -> Res<Value> {
    if !s.is_ascii() {
        return Err(format!(
            "str.{name}() on non-ASCII text is not supported (Python's Unicode rules for it are not reproduced)"
        ));
    }
    let b = s.as_bytes();
    let all = |f: fn(&u8) -> bool| !b.is_empty() && b.iter().all(f);
    let cased = b.iter().any(u8::is_ascii_alphabetic);
    let text = |t: String| Ok(Value::str(&t));
    match name {
        "isalnum" => Ok(Value::Bool(all(u8::is_ascii_alphanumeric))),
        "isalpha" => Ok(Value::Bool(all(u8::is_ascii_alphabetic))),
        "isdigit" | "isdecimal" | "isnumeric" => Ok(Value::Bool(all(u8::is_ascii_digit))),
        "isupper" => Ok(Value::Bool(cased && !b.iter().any(u8::is_ascii_lowercase))),
        "islower" => Ok(Value::Bool(cased && !b.iter().any(u8::is_ascii_uppercase))),
        "isprintable" => Ok(Value::Bool(b.iter().all(|c| (0x20..0x7f).contains(c)))),
        "isidentifier" => Ok(Value::Bool(
            !b.is_empty()
                && (b[0].is_ascii_alphabetic() || b[0] == b'_')
                && b.iter().all(|c| c.is_ascii_alphanumeric() || *c == b'_'),
        )),
        "casefold" => text(s.to_ascii_lowercase()),
        "swapcase" => text(
            s.chars()
                .map(|c| {
                    if c.is_ascii_uppercase() {
                        c.to_ascii_lowercase()
                    } else {
                        c.to_ascii_uppercase()
                    }
                })
                .collect(),
        ),
        "capitalize" => {
            let mut cs = s.chars();
            text(match cs.next() {
                Some(c) => format!(
                    "{}{}",
                    c.to_ascii_uppercase(),
                    cs.as_str().to_ascii_lowercase()
                ),
                None => String::new(),
            })
        }
        "title" => {
            let mut prev = false;
            text(
                s.chars()
                    .map(|c| {
                        let r = if !c.is_ascii_alphabetic() {
                            c
                        } else if prev {
                            c.to_ascii_lowercase()
                        } else {
                            c.to_ascii_uppercase()
                        };
                        prev = c.is_ascii_alphabetic();
                        r
                    })
                    .collect(),
            )
        }
        _ => {
            // istitle: an upper case letter only after an uncased one, a
            // lower case one only after a cased one; at least one cased.
            let mut prev = false;
            let mut ok = cased;
            for c in b {
                if c.is_ascii_uppercase() && prev || c.is_ascii_lowercase() && !prev {
                    ok = false;
                }
                prev = c.is_ascii_alphabetic();
            }
            Ok(Value::Bool(ok))
        }
    }
}

fn strs(v: Vec<String>) -> Value {
    Value::list(v.into_iter().map(|s| Value::str(&s)).collect())
}

/// `sep.join(iterable)`.
fn join(s: &str, a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<Value> {
    let name = "join";
    let a = arity(name, a, kw, 1, 1)?;
    let items = a[0].iter_items(m)?;
    let mut parts = Vec::with_capacity(items.len());
    for (i, x) in items.iter().enumerate() {
        match x {
            Value::Str(p) => parts.push(p.clone()),
            other => {
                return Err(format!(
                    "sequence item {i}: expected str instance, {} found",
                    other.type_name()
                ))
            }
        }
    }
    let total: usize = parts.iter().map(|p| p.len()).sum::<usize>() + s.len() * parts.len();
    m.string(total)?;
    Ok(Value::str(
        &parts.iter().map(|p| &**p).collect::<Vec<_>>().join(s),
    ))
}

/// `partition`/`rpartition`.
fn partition(s: &Rc<str>, name: &str, a: &[Value], kw: &[(String, Value)]) -> Res<Value> {
    let a = arity(name, a, kw, 1, 1)?;
    let sep = str_arg(name, &a[0])?;
    if sep.is_empty() {
        return Err("empty separator".into());
    }
    let at = if name == "partition" {
        s.find(sep)
    } else {
        s.rfind(sep)
    };
    let parts = match (at, name) {
        (Some(i), _) => [&s[..i], sep, &s[i + sep.len()..]],
        (None, "partition") => [&**s, "", ""],
        (None, _) => ["", "", &**s],
    };
    Ok(Value::tuple(parts.iter().map(|p| Value::str(p)).collect()))
}

fn str_method(
    s: &Rc<str>,
    name: &str,
    a: &[Value],
    kw: &[(String, Value)],
    m: &mut Meter,
) -> Res<Value> {
    let text = |t: String, m: &mut Meter| -> Res<Value> {
        m.string(t.len())?;
        Ok(Value::str(&t))
    };
    match name {
        "split" | "rsplit" => split(s, name, a, kw, m).map(strs),
        "splitlines" => splitlines(s, a, kw, m).map(strs),
        "strip" | "lstrip" | "rstrip" => strip(s, name, a, kw).map(Value::str),
        "find" | "rfind" | "index" | "rindex" | "count" | "startswith" | "endswith" => {
            search(s, name, a, kw, m)
        }
        "replace" => replace(s, a, kw, m).map(|t| Value::str(&t)),
        "upper" | "lower" => {
            arity(name, a, kw, 0, 0)?;
            m.scan(s.len())?;
            text(
                if name == "upper" {
                    s.to_uppercase()
                } else {
                    s.to_lowercase()
                },
                m,
            )
        }
        "join" => join(s, a, kw, m),
        "format" => str_format(s, a, kw, m).map(|t| Value::str(&t)),
        "format_map" => {
            let a = arity(name, a, kw, 1, 1)?;
            let Value::Dict(d) = &a[0] else {
                return Err("format_map() argument must be a dict".into());
            };
            let kw2: Vec<(String, Value)> = d
                .items()
                .iter()
                .filter_map(|(k, v)| match k {
                    Value::Str(k) => Some((k.to_string(), v.clone())),
                    _ => None,
                })
                .collect();
            str_format(s, &[], &kw2, m).map(|t| Value::str(&t))
        }
        "partition" | "rpartition" => partition(s, name, a, kw),
        "removeprefix" | "removesuffix" => {
            let a = arity(name, a, kw, 1, 1)?;
            let x = str_arg(name, &a[0])?;
            let r = if name == "removeprefix" {
                s.strip_prefix(x)
            } else {
                s.strip_suffix(x)
            };
            Ok(Value::str(r.unwrap_or(s)))
        }
        "ljust" | "rjust" | "center" => {
            arity(name, a, kw, 1, 2)?;
            pad(s, name, a, m).map(|t| Value::str(&t))
        }
        "zfill" => {
            arity(name, a, kw, 1, 1)?;
            zfill(s, a, m).map(|t| Value::str(&t))
        }
        "expandtabs" => expandtabs(s, a, kw, m).map(|t| Value::str(&t)),
        "isspace" => {
            arity(name, a, kw, 0, 0)?;
            Ok(Value::Bool(!s.is_empty() && s.chars().all(py_space)))
        }
        "isascii" => {
            arity(name, a, kw, 0, 0)?;
            Ok(Value::Bool(s.is_ascii()))
        }
        "encode" => Err("str.encode(): bytes are not supported".into()),
        "translate" => {
            let a = arity(name, a, kw, 1, 1)?;
            translate(s, &a[0], m).map(|t| Value::str(&t))
        }
        "maketrans" => Err("str.maketrans() is not supported; write the table as a dict".into()),
        _ => {
            arity(name, a, kw, 0, 0)?;
            m.scan(s.len())?;
            ascii_method(s, name)
        }
    }
}

/// `str.translate(table)`: each character whose code point is a key of the
/// dict replaced by its value (a string, a code point, or `None`: dropped).
fn translate(s: &str, table: &Value, m: &mut Meter) -> Res<String> {
    let Value::Dict(d) = table else {
        return Err("translate(): the table must be a dict".into());
    };
    m.scan(s.len())?;
    let mut out = String::new();
    for c in s.chars() {
        match dict_get(d, &Value::Int(i64::from(u32::from(c))), m)? {
            None => out.push(c),
            Some(Value::None) => {}
            Some(Value::Str(t)) => out.push_str(&t),
            Some(v) => {
                let k = v
                    .as_int()
                    .and_then(|k| u32::try_from(k).ok())
                    .and_then(char::from_u32);
                out.push(k.ok_or("character mapping must be in range(0x110000)")?);
            }
        }
        m.string(out.len())?;
    }
    Ok(out)
}

/// Whether `v` holds the container at `target` (a mutation that put it
/// there would make a cycle); `depth`: the level of `v`, refused past the
/// value-depth cap.
fn reaches(v: &Value, target: *const (), m: &mut Meter, depth: usize) -> Res<bool> {
    m.step()?;
    if depth > XACRO_MAX_VALUE_DEPTH {
        return Err(too_deep());
    }
    let inside = |items: &[Value], m: &mut Meter| -> Res<bool> {
        for x in items {
            if reaches(x, target, m, depth + 1)? {
                return Ok(true);
            }
        }
        Ok(false)
    };
    match v {
        Value::List(l) => Ok(Rc::as_ptr(l).cast() == target || inside(&l.items(), m)?),
        Value::Dict(d) => {
            if Rc::as_ptr(d).cast() == target {
                return Ok(true);
            }
            let items: Vec<Value> = d
                .items()
                .iter()
                .flat_map(|(k, v)| [k.clone(), v.clone()])
                .collect();
            inside(&items, m)
        }
        Value::Tuple(t) => inside(t.items(), m),
        Value::Method(b) => reaches(&b.0, target, m, depth + 1),
        _ => Ok(false),
    }
}

/// Refuse putting `added` into `container` where it would make a cycle or a
/// value nested deeper than `XACRO_MAX_VALUE_DEPTH`: each item is walked at
/// level 1, the level it takes inside the container, so the depth is capped
/// where a list is made, not only where it is next printed.
fn no_cycle(container: *const (), added: &[Value], m: &mut Meter) -> Res<()> {
    for x in added {
        if reaches(x, container, m, 1)? {
            return Err("a list or dict that would contain itself is not supported".into());
        }
    }
    Ok(())
}

/// `count`/`index` of a list, tuple or range's items.
fn seq_method(
    items: &[Value],
    name: &str,
    a: &[Value],
    kw: &[(String, Value)],
    m: &mut Meter,
) -> Res<Value> {
    match name {
        "count" => {
            let a = arity(name, a, kw, 1, 1)?;
            let mut n = 0;
            for x in items {
                if x.py_eq(&a[0], m)? {
                    n += 1;
                }
            }
            Ok(Value::Int(n))
        }
        _ => {
            let a = arity(name, a, kw, 1, 3)?;
            let len = items.len() as i64;
            let b = |i: usize| a.get(i).map(|v| int_arg(name, v)).transpose();
            let (lo, hi, _) = slice_indices(len, b(1)?, b(2)?, None)?;
            for k in lo..hi.max(lo) {
                if items[k as usize].py_eq(&a[0], m)? {
                    return Ok(Value::Int(k));
                }
            }
            Err(format!("{} is not in list", a[0].show()))
        }
    }
}

fn list_method(
    obj: &Value,
    name: &str,
    a: &[Value],
    kw: &[(String, Value)],
    m: &mut Meter,
) -> Res<Value> {
    let Value::List(l) = obj else {
        return Err("not a list".into());
    };
    let me = Rc::as_ptr(l).cast::<()>();
    match name {
        "append" | "insert" => {
            let a = arity(
                name,
                a,
                kw,
                if name == "append" { 1 } else { 2 },
                if name == "append" { 1 } else { 2 },
            )?;
            let x = a.last().cloned().unwrap_or(Value::None);
            no_cycle(me, std::slice::from_ref(&x), m)?;
            let n = l.items().len();
            m.list(n + 1)?;
            let at = if name == "append" {
                n
            } else {
                let i = int_arg(name, &a[0])?;
                let i = if i < 0 {
                    (i + n as i64).max(0)
                } else {
                    i.min(n as i64)
                };
                i as usize
            };
            l.items_mut().insert(at, x);
            Ok(Value::None)
        }
        "extend" => {
            let a = arity(name, a, kw, 1, 1)?;
            let add = a[0].iter_items(m)?;
            no_cycle(me, &add, m)?;
            m.list(l.items().len() + add.len())?;
            l.items_mut().extend(add);
            Ok(Value::None)
        }
        "pop" => {
            let a = arity(name, a, kw, 0, 1)?;
            let n = l.items().len();
            if n == 0 {
                return Err("pop from empty list".into());
            }
            let i = match a.first() {
                None => n - 1,
                Some(v) => seq_index(v, n).map_err(|_| "pop index out of range".to_string())?,
            };
            Ok(l.items_mut().remove(i))
        }
        "remove" => {
            let a = arity(name, a, kw, 1, 1)?;
            let items = l.items().clone();
            for (i, x) in items.iter().enumerate() {
                if x.py_eq(&a[0], m)? {
                    l.items_mut().remove(i);
                    return Ok(Value::None);
                }
            }
            Err("list.remove(x): x not in list".into())
        }
        "clear" | "reverse" => {
            arity(name, a, kw, 0, 0)?;
            if name == "clear" {
                l.items_mut().clear();
            } else {
                l.items_mut().reverse();
            }
            Ok(Value::None)
        }
        "copy" => {
            arity(name, a, kw, 0, 0)?;
            let v = l.items().clone();
            m.list(v.len())?;
            Ok(Value::list(v))
        }
        _ => {
            let items = l.items().clone();
            seq_method(&items, name, a, kw, m)
        }
    }
}

fn dict_method(
    obj: &Value,
    name: &str,
    a: &[Value],
    kw: &[(String, Value)],
    m: &mut Meter,
) -> Res<Value> {
    let Value::Dict(d) = obj else {
        return Err("not a dict".into());
    };
    let me = Rc::as_ptr(d).cast::<()>();
    let snapshot = || d.items().clone();
    match name {
        "keys" | "values" | "items" => {
            arity(name, a, kw, 0, 0)?;
            let items = snapshot();
            m.list(items.len())?;
            Ok(Value::list(
                items
                    .into_iter()
                    .map(|(k, v)| match name {
                        "keys" => k,
                        "values" => v,
                        _ => Value::tuple(vec![k, v]),
                    })
                    .collect(),
            ))
        }
        "get" => {
            let a = arity(name, a, kw, 1, 2)?;
            Ok(dict_get(d, &a[0], m)?.unwrap_or_else(|| a.get(1).cloned().unwrap_or(Value::None)))
        }
        "pop" => {
            let a = arity(name, a, kw, 1, 2)?;
            let mut items = snapshot();
            for i in 0..items.len() {
                if items[i].0.py_eq(&a[0], m)? {
                    let (_, v) = items.remove(i);
                    *d.items_mut() = items;
                    return Ok(v);
                }
            }
            a.get(1)
                .cloned()
                .ok_or_else(|| format!("KeyError: {}", a[0].show()))
        }
        "popitem" => {
            arity(name, a, kw, 0, 0)?;
            let last = d.items_mut().pop();
            last.map(|(k, v)| Value::tuple(vec![k, v]))
                .ok_or_else(|| "popitem(): dictionary is empty".into())
        }
        "setdefault" => {
            let a = arity(name, a, kw, 1, 2)?;
            if let Some(v) = dict_get(d, &a[0], m)? {
                return Ok(v);
            }
            let v = a.get(1).cloned().unwrap_or(Value::None);
            no_cycle(me, &[a[0].clone(), v.clone()], m)?;
            let mut items = snapshot();
            dict_insert(&mut items, a[0].clone(), v.clone(), m)?;
            m.list(items.len())?;
            *d.items_mut() = items;
            Ok(v)
        }
        "update" => {
            if a.len() > 1 {
                return Err(format!(
                    "update expected at most 1 argument, got {}",
                    a.len()
                ));
            }
            let mut items = snapshot();
            let mut added: Vec<(Value, Value)> = Vec::new();
            if let Some(src) = a.first() {
                match src {
                    Value::Dict(o) => added.extend(o.items().iter().cloned()),
                    other => {
                        for p in other.iter_items(m)? {
                            let kv = p.iter_items(m)?;
                            let [k, v] = <[Value; 2]>::try_from(kv).map_err(|_| {
                                "dictionary update sequence element has the wrong length"
                                    .to_string()
                            })?;
                            added.push((k, v));
                        }
                    }
                }
            }
            added.extend(kw.iter().map(|(k, v)| (Value::str(k), v.clone())));
            let flat: Vec<Value> = added
                .iter()
                .flat_map(|(k, v)| [k.clone(), v.clone()])
                .collect();
            no_cycle(me, &flat, m)?;
            for (k, v) in added {
                dict_insert(&mut items, k, v, m)?;
            }
            m.list(items.len())?;
            *d.items_mut() = items;
            Ok(Value::None)
        }
        "clear" => {
            arity(name, a, kw, 0, 0)?;
            d.items_mut().clear();
            Ok(Value::None)
        }
        "copy" => {
            arity(name, a, kw, 0, 0)?;
            let items = snapshot();
            m.list(items.len())?;
            Ok(Value::dict(items))
        }
        _ => Err("dict.fromkeys() is not supported; build the dict with dict(...)".into()),
    }
}

/// `xacro.tokenize(s, sep=',; ', skip_empty=True)`: split at any of the
/// characters of `sep` (a regular-expression class in Python xacro; the
/// characters special inside one are refused).
pub(super) fn tokenize(s: &str, a: &[Value], kw: &[(String, Value)], m: &mut Meter) -> Res<Value> {
    only_kw("tokenize", kw, &["sep", "skip_empty"])?;
    let get = |i: usize, k: &str| {
        a.get(i)
            .or_else(|| kw.iter().find(|(n, _)| n == k).map(|(_, v)| v))
    };
    let sep = match get(0, "sep") {
        None => ",; ".to_string(),
        Some(v) => str_arg("tokenize", v)?.to_string(),
    };
    let inner_dash = sep.len() > 2 && sep[1..sep.len() - 1].contains('-');
    if sep.contains(['\\', ']', '[']) || sep.starts_with('^') || inner_dash || sep.is_empty() {
        return Err(format!("xacro.tokenize: separator characters {sep:?} with regular-expression meaning are not supported"));
    }
    let skip = get(1, "skip_empty").is_none_or(Value::truthy);
    m.scan(s.len())?;
    let parts: Vec<String> = s
        .split(|c| sep.contains(c))
        .filter(|p| !skip || !p.is_empty())
        .map(String::from)
        .collect();
    m.list(parts.len())?;
    Ok(strs(parts))
}
