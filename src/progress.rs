//! Progress of long work (the threshold calibration's sweep, reading a point
//! file, estimating normals), reported to a caller-supplied [`Progress`]: the
//! library counts steps, the binary decides how to show them (a bar on a
//! terminal's standard error, nothing otherwise). Readers count bytes through
//! [`Counted`]; the LAS/LAZ reader and the normal estimation count points.

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

/// Hands out a fresh [`Progress`] for each piece of work that a command does
/// in turn (reading a scan, then estimating its normals). The library asks
/// only for work long enough to be worth showing (a point file of at least
/// `tolerances::PROGRESS_MIN_BYTES`, at least `PROGRESS_MIN_POINTS` normals):
/// the binary decides how to draw it, never whether.
pub trait ProgressFactory: Sync {
    /// The progress of one piece of work.
    fn progress(&self) -> Box<dyn Progress>;
}

impl ProgressFactory for NoProgress {
    fn progress(&self) -> Box<dyn Progress> {
        Box::new(NoProgress)
    }
}

/// A reader that reports the bytes it reads: the high-water mark of its
/// position, so that bytes read again after a seek back are not counted twice.
pub struct Counted<'a, R> {
    inner: R,
    pos: u64,
    high: u64,
    progress: &'a dyn Progress,
}

impl<'a, R> Counted<'a, R> {
    /// `inner` positioned at byte `at` of the work's total.
    pub fn new(inner: R, at: u64, progress: &'a dyn Progress) -> Self {
        Counted {
            inner,
            pos: at,
            high: at,
            progress,
        }
    }
}

impl<R: std::io::Read> std::io::Read for Counted<'_, R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.pos += n as u64;
        if self.pos > self.high {
            self.progress.advance(self.pos - self.high);
            self.high = self.pos;
        }
        Ok(n)
    }
}

impl<R: std::io::Seek> std::io::Seek for Counted<'_, R> {
    fn seek(&mut self, to: std::io::SeekFrom) -> std::io::Result<u64> {
        self.pos = self.inner.seek(to)?;
        Ok(self.pos)
    }
}
