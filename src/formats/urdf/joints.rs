//! Joint values and edges: `--joint NAME=VALUE`, else the mimic master's value
//! (`multiplier * master + offset`), else 0 with `defaulted` set; the motion
//! (rotation about or translation along the unit axis) composed after the
//! origin.

use super::read::JointRaw;
use crate::diagnostic::{Error, Result, Warning, WarningCode};
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
        };
        match j.jtype {
            None => {
                if set.is_some() {
                    warnings.push(
                        Warning::new(
                            WarningCode::Ignored,
                            format!("--joint {}: a fixed joint has no position; ignored", j.name),
                        )
                        .at(&j.loc),
                    );
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
                let motion = motion(idx, j, jt, value, warnings)?;
                let mut e = edge(
                    j.origin.compose(&motion),
                    format!("joint \"{}\" <origin> + {} motion", j.name, jt),
                );
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
                WarningCode::NonUnitAxis,
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
