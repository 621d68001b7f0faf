//! The user's detector revealed by the configuration file it reads, given
//! among the calibration files (`audit rig.toml icp.yaml --from base_link
//! --to lidar`). Such a file sets detector thresholds and no sensor
//! extrinsic, so it is not an input format: it adds no edge, it reveals the
//! detector and its thresholds ([`DetectorConfig`]), which replace the
//! source's defaults in the rig report's advice.
//!
//! Only `.yaml`/`.yml` files that name the keys below are read as such; any
//! other file goes to the formats. The keys and what reads them:
//!
//! - DCReg (`dcreg`): JokerJohn/DCReg @ 18b173c862e9dcabbc1798e589a4bf80fceb26e0,
//!   DCReg/src/icp_test_runner.cpp `loadConfig` (lines 20-153, the keys at
//!   75-78): when `degeneracy` is present it reads both
//!   `degeneracy.condition_threshold` (`DEGENERACY_THRES_COND`) and
//!   `degeneracy.eigenvalue_threshold` (`DEGENERACY_THRES_EIG`) with
//!   `as<double>()`, and a missing or non-numeric one fails the whole load
//!   (the `YAML::Exception` catch, line 149). Defaults 10 and 120:
//!   DCReg/include/utils.hpp `ICPParameters` (lines 83-84). DCReg/include/dcreg.hpp
//!   `analyzeDegeneracy` compares condition numbers with the first and, for the
//!   `FULL_EVD_MIN_EIGENVALUE` methods (`ME-SR`, `ME-TSVD`, `ME-TReg`),
//!   every eigenvalue of the 6x6 `J^T J` with the second (line 103). Its rows
//!   are `MathUtils::computePointToPlaneJacobian` (include/math_utils.hpp
//!   102-121: `[-n^T R [p]x, n^T R]`, rotation first, right perturbation, the
//!   source cloud's frame, metres) under the default
//!   `use_so3_parameterization = true` (utils.hpp line 170): so the band
//!   bounds that eigenvalue threshold at l = 1 m, with no Euler factor. The
//!   file's `gt_pose` and `initial_noise` are the test's pose of the source
//!   cloud against the target, not a sensor mount: nothing is read from them.
//! - X-ICP (`x-icp`): leggedrobotics/perfectlyconstrained @
//!   3bd12e4ab9073960f0cb70797fa047b9f540fbad,
//!   libpointmatcher/pointmatcher/ICP.cpp `readLocalizabilityAwarenessParameters`
//!   (called from `ICPChainBase::loadFromYaml` with the key
//!   `degeneracyAwareness`): the one key under `degeneracyAwareness` names
//!   the method (`None`, `SolutionRemapping`, `OptimizedEqualityConstraints`,
//!   `EqualityConstraints`, `InequalityConstraints`; any other is an error
//!   there) and its mapping holds `enoughInformationThreshold` and
//!   `insufficientInformationThreshold` (every method but `None`) and
//!   `highInformationThreshold` (the two constraint methods), each required
//!   (the reader returns false without it). Example file:
//!   open3d_slam_rsl/ros/open3d_slam_ros/param/icp.yaml at that commit (300,
//!   150). The sums are frame-invariant: no band.

use crate::analysis::detectors::{ConfiguredThreshold, DetectorConfig, OdometryDetector};
use crate::diagnostic::{Error, Result};
use crate::formats::yaml::{parse_documents, Node, Value};
use crate::tolerances::DEFAULT_MAX_FILE_SIZE;
use std::path::Path;

/// One key a detector's configuration sets.
struct Key {
    /// The key under its section (`condition_threshold`).
    name: &'static str,
    /// The source's name for it.
    upstream: &'static str,
    /// The source's default.
    default: f64,
    /// What the detector compares it with.
    meaning: &'static str,
    /// The smallest value that means anything (exclusive for 0).
    at_least: f64,
    /// An eigenvalue threshold on the 6x6 `H` the band bounds.
    banded: bool,
}

const DCREG_SOURCE: &str = "JokerJohn/DCReg @ 18b173c862e9dcabbc1798e589a4bf80fceb26e0, DCReg/src/icp_test_runner.cpp loadConfig (lines 75-78); defaults DCReg/include/utils.hpp ICPParameters (83-84)";

const DCREG_KEYS: [Key; 2] = [
    Key {
        name: "condition_threshold",
        upstream: "DEGENERACY_THRES_COND",
        default: 10.0,
        meaning: "the condition number above which DCReg flags a direction (Schur blocks; the full-SVD methods)",
        at_least: 1.0,
        banded: false,
    },
    Key {
        name: "eigenvalue_threshold",
        upstream: "DEGENERACY_THRES_EIG",
        default: 120.0,
        meaning: "every eigenvalue of the 6x6 J^T J below it is flagged by the FULL_EVD_MIN_EIGENVALUE methods (ME-SR, ME-TSVD, ME-TReg)",
        at_least: 0.0,
        banded: true,
    },
];

const XICP_SOURCE: &str = "leggedrobotics/perfectlyconstrained @ 3bd12e4ab9073960f0cb70797fa047b9f540fbad, libpointmatcher/pointmatcher/ICP.cpp readLocalizabilityAwarenessParameters";

const XICP_METHODS: [&str; 5] = [
    "None",
    "SolutionRemapping",
    "OptimizedEqualityConstraints",
    "EqualityConstraints",
    "InequalityConstraints",
];

const XICP_ENOUGH: Key = Key {
    name: "enoughInformationThreshold",
    upstream: "enoughInformationThreshold",
    default: 300.0,
    meaning: "the summed alignment of a direction's correspondences at which it is localizable",
    at_least: 0.0,
    banded: false,
};
const XICP_INSUFFICIENT: Key = Key {
    name: "insufficientInformationThreshold",
    upstream: "insufficientInformationThreshold",
    default: 150.0,
    meaning: "the well-aligned sum below which a direction is not localizable",
    at_least: 0.0,
    banded: false,
};
const XICP_HIGH: Key = Key {
    name: "highInformationThreshold",
    upstream: "highInformationThreshold",
    default: 300.0,
    meaning: "the summed alignment above which only the strongly aligned correspondences constrain a direction",
    at_least: 0.0,
    banded: false,
};

/// What [`OdometryDetector::sniff_config`] found in a file.
pub(crate) enum Sniffed {
    /// A detector's configuration.
    Config(DetectorConfig),
    /// Not one; the file (open), its reported size and its bytes when they
    /// can stand for reading it again.
    Other(Option<crate::input::ReadWhole>),
}

impl OdometryDetector {
    /// Read `path` as the configuration file of a detector (DCReg's
    /// `icp.yaml`, an X-ICP libpointmatcher ICP file): `None` when it is not
    /// one (not `.yaml`/`.yml`, or neither a `degeneracy` mapping with
    /// DCReg's keys nor a `degeneracyAwareness` key), so that it goes to the
    /// calibration formats. A value that is not a number the source reads,
    /// or one no detector can use, is an error at its line.
    pub fn read_config(path: &Path) -> Result<Option<DetectorConfig>> {
        Ok(match Self::sniff_config(path)? {
            Sniffed::Config(c) => Some(c),
            Sniffed::Other(_) => None,
        })
    }

    /// [`read_config`](Self::read_config), and when the file is not a
    /// configuration the file as read (open, with its bytes), so that `check`
    /// reads a YAML file once (issue 29: the second open and read were a
    /// quarter of a fleet's system calls). Only plain text is handed on (valid
    /// UTF-8 without a byte-order mark, a CR or a NUL byte): what else a file
    /// holds is read again by the formats as it always was.
    pub(crate) fn sniff_config(path: &Path) -> Result<Sniffed> {
        const WHAT: &str = "detector configuration";
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        if !matches!(ext.as_deref(), Some("yaml" | "yml")) {
            return Ok(Sniffed::Other(None));
        }
        // A configuration is a few kilobytes: a larger file is left to the
        // formats and their own size cap (`--max-file-size`). One `stat` for
        // both questions (a folder, the size).
        match std::fs::metadata(path) {
            Ok(m) if !m.is_dir() && m.len() <= DEFAULT_MAX_FILE_SIZE => {}
            _ => return Ok(Sniffed::Other(None)),
        }
        let (file, len) = crate::input::open_file(path).map_err(|e| e.into_error(path, WHAT))?;
        let bytes = crate::input::read_open(&file, len, DEFAULT_MAX_FILE_SIZE)
            .map_err(|e| e.into_error(path, WHAT))?;
        // Both detectors' sections start a line: skip the parse otherwise.
        let has_section = |t: &str| {
            t.lines()
                .any(|l| l.starts_with("degeneracy:") || l.starts_with("degeneracyAwareness:"))
        };
        let plain = !bytes.starts_with("\u{feff}".as_bytes())
            && memchr::memchr2(b'\r', 0, &bytes).is_none()
            && std::str::from_utf8(&bytes).is_ok_and(|t| !has_section(t));
        if plain {
            return Ok(Sniffed::Other(Some((file, len, bytes))));
        }
        let text = crate::input::decode(bytes).map_err(|e| e.in_file(path))?;
        if !has_section(&text) {
            return Ok(Sniffed::Other(None));
        }
        let docs = parse_documents(&text).map_err(|e| e.in_file(path))?;
        let Some(root) = docs.first() else {
            return Ok(Sniffed::Other(None));
        };
        let file = path.display().to_string();
        if let Some(section) = root.get("degeneracy").filter(|s| is_dcreg(s)) {
            let thresholds = DCREG_KEYS
                .iter()
                .map(|k| {
                    threshold(
                        section,
                        "degeneracy",
                        k,
                        "DCReg's loadConfig reads both keys",
                    )
                })
                .collect::<Result<Vec<_>>>()
                .map_err(|e| e.in_file(path))?;
            return Ok(Sniffed::Config(DetectorConfig {
                file,
                detector: "dcreg",
                source: DCREG_SOURCE,
                thresholds,
            }));
        }
        if let Some(section) = root.get("degeneracyAwareness") {
            let thresholds = xicp(section).map_err(|e| e.in_file(path))?;
            return Ok(Sniffed::Config(DetectorConfig {
                file,
                detector: "x-icp",
                source: XICP_SOURCE,
                thresholds,
            }));
        }
        Ok(Sniffed::Other(None))
    }
}

/// A `degeneracy` mapping holding one of DCReg's keys.
fn is_dcreg(section: &Node) -> bool {
    DCREG_KEYS.iter().any(|k| section.get(k.name).is_some())
}

/// The key `k` of `section` (nested under `prefix`), checked.
fn threshold(section: &Node, prefix: &str, k: &Key, why: &str) -> Result<ConfiguredThreshold> {
    let key = format!("{prefix}.{}", k.name);
    let Some(node) = section.get(k.name) else {
        return Err(Error::parse(format!(
            "expected `{key}` ({}) in this detector configuration ({why}), found none",
            k.upstream
        ))
        .at_line(section.line, Some(section.column)));
    };
    let at = |e: Error| e.at_line(node.line, Some(node.column));
    let value = match (&node.value, node.as_f64()) {
        (Value::Num(_) | Value::Str(_), Some(v)) => v,
        _ => {
            return Err(at(Error::parse(format!(
                "expected a number for `{key}` ({}), found {}",
                k.upstream,
                found(node)
            ))))
        }
    };
    let usable = if k.at_least > 0.0 {
        value >= k.at_least
    } else {
        value > 0.0
    };
    if !value.is_finite() || !usable {
        let expected = if k.at_least > 0.0 {
            format!(
                "at least {} (a condition number is never below 1: every scan would be flagged)",
                k.at_least
            )
        } else {
            "a positive number".to_string()
        };
        return Err(at(Error::invalid(format!(
            "expected {expected} for `{key}` ({}), found {value}",
            k.upstream
        ))));
    }
    Ok(ConfiguredThreshold {
        key,
        line: node.line,
        value,
        default: k.default,
        upstream: k.upstream,
        meaning: k.meaning,
        threshold_in_from: None,
        banded: k.banded,
    })
}

/// What a node holds, for messages.
fn found(node: &Node) -> String {
    match node.as_str() {
        Some(s) => format!("{} `{s}`", node.kind()),
        None => node.kind().to_string(),
    }
}

/// X-ICP's `degeneracyAwareness: {METHOD: {...}}`: the method's thresholds.
fn xicp(section: &Node) -> Result<Vec<ConfiguredThreshold>> {
    let (method, params) = match section.entries() {
        [(k, v)] => (k.as_str().unwrap_or_default(), v),
        _ => {
            return Err(Error::parse(format!(
                "expected one method under `degeneracyAwareness` (one of {}), found {}",
                XICP_METHODS.join(", "),
                match section.entries().len() {
                    0 => found(section),
                    n => format!("{n} keys"),
                }
            ))
            .at_line(section.line, Some(section.column)))
        }
    };
    let prefix = format!("degeneracyAwareness.{method}");
    let why = format!("X-ICP's {method} reads it");
    let keys: &[&Key] = match method.as_str() {
        "None" => &[],
        "SolutionRemapping" | "OptimizedEqualityConstraints" => &[&XICP_ENOUGH, &XICP_INSUFFICIENT],
        "EqualityConstraints" | "InequalityConstraints" => {
            &[&XICP_ENOUGH, &XICP_INSUFFICIENT, &XICP_HIGH]
        }
        other => {
            let key = section.entries().first().map(|(k, _)| k);
            return Err(Error::parse(format!(
                "expected an X-ICP method under `degeneracyAwareness` (one of {}), found `{other}`",
                XICP_METHODS.join(", ")
            ))
            .at_line(key.map_or(section.line, |k| k.line), key.map(|k| k.column)));
        }
    };
    keys.iter()
        .map(|k| threshold(params, &prefix, k, &why))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Option<DetectorConfig>> {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("icp.yaml");
        std::fs::write(&p, text).unwrap();
        OdometryDetector::read_config(&p)
    }

    #[test]
    fn a_calibration_yaml_is_not_a_detector_configuration() {
        assert!(read("extrinsic_T: [0, 0, 0]\n").unwrap().is_none());
        // A `degeneracy` section without DCReg's keys is someone else's.
        assert!(read("degeneracy:\n  enabled: true\n").unwrap().is_none());
    }

    #[test]
    fn xicp_reads_the_thresholds_its_method_reads() {
        let c = read(
            "degeneracyAwareness:\n  EqualityConstraints:\n    highInformationThreshold: 900\n    enoughInformationThreshold: 250\n    insufficientInformationThreshold: 120\n",
        )
        .unwrap()
        .unwrap();
        assert_eq!(c.detector, "x-icp");
        let got: Vec<(&str, f64, usize)> = c
            .thresholds
            .iter()
            .map(|t| (t.key.as_str(), t.value, t.line))
            .collect();
        assert_eq!(
            got,
            [
                (
                    "degeneracyAwareness.EqualityConstraints.enoughInformationThreshold",
                    250.0,
                    4
                ),
                (
                    "degeneracyAwareness.EqualityConstraints.insufficientInformationThreshold",
                    120.0,
                    5
                ),
                (
                    "degeneracyAwareness.EqualityConstraints.highInformationThreshold",
                    900.0,
                    3
                ),
            ]
        );
        assert_eq!(c.detector().threshold, Some(250.0));
        // `None`: X-ICP off, no key read; the advice says so.
        let off = read("degeneracyAwareness:\n  None:\n").unwrap().unwrap();
        assert!(off.thresholds.is_empty() && off.detector().threshold.is_none());
        let t = crate::Transform::from_translation([0.0, 0.0, 1.0]).unwrap();
        let a = off.advise(&t, "base_link", "lidar");
        assert!(
            a.statement
                .ends_with("its method runs no degeneracy detection"),
            "{}",
            a.statement
        );
        assert!(
            a.step.starts_with("icp.yaml turns the detection off"),
            "{}",
            a.step
        );
        let e = read("degeneracyAwareness:\n  Magic:\n    enoughInformationThreshold: 1\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("icp.yaml:2:") && e.contains("found `Magic`"),
            "{e}"
        );
        let e = read("degeneracyAwareness:\n  OptimizedEqualityConstraints:\n    enoughInformationThreshold: 300\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("insufficientInformationThreshold") && e.contains("found none"),
            "{e}"
        );
    }
}
