//! A robot loaded from its calibration files: the object a user keeps to ask
//! for frames, transforms, rig reports and the frame tree.

use crate::diagnostic::{Result, Warning};
use crate::formats::LoadOptions;
use crate::frames::{Chain, Edge};
use crate::geometry::Transform;
use crate::pipeline::{self, Loaded, RigOptions};
use crate::report::frames::{frames_report, FramesReport};
use crate::report::RigReport;
use std::path::{Path, PathBuf};

/// A robot's frames, loaded from its files (URDF, xacro, launch files, TF
/// dumps, bags, LIO and Kalibr YAML, rig TOML, ...) into one frame tree.
///
/// Convention: `transform(from, to)` is the pose of `to` in `from`,
/// `p_from = R p_to + d` (what `tf2_echo FROM TO` prints).
///
/// ```
/// use extrinsic_audit::{LoadOptions, Rename, Robot};
///
/// # fn main() -> extrinsic_audit::Result<()> {
/// let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/urdf/anymal_c_lidar.urdf");
/// // The LiDAR frame renamed as the file loads (`--rename lidar=velodyne`).
/// let mut opts = LoadOptions::default();
/// opts.renames = vec![Rename { file: None, old: "lidar".into(), new: "velodyne".into() }];
/// let robot = Robot::load(&[urdf], &opts)?;
/// assert_eq!(robot.frames(), ["base", "lidar_cage", "velodyne"]);
/// assert!(robot.joints().is_empty()); // fixed joints only
/// // A rename that matches no frame is a typo, not a no-op.
/// opts.renames[0].old = "lidr".into();
/// assert!(Robot::load(&[urdf], &opts).is_err());
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Clone)]
pub struct Robot {
    loaded: Loaded,
    /// The files named to `load`.
    named: Vec<PathBuf>,
}

impl Robot {
    /// Load `files` into one frame tree, read as `opts` says (renames, joint
    /// values, xacro arguments and package paths, `--key`, `--invert`, the
    /// input format). A rename that matches no frame and a joint value that
    /// names no movable joint are errors (typos, not no-ops).
    pub fn load<P: AsRef<Path>>(files: &[P], opts: &LoadOptions) -> Result<Robot> {
        let files: Vec<PathBuf> = files.iter().map(|f| f.as_ref().to_path_buf()).collect();
        let loaded = pipeline::load(&files, opts)?;
        loaded.check_joint_names(opts.joints.keys().map(String::as_str))?;
        Ok(Robot {
            loaded,
            named: files,
        })
    }

    /// The files read: those named to [`Robot::load`], then every other
    /// file an edge came from (a xacro include, a launch file's URDF), each
    /// once (what an output written beside them must not replace).
    ///
    /// ```
    /// use extrinsic_audit::{LoadOptions, Robot};
    ///
    /// # fn main() -> extrinsic_audit::Result<()> {
    /// let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/urdf/anymal_c_lidar.urdf");
    /// let robot = Robot::load(&[urdf], &LoadOptions::default())?;
    /// assert_eq!(robot.files(), [std::path::PathBuf::from(urdf)]);
    /// # Ok(())
    /// # }
    /// ```
    pub fn files(&self) -> Vec<PathBuf> {
        self.loaded.files_read(&self.named)
    }

    /// Every frame, sorted.
    pub fn frames(&self) -> Vec<String> {
        self.loaded.graph.frames()
    }

    /// The edges of the tree, each the pose of its child in its parent, with
    /// where it was read.
    pub fn edges(&self) -> &[Edge] {
        self.loaded.graph.edges()
    }

    /// The names of the movable joints (what [`LoadOptions::joints`] sets).
    pub fn joints(&self) -> Vec<String> {
        self.loaded.graph.joint_names()
    }

    /// The warnings the files gave (suspicious but usable input).
    pub fn warnings(&self) -> &[Warning] {
        self.loaded.graph.warnings()
    }

    /// Notes on how the files were read (a redundant edge that agrees).
    pub fn notes(&self) -> &[String] {
        self.loaded.graph.notes()
    }

    /// The frame pair to report: both given, the pair a rig file declares
    /// when neither is, or the only edge there is.
    pub fn frame_pair(&self, from: Option<&str>, to: Option<&str>) -> Result<(String, String)> {
        self.loaded.frame_pair(from, to)
    }

    /// The chain from `from` to `to`: the composed transform, the edges used
    /// (those walked upwards inverted), and the chain's warnings (a joint at
    /// its default position) and notes.
    pub fn chain(&self, from: &str, to: &str) -> Result<Chain> {
        self.loaded.graph.transform(from, to)
    }

    /// The pose of `to` in `from`, composed along the tree.
    ///
    /// ```
    /// use extrinsic_audit::{LoadOptions, Robot};
    ///
    /// # fn main() -> extrinsic_audit::Result<()> {
    /// let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/urdf/anymal_c_lidar.urdf");
    /// let robot = Robot::load(&[urdf], &LoadOptions::default())?;
    /// let t = robot.transform("base", "lidar")?;
    /// // pytransform3d's (tests/fixtures/diff/expected.json): d, |d| and the angle.
    /// let d = t.translation();
    /// assert!((d - nalgebra::Vector3::new(-0.364, 0.0, 0.1422)).norm() < 1e-12);
    /// assert!((t.lever_arm() - 0.39079002034340643).abs() < 1e-12);
    /// assert!((t.rotation_angle_axis().0.to_degrees() - 89.99999999971945).abs() < 1e-9);
    /// // Composing the steps gives the chain; the other way is the inverse.
    /// let steps = robot.transform("base", "lidar_cage")?.compose(&robot.transform("lidar_cage", "lidar")?);
    /// assert!((steps.matrix4() - t.matrix4()).norm() < 1e-15);
    /// let back = robot.transform("lidar", "base")?;
    /// assert!((back.compose(&t).matrix4() - nalgebra::Matrix4::identity()).norm() < 1e-15);
    /// # Ok(())
    /// # }
    /// ```
    pub fn transform(&self, from: &str, to: &str) -> Result<Transform> {
        Ok(self.chain(from, to)?.transform)
    }

    /// The rig report of the `from` -> `to` chain (lever arm, screw, adjoint,
    /// certificate bands, adapted metric, every detector family's verdict),
    /// with the chain's warnings (the robot's own: [`Robot::warnings`]). Its
    /// 3D scene (MCAP) draws the one transform; set `report.tree` to
    /// [`Robot::frame_tree`] of the chain for the whole tree.
    ///
    /// ```
    /// use extrinsic_audit::{LoadOptions, RigOptions, Robot};
    ///
    /// # fn main() -> extrinsic_audit::Result<()> {
    /// let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/urdf/anymal_c_lidar.urdf");
    /// let robot = Robot::load(&[urdf], &LoadOptions::default())?;
    /// let mut opts = RigOptions::default();
    /// opts.ells = vec![1.0];
    /// let (report, _) = robot.report("base", "lidar", &opts)?;
    /// // The band at l = 1 m, as numpy computes it (tests/fixtures/diff/expected.json).
    /// let band = report.certificate[0].band;
    /// assert!((band[0] - 0.6781782493424238).abs() < 1e-12);
    /// assert!((band[1] - 1.4745385906575763).abs() < 1e-12);
    /// assert_eq!(report.sources.len(), 2); // base -> lidar_cage -> lidar
    /// assert_eq!(report.sources[0].line, Some(15));
    /// # Ok(())
    /// # }
    /// ```
    pub fn report(
        &self,
        from: &str,
        to: &str,
        opts: &RigOptions,
    ) -> Result<(RigReport, Vec<Warning>)> {
        let chain = self.chain(from, to)?;
        Ok((pipeline::report(&chain, opts)?, chain.warnings))
    }

    /// The frame tree as a report (text, JSON, DOT, Mermaid, SVG), the
    /// `chain` highlighted when given.
    pub fn frame_tree(&self, chain: Option<&Chain>) -> FramesReport {
        frames_report(&self.loaded.graph, chain)
    }
}
