//! What evaluating may create. Every value an expression evaluates to is
//! charged its size against one budget (one per launch.py file, one per
//! `$(eval ...)`), and no single string or list may outgrow its cap, checked
//! before it is built: a hostile file is refused with the line that asked,
//! never allowed to exhaust memory. The limits are in [`crate::tolerances`]
//! (`MAX_PY_STR_BYTES`, `MAX_PY_ITEMS`, `MAX_PY_WORK_BYTES`,
//! `MAX_PY_VALUE_DEPTH`).
//!
//! Nesting: every value charged is also measured for depth (lists, tuples
//! and dicts in one another), refused past [`MAX_PY_VALUE_DEPTH`] levels
//! before anything walks it recursively: printing, comparing, `in`, copying
//! a tuple and dropping a value all recurse once per level, so a value
//! nested 10^5 deep (a loop appending `[l[-1]]`, or `(l[-1],)`) would
//! overflow the stack or, copied on each step, take quadratic time. The
//! measure stops one level past the cap, skips a list already on its path
//! (`a.append(a)` is cyclic, not deep: printed `[[...]]` as CPython does)
//! and charges the items of nested lists it reads to the work budget (a
//! tuple's and dict's items are charged by [`cost`] already), so measuring
//! is never more work than the budget allows.

use std::cell::{Cell, RefCell};

use super::caps::limit;
use super::parse::Expr;
use super::value::{Func, Value};
use crate::diagnostic::{Code, Error, Result};
use crate::tolerances::{MAX_PY_VALUE_DEPTH, MAX_PY_WORK_BYTES};

/// The bytes charged so far, and the first refusal (a lenient host turns
/// errors into unknown values; the refusal is still the file's).
#[derive(Default)]
pub struct Budget {
    used: Cell<usize>,
    refused: RefCell<Option<Error>>,
}

impl Budget {
    /// Charge `v`'s size; past [`MAX_PY_WORK_BYTES`] in all, or nested
    /// deeper than [`MAX_PY_VALUE_DEPTH`], refused.
    pub fn charge(&self, v: &Value, at: &Expr) -> Result<()> {
        let mut read = 0usize;
        let depth = nesting(v, 0, &mut Vec::new(), &mut read);
        if depth > MAX_PY_VALUE_DEPTH {
            return Err(limit(
                at,
                format!(
                    "a value nested more than {MAX_PY_VALUE_DEPTH} levels deep (lists, tuples or dicts in one another): not evaluated"
                ),
            ));
        }
        let read = read.saturating_mul(std::mem::size_of::<Value>());
        let used = self.used.get().saturating_add(cost(v)).saturating_add(read);
        self.used.set(used);
        self.check_used(used, at)
    }

    /// `list.append(x)` (`what`) puts `x` one level down: refused when the
    /// list would then nest deeper than [`MAX_PY_VALUE_DEPTH`], where it is
    /// made, naming the call. (A list deepened through another list that
    /// holds it is refused where that one is next evaluated; either way
    /// nothing walks past the cap, and a list is dropped without recursion.)
    pub fn fits_in_list(&self, x: &Value, what: &str, at: &Expr) -> Result<()> {
        let mut read = 0usize;
        if 1 + nesting(x, 1, &mut Vec::new(), &mut read) > MAX_PY_VALUE_DEPTH {
            return Err(limit(
                at,
                format!(
                    "{what} would make a value nested more than {MAX_PY_VALUE_DEPTH} levels deep (lists, tuples or dicts in one another): not evaluated"
                ),
            ));
        }
        self.charge_read(read, at)
    }

    fn charge_read(&self, read: usize, at: &Expr) -> Result<()> {
        let read = read.saturating_mul(std::mem::size_of::<Value>());
        let used = self.used.get().saturating_add(read);
        self.used.set(used);
        self.check_used(used, at)
    }

    fn check_used(&self, used: usize, at: &Expr) -> Result<()> {
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

/// How deep `v` nests (a scalar 0, `[]` 1, `[[1]]` 2), counted up to one
/// level past [`MAX_PY_VALUE_DEPTH`] (`level`: the levels above `v`);
/// `open`: the lists on the path (a list inside itself is not followed);
/// `read`: the items of lists below the first level read so far.
fn nesting(v: &Value, level: usize, open: &mut Vec<*const ()>, read: &mut usize) -> usize {
    if level > MAX_PY_VALUE_DEPTH {
        return 0;
    }
    match v {
        Value::List(l) => {
            let p = std::rc::Rc::as_ptr(l) as *const ();
            if open.contains(&p) {
                return 0;
            }
            let items = l.borrow();
            if level > 0 {
                *read = read.saturating_add(items.len());
            }
            open.push(p);
            let d = deepest(&mut items.iter(), level, open, read);
            open.pop();
            d
        }
        Value::Tuple(t) => deepest(&mut t.iter(), level, open, read),
        Value::Dict(m) => deepest(&mut m.iter().flat_map(|(k, v)| [k, v]), level, open, read),
        _ => 0,
    }
}

/// [`nesting`] of a container at `level` with these items: one more than
/// its deepest item (stopping once past the cap).
fn deepest(
    items: &mut dyn Iterator<Item = &Value>,
    level: usize,
    open: &mut Vec<*const ()>,
    read: &mut usize,
) -> usize {
    let mut d = 0;
    for x in items {
        if matches!(x, Value::List(_) | Value::Tuple(_) | Value::Dict(_)) {
            d = d.max(nesting(x, level + 1, open, read));
            if level + 1 + d > MAX_PY_VALUE_DEPTH {
                break;
            }
        }
    }
    1 + d
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
