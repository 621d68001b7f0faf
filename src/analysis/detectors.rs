//! The user's own detector on this rig (`audit FILE --detector NAME`): where
//! it forms and decides `H`, in which frame and parameterisation, its
//! threshold and units, and whether that threshold depends on the body frame
//! on this rig and by how much. Each detector's behaviour is cited from its
//! source (repository @ commit, file, function) in [`DETECTORS`] and in
//! docs/detectors.md.
//!
//! # The band on a threshold
//!
//! With `T = (R, d)` the pose of the detector's frame (`--to`, the LiDAR) in
//! the frame the user reads (`--from`, base_link), `H_L = Ad(T)^T H_B Ad(T)`,
//! and by Ostrowski's theorem `lambda_k(H_L) = theta_k lambda_k(H_B)` with
//! `theta_k` in the certificate band `[s_min^2, s_max^2]` at `delta = |d| / l`
//! ([`crate::geometry::certificate::band`]). A detector that flags
//! `lambda_k(H_L) < tau` therefore acts on the k-th eigenvalue in the user's
//! frame as a threshold somewhere in `[tau s_min^2, tau s_max^2]`. LIO-SAM,
//! LeGO-LOAM and LOAM work in metres and radians on the unnormalised
//! `J^T J`: `l = 1 m`. Their Jacobians are by Euler-angle rates, which adds
//! the singular values `sqrt(1 -+ |sin p|)` of the Euler-rate map, `p` the
//! LiDAR's pitch (of `R`, taken level in `--from`): the band becomes
//! `[tau s_min^2 (1 - |sin p|), tau s_max^2 (1 + |sin p|)]`. No band bounds a
//! 3x3 principal block (LeGO-LOAM's odometry) or a Schur complement's
//! translation part (DCReg); X-ICP is frame-invariant; FAST-LIO and its
//! family have no detector. Checked numerically in
//! tests/fixtures/detectors/detector_checks.py.
//!
//! A detector's own configuration file ([`DetectorConfig`], read by
//! `pipeline::odometry_config`, where the upstream keys are cited) replaces
//! the source's default thresholds; an eigenvalue threshold on the 6x6 `H`
//! it sets is carried into `--from` by the same band.

use crate::geometry::certificate::band;
use crate::geometry::Transform;
use serde::Serialize;

/// Mount pitch (deg) beyond which an Euler-angle detector's Jacobian is
/// near gimbal lock (its smallest Euler-rate singular value
/// `sqrt(1 - |sin p|)` below 0.13 at 80 deg): it then flags degeneracy on
/// every scan whatever the scene.
pub const EULER_PITCH_WARN_DEG: f64 = 80.0;

/// How a detector's threshold depends on the body frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Dependence {
    /// An eigenvalue threshold on the 6x6 `H`: bounded by the certificate
    /// band (with the Euler factor when `euler`).
    Band,
    /// On 3x3 blocks or Schur complements: frame-dependent, no band bounds it.
    Unbounded,
    /// Frame-invariant by construction.
    Invariant,
    /// No degeneracy detector at all.
    NoDetector,
}

/// One detector as its source has it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OdometryDetector {
    /// `--detector` name.
    pub name: &'static str,
    /// Its name for people.
    pub label: &'static str,
    /// Repository @ commit, file, function (and lines where known).
    pub source: &'static str,
    /// The frame and parameterisation of its `H`.
    pub frame: &'static str,
    /// What it decides and when.
    pub decision: &'static str,
    /// The threshold (`None`: no eigenvalue threshold).
    pub threshold: Option<f64>,
    /// Its units.
    pub units: &'static str,
    /// How it depends on the body frame.
    pub dependence: Dependence,
    /// Whether its Jacobian is by Euler-angle rates.
    pub euler: bool,
}

/// The detectors the tool knows, cited from their sources (the research
/// behind each row: docs/detectors.md).
pub const DETECTORS: [OdometryDetector; 8] = [
    OdometryDetector {
        name: "lio-sam",
        label: "LIO-SAM",
        source: "TixiaoShan/LIO-SAM @ 0be1fbe6275fb8366d5b800af4fc8c76a885c869, src/mapOptmization.cpp, LMOptimization (lines 1158-1280, the check at 1229-1251)",
        frame: "the LiDAR frame (its Euler roll, pitch, yaw in the map, R = Rz Ry Rx; map-axes translation; rotation first)",
        decision: "every eigenvalue of J^T J below the threshold, on the first iteration; the solution is remapped away from those directions",
        threshold: Some(100.0),
        units: "m^2 on rotation directions, 1 on translation (metres, radians)",
        dependence: Dependence::Band,
        euler: true,
    },
    OdometryDetector {
        name: "lego-loam",
        label: "LeGO-LOAM",
        source: "RobustFieldAutonomyLab/LeGO-LOAM @ 896a7a95a8bc510b76819d4cc48707e344bad621, LeGO-LOAM/src/featureAssociation.cpp calculateTransformationSurf and calculateTransformationCorner (odometry, 3x3 blocks, threshold 10); src/mapOptmization.cpp LMOptimization (mapping, 6x6, threshold 100)",
        frame: "the LiDAR frame at the sweep start, in LOAM's camera axes; Euler angles",
        decision: "odometry: an eigenvalue below 10 on either 3x3 block (surf: pitch, roll, z; corner: yaw, x, y); mapping: below 100 on the 6x6 J^T J; first iteration",
        threshold: Some(10.0),
        units: "m^2 on rotation directions, 1 on translation",
        dependence: Dependence::Unbounded,
        euler: true,
    },
    OdometryDetector {
        name: "loam",
        label: "LOAM",
        source: "laboshinl/loam_velodyne @ 0030b6a6b579fe2169ec36ffa939c7dd92f4275c, src/laserOdometry.cpp (eignThre 10) and src/laserMapping.cpp (eignThre 100)",
        frame: "the LiDAR frame in LOAM's camera axes; Euler angles",
        decision: "an eigenvalue of the 6x6 J^T J below 10 (odometry) or 100 (mapping), first iteration",
        threshold: Some(10.0),
        units: "m^2 on rotation directions, 1 on translation",
        dependence: Dependence::Band,
        euler: true,
    },
    OdometryDetector {
        name: "dcreg",
        label: "DCReg",
        source: "JokerJohn/DCReg @ 7df35ed98aa033fa90ba04542eaedb7379eb9116, DCReg/include/dcreg.hpp DetectDegeneracy and CharacterizeDegeneracy",
        frame: "the source cloud's frame (the LiDAR stand-alone); right perturbation on SE(3), rotation first",
        decision: "per physical axis, lambda_max / lambda_axis above 10 on the rotation and the translation Schur complements of H, every iteration",
        threshold: Some(10.0),
        units: "a condition number (dimensionless, within each 3x3 block)",
        dependence: Dependence::Unbounded,
        euler: false,
    },
    OdometryDetector {
        name: "x-icp",
        label: "X-ICP",
        source: "leggedrobotics/perfectlyconstrained @ 3bd12e4ab9073960f0cb70797fa047b9f540fbad, libpointmatcher/pointmatcher/ICP.cpp detectLocalizability and decideLocalizabilityLevel",
        frame: "the reference map's centroid (no body origin enters)",
        decision: "per eigenvector of the 3x3 rotation and translation blocks, the summed alignment of the correspondences: localizable when the combined sum reaches 300 or the well-aligned sum 150",
        threshold: Some(300.0),
        units: "sums of cosines (correspondence counts)",
        dependence: Dependence::Invariant,
        euler: false,
    },
    OdometryDetector {
        name: "fast-lio",
        label: "FAST-LIO",
        source: "hku-mars/FAST_LIO @ 7cc4175de6f8ba2edf34bab02a42195b141027e9, src/laserMapping.cpp h_share_model (lines 638-754)",
        frame: "the IMU frame (points moved by extrinsic_R, extrinsic_T); translation first; IEKF on so(3)",
        decision: "none: h_x^T R^-1 h_x enters the iterated Kalman gain, no eigen-decomposition",
        threshold: None,
        units: "",
        dependence: Dependence::NoDetector,
        euler: false,
    },
    OdometryDetector {
        name: "point-lio",
        label: "Point-LIO",
        source: "hku-mars/Point-LIO @ ef965976719a1ff5fc956631c54eebf3e8023907, src/Estimator.cpp h_model_input and h_model_output",
        frame: "the IMU frame, as FAST-LIO",
        decision: "none",
        threshold: None,
        units: "",
        dependence: Dependence::NoDetector,
        euler: false,
    },
    OdometryDetector {
        name: "dlio",
        label: "DLIO",
        source: "vectr-ucla/direct_lidar_inertial_odometry @ fc8d183f18cdcfb9bb4fc754c6d373cedc4cbd04, src/dlio/odom.cc (GICP in base_link, lines 238-243)",
        frame: "base_link (dlio/extrinsics/baselink2lidar)",
        decision: "none",
        threshold: None,
        units: "",
        dependence: Dependence::NoDetector,
        euler: false,
    },
];

/// The input formats that reveal the user's odometry (the format's id, as
/// the rig report's `sources[].format` names it).
pub const REVEALED_BY: [(&str, &str); 3] = [
    ("lio-sam", "lio-sam"),
    ("fast-lio", "fast-lio"),
    ("dlio", "dlio"),
];

/// The detector an input of format `format` reveals.
pub fn revealed_by(format: &str) -> Option<&'static OdometryDetector> {
    REVEALED_BY
        .iter()
        .find(|(f, _)| *f == format)
        .and_then(|(_, d)| find(d))
}

/// The detector named `name` (`lio-sam`, `LIO_SAM`, `liosam` alike).
pub fn find(name: &str) -> Option<&'static OdometryDetector> {
    let key = |s: &str| s.to_ascii_lowercase().replace(['-', '_'], "");
    DETECTORS.iter().find(|d| key(d.name) == key(name))
}

impl OdometryDetector {
    /// Every detector the tool knows (`--detector` names), cited from its
    /// source.
    pub fn all() -> &'static [OdometryDetector] {
        &DETECTORS
    }

    /// The detector named `name` (`lio-sam`, `LIO_SAM`, `liosam` alike).
    pub fn find(name: &str) -> Option<&'static OdometryDetector> {
        find(name)
    }

    /// The detector an input of format `format` reveals (a LIO-SAM, FAST-LIO
    /// or DLIO config: the format id a rig report's `sources[].format` names).
    pub fn revealed_by(format: &str) -> Option<&'static OdometryDetector> {
        revealed_by(format)
    }

    /// What this detector does on the rig `t`, the pose of its frame `to`
    /// (the LiDAR) in `from` (the frame the user reads): its threshold
    /// carried into `from` by the certificate band at `l = 1 m`, widened by
    /// the Euler-rate factor for LIO-SAM and LOAM, or why no band bounds it.
    ///
    /// ```
    /// use extrinsic_audit::{OdometryDetector, Transform};
    ///
    /// # fn main() -> extrinsic_audit::Result<()> {
    /// // A LiDAR 1 m above base_link, level: the band at |d| / l = 1 is
    /// // [1 / phi^2, phi^2] (phi the golden ratio), LIO-SAM's threshold 100
    /// // acts in base_link between 38.20 and 261.80.
    /// let t = Transform::from_translation([0.0, 0.0, 1.0])?;
    /// let lio_sam = OdometryDetector::find("LIO_SAM").unwrap();
    /// let advice = lio_sam.advise(&t, "base_link", "lidar");
    /// let phi2 = ((1.0 + 5f64.sqrt()) / 2.0).powi(2);
    /// let [lo, hi] = advice.threshold_in_from.unwrap();
    /// assert!((lo - 100.0 / phi2).abs() < 1e-9 && (hi - 100.0 * phi2).abs() < 1e-9);
    /// assert!(advice.frame_dependent);
    /// assert!(advice.statement.contains("between 38.20 and 261.80"));
    /// // X-ICP evaluates in a frame-free way.
    /// let xicp = OdometryDetector::find("x-icp").unwrap().advise(&t, "base_link", "lidar");
    /// assert!(!xicp.frame_dependent && xicp.threshold_in_from.is_none());
    /// # Ok(())
    /// # }
    /// ```
    pub fn advise(&self, t: &Transform, from: &str, to: &str) -> DetectorAdvice {
        advise(self, t, from, to)
    }
}

/// What a detector does on one rig.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DetectorAdvice {
    /// The detector.
    pub detector: OdometryDetector,
    /// `|d|` of the chain `--from` -> `--to` (m), the band's lever arm at
    /// `l = 1 m`.
    pub lever_arm_m: f64,
    /// The pitch of the detector's frame in `--from` (deg), for Euler
    /// detectors.
    pub pitch_deg: Option<f64>,
    /// The detector's threshold as it acts in `--from`: `[a, b]` (with the
    /// Euler factor), when a band bounds it.
    pub threshold_in_from: Option<[f64; 2]>,
    /// Whether the threshold depends on the body frame on this rig.
    pub frame_dependent: bool,
    /// The statement, with the numbers of this rig.
    pub statement: String,
    /// The concrete step to take.
    pub step: String,
    /// The detector's own configuration file, when one among the inputs
    /// revealed it: the thresholds read from it, which replace the source's
    /// defaults in `detector.threshold`, the statement and the step.
    pub config: Option<DetectorConfig>,
}

/// One threshold read from a detector's own configuration file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConfiguredThreshold {
    /// The key as the file nests it (`degeneracy.condition_threshold`).
    pub key: String,
    /// The 1-based line of the value.
    pub line: usize,
    /// The value read.
    pub value: f64,
    /// The source's default for it (what `--detector NAME` assumes).
    pub default: f64,
    /// The name the source's code gives it (`DEGENERACY_THRES_COND`).
    pub upstream: &'static str,
    /// What the detector compares it with.
    pub meaning: &'static str,
    /// The threshold as it acts on the same eigenvalue in `--from`, `[a, b]`:
    /// set for an eigenvalue threshold on the 6x6 `H` the band bounds (l =
    /// 1 m, no Euler factor), `None` for condition numbers and alignment
    /// sums, which no band bounds or which are frame-invariant.
    pub threshold_in_from: Option<[f64; 2]>,
    /// Whether the band applies to it (an eigenvalue threshold on the 6x6
    /// `H` in metres and radians, right perturbation).
    #[serde(skip)]
    pub banded: bool,
}

/// A detector's own configuration file, read
/// (`OdometryDetector::read_config`): which detector it configures and the
/// thresholds it sets, its first one the detector's `threshold`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DetectorConfig {
    /// The file, as given.
    pub file: String,
    /// The `--detector` name it reveals.
    pub detector: &'static str,
    /// Where the source reads these keys (repository @ commit, file,
    /// function).
    pub source: &'static str,
    /// The thresholds read, in the order the source reads them.
    pub thresholds: Vec<ConfiguredThreshold>,
}

impl DetectorConfig {
    /// The detector, its threshold the one this file sets (`None` when the
    /// file sets none: X-ICP's `None` method, detection off).
    pub fn detector(&self) -> OdometryDetector {
        let mut d = *find(self.detector).expect("a detector in DETECTORS");
        d.threshold = self.thresholds.first().map(|t| t.value);
        d
    }

    /// What the configured detector does on the rig `t` (the pose of its
    /// frame `to` in `from`): [`OdometryDetector::advise`] with this file's
    /// thresholds, each said with its key and line, and an eigenvalue
    /// threshold on the 6x6 `H` carried into `from` by the band.
    pub fn advise(&self, t: &Transform, from: &str, to: &str) -> DetectorAdvice {
        let mut a = advise(&self.detector(), t, from, to);
        let mut config = self.clone();
        let name = std::path::Path::new(&self.file)
            .file_name()
            .map_or(self.file.clone(), |n| n.to_string_lossy().into_owned());
        let mut said = Vec::new();
        for th in &mut config.thresholds {
            let mut s = format!(
                "{} = {} ({name}:{}; {}, default {})",
                th.key, th.value, th.line, th.upstream, th.default
            );
            if th.banded {
                let [lo, hi] = threshold_band(th.value, a.lever_arm_m, None);
                th.threshold_in_from = Some([lo, hi]);
                s.push_str(&format!(
                    ", which acts on the same eigenvalue in {from} between {lo:.2} and {hi:.2}"
                ));
                a.step.push_str(&format!(
                    "; its eigenvalue threshold {} ({}) acts in {from} between {lo:.2} and {hi:.2} on this rig: scale it into that range for a detector run in {from}",
                    th.value, th.key
                ));
                a.frame_dependent |= a.lever_arm_m > 0.0;
            }
            said.push(s);
        }
        if said.is_empty() {
            // X-ICP's `degeneracyAwareness: None`: the one method with no keys.
            a.statement.push_str(&format!(
                "; your configuration ({name}) sets no threshold: its method runs no degeneracy detection"
            ));
            a.step = format!("{name} turns the detection off: nothing to scale for the frame");
        } else {
            a.statement.push_str(&format!(
                "; your configuration replaces the defaults: {}",
                said.join("; ")
            ));
        }
        a.config = Some(config);
        a
    }
}

/// `[tau s_min^2, tau s_max^2]` at `|d|` (l = 1 m), widened by the Euler
/// factor `[1 - |sin p|, 1 + |sin p|]` when `pitch` is given.
pub fn threshold_band(tau: f64, lever_arm_m: f64, pitch_rad: Option<f64>) -> [f64; 2] {
    let [lo, hi] = band(lever_arm_m);
    let s = pitch_rad.map_or(0.0, |p| p.sin().abs());
    [tau * lo * (1.0 - s), tau * hi * (1.0 + s)]
}

/// What `d` does on the rig `t` (the pose of its frame `to` in `from`).
pub fn advise(d: &OdometryDetector, t: &Transform, from: &str, to: &str) -> DetectorAdvice {
    let lever = t.lever_arm();
    let pitch = d
        .euler
        .then(|| (-t.rotation()[(2, 0)]).clamp(-1.0, 1.0).asin());
    let (band, dependent, statement, step) = match (d.dependence, d.threshold) {
        (Dependence::Band, Some(tau)) => {
            let b = threshold_band(tau, lever, pitch);
            let euler = pitch.map_or(String::new(), |p| {
                format!(
                    "; the {to} pitch of {:.1} deg widens it by [1 - |sin p|, 1 + |sin p|]",
                    p.to_degrees()
                )
            });
            let statement = format!(
                "{} decides degeneracy in {}: its threshold {tau} ({}) acts on the same eigenvalue in {from} as a threshold between {:.2} and {:.2} (lever arm {:.3} m, l = 1 m{euler})",
                d.label, d.frame, d.units, b[0], b[1], lever
            );
            let mut step = format!(
                "do not carry the threshold {tau} to a detector in {from} (or the IMU) on this rig without scaling it into [{:.2}, {:.2}]; for a frame-free decision use the point-displacement metric",
                b[0], b[1]
            );
            if pitch.is_some_and(|p| p.to_degrees().abs() > EULER_PITCH_WARN_DEG) {
                step.push_str("; the mount is near 90 deg of pitch, where its Euler Jacobian is near singular: expect degeneracy flagged on every scan, or re-frame the LiDAR");
            }
            (Some(b), lever > 0.0 || pitch.is_some_and(|p| p != 0.0), statement, step)
        }
        (Dependence::Unbounded, _) => (
            None,
            true,
            format!(
                "{} decides degeneracy in {}: {}; no band bounds this on a rig (its blocks are not a congruence of H's), so the frame dependence through the lever arm of {:.3} m cannot be bounded from the rig alone",
                d.label, d.frame, d.decision, lever
            ),
            format!(
                "run `audit degeneracy` on a scan in both frames (--shift to the frame {} runs in) to see the change on your data",
                d.label
            ),
        ),
        (Dependence::Invariant, _) => (
            None,
            false,
            format!(
                "{} evaluates in {}: invariant to the body frame on every rig; its thresholds ({}) move with point density and scene scale, not with this rig's lever arm",
                d.label, d.frame, d.units
            ),
            "nothing to change for the frame; tune its thresholds to the point density".into(),
        ),
        _ => (
            None,
            false,
            format!("{} has no degeneracy detector ({}; {})", d.label, d.frame, d.decision),
            format!(
                "a detector you add on its H runs in {}: a threshold taken from LIO-SAM (LiDAR frame) acts there between {:.2} and {:.2} (100 times the band at the lever arm {:.3} m); or use the point-displacement metric, frame-invariant on every rig",
                d.frame,
                threshold_band(100.0, lever, None)[0],
                threshold_band(100.0, lever, None)[1],
                lever
            ),
        ),
    };
    DetectorAdvice {
        detector: *d,
        lever_arm_m: lever,
        pitch_deg: pitch.map(f64::to_degrees),
        threshold_in_from: band,
        frame_dependent: dependent,
        statement,
        step,
        config: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::Value;

    fn checks() -> Value {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/detectors/detector_checks.json"
        );
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
    }

    /// numpy's examples (detector_checks.py): tau times the band at |d|.
    #[test]
    fn the_threshold_band_matches_numpy() {
        let v = checks();
        let rows = v["threshold_band_examples"].as_array().unwrap();
        assert!(rows.len() >= 6);
        for r in rows {
            let tau = r["tau"].as_f64().unwrap();
            let d = r["lever_arm_m"].as_f64().unwrap();
            let want = &r["threshold_in_base_link"];
            let got = threshold_band(tau, d, None);
            for k in 0..2 {
                let w = want[k].as_f64().unwrap();
                assert!((got[k] - w).abs() <= 1e-12 * w, "{r}");
            }
        }
    }

    #[test]
    fn the_euler_factor_widens_the_band_by_the_mount_pitch() {
        // A LiDAR pitched 30 deg, no lever arm: [1 - 1/2, 1 + 1/2] times tau.
        let t = Transform::from_rpy([0.0, 30f64.to_radians(), 0.0], [0.0; 3]).unwrap();
        let a = advise(find("LIO_SAM").unwrap(), &t, "base_link", "lidar");
        let b = a.threshold_in_from.unwrap();
        assert!(
            (b[0] - 50.0).abs() < 1e-9 && (b[1] - 150.0).abs() < 1e-9,
            "{b:?}"
        );
        assert!(
            a.statement.contains("between 50.00 and 150.00"),
            "{}",
            a.statement
        );
        let near = Transform::from_rpy([0.0, 85f64.to_radians(), 0.0], [0.0; 3]).unwrap();
        let a = advise(find("lio-sam").unwrap(), &near, "base_link", "lidar");
        assert!(a.step.contains("near singular"), "{}", a.step);
    }

    /// A configured eigenvalue threshold on a LiDAR 1 m above base_link:
    /// the band at |d| / l = 1 is [1 / phi^2, phi^2] (closed form), so
    /// DCReg's 150 acts in base_link between 150 / phi^2 and 150 phi^2;
    /// the condition threshold (no band) becomes the detector's threshold.
    #[test]
    fn a_configured_eigenvalue_threshold_is_carried_by_the_band() {
        let th = |key: &str, value: f64, banded: bool| ConfiguredThreshold {
            key: key.into(),
            line: 3,
            value,
            default: 1.0,
            upstream: "X",
            meaning: "",
            threshold_in_from: None,
            banded,
        };
        let c = DetectorConfig {
            file: "cfg/icp.yaml".into(),
            detector: "dcreg",
            source: "",
            thresholds: vec![
                th("degeneracy.condition_threshold", 25.0, false),
                th("degeneracy.eigenvalue_threshold", 150.0, true),
            ],
        };
        let t = Transform::from_translation([0.0, 0.0, 1.0]).unwrap();
        let a = c.advise(&t, "base_link", "lidar");
        assert_eq!(a.detector.threshold, Some(25.0));
        let phi2 = ((1.0 + 5f64.sqrt()) / 2.0).powi(2);
        let got = a.config.as_ref().unwrap().thresholds[1]
            .threshold_in_from
            .unwrap();
        assert!((got[0] - 150.0 / phi2).abs() < 1e-9 && (got[1] - 150.0 * phi2).abs() < 1e-9);
        assert!(a.config.as_ref().unwrap().thresholds[0]
            .threshold_in_from
            .is_none());
        assert!(
            a.statement.contains("(icp.yaml:3; X, default 1)"),
            "{}",
            a.statement
        );
        assert!(a.step.contains("between 57.29 and 392.71"), "{}", a.step);
    }

    #[test]
    fn unbounded_invariant_and_absent_detectors_say_so() {
        let t = Transform::from_rpy([0.0; 3], [0.3, 0.0, 0.2]).unwrap();
        let a = advise(find("dcreg").unwrap(), &t, "base_link", "lidar");
        assert!(a.threshold_in_from.is_none() && a.frame_dependent);
        assert!(a.statement.contains("cannot be bounded"));
        let a = advise(find("x-icp").unwrap(), &t, "base_link", "lidar");
        assert!(!a.frame_dependent && a.statement.contains("invariant"));
        let a = advise(find("fast-lio").unwrap(), &t, "imu", "lidar");
        assert!(a
            .statement
            .starts_with("FAST-LIO has no degeneracy detector"));
        assert!(find("no-such").is_none());
    }
}
