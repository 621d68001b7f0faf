//! The run reader as an iterator: [`Run::open`] checks the options, reads
//! the run's plan (the source, the transforms, the frames, the poses) and
//! starts the work; each [`Iterator::next`] hands back the next scan's (or
//! pair's) [`ScanResult`] in run order; [`Run::finish`] gives the summary.
//!
//! Why a thread: the run's work queue (`run::work`) pushes results to a
//! consumer on the thread that runs it, in order, with its memory bounded by
//! the scans in flight. The iterator runs that queue on a thread of its own
//! and takes its results through a bounded channel, so a caller that stops
//! taking results holds the run back (nothing piles up), and one that drops
//! the [`Run`] stops it: the queue's next hand-over fails and the workers
//! wind down before `drop` returns.

use crate::diagnostic::{Code, Error, Result, Warning};
use crate::frames::FrameGraph;
use crate::pipeline::run as pr;
use crate::pipeline::RunOptions;
use crate::progress::{NoProgress, ProgressFactory};
use crate::report::run::{RunHeader, RunReport, RunSink, RunUnit, ScanRecord};
use crate::run::frames::RunFrame;
use crate::run::scan::Outcome;
use std::path::PathBuf;
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::sync::Arc;
use std::thread::JoinHandle;

/// Results the reader may hold ahead of the caller: a few per worker is
/// enough to keep the workers busy while the caller writes one out (a
/// result is a few hundred numbers, never a scan's points).
const RESULTS_AHEAD: usize = 16;

/// What the reader's thread hands over.
enum Message {
    /// The plan is read: the header, the frames and the transforms.
    Begin(Box<Plan>),
    /// One scan's (or pair's) outcome, in run order.
    Scan(Box<Outcome>),
}

/// The header, the frames and the transforms.
type Plan = (Arc<RunHeader>, Vec<RunFrame>, Option<FrameGraph>);

/// What the reader's thread returns: the summary and the warnings.
type Summary = Result<(RunReport, Vec<Warning>)>;

/// The sink the run's work queue writes to: the channel to the iterator,
/// the plan announced once before the first scan.
struct Announce {
    tx: SyncSender<Message>,
    frames: Option<(Vec<RunFrame>, Option<FrameGraph>)>,
}

impl Announce {
    fn send(&self, m: Message) -> Result<()> {
        // The iterator is gone: stop the run (the error is never seen).
        self.tx
            .send(m)
            .map_err(|_| Error::new(Code::Io, "the run's reader was dropped"))
    }
}

impl RunSink for Announce {
    fn frames(&mut self, frames: &[RunFrame], graph: Option<&FrameGraph>) -> Result<()> {
        self.frames = Some((frames.to_vec(), graph.cloned()));
        Ok(())
    }

    fn begin(&mut self, h: &RunHeader) -> Result<()> {
        let (frames, graph) = self.frames.take().unwrap_or_default();
        self.send(Message::Begin(Box::new((
            Arc::new(h.clone()),
            frames,
            graph,
        ))))
    }

    fn outcome(&mut self, _: &RunHeader, o: &Outcome) -> Result<()> {
        self.send(Message::Scan(Box::new(o.clone())))
    }
}

/// A recorded run read scan by scan: every sensor_msgs/PointCloud2 of a
/// bag's topic (MCAP, rosbag2, ROS 1), every scan of a KITTI sequence or
/// every point file of a folder, through the detector in the scan frame and
/// in the body frames the run's transforms (or rig files) give. An
/// [`Iterator`] of [`ScanResult`]s in run order; a scan that cannot be
/// analysed is a result with [`ScanResult::skipped`] set, never an error.
/// [`Run::finish`] gives the summary ([`RunReport`]) and the warnings.
///
/// A run of ten scans of a KITTI sequence, written here: a floor, whose
/// point-displacement eigenvalues are 0 (x, y, yaw: no point moves along
/// the floor's normal) and 1 (z, roll, pitch: wholly along it) in every
/// frame:
///
/// ```
/// use extrinsic_audit::{Run, RunOptions};
///
/// # fn main() -> extrinsic_audit::Result<()> {
/// let dir = tempfile::tempdir().unwrap();
/// let velodyne = dir.path().join("velodyne");
/// std::fs::create_dir(&velodyne).unwrap();
/// for scan in 0..10 {
///     // x y z intensity as little-endian f32, a 4 m square on a 5 cm grid.
///     let mut bytes = Vec::new();
///     for i in 0..81 {
///         for j in 0..81 {
///             for v in [-2.0 + 0.05 * i as f32, -2.0 + 0.05 * j as f32, -1.0, 0.0] {
///                 bytes.extend(v.to_le_bytes());
///             }
///         }
///     }
///     std::fs::write(velodyne.join(format!("{scan:06}.bin")), bytes).unwrap();
/// }
/// let mut opts = RunOptions::default();
/// opts.scans.window.every = 3; // scans 0, 3, 6, 9
/// opts.detector.normals.radius = 0.2;
/// let mut run = Run::open(&[dir.path()], &opts)?;
/// assert_eq!(run.frames(), ["scan"]);
/// let mut indices = Vec::new();
/// for result in &mut run {
///     let result = result?;
///     assert!(result.skipped().is_none());
///     let pd = result.eigenvalues("scan", "point_displacement").unwrap();
///     for (got, want) in pd.iter().zip([0.0, 0.0, 0.0, 1.0, 1.0, 1.0]) {
///         assert!((got - want).abs() < 1e-9, "{got} vs {want}");
///     }
///     indices.push(result.index());
/// }
/// assert_eq!(indices, [0, 3, 6, 9]);
/// let (summary, warnings) = run.finish()?;
/// assert_eq!((summary.read, summary.analysed), (4, 4));
/// assert!(warnings.is_empty(), "{warnings:?}");
/// # Ok(())
/// # }
/// ```
pub struct Run {
    header: Arc<RunHeader>,
    frames: Vec<RunFrame>,
    graph: Option<FrameGraph>,
    inbox: Option<Receiver<Message>>,
    thread: Option<JoinHandle<Summary>>,
    /// The summary once the thread is joined (taken by `finish`).
    end: Option<Summary>,
}

impl std::fmt::Debug for Run {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Run")
            .field("frames", &self.frames())
            .field("families", &self.families())
            .field("pairs", &self.pairs())
            .finish_non_exhaustive()
    }
}

impl Run {
    /// Open the run `paths` (a bag or the parts of one recording, a KITTI
    /// sequence folder, a folder of point files, point files or a quoted
    /// pattern): the options checked, the plan read (the topic, the
    /// transforms, the frames, the poses of a pair run); an error here is a
    /// run that cannot be read at all.
    pub fn open<P: AsRef<std::path::Path>>(paths: &[P], opts: &RunOptions) -> Result<Run> {
        Run::open_with(paths, opts, Arc::new(NoProgress))
    }

    /// [`Run::open`], the scans read reported to a progress from `bars`.
    pub fn open_with<P: AsRef<std::path::Path>>(
        paths: &[P],
        opts: &RunOptions,
        bars: Arc<dyn ProgressFactory + Send>,
    ) -> Result<Run> {
        let inputs: Vec<PathBuf> = paths.iter().map(|p| p.as_ref().to_path_buf()).collect();
        let opts = opts.clone();
        let (tx, rx) = sync_channel(RESULTS_AHEAD);
        let thread = std::thread::Builder::new()
            .name("audit-run".into())
            .spawn(move || {
                let mut sink = Announce { tx, frames: None };
                pr::run(&inputs, &opts, &mut sink, &*bars)
            })
            .map_err(|e| Error::new(Code::Io, format!("cannot start the run's reader: {e}")))?;
        match rx.recv() {
            Ok(Message::Begin(plan)) => {
                let (header, frames, graph) = *plan;
                Ok(Run {
                    header,
                    frames,
                    graph,
                    inbox: Some(rx),
                    thread: Some(thread),
                    end: None,
                })
            }
            // The plan failed (the thread is over), or a bug sent a scan
            // before the plan.
            _ => Err(join(thread)
                .err()
                .unwrap_or_else(|| Error::new(Code::Io, "the run's reader stopped early"))),
        }
    }

    /// The frames every result is reported in, the scan frame (`scan`)
    /// first.
    pub fn frames(&self) -> Vec<&str> {
        self.header.frames.iter().map(|f| f.name.as_str()).collect()
    }

    /// The families every frame is reported with, by key
    /// (`point_displacement`, `characteristic_length@1m`, ...).
    pub fn families(&self) -> Vec<&str> {
        self.header
            .families
            .iter()
            .map(|f| f.key.as_str())
            .collect()
    }

    /// Whether the results are scan pairs.
    pub fn pairs(&self) -> bool {
        self.header.unit == RunUnit::Pairs
    }

    /// The CSV header of [`ScanResult::csv_row`] (`audit run --csv`'s).
    pub fn csv_header(&self) -> Vec<String> {
        self.header.csv_header()
    }

    /// The summary once every scan is read (the ones not yet taken are read
    /// first): scans read and skipped, degenerate intervals per family and
    /// frame, label changes between frames; and the run's warnings
    /// (skipped scans, damage, transforms missing). An error is what
    /// stopped the read (an unreadable file, never a bad scan), if
    /// [`Iterator::next`] has not already returned it (then the same
    /// error again).
    pub fn finish(mut self) -> Result<(RunReport, Vec<Warning>)> {
        for r in self.by_ref() {
            r?;
        }
        self.end
            .take()
            .unwrap_or_else(|| Err(Error::new(Code::Io, "the run's summary was already taken")))
    }

    /// The run's frames and transforms (for the command line's MCAP).
    pub(crate) fn transforms(&self) -> (&[RunFrame], Option<&FrameGraph>) {
        (&self.frames, self.graph.as_ref())
    }

    /// The thread is over: keep its summary, give out its error once.
    fn ended(&mut self) -> Option<Result<ScanResult>> {
        self.inbox = None;
        let thread = self.thread.take()?;
        match join(thread) {
            Ok(s) => {
                self.end = Some(Ok(s));
                None
            }
            Err(e) => {
                self.end = Some(Err(e.clone()));
                Some(Err(e))
            }
        }
    }
}

/// The reader thread's result; a panic (a bug) as an error.
fn join(thread: JoinHandle<Summary>) -> Summary {
    thread.join().unwrap_or_else(|_| {
        Err(Error::new(
            Code::Io,
            "the run's reader failed unexpectedly (a bug: please report it with the run)",
        ))
    })
}

impl Iterator for Run {
    type Item = Result<ScanResult>;

    /// The next scan's (or pair's) result, waiting for it; after the last,
    /// the error that stopped the read if one did, then `None`.
    fn next(&mut self) -> Option<Result<ScanResult>> {
        let msg = self.inbox.as_ref().map(Receiver::recv);
        match msg {
            Some(Ok(Message::Scan(outcome))) => Some(Ok(ScanResult {
                record: self.header.json_line(&outcome),
                header: self.header.clone(),
                outcome,
            })),
            Some(Ok(Message::Begin(..))) | Some(Err(_)) => self.ended(),
            None => None,
        }
    }
}

impl Drop for Run {
    fn drop(&mut self) {
        // Closing the channel stops the run at its next result.
        self.inbox = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// One scan's (or pair's) result: what identifies it, why it was skipped if
/// it was, and every family's eigenvalues, count and footprint in every
/// frame of the run. [`ScanResult::to_json`] is `audit run --jsonl`'s line
/// (`docs/schemas/run-scan.schema.json`), [`ScanResult::csv_row`] its
/// `--csv` row.
#[derive(Debug, Clone)]
pub struct ScanResult {
    header: Arc<RunHeader>,
    outcome: Box<Outcome>,
    record: ScanRecord,
}

impl ScanResult {
    /// The scan's place in the run (a pair's source's).
    pub fn index(&self) -> usize {
        self.record.index
    }

    /// Seconds after the run's first scan, where the run has times.
    pub fn time_s(&self) -> Option<f64> {
        self.record.time_s
    }

    /// The scan's `header.stamp` (ns), for bags.
    pub fn stamp_ns(&self) -> Option<i64> {
        self.record.stamp_ns
    }

    /// The scan frame (`header.frame_id`, or the run's `lidar_frame`).
    pub fn frame_id(&self) -> Option<&str> {
        self.record.frame_id.as_deref()
    }

    /// The file, or where in the bag.
    pub fn place(&self) -> &str {
        &self.record.place
    }

    /// A pair's target scan index.
    pub fn target_index(&self) -> Option<usize> {
        self.record.pair.as_ref().map(|p| p.target_index)
    }

    /// Why the scan was skipped (`empty`, `invalid-cloud`, `too-large`,
    /// `unreadable`, ...) and the message; `None`: analysed.
    pub fn skipped(&self) -> Option<(&str, &str)> {
        let (why, msg) = self.outcome.skipped.as_ref()?;
        Some((why.name(), msg.as_str()))
    }

    /// Points in `H` (a pair's correspondences); `None` when skipped.
    pub fn points(&self) -> Option<usize> {
        self.record.points
    }

    /// The generalized eigenvalues of `H v = lambda M v`, ascending, of
    /// `family` (a key of [`Run::families`]) in `frame` (one of
    /// [`Run::frames`]); `None` when skipped, when the scan's transforms do
    /// not reach the frame, or when the family has no answer.
    pub fn eigenvalues(&self, frame: &str, family: &str) -> Option<[f64; 6]> {
        self.family(frame, family)?.eigenvalues
    }

    /// How many of those eigenvalues are below the family's threshold.
    pub fn degenerate_count(&self, frame: &str, family: &str) -> Option<usize> {
        self.family(frame, family)?.degenerate_count
    }

    /// The per-axis footprint (rot x, y, z, trans x, y, z) of the degenerate
    /// subspace of `family` in `frame`.
    pub fn footprint(&self, frame: &str, family: &str) -> Option<[bool; 6]> {
        self.family(frame, family)?.footprint
    }

    fn family(&self, frame: &str, family: &str) -> Option<&crate::report::run::FamilyRecord> {
        let f = self.record.frames.iter().find(|f| f.frame == frame)?;
        f.families.as_ref()?.iter().find(|x| x.family == family)
    }

    /// This scan's warnings (also summed up in [`Run::finish`]'s).
    pub fn warnings(&self) -> &[Warning] {
        &self.outcome.warnings
    }

    /// The JSON line `audit run --jsonl` writes for this scan.
    pub fn to_json(&self) -> String {
        // Plain numbers, strings and options: serialization cannot fail.
        serde_json::to_string(&self.record).unwrap_or_default()
    }

    /// The CSV row `audit run --csv` writes (fields, not yet quoted; the
    /// columns of [`Run::csv_header`]).
    pub fn csv_row(&self) -> Vec<String> {
        self.header.csv_row(&self.outcome)
    }
}

/// The run's frames and transforms, for `audit run --format mcap`
/// (`internals`).
pub fn run_transforms(run: &Run) -> (&[RunFrame], Option<&FrameGraph>) {
    run.transforms()
}

/// A result's record, for `audit run --format mcap` (`internals`).
pub fn scan_record(r: &ScanResult) -> &ScanRecord {
    &r.record
}
