//! The progress line of a long bag read.

use crate::tolerances::BAG_PROGRESS_MIN_BYTES;
use std::path::Path;

/// A one-line progress indicator on stderr, shown only on a terminal and for
/// reads of at least `BAG_PROGRESS_MIN_BYTES`; erased when dropped.
pub struct Progress {
    label: String,
    total: u64,
    on: bool,
    last: Option<u64>,
}

impl Progress {
    /// A progress line for reading `total` bytes of `path`.
    pub fn new(path: &Path, total: u64) -> Self {
        use std::io::IsTerminal;
        Progress {
            label: path.display().to_string(),
            total,
            on: total >= BAG_PROGRESS_MIN_BYTES && std::io::stderr().is_terminal(),
            last: None,
        }
    }

    /// `done` of the `total` bytes have been read.
    pub fn update(&mut self, done: u64) {
        if !self.on {
            return;
        }
        let pct = done.min(self.total) * 100 / self.total.max(1);
        if self.last != Some(pct) {
            self.last = Some(pct);
            eprint!(
                "\rreading {}: {pct:3}% of {} MiB",
                self.label,
                self.total >> 20
            );
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        if self.last.is_some() {
            eprint!("\r\x1b[K");
        }
    }
}
