//! The run's work queue: a producer (the source, on its own thread) hands
//! jobs to a pool of workers, and their results come back to the caller's
//! thread in the order the jobs were made.
//!
//! What bounds memory: the producer waits while `depth` jobs are in flight
//! (made and not yet handed back in order) or while the cost (cells) of
//! those in flight would pass `budget` (one job always goes through). A slow
//! job therefore holds the run back rather than letting finished results
//! pile up behind it. A worker that panics (a bug, never bad input) gives
//! the job's `on_panic` result instead, so the run goes on.

use crate::diagnostic::{Error, Result};
use crate::formats::bag::Flow;
use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc::{channel, sync_channel, Receiver};
use std::sync::{Condvar, Mutex};

/// How many jobs run at once and how many may wait.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Worker threads (at least 1).
    pub threads: usize,
    /// Most jobs in flight.
    pub depth: usize,
    /// Most cost in flight (one job always goes through).
    pub budget: usize,
}

/// What the producer waits on.
#[derive(Default)]
struct Gate {
    jobs: usize,
    cost: usize,
    stop: bool,
}

/// The gate and its signal.
struct Shared {
    gate: Mutex<Gate>,
    freed: Condvar,
}

impl Shared {
    /// Wait for room for a job of `cost`; `false` when the run stops.
    fn enter(&self, cost: usize, lim: &Limits) -> bool {
        let mut g = self.gate.lock().unwrap_or_else(|p| p.into_inner());
        while !g.stop && g.jobs > 0 && (g.jobs >= lim.depth || g.cost + cost > lim.budget) {
            g = self.freed.wait(g).unwrap_or_else(|p| p.into_inner());
        }
        if g.stop {
            return false;
        }
        g.jobs += 1;
        g.cost += cost;
        true
    }

    fn leave(&self, cost: usize) {
        let mut g = self.gate.lock().unwrap_or_else(|p| p.into_inner());
        g.jobs -= 1;
        g.cost -= cost;
        self.freed.notify_all();
    }

    fn stop(&self) {
        let mut g = self.gate.lock().unwrap_or_else(|p| p.into_inner());
        g.stop = true;
        self.freed.notify_all();
    }
}

/// A submit function: hand one job of a cost to the pool (waits for room);
/// `Flow::Stop` when the run is stopping (the caller's consumer failed).
pub type Submit<'a, J> = dyn FnMut(J, usize) -> Flow + 'a;

/// Run `produce` on its own thread, every job it submits through `work` on
/// `lim.threads` workers, and `consume` on this thread on the results in
/// submission order. The first error of `consume` stops the run and is
/// returned; otherwise what `produce` returned.
pub fn ordered<J, O, R>(
    lim: Limits,
    produce: impl FnOnce(&mut Submit<J>) -> Result<R> + Send,
    work: &(dyn Fn(&J) -> O + Sync),
    on_panic: &(dyn Fn(&J) -> O + Sync),
    consume: &mut dyn FnMut(O) -> Result<()>,
) -> Result<R>
where
    J: Send,
    O: Send,
    R: Send,
{
    let lim = Limits {
        threads: lim.threads.max(1),
        depth: lim.depth.max(1),
        budget: lim.budget.max(1),
    };
    let shared = Shared {
        gate: Mutex::new(Gate::default()),
        freed: Condvar::new(),
    };
    let (job_tx, job_rx) = sync_channel::<(u64, J, usize)>(lim.depth);
    let job_rx = Mutex::new(job_rx);
    let (out_tx, out_rx) = channel::<(u64, O, usize)>();
    std::thread::scope(|sc| {
        let shared = &shared;
        let producer = sc.spawn(move || {
            let mut seq = 0u64;
            let mut submit = |job: J, cost: usize| {
                if !shared.enter(cost, &lim) || job_tx.send((seq, job, cost)).is_err() {
                    return Flow::Stop;
                }
                seq += 1;
                Flow::Continue
            };
            produce(&mut submit)
        });
        for _ in 0..lim.threads {
            let out_tx = out_tx.clone();
            let job_rx = &job_rx;
            sc.spawn(move || worker(job_rx, &out_tx, work, on_panic));
        }
        drop(out_tx);
        let mut failed: Option<Error> = None;
        let mut pending: BTreeMap<u64, (O, usize)> = BTreeMap::new();
        let mut next = 0u64;
        for (seq, out, cost) in out_rx {
            pending.insert(seq, (out, cost));
            while let Some((out, cost)) = pending.remove(&next) {
                next += 1;
                if failed.is_none() {
                    if let Err(e) = consume(out) {
                        failed = Some(e);
                        shared.stop();
                    }
                }
                shared.leave(cost);
            }
        }
        let produced = producer.join().unwrap_or_else(|_| {
            Err(Error::invalid(
                "the run's reader stopped unexpectedly (a bug)",
            ))
        });
        match failed {
            Some(e) => Err(e),
            None => produced,
        }
    })
}

fn worker<J, O>(
    jobs: &Mutex<Receiver<(u64, J, usize)>>,
    out: &std::sync::mpsc::Sender<(u64, O, usize)>,
    work: &(dyn Fn(&J) -> O + Sync),
    on_panic: &(dyn Fn(&J) -> O + Sync),
) {
    loop {
        let next = jobs.lock().unwrap_or_else(|p| p.into_inner()).recv();
        let Ok((seq, job, cost)) = next else { return };
        let o = catch_unwind(AssertUnwindSafe(|| work(&job))).unwrap_or_else(|_| on_panic(&job));
        if out.send((seq, o, cost)).is_err() {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_back_in_order_with_a_bounded_number_in_flight() {
        let lim = Limits {
            threads: 3,
            depth: 4,
            budget: 100,
        };
        let inflight = std::sync::atomic::AtomicUsize::new(0);
        let most = std::sync::atomic::AtomicUsize::new(0);
        let mut got = Vec::new();
        let n = ordered(
            lim,
            |submit| {
                for k in 0..200u64 {
                    let now = inflight.fetch_add(1, std::sync::atomic::Ordering::SeqCst) + 1;
                    most.fetch_max(now, std::sync::atomic::Ordering::SeqCst);
                    if submit(k, 10) == Flow::Stop {
                        break;
                    }
                }
                Ok(200)
            },
            &|k: &u64| {
                // Later jobs finish first now and then.
                std::thread::sleep(std::time::Duration::from_micros((k % 7) * 50));
                *k
            },
            &|_| u64::MAX,
            &mut |k| {
                inflight.fetch_sub(1, std::sync::atomic::Ordering::SeqCst);
                got.push(k);
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(n, 200);
        assert_eq!(got, (0..200).collect::<Vec<_>>());
        // The producer counts a job before submit lets it through: depth + 1.
        assert!(most.load(std::sync::atomic::Ordering::SeqCst) <= 5);
    }

    #[test]
    fn a_panicking_job_and_a_failing_consumer() {
        let lim = Limits {
            threads: 2,
            depth: 2,
            budget: 10,
        };
        let mut got = Vec::new();
        let r = ordered(
            lim,
            |submit| {
                for k in 0..50u32 {
                    if submit(k, 1) == Flow::Stop {
                        return Ok(k);
                    }
                }
                Ok(50)
            },
            &|k: &u32| if *k == 3 { panic!("bug") } else { *k },
            &|_| 999,
            &mut |k| {
                got.push(k);
                if k == 10 {
                    return Err(Error::invalid("stop"));
                }
                Ok(())
            },
        );
        assert!(r.is_err());
        assert_eq!(&got[..5], &[0, 1, 2, 999, 4]);
    }
}
