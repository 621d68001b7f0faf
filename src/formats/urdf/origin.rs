//! Numbers as urdfdom reads them, and `<origin>`: its pose (`rpy`, or
//! `quat_xyzw` from URDF 1.1) and the rounding of its numbers as written,
//! from one reading of each attribute. Nothing is allocated unless an error
//! or a warning is raised: a message names its attribute through [`What`],
//! formatted only then.

use super::stream::{err_at, El};
use super::version::Version;
use crate::diagnostic::{Code, Location, Result, Warning};
use crate::formats::source::LineIndex;
use crate::formats::spec::{locate_warnings, UrdfVersion};
use crate::geometry::uncertainty::{half_units, rounding_covariance, rounding_std};
use crate::geometry::{EdgePrecision, Precision, QuatOrder, Transform};
use std::fmt;

/// A numeric attribute in messages: `joint 'NAME' <TAG ATTR>`.
#[derive(Clone, Copy)]
pub(super) struct What<'n> {
    pub joint: &'n str,
    pub tag: &'n str,
    pub attr: &'n str,
}

impl fmt::Display for What<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "joint '{}' <{} {}>", self.joint, self.tag, self.attr)
    }
}

/// `N` finite numbers separated by ASCII whitespace (a no-break space is no
/// separator for urdfdom), with their texts.
pub(super) fn numbers<'s, const N: usize>(
    s: &'s str,
    what: What,
) -> std::result::Result<([f64; N], [&'s str; N]), String> {
    let (mut parts, mut count) = ([""; N], 0usize);
    for p in s.split_ascii_whitespace() {
        if let Some(slot) = parts.get_mut(count) {
            *slot = p;
        }
        count += 1;
    }
    if count != N {
        return Err(format!(
            "{what}: expected {N} numbers, found {count} ({s:?})"
        ));
    }
    let mut out = [0.0; N];
    for (x, p) in out.iter_mut().zip(parts) {
        *x = p
            .parse::<f64>()
            .map_err(|_| format!("{what}: expected {N} numbers, found {p:?} in {s:?}"))?;
        if !x.is_finite() {
            return Err(format!("{what}: expected finite numbers, found {p:?}"));
        }
    }
    Ok((out, parts))
}

/// `N` finite numbers separated by whitespace.
pub(super) fn numbers_attr<const N: usize>(
    s: &str,
    what: What,
) -> std::result::Result<[f64; N], String> {
    numbers::<N>(s, what).map(|(x, _)| x)
}

/// An attribute not written: three zeros.
const ZEROS: ([f64; 3], [&str; 3]) = ([0.0; 3], ["0"; 3]);

/// `<origin xyz rpy>` or, from URDF 1.1, `<origin xyz quat_xyzw>` (both is
/// an error in every version): the pose and the rounding of its numbers.
/// `loc` locates the warnings (made only when one is raised).
pub(super) fn origin(
    idx: &LineIndex,
    o: &El,
    name: &str,
    version: Version,
    loc: &dyn Fn() -> Location,
    warnings: &mut Vec<Warning>,
) -> Result<(Transform, Precision)> {
    let what = |attr: &'static str| What {
        joint: name,
        tag: "origin",
        attr,
    };
    let read3 = |attr: &'static str| match o.attr(attr) {
        Some(s) => numbers::<3>(s, what(attr)).map_err(|m| err_at(idx, o, m)),
        None => Ok(ZEROS),
    };
    let xyz = read3("xyz")?;
    let rpy = |r: ([f64; 3], [&str; 3])| -> Result<(Transform, Precision)> {
        let t = Transform::from_rpy(r.0, xyz.0).map_err(|e| err_at(idx, o, e.message))?;
        // Kept compact: the covariance is rpy_covariance of these, computed
        // where it is used.
        let u = |texts: &[&str; 3]| half_units(texts).map(rounding_std);
        Ok((t, Precision::rpy(r.0, u(&xyz.1), u(&r.1))))
    };
    match (o.attr("rpy"), o.attr("quat_xyzw")) {
        (Some(_), Some(_)) => Err(err_at(
            idx,
            o,
            format!("joint '{name}' <origin>: expected either rpy or quat_xyzw, found both"),
        )),
        (None, Some(q)) if version.used < UrdfVersion::V1_1 => {
            warnings.push(
                Warning::new(Code::QuatXyzwIgnored, quat_ignored(name, q, version)).at(&loc()),
            );
            rpy(ZEROS)
        }
        (None, Some(q)) => {
            let (q, q_texts) = numbers::<4>(q, what("quat_xyzw")).map_err(|m| err_at(idx, o, m))?;
            let mut ws = Vec::new();
            let t =
                Transform::from_quaternion(q, QuatOrder::Xyzw, xyz.0, &mut ws).map_err(|e| {
                    err_at(
                        idx,
                        o,
                        format!("joint '{name}' <origin quat_xyzw>: {}", e.message),
                    )
                })?;
            if !ws.is_empty() {
                locate_warnings(ws, &loc(), warnings);
            }
            if version.declared.unwrap_or(UrdfVersion::V1_0) < UrdfVersion::V1_1 {
                warnings.push(
                    Warning::new(
                        Code::AssumedConvention,
                        format!(
                            "joint '{name}' <origin quat_xyzw>: applied because of --urdf-version {}; the file {}, so ROS ignores it and runs with the identity rotation",
                            version.used,
                            version.declared_text()
                        ),
                    )
                    .at(&loc()),
                );
            }
            Ok((t, quat_precision(xyz, (q, q_texts))))
        }
        (_, None) => rpy(read3("rpy")?),
    }
}

/// `quat_xyzw` in a file read as URDF 1.0: ROS ignores it.
fn quat_ignored(name: &str, q: &str, version: Version) -> String {
    if version.declared.unwrap_or(UrdfVersion::V1_0) < UrdfVersion::V1_1 {
        format!(
            "joint '{name}' <origin quat_xyzw=\"{q}\">: ignored, as ROS ignores it: the file {} and quat_xyzw exists from URDF 1.1, so urdfdom uses the identity rotation; add version=\"1.1\" to <robot> (or pass --urdf-version 1.1) if the quaternion is meant",
            version.declared_text()
        )
    } else {
        format!(
            "joint '{name}' <origin quat_xyzw=\"{q}\">: ignored because of --urdf-version {}; the file {}, so ROS applies it",
            version.used,
            version.declared_text()
        )
    }
}

/// The rounding of `xyz` and `quat_xyzw` as written (conventions in
/// [`crate::geometry::uncertainty`]): each attribute is one tuple, the
/// covariance carried through the quaternion by finite steps.
fn quat_precision(xyz: ([f64; 3], [&str; 3]), q: ([f64; 4], [&str; 4])) -> Precision {
    let (hd, hq) = (half_units(&xyz.1), half_units(&q.1));
    let params = [xyz.0[0], xyz.0[1], xyz.0[2], q.0[0], q.0[1], q.0[2], q.0[3]];
    let halves = [hd[0], hd[1], hd[2], hq[0], hq[1], hq[2], hq[3]];
    let build = |p: &[f64]| {
        Transform::from_quaternion(
            [p[3], p[4], p[5], p[6]],
            QuatOrder::Xyzw,
            [p[0], p[1], p[2]],
            &mut Vec::new(),
        )
    };
    match rounding_covariance(&params, &halves, build) {
        Ok(c) => EdgePrecision {
            rounding: Some(c),
            user: None,
        }
        .into(),
        Err(_) => Precision::default(),
    }
}
