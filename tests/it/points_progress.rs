//! Progress while reading a point file and estimating normals (issue 13):
//! the library reports every byte (every point, for LAS/LAZ and normals)
//! once; the binary draws a bar only on a terminal's standard error, and only
//! for a file large enough to take about a second.

use crate::common::run_cli;
use crate::widths::{have_pty, pty_run, pty_run_stdout};
use extrinsic_audit::internals::degeneracy::normals::{estimate_normals_progress, NormalParams};
use extrinsic_audit::internals::degeneracy::points::{
    accumulate_file_with, read_xyz_with, write_pcd, write_ply, Encoding,
};
use extrinsic_audit::internals::pipeline::detector::{read_scan, ScanOptions};
use extrinsic_audit::internals::tolerances::PROGRESS_MIN_BYTES;
use extrinsic_audit::{NoProgress, Progress, ProgressFactory};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// Records what it is told.
#[derive(Default)]
struct Record {
    total: AtomicU64,
    done: AtomicU64,
    what: Mutex<Vec<String>>,
    finished: AtomicU64,
}

impl Progress for Record {
    fn start(&self, total: u64, what: &str) {
        self.total.store(total, Ordering::SeqCst);
        self.what.lock().unwrap().push(what.to_string());
    }
    fn advance(&self, n: u64) {
        self.done.fetch_add(n, Ordering::SeqCst);
    }
    fn finish(&self) {
        self.finished.fetch_add(1, Ordering::SeqCst);
    }
}

/// Counts the progress bars the library asks for.
#[derive(Default)]
struct Asks(AtomicU64);

impl ProgressFactory for Asks {
    fn progress(&self) -> Box<dyn Progress> {
        self.0.fetch_add(1, Ordering::SeqCst);
        Box::new(NoProgress)
    }
}

/// Points on three planes (a corner), with their normals.
fn corner(n: usize) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let side = ((n / 3) as f64).sqrt().ceil() as usize;
    let mut p = Vec::new();
    let mut nn = Vec::new();
    for k in 0..n {
        let (i, j) = ((k / 3) % side, (k / 3) / side);
        let (a, b) = (i as f64 * 0.05, j as f64 * 0.05);
        let (q, m) = match k % 3 {
            0 => ([a, b, 0.0], [0.0, 0.0, 1.0]),
            1 => ([a, 0.0, b], [0.0, 1.0, 0.0]),
            _ => ([0.0, a, b], [1.0, 0.0, 0.0]),
        };
        p.push(q);
        nn.push(m);
    }
    (p, nn)
}

#[test]
fn readers_report_every_byte_once_and_las_every_point() {
    let tmp = tempfile::tempdir().unwrap();
    let (p, n) = corner(5000);
    for (name, bytes) in [
        ("c.pcd", write_pcd(&p, &n, Encoding::BinaryLittleEndian)),
        ("c.ply", write_ply(&p, &n, Encoding::Ascii)),
    ] {
        let path = tmp.path().join(name);
        std::fs::write(&path, &bytes).unwrap();
        let len = bytes.len() as u64;
        // Held points, and streamed H and M (the ranges of a binary file).
        let r = Record::default();
        read_xyz_with(&path, &r).unwrap();
        assert_eq!(r.total.load(Ordering::SeqCst), len, "{name}");
        assert_eq!(r.done.load(Ordering::SeqCst), len, "{name}");
        assert_eq!(r.finished.load(Ordering::SeqCst), 1);
        let r = Record::default();
        accumulate_file_with(&path, None, &r).unwrap();
        assert_eq!(r.total.load(Ordering::SeqCst), len, "{name}");
        // The header and the first buffer are read by the detector, then
        // again by the range that holds them: counted at most twice.
        let done = r.done.load(Ordering::SeqCst);
        assert!(
            done >= len && done <= len + (1 << 16),
            "{name}: {done} of {len}"
        );
    }
    // The real LAS and LAZ scans (the test-data folder), where they are there.
    use crate::common::testdata::{file, AUTZEN_LAS, LAS_1_4};
    for path in [AUTZEN_LAS, LAS_1_4].into_iter().filter_map(file) {
        let r = Record::default();
        let d = read_xyz_with(&path, &r).unwrap();
        assert_eq!(r.total.load(Ordering::SeqCst), d.points.len() as u64);
        assert_eq!(r.done.load(Ordering::SeqCst), d.points.len() as u64);
        assert_eq!(*r.what.lock().unwrap(), ["points read"]);
    }
}

#[test]
fn normal_estimation_reports_every_point_once_on_any_thread_count() {
    let (p, _) = corner(20_000);
    let prm = NormalParams {
        radius: 0.2,
        knn: None,
        min_neighbours: 8,
        min_planarity: None,
        viewpoint: [1.0, 1.0, 1.0],
    };
    for threads in [1, 2, 3] {
        let r = Record::default();
        estimate_normals_progress(&p, &prm, threads, &r).unwrap();
        assert_eq!(r.total.load(Ordering::SeqCst), 20_000);
        assert_eq!(r.done.load(Ordering::SeqCst), 20_000, "{threads} threads");
        assert_eq!(r.finished.load(Ordering::SeqCst), 1);
    }
}

#[test]
fn a_big_file_draws_a_bar_on_a_terminal_and_nothing_in_a_pipe() {
    let tmp = tempfile::tempdir().unwrap();
    // Just over the threshold: 48-byte records.
    let n = (PROGRESS_MIN_BYTES / 48 + 1000) as usize;
    let (p, nn) = corner(n);
    let path = tmp.path().join("big.pcd");
    std::fs::write(&path, write_pcd(&p, &nn, Encoding::BinaryLittleEndian)).unwrap();
    let args = ["degeneracy", path.to_str().unwrap(), "--format", "json"];
    let (code, out, err) = run_cli(&args);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("point_displacement"));
    // Piped: not one byte of progress (nor a carriage return).
    assert!(err.is_empty(), "{err:?}");
    // A small file gets no bar even on a terminal.
    let small = tmp.path().join("small.pcd");
    std::fs::write(
        &small,
        write_pcd(&p[..3000], &nn[..3000], Encoding::BinaryLittleEndian),
    )
    .unwrap();
    // The library decides, the binary only draws: one bar asked for the big
    // file, none for the small one.
    let asked = Asks::default();
    let big = read_scan(&ScanOptions::new(&path), &asked).unwrap();
    assert_eq!(big.assembly.count, n);
    assert_eq!(asked.0.load(Ordering::SeqCst), 1);
    read_scan(&ScanOptions::new(&small), &asked).unwrap();
    assert_eq!(asked.0.load(Ordering::SeqCst), 1);
    if !have_pty() {
        return;
    }
    let shown = pty_run(80, &args);
    assert!(shown.contains("bytes read ["), "{shown}");
    // Never a bar of nothing first (issue 33: a full `0/0` bar was drawn
    // before the length was known), and every bar drawn has the file's length.
    assert!(!shown.contains(" 0/0 "), "{shown}");
    let len = std::fs::metadata(&path).unwrap().len();
    let bars: Vec<&str> = shown
        .lines()
        .filter(|l| l.contains("bytes read ["))
        .collect();
    assert!(
        bars.iter().all(|l| l.contains(&format!("/{len} "))),
        "{len}: {bars:?}"
    );
    assert!(!pty_run_stdout(80, &args).contains("bytes read ["));
    let quiet = pty_run(
        80,
        &["degeneracy", small.to_str().unwrap(), "--format", "json"],
    );
    assert!(!quiet.contains("bytes read ["), "{quiet}");
}
