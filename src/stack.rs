//! Deep-recursion guard: the parsers that recurse once per nesting level
//! (YAML, xacro) run on a thread with a [`LARGE`] stack, so their nesting
//! limits hold whatever stack the caller has (a stack overflow is an abort,
//! not an error).
//!
//! Starting that thread per file cost more than the parse (a 64 MiB mapping
//! and a context switch per YAML file in `check`/`spread`): the pipeline's
//! workers are themselves started with the large stack ([`spawn_large`] marks
//! them), and [`deep`] runs inline on a marked thread, starting a thread only
//! for callers with an unknown stack (the main thread, test threads).

use std::cell::Cell;

/// Stack for code that recurses per nesting level: tens of KiB per level in a
/// debug build, times the nesting limits (e.g. `MAX_YAML_DEPTH`), with room.
pub(crate) const LARGE: usize = 64 * 1024 * 1024;

thread_local! {
    /// Whether this thread was started with a [`LARGE`] stack.
    static ON_LARGE: Cell<bool> = const { Cell::new(false) };
}

/// Run `f` on a [`LARGE`] stack: inline when this thread has one, otherwise on
/// a scoped thread named `name` (or inline when no thread can be started).
pub(crate) fn deep<T: Send>(name: &str, f: impl Fn() -> T + Sync) -> T {
    if ON_LARGE.with(Cell::get) {
        return f();
    }
    std::thread::scope(|s| match spawn_large_named(s, Some(name), &f) {
        Some(h) => h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)),
        None => f(),
    })
}

/// Start a scoped thread with a [`LARGE`] stack, marked so that [`deep`] runs
/// inline on it; `None` when it cannot be started.
pub(crate) fn spawn_large<'s, 'e, T: Send + 's>(
    s: &'s std::thread::Scope<'s, 'e>,
    f: impl FnOnce() -> T + Send + 's,
) -> Option<std::thread::ScopedJoinHandle<'s, T>> {
    spawn_large_named(s, None, f)
}

/// [`spawn_large`], the thread named `name` when given.
fn spawn_large_named<'s, 'e, T: Send + 's>(
    s: &'s std::thread::Scope<'s, 'e>,
    name: Option<&str>,
    f: impl FnOnce() -> T + Send + 's,
) -> Option<std::thread::ScopedJoinHandle<'s, T>> {
    let mut b = std::thread::Builder::new().stack_size(LARGE);
    if let Some(n) = name {
        b = b.name(n.into());
    }
    b.spawn_scoped(s, move || {
        ON_LARGE.with(|c| c.set(true));
        f()
    })
    .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn name() -> Option<String> {
        std::thread::current().name().map(str::to_string)
    }

    #[test]
    fn an_unmarked_caller_gets_a_thread_of_its_own() {
        let me = std::thread::current().id();
        let (id, n) = deep("yaml", || (std::thread::current().id(), name()));
        assert_ne!(id, me);
        assert_eq!(n.as_deref(), Some("yaml"));
    }

    #[test]
    fn a_large_stack_worker_runs_it_inline() {
        std::thread::scope(|s| {
            let h = spawn_large(s, || {
                let me = std::thread::current().id();
                let id = deep("yaml", || std::thread::current().id());
                // Still marked after a nested call.
                (me, id, ON_LARGE.with(Cell::get))
            })
            .expect("a worker thread");
            let (me, id, marked) = h.join().expect("no panic");
            assert_eq!(id, me);
            assert!(marked);
        });
    }
}
