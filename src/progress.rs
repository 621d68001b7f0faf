//! Progress of long work (the threshold calibration's sweep), reported to a
//! caller-supplied [`Progress`]: the library counts steps, the binary decides
//! how to show them (a bar on a terminal's standard error, nothing otherwise).

/// Receives the progress of one piece of work; every method may be called
/// from several threads.
pub trait Progress: Sync {
    /// The work begins: `total` steps of `what`.
    fn start(&self, _total: u64, _what: &str) {}
    /// `n` more steps are done.
    fn advance(&self, _n: u64) {}
    /// The work is over (done or failed).
    fn finish(&self) {}
}

/// Reports nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoProgress;

impl Progress for NoProgress {}
