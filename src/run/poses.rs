//! A run's poses: where each scan was taken, for the scan pairs' initial
//! guesses. A pose `P_k` is the pose of a frame in a fixed frame (odom,
//! world, the first scan's frame): `p_fixed = R p + d`. Which frame the
//! poses are of is given, never guessed: the scan frame by default,
//! `--poses-frame` otherwise (then composed with that frame's pose of the
//! scan frame).
//!
//! Pose files (`--poses`, `--poses-format`):
//!
//! - `tum`: `timestamp tx ty tz qx qy qz qw` per line, `#` comments (the TUM
//!   RGB-D benchmark's trajectory format: the frame's position and Hamilton
//!   quaternion x y z w in the world). Matched by time: a scan's stamp in
//!   seconds, or, for a sequence without stamps, its `times.txt` time.
//! - `kitti`: the KITTI odometry benchmark's `poses/NN.txt`: row `i`, 12
//!   numbers, the 3x4 row-major pose of the left camera `cam0` of frame `i` in
//!   `cam0` of frame 0 (devkit_odometry `readme.txt`); the LiDAR's is
//!   `Tr^-1 P_i Tr` with `Tr` (`calib.txt`, "velodyne to camera") as
//!   PRBonn/semantic-kitti-api `parse_poses` computes it. Matched by index.
//! - `kitti-lidar`: the same 12 numbers, poses of the LiDAR itself (KISS-ICP
//!   and most LiDAR odometry write these). Matched by index.
//! - `named`: `name` then the 12 numbers (PJLab-ADG SensorsCalibration's
//!   `*-pose.txt`, read by `LoadTimeAndPoes`): matched by the scan file's
//!   stem.
//! - `relative`: 4x4 matrices (16 numbers each), the pose of scan `k + 1`'s
//!   frame in scan `k`'s (koide3/fast_gicp's `relative.txt`).
//!
//! The 8-column and the named layouts say what they are and are read
//! without `--poses-format`; 12 columns are camera or LiDAR poses, which
//! the file does not say: `--poses-format` is then required.
//!
//! From a bag (`--poses-topic`): `nav_msgs/Odometry` (`pose.pose`, the pose of
//! `child_frame_id` in `header.frame_id`) or `tf2_msgs/TFMessage` on `/tf`
//! (the transforms whose child is the poses frame). Matched by the scan's
//! `header.stamp`.
//!
//! Matching by time follows tf2: a sample within [`POSE_TIME_TOL_S`] of the
//! scan's time is used as it is; between two samples the pose is
//! interpolated (translation linearly, rotation by slerp); before the first
//! or after the last sample there is no pose (tf2 refuses to extrapolate).
//! Rotations are checked as every rotation the tool reads (projected with a
//! warning when off orthonormal by rounding).

use crate::diagnostic::{Error, Location, Result, Warning};
use crate::formats::bag::{self, decode, BagLimits, Flow, RawMessage};
use crate::geometry::se3::{QuatOrder, Transform};
use crate::tolerances::{MAX_POSE_FILE_BYTES, POSE_TIME_TOL_S};
use nalgebra::{UnitQuaternion, Vector3};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What a poses file holds (`--poses-format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PoseFormat {
    /// `timestamp tx ty tz qx qy qz qw`.
    Tum,
    /// KITTI odometry camera (`cam0`) poses, with `calib.txt`'s `Tr`.
    Kitti,
    /// 12 numbers per line, poses of the LiDAR.
    KittiLidar,
    /// A name, then 12 numbers (LiDAR poses).
    Named,
    /// 4x4 matrices: scan `k + 1` in scan `k`.
    Relative,
}

impl PoseFormat {
    /// The name `--poses-format` takes.
    pub fn name(self) -> &'static str {
        match self {
            PoseFormat::Tum => "tum",
            PoseFormat::Kitti => "kitti",
            PoseFormat::KittiLidar => "kitti-lidar",
            PoseFormat::Named => "named",
            PoseFormat::Relative => "relative",
        }
    }

    /// Every format, for `--help` and messages.
    pub const ALL: [PoseFormat; 5] = [
        PoseFormat::Tum,
        PoseFormat::Kitti,
        PoseFormat::KittiLidar,
        PoseFormat::Named,
        PoseFormat::Relative,
    ];

    /// The format named `s` (one of [`PoseFormat::name`]'s); a usage error
    /// listing the names otherwise.
    pub fn parse(s: &str) -> Result<PoseFormat> {
        Self::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| {
                let all: Vec<&str> = Self::ALL.iter().map(|f| f.name()).collect();
                Error::usage(format!("expected one of {}, found `{s}`", all.join(", ")))
            })
    }
}

/// How the samples of a track are matched to scans.
#[derive(Debug, Clone, PartialEq)]
enum Keys {
    /// Sample `k` for scan `k`.
    Index,
    /// By time (ns), tf2's rule.
    Time(Vec<i128>),
    /// By the scan file's stem.
    Name(BTreeMap<String, usize>),
}

/// Poses, and how they are matched to scans.
#[derive(Debug, Clone)]
pub struct PoseTrack {
    /// Where they come from, for messages (`poses.txt (kitti)`, `/tf`).
    pub what: String,
    /// The frame they are poses of (`None`: the scan frame).
    pub frame: Option<String>,
    poses: Vec<Transform>,
    keys: Keys,
}

/// What a scan is matched by.
#[derive(Debug, Clone, Copy)]
pub struct ScanKey<'a> {
    /// Its place in the run.
    pub index: usize,
    /// Its stamp (ns), when it has one.
    pub stamp_ns: Option<i128>,
    /// Its time in the run (s).
    pub time_s: Option<f64>,
    /// Its file.
    pub file: &'a Path,
}

impl PoseTrack {
    /// The pose of the track's frame at `scan`, or why there is none.
    pub fn at(&self, scan: ScanKey) -> std::result::Result<Transform, String> {
        match &self.keys {
            Keys::Index => self.poses.get(scan.index).copied().ok_or_else(|| {
                format!(
                    "no pose for scan {}: {} holds {} poses",
                    scan.index,
                    self.what,
                    self.poses.len()
                )
            }),
            Keys::Name(names) => {
                let stem = scan
                    .file
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default();
                names.get(&stem).map(|&i| self.poses[i]).ok_or_else(|| {
                    format!(
                        "no pose named `{}` in {}",
                        crate::sanitize::quote(&stem),
                        self.what
                    )
                })
            }
            Keys::Time(times) => {
                let t = match (scan.stamp_ns, scan.time_s) {
                    (Some(ns), _) => ns,
                    (None, Some(s)) => (s * 1e9).round() as i128,
                    (None, None) => {
                        return Err(format!(
                            "scan {} has no time to look up its pose in {}",
                            scan.index, self.what
                        ))
                    }
                };
                interpolate(times, &self.poses, t).ok_or_else(|| {
                    format!(
                        "no pose at t = {} s: {} covers {} to {} s (no extrapolation, as tf2)",
                        seconds(t),
                        self.what,
                        times.first().map_or("-".into(), |&a| seconds(a)),
                        times.last().map_or("-".into(), |&b| seconds(b)),
                    )
                })
            }
        }
    }
}

fn seconds(ns: i128) -> String {
    format!("{:.6}", ns as f64 * 1e-9)
}

/// tf2's lookup: the sample within the tolerance, else the interpolation of
/// the two around `t`; `None` outside the samples.
fn interpolate(times: &[i128], poses: &[Transform], t: i128) -> Option<Transform> {
    let tol = (POSE_TIME_TOL_S * 1e9) as i128;
    let i = times.partition_point(|&x| x < t);
    for k in [i.wrapping_sub(1), i] {
        if let Some(&x) = times.get(k) {
            if (x - t).abs() <= tol {
                return Some(poses[k]);
            }
        }
    }
    if i == 0 || i >= times.len() {
        return None;
    }
    let (a, b) = (&poses[i - 1], &poses[i]);
    let s = (t - times[i - 1]) as f64 / (times[i] - times[i - 1]) as f64;
    let qa = UnitQuaternion::from_matrix(a.rotation());
    let qb = UnitQuaternion::from_matrix(b.rotation());
    let q = qa.slerp(&qb, s);
    let d: Vector3<f64> = a.translation() * (1.0 - s) + b.translation() * s;
    let c = q.quaternion().coords;
    Transform::from_quaternion(
        [c.x, c.y, c.z, c.w],
        QuatOrder::Xyzw,
        d.into(),
        &mut Vec::new(),
    )
    .ok()
}

/// A poses file read: the track and its warnings.
pub fn read_file(
    path: &Path,
    format: Option<PoseFormat>,
    calib: Option<&Path>,
    warnings: &mut Vec<Warning>,
) -> Result<PoseTrack> {
    let text = crate::input::read_text(path, MAX_POSE_FILE_BYTES, "the poses file size cap")?;
    let rows = rows(&text);
    let format = match format {
        Some(f) => f,
        None => detect(path, &rows)?,
    };
    let mut rot = Rotations::default();
    let what = format!(
        "{} ({})",
        path.file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned()),
        format.name()
    );
    let (poses, keys) = match format {
        PoseFormat::Tum => tum(path, &rows, &mut rot)?,
        PoseFormat::KittiLidar => (twelve(path, &rows, 0, &mut rot)?, Keys::Index),
        PoseFormat::Kitti => {
            let calib = calib.ok_or_else(|| {
                Error::usage("--poses-format kitti: camera poses need calib.txt (its `Tr`, velodyne to camera): give --calib FILE").in_file(path)
            })?;
            let tr = kitti_tr(calib, &mut rot)?;
            let cam = twelve(path, &rows, 0, &mut rot)?;
            let ti = tr.inverse();
            let p = cam.iter().map(|c| ti.compose(c).compose(&tr)).collect();
            (p, Keys::Index)
        }
        PoseFormat::Named => {
            let p = twelve(path, &rows, 1, &mut rot)?;
            let mut names = BTreeMap::new();
            for (i, (line, r)) in rows.iter().enumerate() {
                if names.insert(r[0].to_string(), i).is_some() {
                    return Err(Error::parse(format!(
                        "pose name `{}` given twice",
                        crate::sanitize::quote(r[0])
                    ))
                    .at(&Location::at(path, *line, None)));
                }
            }
            (p, Keys::Name(names))
        }
        PoseFormat::Relative => (relative(path, &text, &mut rot)?, Keys::Index),
    };
    rot.report(&what, warnings);
    Ok(PoseTrack {
        what,
        frame: None,
        poses,
        keys,
    })
}

/// The non-empty, non-comment lines (1-based numbers) split on whitespace
/// and commas.
fn rows(text: &str) -> Vec<(usize, Vec<&str>)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
        .map(|(i, l)| {
            let v: Vec<&str> = l
                .split(|c: char| c.is_whitespace() || c == ',')
                .filter(|t| !t.is_empty())
                .collect();
            (i, v)
        })
        .collect()
}

/// The layouts that say what they are (see the module docs).
fn detect(path: &Path, rows: &[(usize, Vec<&str>)]) -> Result<PoseFormat> {
    let Some((_, first)) = rows.first() else {
        return Err(Error::parse("expected poses, found no line").in_file(path));
    };
    let numeric = |t: &&str| t.parse::<f64>().is_ok();
    match (first.len(), first.first().is_some_and(|t| !numeric(t))) {
        (8, false) => Ok(PoseFormat::Tum),
        (13, true) => Ok(PoseFormat::Named),
        (12, false) => Err(Error::usage(
            "12 numbers per line: KITTI-layout poses, of the left camera (the odometry benchmark's poses/NN.txt, with calib.txt) or of the LiDAR (what LiDAR odometry writes); the file does not say: give --poses-format kitti (with --calib) or kitti-lidar",
        )
        .in_file(path)),
        (n, _) => Err(Error::usage(format!(
            "{n} values on the first line: give --poses-format ({})",
            PoseFormat::ALL.map(|f| f.name()).join(", ")
        ))
        .in_file(path)),
    }
}

/// Rotations read, and the warnings their checks gave (kept to the first,
/// with a count: a pose file has one rotation per line).
#[derive(Default)]
struct Rotations {
    first: Option<Warning>,
    count: usize,
}

impl Rotations {
    fn take(&mut self, ws: Vec<Warning>, path: &Path, line: usize) {
        for w in ws {
            self.count += 1;
            if self.first.is_none() {
                self.first = Some(w.at(&Location::at(path, line, None)));
            }
        }
    }

    fn report(self, what: &str, warnings: &mut Vec<Warning>) {
        if let Some(mut w) = self.first {
            if self.count > 1 {
                w.message = format!(
                    "{what}: {} (and {} more rotations of the file like it)",
                    w.message,
                    self.count - 1
                );
            }
            warnings.push(w);
        }
    }
}

fn numbers(path: &Path, line: usize, toks: &[&str]) -> Result<Vec<f64>> {
    toks.iter()
        .map(|t| {
            t.parse::<f64>().map_err(|_| {
                Error::parse(format!(
                    "expected a number, found `{}`",
                    crate::sanitize::quote(t)
                ))
                .at(&Location::at(path, line, None))
            })
        })
        .collect()
}

/// A 3x4 row-major pose from 12 numbers.
fn pose12(v: &[f64], path: &Path, line: usize, rot: &mut Rotations) -> Result<Transform> {
    let r = [[v[0], v[1], v[2]], [v[4], v[5], v[6]], [v[8], v[9], v[10]]];
    let mut ws = Vec::new();
    let t = Transform::from_matrix3(r, [v[3], v[7], v[11]], &mut ws)
        .map_err(|e| e.at(&Location::at(path, line, None)))?;
    rot.take(ws, path, line);
    Ok(t)
}

/// Lines of `skip` leading tokens and 12 numbers.
fn twelve(
    path: &Path,
    rows: &[(usize, Vec<&str>)],
    skip: usize,
    rot: &mut Rotations,
) -> Result<Vec<Transform>> {
    rows.iter()
        .map(|(line, r)| {
            if r.len() != 12 + skip {
                return Err(Error::parse(format!(
                    "expected {} values (a 3x4 row-major pose{}), found {}",
                    12 + skip,
                    if skip > 0 { " after its name" } else { "" },
                    r.len()
                ))
                .at(&Location::at(path, *line, None)));
            }
            let v = numbers(path, *line, &r[skip..])?;
            pose12(&v, path, *line, rot)
        })
        .collect()
}

fn tum(
    path: &Path,
    rows: &[(usize, Vec<&str>)],
    rot: &mut Rotations,
) -> Result<(Vec<Transform>, Keys)> {
    let mut samples: Vec<(i128, Transform)> = Vec::with_capacity(rows.len());
    for (line, r) in rows {
        if r.len() != 8 {
            return Err(Error::parse(format!(
                "expected 8 values (timestamp tx ty tz qx qy qz qw), found {}",
                r.len()
            ))
            .at(&Location::at(path, *line, None)));
        }
        let v = numbers(path, *line, r)?;
        let mut ws = Vec::new();
        let t = Transform::from_quaternion(
            [v[4], v[5], v[6], v[7]],
            QuatOrder::Xyzw,
            [v[1], v[2], v[3]],
            &mut ws,
        )
        .map_err(|e| e.at(&Location::at(path, *line, None)))?;
        rot.take(ws, path, *line);
        if !v[0].is_finite() {
            return Err(Error::parse(format!(
                "timestamp {}: expected a finite number of seconds",
                v[0]
            ))
            .at(&Location::at(path, *line, None)));
        }
        samples.push(((v[0] * 1e9).round() as i128, t));
    }
    Ok(by_time(samples))
}

/// Samples sorted by time (stable: equal times keep their order).
fn by_time(mut samples: Vec<(i128, Transform)>) -> (Vec<Transform>, Keys) {
    samples.sort_by_key(|s| s.0);
    let (t, p): (Vec<i128>, Vec<Transform>) = samples.into_iter().unzip();
    (p, Keys::Time(t))
}

/// `Tr` of a KITTI `calib.txt`: velodyne to camera, `p_cam = Tr p_velo`.
fn kitti_tr(calib: &Path, rot: &mut Rotations) -> Result<Transform> {
    let text = crate::input::read_text(calib, MAX_POSE_FILE_BYTES, "the calib.txt size cap")?;
    for (i, l) in text.lines().enumerate() {
        if let Some(rest) = l.trim().strip_prefix("Tr:") {
            let toks: Vec<&str> = rest.split_whitespace().collect();
            if toks.len() != 12 {
                return Err(
                    Error::parse(format!("Tr: expected 12 numbers, found {}", toks.len()))
                        .at(&Location::at(calib, i + 1, None)),
                );
            }
            let v = numbers(calib, i + 1, &toks)?;
            return pose12(&v, calib, i + 1, rot);
        }
    }
    Err(Error::parse("expected a line `Tr: ...` (velodyne to camera), found none").in_file(calib))
}

/// 4x4 matrices, 16 numbers each: the pose of scan `k + 1` in scan `k`,
/// chained from the first scan's frame.
fn relative(path: &Path, text: &str, rot: &mut Rotations) -> Result<Vec<Transform>> {
    let v: Vec<f64> = text
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|t| !t.is_empty())
        .map(|t| t.parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| Error::parse("expected 4x4 matrices (16 numbers each)").in_file(path))?;
    if v.is_empty() || !v.len().is_multiple_of(16) {
        return Err(Error::parse(format!(
            "expected 4x4 matrices (16 numbers each), found {} numbers",
            v.len()
        ))
        .in_file(path));
    }
    let mut out = vec![Transform::identity()];
    for (k, m) in v.chunks_exact(16).enumerate() {
        let mut ws = Vec::new();
        let a: [[f64; 4]; 4] = std::array::from_fn(|i| std::array::from_fn(|j| m[4 * i + j]));
        let g = Transform::from_matrix4(a, &mut ws).map_err(|e| e.in_file(path))?;
        rot.take(ws, path, 4 * k + 1);
        let last = out[out.len() - 1];
        out.push(last.compose(&g));
    }
    Ok(out)
}

/// Poses from a bag topic: `nav_msgs/Odometry`, or the `/tf` transforms
/// whose child is `child` (`None`: an Odometry topic names its own).
pub fn read_bag(
    bags: &[PathBuf],
    topic: &str,
    child: Option<&str>,
    limits: BagLimits,
    warnings: &mut Vec<Warning>,
) -> Result<PoseTrack> {
    let mut samples: Vec<(i128, Transform)> = Vec::new();
    let mut frames: Option<(String, String)> = None;
    let mut each = |m: RawMessage| -> Result<Flow> {
        let err =
            |e: String| Error::parse(format!("{} at {}: {e}", m.topic, m.place)).in_file(&m.file);
        let mut ws = Vec::new();
        if m.type_name.contains("Odometry") {
            let o = decode::odometry(&m.data, m.encoding).map_err(err)?;
            let pair = (
                o.parent.trim_start_matches('/').to_string(),
                o.child.trim_start_matches('/').to_string(),
            );
            if child.is_some_and(|c| c != pair.1) {
                return Ok(Flow::Continue);
            }
            same_frames(&mut frames, pair, &m)?;
            let t = Transform::from_quaternion(o.rotation, QuatOrder::Xyzw, o.translation, &mut ws)
                .map_err(|e| err(e.message))?;
            samples.push((o.stamp_ns, t));
        } else {
            let recs = decode::tf_message(&m.data, m.encoding).map_err(err)?;
            for r in recs {
                let pair = (
                    r.parent.trim_start_matches('/').to_string(),
                    r.child.trim_start_matches('/').to_string(),
                );
                if child != Some(pair.1.as_str()) {
                    continue;
                }
                same_frames(&mut frames, pair, &m)?;
                let t =
                    Transform::from_quaternion(r.rotation, QuatOrder::Xyzw, r.translation, &mut ws)
                        .map_err(|e| err(e.message))?;
                samples.push((r.stamp_ns, t));
            }
        }
        if let Some(w) = ws.into_iter().next() {
            if warnings.is_empty() {
                warnings.push(w.at(&Location::file(&m.file)));
            }
        }
        Ok(Flow::Continue)
    };
    for b in bags {
        bag::stream(b, &|t| t == topic, limits, &mut each)?;
    }
    let Some((parent, child)) = frames else {
        return Err(Error::usage(format!(
            "--poses-topic {topic}: no pose{} on it",
            child.map_or(String::new(), |c| format!(" of frame `{c}`"))
        ))
        .in_file(&bags[0]));
    };
    let n = samples.len();
    let (poses, keys) = by_time(samples);
    Ok(PoseTrack {
        what: format!("{topic} ({child} in {parent}, {n} samples)"),
        frame: Some(child),
        poses,
        keys,
    })
}

/// Every pose of a topic must name the same pair of frames.
fn same_frames(
    frames: &mut Option<(String, String)>,
    pair: (String, String),
    m: &RawMessage,
) -> Result<()> {
    match frames {
        None => {
            *frames = Some(pair);
            Ok(())
        }
        Some(f) if *f == pair => Ok(()),
        Some(f) => Err(Error::parse(format!(
            "{} at {}: pose of `{}` in `{}`, where earlier ones are of `{}` in `{}`: expected one pair of frames",
            m.topic,
            m.place,
            crate::sanitize::quote(&pair.1),
            crate::sanitize::quote(&pair.0),
            crate::sanitize::quote(&f.1),
            crate::sanitize::quote(&f.0)
        ))
        .in_file(&m.file)),
    }
}
