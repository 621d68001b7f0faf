//! The caps a single value meets before it is built (a string's bytes, a
//! collection's items), checked from its size alone: the leaf that the
//! values, the evaluator and the budget ([`super::budget`], which charges what
//! is built) share.

use super::parse::Expr;
use crate::diagnostic::{Error, Result};
use crate::tolerances::{MAX_PY_ITEMS, MAX_PY_STR_BYTES};

/// A [`Code::Limit`](crate::diagnostic::Code::Limit) error at `e`.
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
