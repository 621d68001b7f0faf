//! Subscripts and slices of `${...}` expressions with Python's semantics:
//! `b[i]` (negative indices from the end, a dict by key), `b[i:j:k]`.

use super::limits::Meter;
use super::value::{overflow, range_len, Res, Value};

/// A sequence index (negative from the end), checked against `len`.
pub(super) fn seq_index(i: &Value, len: usize) -> Res<usize> {
    let k = i
        .as_int()
        .ok_or_else(|| format!("indices must be integers or slices, not {}", i.type_name()))?;
    let len_i = len as i64;
    let k2 = if k < 0 { k + len_i } else { k };
    if k2 < 0 || k2 >= len_i {
        return Err(format!("index {k} out of range (length {len})"));
    }
    Ok(k2 as usize)
}

/// `b[i]`.
pub(super) fn index(b: &Value, i: &Value, m: &mut Meter) -> Res<Value> {
    m.step()?;
    match b {
        Value::List(l) => {
            let l = l.items();
            Ok(l[seq_index(i, l.len())?].clone())
        }
        Value::Tuple(t) => Ok(t.items()[seq_index(i, t.items().len())?].clone()),
        Value::Str(s) => {
            m.scan(s.len())?;
            let n = s.chars().count();
            let k = seq_index(i, n)?;
            let c = s.chars().nth(k).unwrap_or(' ');
            Ok(Value::str(c.encode_utf8(&mut [0; 4])))
        }
        Value::Range(r) => {
            let n = usize::try_from(range_len(r)).unwrap_or(usize::MAX);
            let k = seq_index(i, n)? as i64;
            Ok(Value::Int(r[0] + k * r[2]))
        }
        Value::Dict(d) => {
            dict_get(d, i, m)?.ok_or_else(|| format!("key {} not found in the dict", i.show()))
        }
        other => Err(format!(
            "'{}' object is not subscriptable",
            other.type_name()
        )),
    }
}

/// The value of key `k` in `d`.
pub(super) fn dict_get(d: &super::value::Dict, k: &Value, m: &mut Meter) -> Res<Option<Value>> {
    if !k.hashable() {
        return Err(format!("unhashable type: '{}'", k.type_name()));
    }
    for (key, v) in d.items().iter() {
        if key.py_eq(k, m)? {
            return Ok(Some(v.clone()));
        }
    }
    Ok(None)
}

/// Python's `slice.indices(len)`: (start, stop, step) of `[a:b:c]`.
pub(super) fn slice_indices(
    len: i64,
    a: Option<i64>,
    b: Option<i64>,
    c: Option<i64>,
) -> Res<(i64, i64, i64)> {
    let step = c.unwrap_or(1);
    if step == 0 {
        return Err("slice step cannot be zero".into());
    }
    let (lower, upper) = if step < 0 { (-1, len - 1) } else { (0, len) };
    let adjust = |x: Option<i64>, default: i64| match x {
        None => default,
        Some(x) if x < 0 => (x + len).max(lower),
        Some(x) => x.min(upper),
    };
    let start = adjust(a, if step < 0 { upper } else { lower });
    let stop = adjust(b, if step < 0 { lower } else { upper });
    Ok((start, stop, step))
}

/// The positions a slice selects.
fn positions(start: i64, stop: i64, step: i64) -> impl Iterator<Item = usize> {
    let mut i = start;
    std::iter::from_fn(move || {
        let more = if step > 0 { i < stop } else { i > stop };
        more.then(|| {
            let k = i as usize;
            i += step;
            k
        })
    })
}

fn bound(v: &Value) -> Res<Option<i64>> {
    match v {
        Value::None => Ok(None),
        other => other
            .as_int()
            .map(Some)
            .ok_or_else(|| "slice indices must be integers or None".to_string()),
    }
}

/// `b[lo:hi:step]` (each part `None` when left out).
pub(super) fn slice(b: &Value, parts: [&Value; 3], m: &mut Meter) -> Res<Value> {
    let [a, z, c] = [bound(parts[0])?, bound(parts[1])?, bound(parts[2])?];
    let pick = |items: &[Value], m: &mut Meter| -> Res<Vec<Value>> {
        let (s, e, st) = slice_indices(items.len() as i64, a, z, c)?;
        let v: Vec<Value> = positions(s, e, st).map(|k| items[k].clone()).collect();
        m.list(v.len())?;
        Ok(v)
    };
    match b {
        Value::List(l) => Ok(Value::list(pick(&l.items(), m)?)),
        Value::Tuple(t) => Ok(Value::tuple(pick(t.items(), m)?)),
        Value::Str(s) => {
            m.scan(s.len())?;
            let chars: Vec<char> = s.chars().collect();
            let (st, e, step) = slice_indices(chars.len() as i64, a, z, c)?;
            let out: String = positions(st, e, step).map(|k| chars[k]).collect();
            m.string(out.len())?;
            Ok(Value::str(&out))
        }
        Value::Range(r) => {
            let (st, e, step) = slice_indices(range_len(r), a, z, c)?;
            let at = |k: i64| r[0].checked_add(k.checked_mul(r[2])?);
            let (Some(s2), Some(e2), Some(step2)) = (at(st), at(e), r[2].checked_mul(step)) else {
                return Err(overflow());
            };
            Ok(Value::Range(std::rc::Rc::new([s2, e2, step2])))
        }
        other => Err(format!(
            "'{}' object is not subscriptable",
            other.type_name()
        )),
    }
}

/// Insert into dict entries, an equal key keeping its place (Python's dict).
pub(super) fn dict_insert(
    pairs: &mut Vec<(Value, Value)>,
    k: Value,
    v: Value,
    m: &mut Meter,
) -> Res<()> {
    if !k.hashable() {
        return Err(format!("unhashable type: '{}'", k.type_name()));
    }
    for (key, slot) in pairs.iter_mut() {
        if key.py_eq(&k, m)? {
            *slot = v;
            return Ok(());
        }
    }
    pairs.push((k, v));
    Ok(())
}
