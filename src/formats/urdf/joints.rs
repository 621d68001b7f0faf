//! Joint values and edges: `--joint NAME=VALUE`, else the mimic master's value
//! (`multiplier * master + offset`), else 0 with `defaulted` set; the motion
//! (rotation about or translation along the unit axis) composed after the
//! origin. A value outside `<limit>` is kept, as robot_state_publisher keeps it
//! (pytransform3d clamps), with a `joint-outside-limit` warning.

use super::read::JointRaw;
use crate::diagnostic::{Code, Error, Result, Warning};
use crate::formats::source::LineIndex;
use crate::formats::{xml, LoadOptions};
use crate::frames::{Edge, JointState, JointType};
use crate::geometry::se3::{robust_norm, scaled_unit};
use crate::geometry::Transform;
use crate::tolerances::AXIS_MIN_NORM;
use crate::tolerances::UNIT_AXIS_TOL;
use nalgebra::Vector3;
use std::collections::HashMap;

/// One edge per joint, in file order.
pub(super) fn edges(
    idx: &LineIndex,
    joints: &[JointRaw],
    opts: &LoadOptions,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<Edge>> {
    let by_name: HashMap<&str, &JointRaw> = joints.iter().map(|j| (j.name.as_str(), j)).collect();
    let mut edges = Vec::with_capacity(joints.len());
    for j in joints {
        let set = opts.joints.get(&j.name).copied();
        let key = format!("joint \"{}\" <origin>", j.name);
        let edge = |t: Transform, key: String| {
            Edge::new(&j.parent, &j.child, t, j.loc.clone(), super::SPEC.id, key)
                .with_precision(j.origin_precision)
        };
        match j.jtype {
            None => {
                if let Some(v) = set {
                    return Err(fixed_joint_set(j, v, joints));
                }
                edges.push(edge(j.origin, key));
            }
            Some(jt) if !jt.has_one_value() => {
                let mut e = edge(j.origin, key);
                e.joint = Some(JointState {
                    name: j.name.clone(),
                    joint_type: jt,
                    value: unset_pose_value(j, jt, set)?,
                    defaulted: false,
                });
                edges.push(e);
            }
            Some(jt) => {
                let (value, defaulted) = joint_value(j, set, &by_name, opts)?;
                if !defaulted {
                    // A default (0) is already reported on the path as joint-at-default.
                    check_limit(j, jt, value, set.is_some(), warnings);
                }
                let motion = motion(idx, j, jt, value, warnings)?;
                let mut e = edge(
                    j.origin.compose(&motion),
                    format!("joint \"{}\" <origin> + {} motion", j.name, jt),
                );
                // Origin Exp(xi) motion = (origin motion) Exp(Ad(motion^-1) xi).
                if let Some(c) = &mut e.precision.rounding {
                    let a = motion.adjoint_inverse();
                    *c = a * *c * a.transpose();
                }
                e.joint = Some(JointState {
                    name: j.name.clone(),
                    joint_type: jt,
                    value: Some(value),
                    defaulted,
                });
                edges.push(e);
            }
        }
    }
    Ok(edges)
}

/// `--joint NAME=VALUE` on a fixed joint: one error, with the movable joints.
fn fixed_joint_set(j: &JointRaw, v: f64, joints: &[JointRaw]) -> Error {
    let movable: Vec<&str> = joints
        .iter()
        .filter(|k| k.jtype.is_some_and(|t| t.has_one_value()))
        .map(|k| k.name.as_str())
        .collect();
    Error::usage(format!(
        "--joint {}={v}: joint '{}' is fixed and has no position to set; expected a revolute, continuous or prismatic joint ({})",
        j.name,
        j.name,
        if movable.is_empty() {
            "this file has none".to_string()
        } else {
            format!("this file has: {}", movable.join(", "))
        }
    ))
    .at(&j.loc)
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

/// The position of a one-value joint and whether it is the default.
fn joint_value(
    j: &JointRaw,
    set: Option<f64>,
    by_name: &HashMap<&str, &JointRaw>,
    opts: &LoadOptions,
) -> Result<(f64, bool)> {
    let (value, defaulted) = match (set, &j.mimic) {
        (Some(v), _) => (v, false),
        (None, Some(m)) => {
            let Some(master) = by_name.get(m.master.as_str()) else {
                return Err(Error::parse(format!(
                    "joint '{}': <mimic joint=\"{}\"> names no joint in this file",
                    j.name, m.master
                ))
                .at(&j.loc));
            };
            match opts.joints.get(&master.name) {
                Some(mv) => (m.multiplier * mv + m.offset, false),
                None => (m.offset, true),
            }
        }
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
    idx: &LineIndex,
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
        let (l, c) = xml::pos_of(idx, j.node);
        return Err(Error::invalid(format!(
            "{jt} joint '{}': expected a non-zero <axis xyz>, found {:?}",
            j.name, j.axis
        ))
        .at_line(l, Some(c)));
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
