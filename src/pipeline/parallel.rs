//! Work on every core, results in order: the engine of `check` and `survey`
//! over many files.
//!
//! A shared work queue (an atomic index into the items: each worker takes the
//! next few items when it is free, so a core slowed by other work simply
//! takes fewer, and the run is never slower than one thread) feeds a reorder
//! buffer on the calling thread, which hands each result to the sink in item
//! order as soon as every earlier one is done. The buffer is bounded: a worker
//! does not start an item more than [`WINDOW`] places ahead of the next result
//! due, so one slow item holds at most `WINDOW` results in memory, never the
//! run's. The sink runs on the calling thread (it needs no `Send`), while the
//! workers go on.
//!
//! Items are taken and their results sent in batches of up to [`BATCH`]
//! (fewer when there are few items per worker): one message, and at most one
//! wake-up of the calling thread, per batch rather than per item; a worker
//! is woken only when it waits on the window (thread switches per file were
//! a large part of the system time over 10,000 files, issue 29).
//!
//! Why not rayon or crossbeam: this is the whole of it (an index, a channel, a
//! condition variable), and an ordered, bounded, streaming map is not what
//! rayon's `par_iter` gives without collecting.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Condvar, Mutex};

/// How far (in items) a worker may run ahead of the next result due.
pub const WINDOW: usize = 256;

/// The most items a worker takes (and sends the results of) at once; well
/// below [`WINDOW`].
pub const BATCH: usize = 16;

/// The worker threads to use: `AUDIT_JOBS` when set to a positive number,
/// else the cores the process may run on.
pub fn threads() -> usize {
    std::env::var("AUDIT_JOBS")
        .ok()
        .and_then(|s| s.trim().parse::<usize>().ok())
        .filter(|&n| n > 0)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// Run `work` on each item on [`threads`] workers; `sink` receives every
/// result with its item's index, in item order. `sink` returning `false`
/// stops the run: no further item is started and no further result handed on.
pub fn ordered<I, R, W, S>(items: &[I], work: W, sink: S)
where
    I: Sync,
    R: Send,
    W: Fn(usize, &I) -> R + Sync,
    S: FnMut(usize, R) -> bool,
{
    ordered_on(threads(), items, work, sink)
}

/// The items a worker takes at once: [`BATCH`], fewer when that would leave
/// a worker without a share of the first items (eight batches per worker).
fn batch_size(items: usize, threads: usize) -> usize {
    (items / (threads * 8)).clamp(1, BATCH)
}

/// What the workers and the calling thread share: the next item to take, the
/// next result due (mirrored in an atomic, read without the lock while a
/// worker is within the window), whether the run was stopped, and how many
/// workers wait on the window (the calling thread wakes them only then).
struct Shared {
    next: AtomicUsize,
    due: AtomicUsize,
    stopped: AtomicBool,
    /// (next result due, stopped, workers waiting).
    state: Mutex<(usize, bool, usize)>,
    moved: Condvar,
}

impl Shared {
    /// Whether item `i` may start: at once when it is within the window,
    /// else after waiting for the window to reach it; `false` once stopped.
    fn may_start(&self, i: usize) -> bool {
        if self.stopped.load(Ordering::Acquire) {
            return false;
        }
        if i < self.due.load(Ordering::Acquire) + WINDOW {
            return true;
        }
        let mut g = self.state.lock().unwrap_or_else(|e| e.into_inner());
        while !g.1 && i >= g.0 + WINDOW {
            g.2 += 1;
            g = self.moved.wait(g).unwrap_or_else(|e| e.into_inner());
            g.2 -= 1;
        }
        !g.1
    }

    /// The calling thread's news: `due` results handed on, or the run stopped.
    fn advance(&self, due: usize, stopped: bool) {
        let mut g = self.state.lock().unwrap_or_else(|e| e.into_inner());
        g.0 = due;
        g.1 = stopped;
        self.due.store(due, Ordering::Release);
        self.stopped.store(stopped, Ordering::Release);
        if g.2 > 0 {
            self.moved.notify_all();
        }
    }
}

/// [`ordered`] on `threads` workers (at least one).
pub fn ordered_on<I, R, W, S>(threads: usize, items: &[I], work: W, mut sink: S)
where
    I: Sync,
    R: Send,
    W: Fn(usize, &I) -> R + Sync,
    S: FnMut(usize, R) -> bool,
{
    let threads = threads.clamp(1, items.len().max(1));
    if threads == 1 {
        // No thread to start: the same order, the same early stop.
        for (i, item) in items.iter().enumerate() {
            if !sink(i, work(i, item)) {
                return;
            }
        }
        return;
    }
    let batch = batch_size(items.len(), threads);
    let shared = Shared {
        next: AtomicUsize::new(0),
        due: AtomicUsize::new(0),
        stopped: AtomicBool::new(false),
        state: Mutex::new((0, false, 0)),
        moved: Condvar::new(),
    };
    // A batch's results: the index of its first item, then one per item.
    let (tx, rx) = mpsc::channel::<(usize, Vec<R>)>();
    std::thread::scope(|s| {
        let (shared, work) = (&shared, &work);
        let job = move |tx: mpsc::Sender<(usize, Vec<R>)>| {
            move || loop {
                let start = shared.next.fetch_add(batch, Ordering::Relaxed);
                if start >= items.len() {
                    return;
                }
                let end = (start + batch).min(items.len());
                let mut done = Vec::with_capacity(end - start);
                for (i, item) in items.iter().enumerate().take(end).skip(start) {
                    if i >= shared.due.load(Ordering::Acquire) + WINDOW && !done.is_empty() {
                        // About to wait: what is done goes first (the result
                        // due may be among it).
                        let first = i - done.len();
                        let out = std::mem::replace(&mut done, Vec::with_capacity(end - i));
                        if tx.send((first, out)).is_err() {
                            return;
                        }
                    }
                    if !shared.may_start(i) {
                        return;
                    }
                    done.push(work(i, item));
                }
                let first = end - done.len();
                if tx.send((first, done)).is_err() {
                    return;
                }
            }
        };
        for _ in 0..threads {
            // A large stack, so the parsers' deep-recursion guard runs inline;
            // without one (it could not be had) they start their own.
            if crate::stack::spawn_large(s, job(tx.clone())).is_none() {
                s.spawn(job(tx.clone()));
            }
        }
        drop(tx);
        let mut buffer: VecDeque<Option<R>> = VecDeque::new();
        let mut first = 0usize;
        let mut stopped = false;
        for (start, results) in rx.iter() {
            if stopped {
                continue;
            }
            for (k, r) in results.into_iter().enumerate() {
                let at = start + k - first;
                if buffer.len() <= at {
                    buffer.resize_with(at + 1, || None);
                }
                buffer[at] = Some(r);
            }
            let before = first;
            while let Some(Some(_)) = buffer.front() {
                let r = buffer.pop_front().flatten().expect("checked above");
                if !sink(first, r) {
                    stopped = true;
                    break;
                }
                first += 1;
            }
            if first != before || stopped {
                shared.advance(first, stopped);
            }
        }
    });
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_arrive_in_order_whatever_the_timing() {
        let items: Vec<u64> = (0..2000).collect();
        for threads in [1, 2, 3, 8] {
            let mut seen = Vec::new();
            ordered_on(
                threads,
                &items,
                |i, x| {
                    // Uneven work: some items take far longer than others.
                    if i % 97 == 0 {
                        std::thread::sleep(std::time::Duration::from_millis(2));
                    }
                    x * x
                },
                |i, r| {
                    seen.push((i, r));
                    true
                },
            );
            let want: Vec<(usize, u64)> = items.iter().map(|&x| (x as usize, x * x)).collect();
            assert_eq!(seen, want, "{threads} threads");
        }
    }

    #[test]
    fn a_stopped_run_hands_on_nothing_more_and_returns() {
        let items: Vec<usize> = (0..10_000).collect();
        let started = AtomicUsize::new(0);
        let mut got = Vec::new();
        ordered_on(
            4,
            &items,
            |_, &x| {
                started.fetch_add(1, Ordering::Relaxed);
                x
            },
            |i, r| {
                got.push(r);
                i < 9
            },
        );
        assert_eq!(got, (0..10).collect::<Vec<_>>());
        // Workers stop within the window past the stop.
        assert!(started.load(Ordering::Relaxed) <= 10 + WINDOW + 4);
    }

    #[test]
    fn workers_never_run_more_than_the_window_ahead() {
        // The first item is slow: the others may not pile up beyond WINDOW.
        let items: Vec<usize> = (0..5 * WINDOW).collect();
        let done = AtomicUsize::new(0);
        let mut max_ahead = 0;
        ordered_on(
            3,
            &items,
            |i, _| {
                if i == 0 {
                    std::thread::sleep(std::time::Duration::from_millis(50));
                }
                done.fetch_add(1, Ordering::SeqCst)
            },
            |i, _| {
                let ahead = done.load(Ordering::SeqCst) - i;
                max_ahead = max_ahead.max(ahead);
                true
            },
        );
        assert!(max_ahead <= WINDOW + 3, "ran {max_ahead} items ahead");
    }
}
