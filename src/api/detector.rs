//! The degeneracy detector as an object: its options checked once, then run
//! on each input, points held in memory ([`Detector::points`]) or a scan file
//! ([`Detector::scan`], a scan pair included), each giving one report.

use crate::diagnostic::Result;
use crate::geometry::Transform;
use crate::pipeline::detector::{
    self as det, check_tau_ells, DegeneracyOptions, DetectorOptions, InitialGuess, Points,
    ScanOptions,
};
use crate::progress::{NoProgress, ProgressFactory};
use crate::report::detector::{DegeneracyReport, SweepReport};
use crate::tolerances::PAIR_GATE_M;
use std::path::PathBuf;

/// A point file for the detector (CSV, PLY, PCD with normals; any of them or
/// LAS/LAZ as a raw scan), optionally the source of a scan pair.
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct ScanFile {
    /// The point file (`-`: standard input).
    pub points: PathBuf,
    /// A raw scan: estimate the normals ([`DetectorOptions::normals`])
    /// instead of reading them.
    pub estimate_normals: bool,
    /// A raw scan's LAS/LAZ classifications to keep (empty: every point).
    pub classes: Vec<u8>,
    /// A scan pair: `points` is the source, matched against this target.
    pub pair: Option<PairOptions>,
    /// Keep (a stride of) the points in the report, for the 3D scene that
    /// [`render_bytes`](crate::render_bytes) writes as MCAP.
    pub keep_points: bool,
}

impl ScanFile {
    /// Points with normals read from `points`.
    pub fn new(points: impl Into<PathBuf>) -> Self {
        ScanFile {
            points: points.into(),
            ..ScanFile::default()
        }
    }
}

/// The target of a scan pair: `H` and `M` from the correspondences of the
/// source's points, moved by the initial guess, with their nearest target
/// point within the gate, as point-to-plane ICP pairs them.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct PairOptions {
    /// The target's point file (normals read, or estimated with the source's
    /// `estimate_normals`).
    pub target: PathBuf,
    /// The correspondence gate (m), default the paper's 1 m.
    pub gate: f64,
    /// The pose of the source frame in the target frame.
    pub initial_guess: InitialGuess,
}

impl PairOptions {
    /// A pair with `target`, the default gate and the identity guess.
    pub fn new(target: impl Into<PathBuf>) -> Self {
        PairOptions {
            target: target.into(),
            gate: PAIR_GATE_M,
            initial_guess: InitialGuess::Identity,
        }
    }
}

/// The degeneracy detector: every metric family's generalized eigenvalues of
/// `H v = lambda M v`, its decision, the degenerate subspace as screws and
/// its per-axis footprint, on each input it is given.
#[derive(Debug, Clone)]
pub struct Detector {
    opts: DetectorOptions,
}

impl Detector {
    /// A detector with these options, checked: a positive finite `tau`, 1 to
    /// `MAX_ELLS` finite positive lengths.
    pub fn new(opts: DetectorOptions) -> Result<Detector> {
        check_tau_ells(opts.tau, &opts.ells)?;
        Ok(Detector { opts })
    }

    /// Its options.
    pub fn options(&self) -> &DetectorOptions {
        &self.opts
    }

    /// Every family on points held in memory (normals estimated when there
    /// are none).
    ///
    /// ```
    /// use extrinsic_audit::{Detector, DetectorOptions, Family, Points};
    ///
    /// # fn main() -> extrinsic_audit::Result<()> {
    /// // The paper's circular tunnel (radius 2.85 m about z) as f32 rows, its
    /// // exact radial normals pointing at the axis.
    /// let (mut xyz, mut normals) = (Vec::new(), Vec::new());
    /// for ring in 0..100 {
    ///     for k in 0..36 {
    ///         let a = k as f32 * std::f32::consts::TAU / 36.0;
    ///         xyz.push([2.85 * a.cos(), 2.85 * a.sin(), -5.0 + 0.1 * ring as f32]);
    ///         normals.push([-a.cos(), -a.sin(), 0.0]);
    ///     }
    /// }
    /// let detector = Detector::new(DetectorOptions::default())?;
    /// let report = detector.points(&Points::new(&xyz).with_normals(&normals))?;
    /// assert_eq!(report.points, 3600);
    /// // The closed form: on the axis, the degenerate twists are the rotation
    /// // about z and the translation along it (nullity 2).
    /// let pd = report.families.iter().find(|f| f.family == Family::PointDisplacement).unwrap();
    /// assert_eq!(pd.degenerate_count, Some(2));
    /// // Footprint axes: rot-x, rot-y, rot-z, trans-x, trans-y, trans-z.
    /// assert_eq!(report.footprint, [false, false, true, false, false, true]);
    /// // One normal per point, or an error.
    /// assert!(detector.points(&Points::new(&xyz).with_normals(&normals[1..])).is_err());
    /// # Ok(())
    /// # }
    /// ```
    pub fn points(&self, points: &Points) -> Result<DegeneracyReport> {
        det::degeneracy_points(points, &self.opts, &NoProgress)
    }

    /// Every family on a scan file (streamed when it has normals).
    ///
    /// ```
    /// use extrinsic_audit::{Detector, DetectorOptions, Family, ScanFile};
    ///
    /// # fn main() -> extrinsic_audit::Result<()> {
    /// // A flat floor without normals, 4 m by 4 m on a 5 cm grid; PCA normals
    /// // within 0.2 m.
    /// let dir = tempfile::tempdir().unwrap();
    /// let path = dir.path().join("floor.csv");
    /// let mut text = String::from("x,y,z\n");
    /// for i in 0..81 {
    ///     for j in 0..81 {
    ///         text += &format!("{},{},0\n", -2.0 + 0.05 * i as f64, -2.0 + 0.05 * j as f64);
    ///     }
    /// }
    /// std::fs::write(&path, text).unwrap();
    /// let mut opts = DetectorOptions::default();
    /// opts.normals.radius = 0.2;
    /// let detector = Detector::new(opts)?;
    /// let mut scan = ScanFile::new(&path);
    /// scan.estimate_normals = true;
    /// let report = detector.scan(&scan)?;
    /// assert_eq!(report.normals.as_ref().map(|n| n.kept), Some(81 * 81));
    /// // Closed form: a plane moves its points along its normal only under z,
    /// // roll and pitch, and then wholly so (eigenvalue 1 of H against the
    /// // point-displacement metric M); rotation about the normal and the two
    /// // in-plane translations move no point along the normal (eigenvalue 0).
    /// let pd = report.families.iter().find(|f| f.family == Family::PointDisplacement).unwrap();
    /// for (got, want) in pd.eigenvalues.unwrap().iter().zip([0.0, 0.0, 0.0, 1.0, 1.0, 1.0]) {
    ///     assert!((got - want).abs() < 1e-9, "{got} vs {want}");
    /// }
    /// assert_eq!(pd.degenerate_count, Some(3));
    /// assert_eq!(report.footprint, [false, false, true, true, true, false]);
    /// # Ok(())
    /// # }
    /// ```
    pub fn scan(&self, scan: &ScanFile) -> Result<DegeneracyReport> {
        self.scan_with(scan, &NoProgress)
    }

    /// [`Detector::scan`], long reads and normal estimations reported to a
    /// progress from `bars`.
    pub fn scan_with(
        &self,
        scan: &ScanFile,
        bars: &dyn ProgressFactory,
    ) -> Result<DegeneracyReport> {
        let opts = DegeneracyOptions {
            scan: self.scan_options(scan),
            tau: self.opts.tau,
            ells: self.opts.ells.clone(),
            show_matrices: self.opts.show_matrices,
        };
        det::degeneracy_scan(&opts, bars)
    }

    /// The paper's 861-change frame sweep on a scan file (seeded): for every
    /// family, how many frame changes flip its decision; with `rig` (the pose
    /// of the rig's other frame in the scan's), the decision in that frame.
    pub fn sweep(
        &self,
        scan: &ScanFile,
        seed: u64,
        rig: Option<&Transform>,
        bars: &dyn ProgressFactory,
    ) -> Result<SweepReport> {
        let opts = self.scan_options(scan);
        let read = det::read_scan(&opts, bars)?;
        det::sweep(&read.assembly, self.opts.tau, &self.opts.ells, seed, rig)
            .map_err(|e| e.in_file(&scan.points))
    }

    fn scan_options(&self, scan: &ScanFile) -> ScanOptions {
        let mut s = ScanOptions::new(&scan.points);
        s.frame = self.opts.frame;
        s.estimate_normals = scan.estimate_normals;
        s.normals = self.opts.normals;
        s.classes = scan.classes.clone();
        s.keep_points = scan.keep_points;
        if let Some(p) = &scan.pair {
            s.target = Some(p.target.clone());
            s.gate = p.gate;
            s.initial_guess = p.initial_guess.clone();
        }
        s
    }
}
