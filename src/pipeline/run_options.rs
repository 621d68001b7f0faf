//! What a run read is asked for ([`RunOptions`]), grouped as a user thinks of
//! it: which scans ([`RunScans`]), which body frames ([`RunFrames`]), how
//! each scan is analysed ([`RunDetector`]) and, optionally, scan pairs at
//! their relative pose ([`RunPairs`]). `Default` gives `audit run`'s
//! defaults; [`RunOptions::settings`] checks the detector's numbers once,
//! naming the field at fault.

use super::detector::{check_tau_ells, NormalOptions};
use crate::degeneracy::MetricRule;
use crate::diagnostic::{Error, Result};
use crate::formats::LoadOptions;
use crate::run::poses::PoseFormat;
use crate::run::scan::Settings;
use crate::run::source::ScanWindow;
use crate::tolerances::{
    DEFAULT_ELLS, DEFAULT_TAU, MAX_SCAN_CELLS, PAIR_GATE_M, RAW_VOXEL_RANGE_M, RUN_VOXEL_M,
};
use std::path::PathBuf;

/// How a recorded run is read ([`Run::open`](crate::Run::open)); the
/// command line's `audit run` flags, grouped.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct RunOptions {
    /// Which scans: the topic, the window, the scan frame of files.
    pub scans: RunScans,
    /// The body frames every scan is also reported in.
    pub frames: RunFrames,
    /// How each scan is made into `H` and `M` and decided.
    pub detector: RunDetector,
    /// Scan pairs at their relative pose instead of single scans (`None`:
    /// single scans).
    pub pairs: Option<RunPairs>,
    /// Worker threads (0: `AUDIT_JOBS` when set, else one per core).
    pub threads: usize,
    /// How calibration files (and a bag's transforms) are read.
    pub load: LoadOptions,
}

/// Which scans of the run are read.
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct RunScans {
    /// A bag's `PointCloud2` topic (default: the bag's only one); bags only.
    pub topic: Option<String>,
    /// From `start` to `end`, every `every`-th scan.
    pub window: ScanWindow,
    /// The scan frame of files that name none (KITTI, point files).
    pub lidar_frame: Option<String>,
}

/// The frames each scan is reported in besides its own (`scan`).
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct RunFrames {
    /// Body frames of the run's transforms, by name (default: the root of
    /// the scan frame's tree).
    pub names: Vec<String>,
    /// Every frame of the run's transforms but the scan frame.
    pub all: bool,
    /// Calibration files (URDF, TF, LIO YAML, ...) whose transforms join
    /// the run's (a bag's `/tf_static` and `/robot_description`).
    pub extrinsics: Vec<PathBuf>,
    /// Rig files (or folders of them): each gives a body frame (the scan
    /// taken as its LiDAR's) and its lever arm alone.
    pub rig_files: Vec<PathBuf>,
}

/// How each scan is analysed: the scan's normal fields as stored, or else a
/// voxel grid and PCA normals; then every family's eigenvalues.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct RunDetector {
    /// Point-displacement threshold (default [`DEFAULT_TAU`]); the other
    /// families use their calibrated thresholds.
    pub tau: f64,
    /// Characteristic lengths (m) of the characteristic length family
    /// (default [`DEFAULT_ELLS`]).
    pub ells: Vec<f64>,
    /// Normal estimation of scans without normal fields; its `voxel`
    /// defaults to [`RUN_VOXEL_M`] here (`None`: every point).
    pub normals: NormalOptions,
    /// Estimate normals even where the scans have normal fields.
    pub estimate_normals: bool,
}

impl Default for RunDetector {
    fn default() -> Self {
        let normals = NormalOptions {
            voxel: Some(RUN_VOXEL_M),
            ..NormalOptions::default()
        };
        RunDetector {
            tau: DEFAULT_TAU,
            ells: DEFAULT_ELLS.to_vec(),
            normals,
            estimate_normals: false,
        }
    }
}

/// Scan pairs: each scan (the source) with the one `step` before it (the
/// target) at their relative pose from the poses, as `audit degeneracy
/// --target` pairs two files.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct RunPairs {
    /// Pair each scan with the `step`-th before it (1 to `MAX_PAIR_STEP`).
    pub step: usize,
    /// Correspondence gate (m), default [`PAIR_GATE_M`].
    pub gate: f64,
    /// A poses file (default: the bag's `/tf`, or its only
    /// `nav_msgs/Odometry` topic).
    pub poses: Option<PathBuf>,
    /// What `poses` holds (`None`: told from its layout).
    pub poses_format: Option<PoseFormat>,
    /// KITTI `calib.txt` (its `Tr`) for [`PoseFormat::Kitti`].
    pub calib: Option<PathBuf>,
    /// A bag topic with the poses (`/tf` or a `nav_msgs/Odometry` topic).
    pub poses_topic: Option<String>,
    /// The frame the poses are of (default: the scan frame; for `/tf` the
    /// root of the scan frame's tree).
    pub poses_frame: Option<String>,
}

impl Default for RunPairs {
    fn default() -> Self {
        RunPairs {
            step: 1,
            gate: PAIR_GATE_M,
            poses: None,
            poses_format: None,
            calib: None,
            poses_topic: None,
            poses_frame: None,
        }
    }
}

impl RunOptions {
    /// The per-scan settings, every number checked (a usage error names the
    /// field and what it expected).
    pub(crate) fn settings(&self) -> Result<Settings> {
        let d = &self.detector;
        check_tau_ells(d.tau, &d.ells)?;
        let n = &d.normals;
        let (lo, hi) = RAW_VOXEL_RANGE_M;
        if let Some(v) = n.voxel.filter(|v| !(lo..=hi).contains(v)) {
            return Err(Error::usage(format!(
                "normals.voxel: expected None (no grid) or {lo} to {hi} m, found {v}"
            )));
        }
        if !(n.radius.is_finite() && n.radius > 0.0) {
            return Err(Error::usage(format!(
                "normals.radius: expected a positive number of metres, found {}",
                n.radius
            )));
        }
        if self.scans.window.every == 0 {
            return Err(Error::usage("scans.window.every: expected at least 1"));
        }
        // The pair step is checked with the run's plan (`pipeline::run`).
        let gate = match &self.pairs {
            Some(p) if !(p.gate.is_finite() && p.gate > 0.0) => {
                return Err(Error::usage(format!(
                    "pairs.gate: expected a positive number of metres, found {}",
                    p.gate
                )))
            }
            Some(p) => p.gate,
            None => PAIR_GATE_M,
        };
        Ok(Settings {
            rules: MetricRule::default_set(&d.ells, None),
            tau: d.tau,
            voxel: n.voxel,
            normals: n.params(),
            estimate: d.estimate_normals,
            gate,
            max_cells: MAX_SCAN_CELLS,
        })
    }
}
