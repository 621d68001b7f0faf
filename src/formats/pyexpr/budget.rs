//! What evaluating may create. Every value an expression evaluates to is
//! charged its size against one budget (one per launch.py file, one per
//! `$(eval ...)`), and no single string or list may outgrow its cap, checked
//! before it is built: a hostile file is refused with the line that asked,
//! never allowed to exhaust memory. The limits are in [`crate::tolerances`]
//! (`MAX_PY_STR_BYTES`, `MAX_PY_ITEMS`, `MAX_PY_WORK_BYTES`).

use std::cell::{Cell, RefCell};

use super::parse::Expr;
use super::value::{Func, Value};
use crate::diagnostic::{Code, Error, Result};
use crate::tolerances::{MAX_PY_ITEMS, MAX_PY_STR_BYTES, MAX_PY_WORK_BYTES};

/// The bytes charged so far, and the first refusal (a lenient host turns
/// errors into unknown values; the refusal is still the file's).
#[derive(Default)]
pub struct Budget {
    used: Cell<usize>,
    refused: RefCell<Option<Error>>,
}

impl Budget {
    /// Charge `v`'s size; past [`MAX_PY_WORK_BYTES`] in all, refused.
    pub fn charge(&self, v: &Value, at: &Expr) -> Result<()> {
        let used = self.used.get().saturating_add(cost(v));
        self.used.set(used);
        if used > MAX_PY_WORK_BYTES {
            return Err(limit(
                at,
                format!(
                    "the values this file's Python creates exceed {MAX_PY_WORK_BYTES} bytes in all: not evaluated"
                ),
            ));
        }
        Ok(())
    }

    /// Keep the first limit error seen.
    pub fn note(&self, e: &Error) {
        if e.code == Code::Limit && self.refused.borrow().is_none() {
            *self.refused.borrow_mut() = Some(e.clone());
        }
    }

    /// The first limit a file ran into.
    pub fn refused(&self) -> Option<Error> {
        self.refused.borrow().clone()
    }
}

/// A [`Code::Limit`] error at `e`.
pub fn limit(e: &Expr, msg: impl Into<String>) -> Error {
    Error::limit(msg.into()).at_line(e.line, Some(e.col))
}

/// Refuse a string of `bytes` (`what` makes it) past [`MAX_PY_STR_BYTES`].
pub fn str_fits(bytes: usize, what: &str, at: &Expr) -> Result<()> {
    if bytes > MAX_PY_STR_BYTES {
        return Err(limit(
            at,
            format!(
                "{what} would make a string of {bytes} bytes, more than {MAX_PY_STR_BYTES}: not evaluated"
            ),
        ));
    }
    Ok(())
}

/// Refuse a list, tuple or dict of `n` items past [`MAX_PY_ITEMS`].
pub fn items_fit(n: usize, what: &str, at: &Expr) -> Result<()> {
    if n > MAX_PY_ITEMS {
        return Err(limit(
            at,
            format!("{what} would make {n} items, more than {MAX_PY_ITEMS}: not evaluated"),
        ));
    }
    Ok(())
}

/// What holding `v` costs: its bytes, a tuple's or dict's items, a list's
/// slots (its items are shared, not copied, when a list is passed on).
pub fn cost(v: &Value) -> usize {
    const SLOT: usize = std::mem::size_of::<Value>();
    SLOT + match v {
        Value::Str(s) => s.len(),
        Value::List(l) => l.borrow().len() * SLOT,
        Value::Tuple(t) => t.iter().map(cost).sum(),
        Value::Dict(d) => d.iter().map(|(k, v)| cost(k) + cost(v)).sum(),
        Value::Func(Func::Method(recv, name)) => cost(recv) + name.len(),
        _ => 0,
    }
}
