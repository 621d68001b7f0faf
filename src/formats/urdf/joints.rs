//! Joint values and edges: `--joint NAME=VALUE`, else the mimic master's value
//! (`multiplier * master + offset`), else 0 with `defaulted` set; the motion
//! (rotation about or translation along the unit axis) composed after the
//! origin. A value outside `<limit>` is kept, as robot_state_publisher keeps it
//! (pytransform3d clamps), with a `joint-outside-limit` warning.

use super::read::JointRaw;
use crate::diagnostic::{Code, Error, Result, Warning};
use crate::formats::spec::LoadOptions;
use crate::frames::{Edge, JointState, JointType, Provenance};
use crate::geometry::se3::{robust_norm, scaled_unit};
use crate::geometry::Transform;
use crate::tolerances::AXIS_MIN_NORM;
use crate::tolerances::UNIT_AXIS_TOL;
use nalgebra::Vector3;

/// One edge per joint, in file order, built as each joint is read (the
/// joints are not kept: issue 12). What needs the whole file (a mimic master
/// declared later, the list of movable joints in an error) is settled by
/// [`Builder::finish`]; the error reported is the one of the first joint in
/// file order that has one, as when all joints were read first.
pub(super) struct Builder<'o> {
    opts: &'o LoadOptions,
    /// The format id the edges carry.
    format: &'static str,
    edges: Vec<Edge>,
    /// Warnings of the edges, reported after those of the reading.
    warnings: Vec<Warning>,
    /// Names of the movable joints, in file order.
    movable: Vec<String>,
    /// Mimic joints whose master must exist: (joint index, name, master, location).
    mimics: Vec<(usize, String, String, crate::diagnostic::Location)>,
    /// The first joint whose edge cannot be built, and why.
    failed: Option<(usize, Failure)>,
    count: usize,
}

enum Failure {
    Ready(Error),
    /// `--joint` on a fixed joint: the message lists every movable joint.
    FixedSet(String, f64, crate::diagnostic::Location),
}

impl<'o> Builder<'o> {
    pub(super) fn new(opts: &'o LoadOptions, joints: usize, format: &'static str) -> Self {
        Builder {
            opts,
            format,
            edges: Vec::with_capacity(joints),
            warnings: Vec::new(),
            movable: Vec::new(),
            mimics: Vec::new(),
            failed: None,
            count: 0,
        }
    }

    /// The edge of the next joint in file order.
    pub(super) fn push(&mut self, j: JointRaw) {
        let i = self.count;
        self.count += 1;
        if j.jtype.is_some_and(|t| t.has_one_value()) {
            self.movable.push(j.name.clone());
        }
        if self.failed.is_some() {
            return;
        }
        if let Err(f) = self.edge(i, j) {
            self.failed = Some((i, f));
        }
    }

    fn edge(&mut self, i: usize, j: JointRaw) -> std::result::Result<(), Failure> {
        let opts = self.opts;
        // Most loads set no joint: no lookup then.
        let set = match opts.joints.is_empty() {
            true => None,
            false => opts.joints.get(&j.name).copied(),
        };
        let origin_key = || key(&["joint \"", &j.name, "\" <origin>"]);
        let mut carried = None;
        let (transform, key, state) = match j.jtype {
            None => {
                if let Some(v) = set {
                    return Err(Failure::FixedSet(j.name, v, j.loc));
                }
                (j.origin, origin_key(), None)
            }
            Some(jt) if !jt.has_one_value() => {
                let value = unset_pose_value(&j, jt, set).map_err(Failure::Ready)?;
                (j.origin, origin_key(), Some((jt, value, false)))
            }
            Some(jt) => {
                if let (None, Some(m)) = (set, &j.mimic) {
                    self.mimics
                        .push((i, j.name.clone(), m.master.clone(), j.loc.clone()));
                }
                let (value, defaulted) = joint_value(&j, set, opts).map_err(Failure::Ready)?;
                if !defaulted {
                    // A default (0) is already reported on the path as joint-at-default.
                    check_limit(&j, jt, value, set.is_some(), &mut self.warnings);
                }
                let motion = motion(&j, jt, value, &mut self.warnings).map_err(Failure::Ready)?;
                // Origin Exp(xi) motion = (origin motion) Exp(Ad(motion^-1) xi).
                carried = Some(motion.adjoint_inverse());
                let key = key(&["joint \"", &j.name, "\" <origin> + ", jt.name(), " motion"]);
                (
                    j.origin.compose(&motion),
                    key,
                    Some((jt, Some(value), defaulted)),
                )
            }
        };
        let mut precision = j.origin_precision;
        if let Some(a) = carried {
            precision.transform_rounding(&a);
        }
        let joint = state.map(|(joint_type, value, defaulted)| {
            Box::new(JointState {
                name: j.name,
                joint_type,
                value,
                defaulted,
            })
        });
        // The joint's strings move into the edge, built in place (a chain of
        // `Edge::with_*` moved the whole edge once per call: issue 29).
        self.edges.push(Edge {
            parent: j.parent,
            child: j.child,
            transform,
            provenance: Provenance {
                location: j.loc,
                format: self.format,
                key,
                values: j.values,
            },
            joint,
            precision,
        });
        Ok(())
    }

    /// The edges and their warnings, or the first joint's error;
    /// `is_joint(name)`: whether the file has a joint `name` (the mimic masters).
    pub(super) fn finish(
        self,
        is_joint: impl Fn(&str) -> bool,
    ) -> Result<(Vec<Edge>, Vec<Warning>)> {
        let before = self.failed.as_ref().map_or(usize::MAX, |(i, _)| *i);
        // At the same joint the mimic master is checked first.
        let mimic = self
            .mimics
            .iter()
            .find(|(i, _, master, _)| *i <= before && !is_joint(master.as_str()));
        if let Some((_, name, master, loc)) = mimic {
            return Err(Error::parse(format!(
                "joint '{name}': <mimic joint=\"{master}\"> names no joint in this file"
            ))
            .at(loc));
        }
        match self.failed {
            Some((_, Failure::Ready(e))) => Err(e),
            Some((_, Failure::FixedSet(name, v, loc))) => {
                Err(fixed_joint_set(&name, v, &loc, &self.movable))
            }
            None => Ok((self.edges, self.warnings)),
        }
    }
}

/// The edge's key, `parts` joined in a string of exactly their length
/// (`format!` reserves twice its literal text: a 23-byte key took a 48-byte
/// allocation, issue 29).
fn key(parts: &[&str]) -> String {
    let mut s = String::with_capacity(parts.iter().map(|p| p.len()).sum());
    parts.iter().for_each(|p| s.push_str(p));
    s
}

/// `--joint NAME=VALUE` on a fixed joint: one error, with the movable joints.
fn fixed_joint_set(
    name: &str,
    v: f64,
    loc: &crate::diagnostic::Location,
    movable: &[String],
) -> Error {
    Error::usage(format!(
        "--joint {name}={v}: joint '{name}' is fixed and has no position to set; expected a revolute, continuous or prismatic joint ({})",
        if movable.is_empty() {
            "this file has none".to_string()
        } else {
            format!("this file has: {}", movable.join(", "))
        }
    ))
    .at(loc)
}

/// A position outside `<limit lower upper>` is used as given (as
/// robot_state_publisher does), with a warning naming the limit.
fn check_limit(j: &JointRaw, jt: JointType, value: f64, set: bool, warnings: &mut Vec<Warning>) {
    let Some(l) = j.limit else { return };
    if value >= l.lower && value <= l.upper {
        return;
    }
    let unit = if jt == JointType::Prismatic {
        "m"
    } else {
        "rad"
    };
    let how = match (set, &j.mimic) {
        (false, Some(m)) => format!("from <mimic joint=\"{}\">", m.master),
        _ => "set by --joint".to_string(),
    };
    warnings.push(
        Warning::new(
            Code::JointOutsideLimit,
            format!(
                "{jt} joint '{}': position {value} {unit} ({how}) is outside <limit lower=\"{}\" upper=\"{}\"> (line {}); used as given, as robot_state_publisher does (it does not clamp)",
                j.name, l.lower, l.upper, l.line
            ),
        )
        .at(&j.loc),
    );
}

/// Floating and planar joints: only 0 (the joint at its origin) is accepted.
fn unset_pose_value(j: &JointRaw, jt: JointType, set: Option<f64>) -> Result<Option<f64>> {
    match set {
        None => Ok(None),
        Some(v) if v.abs() < f64::MIN_POSITIVE => Ok(Some(0.0)),
        Some(v) => Err(Error::usage(format!(
            "--joint {}={v}: joint '{}' is {jt}; only 0 (the joint at its origin) is accepted, a {jt} pose needs more than one number: give it as a static transform instead",
            j.name, j.name
        ))
        .at(&j.loc)),
    }
}

/// The position of a one-value joint and whether it is the default (a mimic
/// master's existence is checked by [`Builder::finish`]).
fn joint_value(j: &JointRaw, set: Option<f64>, opts: &LoadOptions) -> Result<(f64, bool)> {
    let (value, defaulted) = match (set, &j.mimic) {
        (Some(v), _) => (v, false),
        (None, Some(m)) => match opts.joints.get(&m.master) {
            Some(mv) => (m.multiplier * mv + m.offset, false),
            None => (m.offset, true),
        },
        (None, None) => (0.0, true),
    };
    if !value.is_finite() {
        return Err(Error::usage(format!(
            "joint '{}': expected a finite position, found {value}",
            j.name
        ))
        .at(&j.loc));
    }
    Ok((value, defaulted))
}

/// The joint's motion at `value` about or along its unit axis.
fn motion(
    j: &JointRaw,
    jt: JointType,
    value: f64,
    warnings: &mut Vec<Warning>,
) -> Result<Transform> {
    // Scaled norm: an axis like [1e300, 1e300, 0] must not square to inf
    // (dividing by it would give a zero axis and, for a prismatic joint, a
    // silently zero motion).
    let axis = Vector3::from(j.axis);
    let n = robust_norm(&axis);
    if n.is_nan() || n < AXIS_MIN_NORM {
        return Err(Error::invalid(format!(
            "{jt} joint '{}': expected a non-zero <axis xyz>, found {:?}",
            j.name, j.axis
        ))
        .at_line(j.loc.line.unwrap_or(0), j.loc.column));
    }
    if (n - 1.0).abs() > UNIT_AXIS_TOL {
        warnings.push(
            Warning::new(
                Code::NonUnitAxis,
                format!(
                    "{jt} joint '{}': axis {:?} has norm {}, expected 1; normalised",
                    j.name,
                    j.axis,
                    if n < 1e9 {
                        format!("{n:.9}")
                    } else {
                        format!("{n:e}")
                    }
                ),
            )
            .at(&j.loc),
        );
    }
    let e = scaled_unit(&axis);
    if jt == JointType::Prismatic {
        Transform::from_translation([e.x * value, e.y * value, e.z * value])
    } else {
        Transform::from_axis_angle([e.x, e.y, e.z], value, [0.0; 3])
    }
}
