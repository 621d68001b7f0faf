//! The keyword arguments of a call (`f(x, key=...)`): which are allowed, and
//! one by name. Shared by the builtins and the methods.

use super::value::{Res, Value};

/// No keyword arguments allowed.
pub(super) fn no_kw(name: &str, kw: &[(String, Value)]) -> Res<()> {
    match kw.first() {
        None => Ok(()),
        Some((k, _)) => Err(format!("{name}() got an unexpected keyword argument '{k}'")),
    }
}

/// The keyword `key` of `kw`, and whether any other was given.
pub(super) fn kwarg<'a>(kw: &'a [(String, Value)], key: &str) -> Option<&'a Value> {
    kw.iter().find(|(k, _)| k == key).map(|(_, v)| v)
}

/// Only the keywords in `allowed`.
pub(super) fn only_kw(name: &str, kw: &[(String, Value)], allowed: &[&str]) -> Res<()> {
    match kw.iter().find(|(k, _)| !allowed.contains(&k.as_str())) {
        None => Ok(()),
        Some((k, _)) => Err(format!("{name}() got an unexpected keyword argument '{k}'")),
    }
}
