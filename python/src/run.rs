//! The run reader (`extrinsic_audit.run`): the face's `Run` behind a Python
//! iterator. Each `__next__` waits for the next scan's result with the GIL
//! released and hands back its JSON line (`audit run --jsonl`'s, byte for
//! byte); `finish` gives the summary's JSON (`--format json`) and the
//! warnings.

use crate::diag::{json, tuples, DiagTuple, IntoPy, LoadArgs};
use extrinsic_audit::{
    Error, PoseFormat, Run, RunOptions, RunPairs, ScanBound, ScanResult, Warning,
};
use pyo3::exceptions::PyStopIteration;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Mutex;

/// `run`'s keyword arguments (every key passed by the Python layer; `None`:
/// the CLI's default).
#[derive(Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct RunArgs {
    pub topic: Option<String>,
    pub start: Option<String>,
    pub end: Option<String>,
    pub every: usize,
    pub lidar_frame: Option<String>,
    pub frames: Vec<String>,
    pub all_frames: bool,
    pub extrinsics: Vec<PathBuf>,
    pub rig_frames: Vec<PathBuf>,
    pub tau: Option<f64>,
    pub ells: Option<Vec<f64>>,
    /// `None`: the run's default grid; 0: none.
    pub voxel: Option<f64>,
    pub radius: Option<f64>,
    pub knn: Option<usize>,
    pub min_neighbours: Option<usize>,
    pub viewpoint: Option<[f64; 3]>,
    pub estimate_normals: bool,
    pub pairs: bool,
    pub pair_step: usize,
    pub gate: Option<f64>,
    pub poses: Option<PathBuf>,
    pub poses_format: Option<String>,
    pub calib: Option<PathBuf>,
    pub poses_topic: Option<String>,
    pub poses_frame: Option<String>,
    pub threads: usize,
}

impl RunArgs {
    fn options(&self, load: &LoadArgs) -> extrinsic_audit::Result<RunOptions> {
        let bound = |v: &Option<String>, what| v.as_deref().map(|s| ScanBound::parse(s, what));
        let mut o = RunOptions::default();
        o.scans.topic = self.topic.clone();
        o.scans.window.start = bound(&self.start, "start").transpose()?;
        o.scans.window.end = bound(&self.end, "end").transpose()?;
        o.scans.window.every = self.every;
        o.scans.lidar_frame = self.lidar_frame.clone();
        o.frames.names = self.frames.clone();
        o.frames.all = self.all_frames;
        o.frames.extrinsics = self.extrinsics.clone();
        o.frames.rig_files = self.rig_frames.clone();
        let d = &mut o.detector;
        d.tau = self.tau.unwrap_or(d.tau);
        d.ells = self.ells.clone().unwrap_or_else(|| d.ells.clone());
        if let Some(v) = self.voxel {
            d.normals.voxel = (v != 0.0).then_some(v);
        }
        d.normals.radius = self.radius.unwrap_or(d.normals.radius);
        d.normals.knn = self.knn;
        d.normals.min_neighbours = self.min_neighbours.unwrap_or(d.normals.min_neighbours);
        d.normals.viewpoint = self.viewpoint;
        d.estimate_normals = self.estimate_normals;
        if !self.pairs && (self.poses.is_some() || self.poses_topic.is_some()) {
            return Err(Error::usage("poses and poses_topic apply with pairs=True"));
        }
        if self.pairs {
            let mut p = RunPairs::default();
            p.step = self.pair_step;
            p.gate = self.gate.unwrap_or(p.gate);
            p.poses = self.poses.clone();
            p.poses_format = self
                .poses_format
                .as_deref()
                .map(|s| {
                    PoseFormat::parse(s)
                        .map_err(|e| Error::usage(format!("poses_format: {}", e.message)))
                })
                .transpose()?;
            p.calib = self.calib.clone();
            p.poses_topic = self.poses_topic.clone();
            p.poses_frame = self.poses_frame.clone();
            o.pairs = Some(p);
        }
        o.threads = self.threads;
        o.load = load.options()?;
        Ok(o)
    }
}

/// A run being read: an iterator of JSON lines, then the summary.
#[pyclass(name = "Run", module = "extrinsic_audit._native")]
pub struct PyRun {
    /// `None` once finished. A mutex: the class may be shared between
    /// threads (the face's `Run` is `Send`, not `Sync`).
    run: Mutex<Option<Run>>,
    frames: Vec<String>,
    families: Vec<String>,
    pairs: bool,
}

/// Open the run `paths` (GIL released while its plan is read).
#[pyfunction]
pub fn run(py: Python<'_>, paths: Vec<PathBuf>, args: RunArgs, load: LoadArgs) -> PyResult<PyRun> {
    let opts = args.options(&load).py()?;
    let run = py.detach(|| Run::open(&paths, &opts)).py()?;
    Ok(PyRun {
        frames: run.frames().iter().map(|s| s.to_string()).collect(),
        families: run.families().iter().map(|s| s.to_string()).collect(),
        pairs: run.pairs(),
        run: Mutex::new(Some(run)),
    })
}

impl PyRun {
    /// The run, locked (a poisoned lock still holds a usable run: nothing
    /// panics while holding it but the library's bugs).
    fn with<T>(&self, f: impl FnOnce(&mut Option<Run>) -> T) -> T {
        let mut g = self.run.lock().unwrap_or_else(|p| p.into_inner());
        f(&mut g)
    }
}

#[pymethods]
impl PyRun {
    /// The frames every result is reported in (`scan` first).
    #[getter]
    fn frames(&self) -> Vec<String> {
        self.frames.clone()
    }

    /// The families' keys.
    #[getter]
    fn families(&self) -> Vec<String> {
        self.families.clone()
    }

    /// Whether the results are scan pairs.
    #[getter]
    fn pairs(&self) -> bool {
        self.pairs
    }

    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    /// The next result's JSON line; the read's error, if one stopped it;
    /// then `StopIteration`. GIL released while the scan is read.
    fn __next__(&self, py: Python<'_>) -> PyResult<String> {
        let next = py.detach(|| self.with(|r| r.as_mut().and_then(Iterator::next)));
        match next {
            Some(r) => r.map(|s: ScanResult| s.to_json()).py(),
            None => Err(PyStopIteration::new_err(())),
        }
    }

    /// The summary's JSON (the CLI's `--format json`, the warnings in it)
    /// and the warnings, once the scans not yet taken are read (GIL
    /// released).
    fn finish(&self, py: Python<'_>) -> PyResult<(String, Vec<DiagTuple>)> {
        let run = self.with(Option::take);
        let Some(run) = run else {
            return Err(crate::diag::to_py(Error::usage(
                "finish: the run was already finished",
            )));
        };
        py.detach(|| {
            let (report, warnings): (_, Vec<Warning>) = run.finish()?;
            Ok((json(&report, &warnings)?, tuples(&warnings)))
        })
        .py()
    }
}
