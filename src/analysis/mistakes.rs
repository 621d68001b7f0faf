//! The convention mistake named: when two sources of one edge disagree, try
//! the usual mistakes and name those that reconcile them within tolerance
//! ("new equals old inverted (residual 0.019 mm, 0.001 deg)").
//!
//! # Conventions (stated once here)
//!
//! Both sources are `T = (R, t)`, the pose of the child in the parent
//! ([`crate::geometry::se3`]). A mistake maps the transform as intended to
//! the one read, `T' = f(T)`; those that live in the written numbers
//! (quaternion order, Euler order, degrees against radians) act on the
//! numbers a file would write: the quaternion `[x, y, z, w]` with `w >= 0`,
//! and both fixed-axis rpy branches `(r, p, y)` and `(r + pi, pi - p, y + pi)`
//! (the moving-axis XYZ angles likewise), because only `T` is held. The
//! candidates ([`CANDIDATES`]):
//!
//! | name | `T' = f(T)` |
//! |---|---|
//! | `inverse` (parent and child swapped) | `(R^T, -R^T t)` |
//! | `rotation_transposed` (read column-major) | `(R^T, t)` |
//! | `quaternion_wxyz_read_as_xyzw` | written `w,x,y,z`, read as `x,y,z,w` |
//! | `quaternion_xyzw_read_as_wxyz` | written `x,y,z,w`, read as `w,x,y,z` |
//! | `euler_rpy_read_as_ypr` | `(a, b, c)` written roll, pitch, yaw, read yaw, pitch, roll |
//! | `euler_extrinsic_read_as_intrinsic` | fixed-axis `Rz(c) Ry(b) Rx(a)` read as moving-axis `Rx(a) Ry(b) Rz(c)` |
//! | `euler_intrinsic_read_as_extrinsic` | the reverse |
//! | `degrees_read_as_radians`, `radians_read_as_degrees` | rpy numbers scaled by `180/pi`, `pi/180` |
//! | `millimetres_read_as_metres`, `centimetres_read_as_metres` | `t' = 1000 t`, `100 t` |
//! | `metres_read_as_millimetres`, `metres_read_as_centimetres` | `t' = t / 1000`, `t / 100` |
//! | `child_is_optical_frame` / `child_is_body_frame` | `R' = R R_bo` / `R R_bo^T` |
//! | `parent_is_optical_frame` / `parent_is_body_frame` | `(R_bo^T R, R_bo^T t)` / `(R_bo R, R_bo t)` |
//!
//! `R_bo = [[0,0,1],[-1,0,0],[0,-1,0]]` is the pose of the REP-103 optical
//! frame (x right, y down, z forward) in the camera's body frame (x forward,
//! y left, z up): URDF `rpy = (-pi/2, 0, -pi/2)`, the usual
//! `*_optical_frame` joint (REP 103, "Suffix Frames").
//!
//! The decision, for a candidate and a direction (`b = f(a)`, tried both
//! ways): residual `r_t = |t_f - t_b|` (mm) and `r_R = angle(R_f^T R_b)`
//! (deg), the branch with the smallest `r_t / tol_t + r_R / tol_R` kept. A
//! candidate is named when the two sources disagree beyond the tolerance, the
//! candidate is observable on this pair (it moves `a` beyond the tolerance: a
//! transposed half-turn or a unit change of a zero translation is not), and
//! both residuals are within it. Every candidate that reconciles is named:
//! several at once means the pair is ambiguous (with a zero translation,
//! `inverse` and `rotation_transposed` are the same map). Euler candidates are
//! skipped when either source is at gimbal lock (the triple is not unique).

use crate::geometry::se3::{matrix_to_rpy, rpy_to_matrix};
use crate::geometry::Transform;
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use serde::Serialize;
use std::f64::consts::PI;

/// `1 - |R[2][0]|` (fixed axes) or `1 - |R[0][2]|` (moving axes) below which
/// the Euler triple of a rotation is not unique (pitch at +-90 deg): the
/// Euler candidates are skipped.
pub const GIMBAL_TOL: f64 = 1e-9;

/// The pose of the REP-103 optical frame in the camera's body frame.
pub const R_BODY_OPTICAL: [[f64; 3]; 3] = [[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]];

/// The tolerance within which a candidate reconciles two sources.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MistakeTol {
    /// On the translation residual (mm).
    pub translation_mm: f64,
    /// On the rotation residual (deg).
    pub rotation_deg: f64,
}

/// Which way a mistake maps one source onto the other.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// The second source is the first one misread: `b = f(a)`.
    SecondFromFirst,
    /// The first is the second misread: `a = f(b)`.
    FirstFromSecond,
}

/// One candidate mistake: its name, how a sentence says it, its map.
pub struct Candidate {
    /// The stable name (JSON, tests).
    pub name: &'static str,
    /// "`b` equals `a` ..." (the phrase after the first source's name).
    pub phrase: &'static str,
    /// Whether it acts on Euler angles (skipped at gimbal lock).
    pub euler: bool,
    map: fn(&Transform) -> Vec<Transform>,
}

/// A mistake that reconciles the two sources.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Found {
    /// The candidate's name.
    pub mistake: &'static str,
    /// Which source is the other misread.
    pub direction: Direction,
    /// Translation residual (mm).
    pub residual_mm: f64,
    /// Rotation residual (deg).
    pub residual_deg: f64,
}

/// What the two sources say together.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Explanation {
    /// `|t_b - t_a|` (mm).
    pub translation_mm: f64,
    /// The angle of `R_a^T R_b` (deg).
    pub rotation_deg: f64,
    /// They agree within the tolerance (nothing to explain).
    pub agree: bool,
    /// The mistakes that reconcile them (empty: a genuine disagreement).
    pub mistakes: Vec<Found>,
    /// The Euler candidates were not tried (gimbal lock).
    pub euler_skipped: bool,
}

fn parts(t: &Transform) -> (Matrix3<f64>, Vector3<f64>) {
    (*t.rotation(), *t.translation())
}

fn make(r: Matrix3<f64>, t: Vector3<f64>) -> Transform {
    Transform::from_parts_unchecked(r, t)
}

fn rot(r: Matrix3<f64>, t: &Transform) -> Vec<Transform> {
    vec![make(r, *t.translation())]
}

fn quat_matrix(x: f64, y: f64, z: f64, w: f64) -> Matrix3<f64> {
    let q = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
    *q.to_rotation_matrix().matrix()
}

fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(2.0 * PI) - PI
}

/// Both triples of one Euler convention.
fn branches(e: [f64; 3]) -> [[f64; 3]; 2] {
    [e, [wrap(e[0] + PI), wrap(PI - e[1]), wrap(e[2] + PI)]]
}

/// `Rx(a) Ry(b) Rz(c)` (moving axes XYZ).
fn intrinsic_matrix(e: [f64; 3]) -> Matrix3<f64> {
    let ax = |v: Vector3<f64>, a: f64| {
        *nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(v), a).matrix()
    };
    ax(Vector3::x(), e[0]) * ax(Vector3::y(), e[1]) * ax(Vector3::z(), e[2])
}

/// `(a, b, c)` with `R = Rx(a) Ry(b) Rz(c)`.
fn matrix_to_intrinsic(r: &Matrix3<f64>) -> [f64; 3] {
    let b = r[(0, 2)].clamp(-1.0, 1.0).atan2(r[(0, 0)].hypot(r[(0, 1)]));
    [
        (-r[(1, 2)]).atan2(r[(2, 2)]),
        b,
        (-r[(0, 1)]).atan2(r[(0, 0)]),
    ]
}

fn rpy_m(e: [f64; 3]) -> Matrix3<f64> {
    rpy_to_matrix(e[0], e[1], e[2])
}

fn rpy_branches(t: &Transform) -> [[f64; 3]; 2] {
    branches(matrix_to_rpy(t.rotation()))
}

fn per_branch(t: &Transform, f: impl Fn([f64; 3]) -> Matrix3<f64>) -> Vec<Transform> {
    rpy_branches(t)
        .into_iter()
        .map(|e| make(f(e), *t.translation()))
        .collect()
}

fn scaled(t: &Transform, k: f64) -> Vec<Transform> {
    vec![make(*t.rotation(), t.translation() * k)]
}

/// `t` with its quaternion's written components `[x, y, z, w]` read back
/// by `read` as `[w, x, y, z]`.
fn reread_quaternion(t: &Transform, read: fn([f64; 4]) -> [f64; 4]) -> Vec<Transform> {
    let [w, x, y, z] = read(t.quaternion_xyzw());
    rot(quat_matrix(w, x, y, z), t)
}

fn r_bo() -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| R_BODY_OPTICAL[i][j])
}

/// Every candidate, in a fixed order.
pub const CANDIDATES: [Candidate; 17] = [
    Candidate {
        name: "inverse",
        phrase: "inverted (parent and child swapped)",
        euler: false,
        map: |t| vec![t.inverse()],
    },
    Candidate {
        name: "rotation_transposed",
        phrase: "with its rotation matrix transposed (read column-major)",
        euler: false,
        map: |t| rot(t.rotation().transpose(), t),
    },
    Candidate {
        name: "quaternion_wxyz_read_as_xyzw",
        phrase: "with its quaternion written w,x,y,z read as x,y,z,w",
        euler: false,
        map: |t| reread_quaternion(t, |[x, y, z, w]| [w, x, y, z]),
    },
    Candidate {
        name: "quaternion_xyzw_read_as_wxyz",
        phrase: "with its quaternion written x,y,z,w read as w,x,y,z",
        euler: false,
        map: |t| reread_quaternion(t, |[x, y, z, w]| [y, z, w, x]),
    },
    Candidate {
        name: "euler_rpy_read_as_ypr",
        phrase: "with its roll, pitch, yaw read as yaw, pitch, roll",
        euler: true,
        map: |t| per_branch(t, |[a, b, c]| rpy_m([c, b, a])),
    },
    Candidate {
        name: "euler_extrinsic_read_as_intrinsic",
        phrase: "with its fixed-axis angles read as moving-axis (extrinsic xyz as intrinsic XYZ)",
        euler: true,
        map: |t| per_branch(t, intrinsic_matrix),
    },
    Candidate {
        name: "euler_intrinsic_read_as_extrinsic",
        phrase: "with its moving-axis angles read as fixed-axis (intrinsic XYZ as extrinsic xyz)",
        euler: true,
        map: |t| {
            branches(matrix_to_intrinsic(t.rotation()))
                .into_iter()
                .map(|e| make(rpy_m(e), *t.translation()))
                .collect()
        },
    },
    Candidate {
        name: "degrees_read_as_radians",
        phrase: "with its angles in degrees read as radians",
        euler: true,
        map: |t| per_branch(t, |e| rpy_m(e.map(f64::to_degrees))),
    },
    Candidate {
        name: "radians_read_as_degrees",
        phrase: "with its angles in radians read as degrees",
        euler: true,
        map: |t| per_branch(t, |e| rpy_m(e.map(f64::to_radians))),
    },
    Candidate {
        name: "millimetres_read_as_metres",
        phrase: "with its translation in millimetres read as metres",
        euler: false,
        map: |t| scaled(t, 1e3),
    },
    Candidate {
        name: "centimetres_read_as_metres",
        phrase: "with its translation in centimetres read as metres",
        euler: false,
        map: |t| scaled(t, 1e2),
    },
    Candidate {
        name: "metres_read_as_millimetres",
        phrase: "with its translation in metres read as millimetres",
        euler: false,
        map: |t| scaled(t, 1e-3),
    },
    Candidate {
        name: "metres_read_as_centimetres",
        phrase: "with its translation in metres read as centimetres",
        euler: false,
        map: |t| scaled(t, 1e-2),
    },
    Candidate {
        name: "child_is_optical_frame",
        phrase: "with its child taken as the camera's optical frame (REP-103, z forward)",
        euler: false,
        map: |t| rot(t.rotation() * r_bo(), t),
    },
    Candidate {
        name: "child_is_body_frame",
        phrase: "with its child taken as the camera's body frame (REP-103, x forward)",
        euler: false,
        map: |t| rot(t.rotation() * r_bo().transpose(), t),
    },
    Candidate {
        name: "parent_is_optical_frame",
        phrase: "with its parent taken as the camera's optical frame (REP-103, z forward)",
        euler: false,
        map: |t| {
            let (r, d) = parts(t);
            vec![make(r_bo().transpose() * r, r_bo().transpose() * d)]
        },
    },
    Candidate {
        name: "parent_is_body_frame",
        phrase: "with its parent taken as the camera's body frame (REP-103, x forward)",
        euler: false,
        map: |t| {
            let (r, d) = parts(t);
            vec![make(r_bo() * r, r_bo() * d)]
        },
    },
];

/// `(|t_a - t_b|` mm, angle of `R_a^T R_b` deg`)`.
pub fn residual(a: &Transform, b: &Transform) -> (f64, f64) {
    let mm = (a.translation() - b.translation()).norm() * 1e3;
    let deg = a.inverse().compose(b).rotation_angle_axis().0.to_degrees();
    (mm, deg)
}

fn within(r: (f64, f64), tol: &MistakeTol) -> bool {
    r.0 <= tol.translation_mm && r.1 <= tol.rotation_deg
}

/// The branch of `f(a)` nearest `b` and how far `f` moves `a` at least.
fn try_one(c: &Candidate, a: &Transform, b: &Transform, tol: &MistakeTol) -> ((f64, f64), bool) {
    let score = |r: &(f64, f64)| r.0 / tol.translation_mm + r.1 / tol.rotation_deg;
    let images = (c.map)(a);
    let pick = |target: &Transform| {
        images
            .iter()
            .map(|f| residual(f, target))
            .min_by(|x, y| score(x).total_cmp(&score(y)))
            .unwrap_or((f64::INFINITY, f64::INFINITY))
    };
    let observable = !within(pick(a), tol);
    (pick(b), observable)
}

fn gimbal(t: &Transform) -> bool {
    let r = t.rotation();
    1.0 - r[(2, 0)].abs() < GIMBAL_TOL || 1.0 - r[(0, 2)].abs() < GIMBAL_TOL
}

/// Compare two sources of one edge and name the mistakes that reconcile them.
pub fn explain(a: &Transform, b: &Transform, tol: &MistakeTol) -> Explanation {
    let (translation_mm, rotation_deg) = residual(a, b);
    let agree = within((translation_mm, rotation_deg), tol);
    let euler_skipped = gimbal(a) || gimbal(b);
    let mut mistakes = Vec::new();
    if !agree {
        for c in CANDIDATES.iter().filter(|c| !(c.euler && euler_skipped)) {
            for (direction, (x, y)) in [
                (Direction::SecondFromFirst, (a, b)),
                (Direction::FirstFromSecond, (b, a)),
            ] {
                let (r, observable) = try_one(c, x, y, tol);
                if observable && within(r, tol) {
                    mistakes.push(Found {
                        mistake: c.name,
                        direction,
                        residual_mm: r.0,
                        residual_deg: r.1,
                    });
                }
            }
        }
    }
    Explanation {
        translation_mm,
        rotation_deg,
        agree,
        mistakes,
        euler_skipped,
    }
}

impl Found {
    /// "`new` equals `old` inverted (residual 0.019 mm, 0.0010 deg)", the
    /// sources named `first` and `second`.
    pub fn sentence(&self, first: &str, second: &str) -> String {
        let (to, of) = match self.direction {
            Direction::SecondFromFirst => (second, first),
            Direction::FirstFromSecond => (first, second),
        };
        let phrase = CANDIDATES
            .iter()
            .find(|c| c.name == self.mistake)
            .map_or(self.mistake, |c| c.phrase);
        let residual = format!(
            "residual {:.3} mm, {:.4} deg",
            self.residual_mm, self.residual_deg
        );
        // A phrase with a gloss in parentheses takes the residual inside it.
        match phrase.strip_suffix(')') {
            Some(p) => format!("{to} equals {of} {p}; {residual})"),
            None => format!("{to} equals {of} {phrase} ({residual})"),
        }
    }
}

impl Explanation {
    /// The mistakes as one sentence, or `None` when none reconciles the two.
    /// The two directions of one mistake that is its own reverse (inverse,
    /// transposed, rpy/ypr) are said once.
    pub fn sentence(&self, first: &str, second: &str) -> Option<String> {
        let mut said: Vec<String> = Vec::new();
        let mut seen: Vec<&str> = Vec::new();
        for f in &self.mistakes {
            if seen.contains(&f.mistake) {
                continue;
            }
            seen.push(f.mistake);
            said.push(f.sentence(first, second));
        }
        match said.len() {
            0 => None,
            1 => Some(said.remove(0)),
            _ => Some(format!("ambiguous: {}", said.join("; or "))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::Value;

    fn transform(v: &Value) -> Transform {
        let m: Vec<Vec<f64>> = serde_json::from_value(v["rotation_matrix"].clone()).unwrap();
        let t: Vec<f64> = serde_json::from_value(v["translation_m"].clone()).unwrap();
        let r = Matrix3::from_fn(|i, j| m[i][j]);
        make(r, Vector3::new(t[0], t[1], t[2]))
    }

    fn pairs() -> Value {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/mistakes/mistake_pairs.json"
        );
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
    }

    fn key(f: &Found) -> String {
        let d = match f.direction {
            Direction::SecondFromFirst => "new_from_old",
            Direction::FirstFromSecond => "old_from_new",
        };
        format!("{}:{d}", f.mistake)
    }

    /// Each of the 19 authored pairs (numpy/scipy, make_mistake_pairs.py):
    /// exactly the expected mistakes are named, with scipy's residuals, and
    /// none where none applies (recalibration, unrelated, agree).
    #[test]
    fn each_mistake_is_named_on_its_pair_and_on_no_other() {
        let all = pairs();
        let tol = MistakeTol {
            translation_mm: all["tolerance_mm"].as_f64().unwrap(),
            rotation_deg: all["tolerance_deg"].as_f64().unwrap(),
        };
        let list = all["pairs"].as_array().unwrap();
        assert_eq!(list.len(), 19);
        let names: Vec<&str> = CANDIDATES.iter().map(|c| c.name).collect();
        let mut want_names: Vec<&str> = all["candidates"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_str().unwrap())
            .collect();
        want_names.sort_unstable();
        let mut sorted = names.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, want_names);
        for p in list {
            let (old, new) = (transform(&p["old"]), transform(&p["new"]));
            let e = explain(&old, &new, &tol);
            let mut got: Vec<String> = e.mistakes.iter().map(key).collect();
            got.sort();
            let want: Vec<String> =
                serde_json::from_value(p["expected_reconciling"].clone()).unwrap();
            assert_eq!(got, want, "{}", p["name"]);
            let verdict = match (e.agree, e.mistakes.is_empty()) {
                (true, _) => "agree",
                (false, false) => "mistake",
                (false, true) => "disagree",
            };
            assert_eq!(verdict, p["verdict"], "{}", p["name"]);
            assert_eq!(e.euler_skipped, p["name"] == "gimbal_inverse");
            let d = &p["disagreement"];
            assert!((e.translation_mm - d["translation_mm"].as_f64().unwrap()).abs() < 1e-9);
            assert!((e.rotation_deg - d["rotation_deg"].as_f64().unwrap()).abs() < 1e-9);
            for f in &e.mistakes {
                let dir = key(f).split(':').nth(1).unwrap().to_string();
                let c = &p["candidates"][f.mistake][&dir];
                let (mm, deg) = (
                    c["residual_mm"].as_f64().unwrap(),
                    c["residual_deg"].as_f64().unwrap(),
                );
                assert!(
                    (f.residual_mm - mm).abs() < 1e-6,
                    "{} {}",
                    p["name"],
                    f.mistake
                );
                assert!(
                    (f.residual_deg - deg).abs() < 1e-6,
                    "{} {}",
                    p["name"],
                    f.mistake
                );
            }
        }
    }

    #[test]
    fn the_sentence_names_the_mistake_with_its_residual() {
        let t = Transform::from_rpy([0.12, -0.35, 1.1], [0.215, -0.043, 0.3185]).unwrap();
        let tol = MistakeTol {
            translation_mm: 1.0,
            rotation_deg: 0.05,
        };
        let e = explain(&t, &t.inverse(), &tol);
        assert_eq!(
            e.sentence("old", "new").unwrap(),
            "new equals old inverted (parent and child swapped; residual 0.000 mm, 0.0000 deg)"
        );
        let zero = Transform::from_rpy([0.3, 0.2, -0.7], [0.0; 3]).unwrap();
        let e = explain(&zero, &zero.inverse(), &tol);
        assert!(e
            .sentence("a", "b")
            .unwrap()
            .starts_with("ambiguous: b equals a inverted"));
        assert!(explain(&t, &t, &tol).sentence("a", "b").is_none());
    }
}
