//! Python's text formatting for `${...}`: `format(value, spec)` and the
//! format-spec mini-language (`[[fill]align][sign][#][0][width][,|_][.precision][type]`),
//! `str.format` (`{}`, `{0}`, `{name}`, `{0[1]}`, `!r`/`!s`, nested `{:{w}}`),
//! and printf-style `str % args` (`%s %r %d %i %f %e %g %x %o %c %%`, flags,
//! width, precision, `%(key)s`). Floats follow CPython's
//! `PyOS_double_to_string` (`f` is correctly rounded here as there; `g`
//! switches to an exponent as CPython does, `repr` for an omitted type).
//! Widths and precisions count against the string cap before text is made.

use super::limits::Meter;
use super::subscript::index;
use super::value::{float_repr, Res, Value};

/// One parsed format spec.
#[derive(Debug, Default)]
struct Spec {
    fill: Option<char>,
    align: Option<char>,
    sign: char,
    alt: bool,
    zero: bool,
    width: usize,
    group: Option<char>,
    precision: Option<usize>,
    ty: Option<char>,
}

fn parse_spec(s: &str) -> Res<Spec> {
    let c: Vec<char> = s.chars().collect();
    let mut sp = Spec {
        sign: '-',
        ..Spec::default()
    };
    let mut i = 0;
    let is_align = |ch: char| matches!(ch, '<' | '>' | '^' | '=');
    if c.len() >= 2 && is_align(c[1]) {
        sp.fill = Some(c[0]);
        sp.align = Some(c[1]);
        i = 2;
    } else if !c.is_empty() && is_align(c[0]) {
        sp.align = Some(c[0]);
        i = 1;
    }
    if let Some(&s) = c.get(i).filter(|s| matches!(s, '+' | '-' | ' ')) {
        sp.sign = s;
        i += 1;
    }
    if c.get(i) == Some(&'z') {
        return Err("the 'z' format option is not supported".into());
    }
    if c.get(i) == Some(&'#') {
        sp.alt = true;
        i += 1;
    }
    if c.get(i) == Some(&'0') {
        sp.zero = true;
        i += 1;
    }
    let digits = |i: &mut usize| -> Res<Option<usize>> {
        let start = *i;
        while c.get(*i).is_some_and(char::is_ascii_digit) {
            *i += 1;
        }
        if *i == start {
            return Ok(None);
        }
        let t: String = c[start..*i].iter().collect();
        t.parse::<usize>()
            .map(Some)
            .map_err(|_| "too many decimal digits in format string".to_string())
    };
    sp.width = digits(&mut i)?.unwrap_or(0);
    if let Some(&g) = c.get(i).filter(|g| matches!(g, ',' | '_')) {
        sp.group = Some(g);
        i += 1;
    }
    if c.get(i) == Some(&'.') {
        i += 1;
        sp.precision = Some(digits(&mut i)?.ok_or("format specifier missing precision")?);
    }
    if i < c.len() {
        sp.ty = Some(c[i]);
        i += 1;
    }
    if i < c.len() {
        return Err(format!("invalid format specifier {s:?}"));
    }
    Ok(sp)
}

/// Thousands (or `_`) separators in the integer digits `d` (groups of `n`).
fn group(d: &str, sep: char, n: usize) -> String {
    let mut out = String::with_capacity(d.len() + d.len() / n);
    for (i, ch) in d.chars().enumerate() {
        if i > 0 && (d.len() - i).is_multiple_of(n) {
            out.push(sep);
        }
        out.push(ch);
    }
    out
}

/// `body` (digits, no sign) padded to the spec: sign, fill, alignment.
fn pad(body: &str, negative: bool, sp: &Spec, numeric: bool, m: &mut Meter) -> Res<String> {
    m.string(sp.width.max(body.len()) + 1)?;
    let sign = match (negative, sp.sign) {
        (true, _) => "-",
        (false, '+') => "+",
        (false, ' ') => " ",
        _ => "",
    };
    let (fill, align) = if sp.zero && sp.align.is_none() && numeric {
        ('0', '=')
    } else {
        (
            sp.fill.unwrap_or(' '),
            sp.align.unwrap_or(if numeric { '>' } else { '<' }),
        )
    };
    let len = sign.chars().count() + body.chars().count();
    let room = sp.width.saturating_sub(len);
    let fills = |n: usize| fill.to_string().repeat(n);
    Ok(match align {
        '<' => format!("{sign}{body}{}", fills(room)),
        '>' => format!("{}{sign}{body}", fills(room)),
        '^' => format!("{}{sign}{body}{}", fills(room / 2), fills(room - room / 2)),
        _ => format!("{sign}{}{body}", fills(room)),
    })
}

/// The digits of `x` (finite, non-negative) in `ty` (`e`, `f`, `g`, `%`, or
/// `r` for the omitted type) at `prec`, as CPython's `PyOS_double_to_string`.
pub(super) fn float_digits(x: f64, ty: char, prec: Option<usize>, alt: bool) -> String {
    let upper = ty.is_ascii_uppercase();
    let t = ty.to_ascii_lowercase();
    if !x.is_finite() {
        let s = if x.is_nan() { "nan" } else { "inf" };
        return if upper { s.to_uppercase() } else { s.into() };
    }
    let out = match (t, prec) {
        ('f', p) => format!("{x:.*}", p.unwrap_or(6)),
        ('%', p) => format!("{:.*}%", p.unwrap_or(6), x * 100.0),
        ('e', p) => exp_form(x, p.unwrap_or(6)),
        ('r', None) => float_repr(x),
        ('g' | 'r', p) => {
            let p = p.unwrap_or(6).max(1);
            let add_dot_0 = t == 'r';
            let sci = exp_form(x, p - 1);
            let exp: i64 = sci
                .rsplit_once('e')
                .and_then(|(_, e)| e.parse().ok())
                .unwrap_or(0);
            let limit = if add_dot_0 { p as i64 - 1 } else { p as i64 };
            let mut s = if exp < -4 || exp + 1 > limit {
                sci
            } else {
                format!("{x:.*}", (p as i64 - 1 - exp).max(0) as usize)
            };
            if !alt {
                s = strip_zeros(&s);
            }
            if add_dot_0 && !s.contains(['.', 'e']) {
                s.push_str(".0");
            }
            s
        }
        _ => format!("{x}"),
    };
    if upper {
        out.to_uppercase()
    } else {
        out
    }
}

/// `d.ddde+XX` with `p` digits after the point (Python's exponent: a sign
/// and at least two digits).
fn exp_form(x: f64, p: usize) -> String {
    let s = format!("{x:.p$e}");
    let (mant, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let e: i64 = exp.parse().unwrap_or(0);
    format!("{mant}e{}{:02}", if e < 0 { '-' } else { '+' }, e.abs())
}

/// Trailing zeros of the significand dropped, and a point left bare.
fn strip_zeros(s: &str) -> String {
    let (mant, exp) = match s.split_once('e') {
        Some((m, e)) => (m, Some(e)),
        None => (s, None),
    };
    let mant = if mant.contains('.') {
        mant.trim_end_matches('0').trim_end_matches('.')
    } else {
        mant
    };
    match exp {
        Some(e) => format!("{mant}e{e}"),
        None => mant.to_string(),
    }
}

fn format_int(i: i64, sp: &Spec, m: &mut Meter) -> Res<String> {
    let mag = i.unsigned_abs();
    let (digits, prefix, n) = match sp.ty {
        None | Some('d') | Some('n') => (mag.to_string(), "", 3),
        Some('x') => (format!("{mag:x}"), "0x", 4),
        Some('X') => (format!("{mag:X}"), "0X", 4),
        Some('o') => (format!("{mag:o}"), "0o", 4),
        Some('b') => (format!("{mag:b}"), "0b", 4),
        Some('c') => {
            let ch = u32::try_from(i)
                .ok()
                .and_then(char::from_u32)
                .ok_or("%c arg not in range(0x110000)")?;
            return pad(&ch.to_string(), false, sp, false, m);
        }
        Some(t @ ('e' | 'E' | 'f' | 'F' | 'g' | 'G' | '%')) => {
            return format_float(
                i as f64,
                &Spec {
                    ty: Some(t),
                    ..copy(sp)
                },
                m,
            )
        }
        Some(t) => {
            return Err(format!(
                "Unknown format code '{t}' for object of type 'int'"
            ))
        }
    };
    if sp.precision.is_some() {
        return Err("Precision not allowed in integer format specifier".into());
    }
    let grouped = match sp.group {
        Some(g) => group(&digits, g, n),
        None => digits,
    };
    let body = if sp.alt {
        format!("{prefix}{grouped}")
    } else {
        grouped
    };
    pad(&body, i < 0, sp, true, m)
}

fn copy(sp: &Spec) -> Spec {
    Spec {
        fill: sp.fill,
        align: sp.align,
        sign: sp.sign,
        alt: sp.alt,
        zero: sp.zero,
        width: sp.width,
        group: sp.group,
        precision: sp.precision,
        ty: sp.ty,
    }
}

fn format_float(x: f64, sp: &Spec, m: &mut Meter) -> Res<String> {
    let ty = match sp.ty {
        None => 'r',
        Some(t @ ('e' | 'E' | 'f' | 'F' | 'g' | 'G' | '%')) => t,
        Some('n') => 'g',
        Some(t) => {
            return Err(format!(
                "Unknown format code '{t}' for object of type 'float'"
            ))
        }
    };
    m.string(sp.precision.unwrap_or(0) + 32)?;
    let mut s = float_digits(x.abs(), ty, sp.precision, sp.alt);
    if let Some(g) = sp.group {
        let end = s.find(|c: char| !c.is_ascii_digit()).unwrap_or(s.len());
        s = format!("{}{}", group(&s[..end], g, 3), &s[end..]);
    }
    pad(&s, x.is_sign_negative() && !x.is_nan(), sp, true, m)
}

/// Python's `format(value, spec)`.
pub(super) fn format_value(v: &Value, spec: &str, m: &mut Meter) -> Res<String> {
    m.step()?;
    if spec.is_empty() {
        return v.to_py_str(m);
    }
    let sp = parse_spec(spec)?;
    match v {
        Value::Str(s) => {
            if let Some(t) = sp.ty.filter(|t| *t != 's') {
                return Err(format!(
                    "Unknown format code '{t}' for object of type 'str'"
                ));
            }
            if sp.sign != '-' || sp.alt || sp.group.is_some() {
                return Err("sign, '#' and grouping are not allowed in a string format".into());
            }
            let body: String = match sp.precision {
                Some(p) => s.chars().take(p).collect(),
                None => s.to_string(),
            };
            pad(&body, false, &sp, false, m)
        }
        Value::Bool(_) | Value::Int(_) => format_int(v.as_int().unwrap_or(0), &sp, m),
        Value::Float(f) => format_float(*f, &sp, m),
        other => Err(format!(
            "unsupported format string passed to {}.__format__",
            other.type_name()
        )),
    }
}

/// The value a `str.format` field names: `0`, `name`, then `[i]` items.
fn field<'a>(
    name: &str,
    args: &'a [Value],
    kwargs: &'a [(String, Value)],
    auto: &mut usize,
    m: &mut Meter,
) -> Res<Value> {
    let (head, rest) = match name.find(['[', '.']) {
        Some(i) => (&name[..i], &name[i..]),
        None => (name, ""),
    };
    let mut v = if head.is_empty() {
        let v = args.get(*auto).ok_or_else(|| {
            format!("Replacement index {auto} out of range for positional args tuple")
        })?;
        *auto += 1;
        v.clone()
    } else if let Ok(i) = head.parse::<usize>() {
        args.get(i).cloned().ok_or_else(|| {
            format!("Replacement index {i} out of range for positional args tuple")
        })?
    } else {
        kwargs
            .iter()
            .find(|(k, _)| k == head)
            .map(|(_, v)| v.clone())
            .ok_or_else(|| format!("KeyError: '{head}'"))?
    };
    let mut r = rest;
    while !r.is_empty() {
        let Some(inner) = r.strip_prefix('[') else {
            return Err(format!(
                "format field {name:?}: attribute access is not supported"
            ));
        };
        let close = inner.find(']').ok_or("Missing ']' in format string")?;
        let key = &inner[..close];
        let k = match key.parse::<i64>() {
            Ok(i) => Value::Int(i),
            Err(_) => Value::str(key),
        };
        v = index(&v, &k, m)?;
        r = &inner[close + 1..];
    }
    Ok(v)
}

/// `fmt.format(*args, **kwargs)`.
pub(super) fn str_format(
    fmt: &str,
    args: &[Value],
    kwargs: &[(String, Value)],
    m: &mut Meter,
) -> Res<String> {
    format_fields(fmt, args, kwargs, m, &mut 0, 0)
}

fn format_fields(
    fmt: &str,
    args: &[Value],
    kwargs: &[(String, Value)],
    m: &mut Meter,
    auto: &mut usize,
    depth: usize,
) -> Res<String> {
    if depth > 1 {
        return Err("Max string recursion exceeded".into());
    }
    m.scan(fmt.len())?;
    let mut out = String::new();
    let mut rest = fmt;
    while let Some(i) = rest.find(['{', '}']) {
        out.push_str(&rest[..i]);
        let c = rest.as_bytes()[i];
        let after = &rest[i + 1..];
        if after.as_bytes().first() == Some(&c) {
            out.push(c as char);
            rest = &after[1..];
            continue;
        }
        if c == b'}' {
            return Err("Single '}' encountered in format string".into());
        }
        // The field ends at the '}' that balances it (a spec may nest one).
        let mut level = 1;
        let end = after
            .char_indices()
            .find(|&(_, ch)| {
                level += match ch {
                    '{' => 1,
                    '}' => -1,
                    _ => 0,
                };
                level == 0
            })
            .map(|(j, _)| j)
            .ok_or("Single '{' encountered in format string")?;
        let body = &after[..end];
        let (name_conv, spec) = match body.find(':') {
            Some(j) => (&body[..j], &body[j + 1..]),
            None => (body, ""),
        };
        let (name, conv) = match name_conv.split_once('!') {
            Some((n, c)) => (n, Some(c)),
            None => (name_conv, None),
        };
        let v = field(name, args, kwargs, auto, m)?;
        let v = match conv {
            None | Some("s") => v,
            Some("r") | Some("a") => Value::str(&v.repr(m)?),
            Some(c) => return Err(format!("Unknown conversion specifier {c}")),
        };
        let spec = if spec.contains('{') {
            format_fields(spec, args, kwargs, m, auto, depth + 1)?
        } else {
            spec.to_string()
        };
        let piece = if conv.is_some() && spec.is_empty() {
            v.to_py_str(m)?
        } else {
            format_value(&v, &spec, m)?
        };
        m.string(out.len() + piece.len())?;
        out.push_str(&piece);
        rest = &after[end + 1..];
    }
    out.push_str(rest);
    m.string(out.len())?;
    Ok(out)
}

/// One `%` conversion's flags, width, precision and type.
struct Conv {
    key: Option<String>,
    flags: String,
    width: Option<usize>,
    prec: Option<usize>,
    ty: char,
}

fn parse_conv(c: &[char], i: &mut usize) -> Res<Conv> {
    let mut key = None;
    if c.get(*i) == Some(&'(') {
        let close = c[*i..]
            .iter()
            .position(|x| *x == ')')
            .ok_or("incomplete format key")?;
        key = Some(c[*i + 1..*i + close].iter().collect());
        *i += close + 1;
    }
    let mut flags = String::new();
    while let Some(&f) = c
        .get(*i)
        .filter(|f| matches!(f, '-' | '+' | ' ' | '#' | '0'))
    {
        flags.push(f);
        *i += 1;
    }
    let num = |i: &mut usize| -> Res<Option<usize>> {
        if c.get(*i) == Some(&'*') {
            return Err("'*' widths in % formatting are not supported".into());
        }
        let start = *i;
        while c.get(*i).is_some_and(char::is_ascii_digit) {
            *i += 1;
        }
        let t: String = c[start..*i].iter().collect();
        Ok((!t.is_empty()).then(|| t.parse().unwrap_or(usize::MAX)))
    };
    let width = num(i)?;
    let mut prec = None;
    if c.get(*i) == Some(&'.') {
        *i += 1;
        prec = Some(num(i)?.unwrap_or(0));
    }
    while matches!(c.get(*i), Some('h' | 'l' | 'L')) {
        *i += 1;
    }
    let ty = *c.get(*i).ok_or("incomplete format")?;
    *i += 1;
    Ok(Conv {
        key,
        flags,
        width,
        prec,
        ty,
    })
}

/// printf-style `fmt % args`.
pub(super) fn percent(fmt: &str, args: &Value, m: &mut Meter) -> Res<String> {
    m.scan(fmt.len())?;
    let items: Vec<Value> = match args {
        Value::Tuple(t) => t.items().to_vec(),
        other => vec![other.clone()],
    };
    let c: Vec<char> = fmt.chars().collect();
    let (mut out, mut i, mut next) = (String::new(), 0, 0);
    while i < c.len() {
        if c[i] != '%' {
            out.push(c[i]);
            i += 1;
            continue;
        }
        i += 1;
        let conv = parse_conv(&c, &mut i)?;
        if conv.ty == '%' {
            out.push('%');
            continue;
        }
        let v = match &conv.key {
            Some(k) => index(args, &Value::str(k), m)?,
            None => {
                let v = items
                    .get(next)
                    .cloned()
                    .ok_or("not enough arguments for format string")?;
                next += 1;
                v
            }
        };
        let piece = convert(&conv, &v, m)?;
        m.string(out.len() + piece.len())?;
        out.push_str(&piece);
    }
    if next < items.len() && !matches!(args, Value::Dict(_)) {
        return Err("not all arguments converted during string formatting".into());
    }
    Ok(out)
}

fn convert(conv: &Conv, v: &Value, m: &mut Meter) -> Res<String> {
    let f = &conv.flags;
    let mut sp = Spec {
        sign: if f.contains('+') {
            '+'
        } else if f.contains(' ') {
            ' '
        } else {
            '-'
        },
        alt: f.contains('#'),
        width: conv.width.unwrap_or(0),
        align: Some(if f.contains('-') { '<' } else { '>' }),
        ..Spec::default()
    };
    if f.contains('0') && !f.contains('-') {
        sp.align = None;
        sp.zero = true;
    }
    match conv.ty {
        's' | 'r' | 'a' => {
            let s = if conv.ty == 's' {
                v.to_py_str(m)?
            } else {
                v.repr(m)?
            };
            let s: String = match conv.prec {
                Some(p) => s.chars().take(p).collect(),
                None => s,
            };
            sp.zero = false;
            sp.align = Some(if f.contains('-') { '<' } else { '>' });
            pad(&s, false, &sp, false, m)
        }
        'c' if matches!(v, Value::Str(s) if s.chars().count() == 1) => {
            sp.zero = false;
            pad(&v.to_py_str(m)?, false, &sp, false, m)
        }
        'd' | 'i' | 'u' | 'x' | 'X' | 'o' | 'c' => {
            let i = match v {
                Value::Float(x) if matches!(conv.ty, 'd' | 'i' | 'u') && x.is_finite() => {
                    super::value::float_to_int(x.trunc(), "%d")?
                        .as_int()
                        .unwrap_or(0)
                }
                other => other.as_int().ok_or_else(|| {
                    format!(
                        "%{} format: an integer is required, not {}",
                        conv.ty,
                        other.type_name()
                    )
                })?,
            };
            sp.ty = Some(match conv.ty {
                'i' | 'u' => 'd',
                t => t,
            });
            format_int(i, &sp, m)
        }
        'e' | 'E' | 'f' | 'F' | 'g' | 'G' => {
            let x = v
                .as_f64()
                .ok_or_else(|| format!("must be real number, not {}", v.type_name()))?;
            sp.ty = Some(conv.ty);
            sp.precision = Some(conv.prec.unwrap_or(6));
            format_float(x, &sp, m)
        }
        t => Err(format!("unsupported format character '{t}'")),
    }
}
