//! Files on disk: binary PLY and PCD large enough are split into blocks,
//! which scoped threads take one at a time from a shared counter, each block
//! decoded from its own file handle into its own accumulator; the block sums
//! are then added in file order, so the result does not depend on the thread
//! count or on which thread took which block. Everything else is decoded on
//! this thread.

use super::binary::{decode_records, Layout, Run};
use super::check::{Checker, Stats};
use super::decode::{decode, detect, Kind};
use super::record::{PointFormat, Sink};
use super::source::{io_error, Source};
use super::{pcd, ply};
use crate::degeneracy::{worker_count, Accumulator, Block, Kernel, BLOCK};
use crate::diagnostic::Result;
use crate::progress::{Counted, Progress};
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Decode the file `path` (`len` bytes, open in `src`) into `acc`.
pub(super) fn decode_file<R: Read>(
    path: &Path,
    len: u64,
    src: &mut Source<R>,
    acc: &mut Accumulator,
    progress: &dyn Progress,
) -> Result<(PointFormat, Stats)> {
    match detect(src)? {
        Kind::Ply => {
            let h = ply::read_header(src, false)?;
            if h.format == PointFormat::PlyAscii {
                return ply::body(src, &h, acc);
            }
            let (skip, layout) = ply::binary_plan(&h)?;
            let start = src.offset().saturating_add(skip);
            let total = h.count();
            let stats = records(
                path,
                (len, ply::tail_bytes(&h)),
                start,
                &layout,
                &|a, b| ply::run(&h, a, b),
                (total, progress),
                acc,
            )?;
            if ply::tail_bytes(&h).is_none() {
                // List elements after the vertices: read them by their counts.
                let end = start.saturating_add((total as u64).saturating_mul(layout.rec as u64));
                let mut f = crate::input::open_regular(path)?;
                f.seek(SeekFrom::Start(end)).map_err(|e| io_error(&e))?;
                ply::list_tail(&mut Source::at(f, end), &h)?;
            }
            Ok((h.format, stats))
        }
        Kind::Pcd => {
            let h = pcd::read_header(src, false)?;
            if h.format != PointFormat::PcdBinary {
                return pcd::body(src, &h, acc);
            }
            let start = src.offset();
            let layout = pcd::layout(&h);
            let stats = records(
                path,
                (len, Some(0)),
                start,
                &layout,
                &|a, b| pcd::run(&h, a, b),
                (h.n, progress),
                acc,
            )?;
            Ok((h.format, stats))
        }
        Kind::Las | Kind::Csv => decode(src, acc, false),
    }
}

/// `total` records of `layout` from byte `start` of the file, which is
/// `len` bytes long and holds `tail` bytes after the records (`None`: not
/// known, e.g. PLY faces after the vertices).
fn records(
    path: &Path,
    (len, tail): (u64, Option<u64>),
    start: u64,
    layout: &Layout,
    run: &(dyn Fn(usize, usize) -> Run + Sync),
    (total, progress): (usize, &dyn Progress),
    acc: &mut Accumulator,
) -> Result<Stats> {
    // The file's length settles a lying header before any decoding.
    let avail = len.saturating_sub(start) / layout.rec as u64;
    if avail < total as u64 {
        return Err(run(0, total).truncated(layout.rec, avail as usize));
    }
    // ... and a header that claims fewer records than the file holds (issue 12).
    let end = (total as u64)
        .saturating_mul(layout.rec as u64)
        .saturating_add(start);
    if let Some(extra) = tail.and_then(|t| len.saturating_sub(end).checked_sub(t)) {
        if extra > 0 {
            return Err(run(0, total).excess(
                layout.rec,
                extra,
                end.saturating_add(tail.unwrap_or(0)),
            ));
        }
    }
    let blocks = total.div_ceil(BLOCK);
    let threads = worker_count(0, blocks, total);
    // One block per work item, taken from a shared counter: a core that is
    // busy elsewhere takes fewer blocks instead of holding up a fixed half
    // of the file (the fixed halves made this run bimodal on a machine with
    // any other load: BENCHMARKS.md, issue 24).
    let ranges: Vec<(usize, usize)> = (0..total)
        .step_by(BLOCK)
        .map(|a| (a, (a + BLOCK).min(total)))
        .collect();
    let kernel = acc.kernel();
    let work = |&(a, b): &(usize, usize)| {
        decode_range(path, start, layout, &run(a, b - a), (kernel, progress))
    };
    let parts = if threads <= 1 {
        ranges.iter().map(work).collect()
    } else {
        queued(&ranges, threads, &work)
    };
    let mut stats = Stats::default();
    for p in parts {
        let p = p?;
        for b in &p.blocks {
            acc.add_block(b);
        }
        acc.add_count(p.count);
        stats.merge(&p.stats);
    }
    Ok(stats)
}

/// `work` of every range, in order, on `threads` threads (this one among
/// them) that take the next range from a shared counter. A range whose
/// thread could not start or panicked (a bug) is decoded here afterwards.
fn queued<W>(ranges: &[(usize, usize)], threads: usize, work: &W) -> Vec<Result<Part>>
where
    W: Fn(&(usize, usize)) -> Result<Part> + Sync,
{
    let next = AtomicUsize::new(0);
    let drain = || {
        let mut done = Vec::new();
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(r) = ranges.get(i) else { break done };
            done.push((i, work(r)));
        }
    };
    let mut out: Vec<Option<Result<Part>>> = ranges.iter().map(|_| None).collect();
    std::thread::scope(|s| {
        let drain = &drain;
        let handles: Vec<_> = (1..threads)
            .map(|_| std::thread::Builder::new().spawn_scoped(s, drain))
            .collect();
        let mut all = drain();
        for h in handles.into_iter().flatten() {
            all.extend(h.join().unwrap_or_default());
        }
        for (i, part) in all {
            out[i] = Some(part);
        }
    });
    out.into_iter()
        .zip(ranges)
        .map(|(part, r)| part.unwrap_or_else(|| work(r)))
        .collect()
}

/// What one range gave: its block sums in order, its point count, its stats.
struct Part {
    blocks: Vec<Block>,
    count: usize,
    stats: Stats,
}

/// Collects block sums instead of adding them up.
struct BlockSink {
    acc: Accumulator,
    blocks: Vec<Block>,
}

impl Sink for BlockSink {
    fn begin(&mut self, _weighted: bool, _hint: usize) {}
    #[inline(always)]
    fn point(&mut self, p: &[f64; 3], n: &[f64; 3], w: f64) {
        self.acc.push_point(p, n, w);
    }
    fn points(&mut self, p: &[[f64; 3]], n: &[[f64; 3]], w: &[f64]) {
        self.acc.push_slices(p, n, Some(w));
    }
    fn end_block(&mut self) {
        self.blocks.push(self.acc.take_block());
    }
}

fn decode_range(
    path: &Path,
    start: u64,
    layout: &Layout,
    run: &Run,
    (kernel, progress): (Kernel, &dyn Progress),
) -> Result<Part> {
    let mut f = crate::input::open_regular(path)?;
    let at = start + (run.first as u64) * layout.rec as u64;
    f.seek(SeekFrom::Start(at)).map_err(|e| io_error(&e))?;
    let bytes = f.take((run.count as u64) * layout.rec as u64);
    let mut src = Source::at(Counted::new(bytes, at, progress), at);
    let mut sink = BlockSink {
        acc: Accumulator::with_kernel(kernel).threads(1),
        blocks: Vec::new(),
    };
    let stats = {
        let mut ck = Checker::new(&mut sink, layout.roles[6].is_some(), 0);
        decode_records(&mut src, layout, run, &mut ck)?;
        ck.stats
    };
    // The last range ends with a partial block (or none).
    if !run.count.is_multiple_of(BLOCK) {
        sink.end_block();
    }
    Ok(Part {
        count: sink.acc.count(),
        blocks: sink.blocks,
        stats,
    })
}
