//! From XML to links and raw joints: the URDF version, names, types, origins
//! (`rpy`, or `quat_xyzw` from URDF 1.1), axes, limits and mimic tags, each
//! checked where it is written. The elements come from [`super::stream`],
//! one joint at a time; the numbers and `<origin>` are read by
//! [`super::origin`].

use super::lines::Lines;
use super::origin::{self, numbers_attr, What};
use super::stream::{err_at, fail_at, El, JointEl};
use super::version::Version;
use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::spec::UrdfVersion;
use crate::frames::{JointType, ValuesAt};
use crate::geometry::{EdgePrecision, Precision, Transform};
use std::borrow::Cow;
use std::collections::VecDeque;
use std::path::Path;
use std::sync::Arc;

pub(super) use super::names::Links;

/// The `type` names URDF accepts, in the order error messages list them.
const JOINT_TYPES: &[&str] = &[
    "fixed",
    "revolute",
    "continuous",
    "prismatic",
    "floating",
    "planar",
];

/// `<mimic joint multiplier offset>`.
pub(super) struct Mimic {
    pub master: String,
    pub multiplier: f64,
    pub offset: f64,
}

/// `<limit lower upper>` of a revolute or prismatic joint (urdfdom's defaults:
/// 0 for a bound not written).
#[derive(Debug, Clone, Copy)]
pub(super) struct Limit {
    pub lower: f64,
    pub upper: f64,
    /// Line of the `<limit>` element.
    pub line: usize,
}

/// A joint as written, before any value is applied.
pub(super) struct JointRaw {
    pub name: String,
    /// `None` for a fixed joint.
    pub jtype: Option<JointType>,
    pub parent: String,
    pub child: String,
    pub origin: Transform,
    /// The rounding of `<origin>`'s numbers as written.
    pub origin_precision: Precision,
    pub axis: [f64; 3],
    pub limit: Option<Limit>,
    pub mimic: Option<Mimic>,
    pub loc: Location,
    /// Where `<origin>`'s `xyz` and `rpy` (or `quat_xyzw`) are written.
    pub values: ValuesAt,
}

/// What a joint is read against: the links declared so far and the version.
pub(super) struct Context<'c, 'a> {
    pub idx: &'c Lines<'a>,
    /// The file, shared by the locations of every edge.
    pub file: &'c Arc<Path>,
    pub version: Version,
    pub links: &'c Links<'a>,
}

/// A parent or child link not declared (yet) when its joint was read: the
/// joint's error unless a later `<link>` declares it (the file is read once,
/// and a link may follow the joints that name it).
pub(super) struct PendingLink<'a> {
    /// The joint's index in file order.
    pub joint: usize,
    name: Cow<'a, str>,
    tag: &'static str,
    pub link: Cow<'a, str>,
    /// Offset of the `<parent>` or `<child>` element.
    start: usize,
}

impl PendingLink<'_> {
    /// The error when no `<link>` declares it.
    pub fn error(&self, idx: &Lines) -> Error {
        let (name, tag, l) = (&self.name, self.tag, &self.link);
        fail_at(
            idx,
            self.start,
            format!("joint '{name}': {tag} link '{l}' is not declared as a <link>"),
        )
    }
}

/// A top-level `<joint>` (the `index`-th in file order) as written; links
/// not declared yet go to `pending`.
pub(super) fn joint<'a>(
    cx: &Context<'_, 'a>,
    jel: &JointEl<'_, 'a>,
    index: usize,
    pending: &mut VecDeque<PendingLink<'a>>,
    warnings: &mut Vec<Warning>,
) -> Result<JointRaw> {
    let (idx, j) = (cx.idx, &jel.el);
    let Some(name_attr) = j.attribute("name") else {
        return Err(err_at(
            idx,
            j,
            "<joint> without a name: expected name=\"...\"".into(),
        ));
    };
    let name = name_attr.value.as_ref();
    let jtype = j.attr("type").unwrap_or("");
    if !JOINT_TYPES.contains(&jtype) {
        return Err(err_at(
            idx,
            j,
            format!(
                "joint '{name}': expected type one of {}, found {:?}",
                JOINT_TYPES.join(", "),
                jtype
            ),
        ));
    }
    let kids = jel.first_children(KIDS);
    let [parent_el, child_el, origin_el, axis_el, mimic_el, limit_el] = kids;
    let mut link_of = |tag: &'static str, el: Option<El<'_, 'a>>| -> Result<String> {
        let el = el.ok_or_else(|| {
            err_at(
                idx,
                j,
                format!("joint '{name}': expected a <{tag} link=\"...\"/>, found none"),
            )
        })?;
        let l = el.attribute("link").ok_or_else(|| {
            err_at(
                idx,
                &el,
                format!("joint '{name}': <{tag}> without link=\"...\""),
            )
        })?;
        if !cx.links.contains(l.value.as_ref()) {
            pending.push_back(PendingLink {
                joint: index,
                name: name_attr.value.clone(),
                tag,
                link: l.value.clone(),
                start: el.start,
            });
        }
        Ok(l.value.to_string())
    };
    let parent = link_of("parent", parent_el)?;
    let child = link_of("child", child_el)?;
    let loc_of = |n: &El| {
        let (l, c) = idx.pos(n.start);
        Location::in_shared(cx.file, l, Some(c))
    };
    // Positions asked in file order: `idx` moves forwards (super::lines).
    let loc = loc_of(j);
    let (origin, origin_precision) = match origin_el {
        None => (Transform::identity(), EdgePrecision::exact().into()),
        Some(o) => origin::origin(idx, &o, name, cx.version, &|| loc_of(&o), warnings)?,
    };
    let values = origin_el.map_or_else(ValuesAt::default, |o| {
        let at = |names: &[&str]| {
            let attr = names.iter().find_map(|n| o.attribute(n));
            attr.and_then(|a| idx.pos_of(a.raw))
                .or_else(|| Some(idx.pos(o.start)))
        };
        ValuesAt::new(at(&["xyz"]), at(&["rpy", "quat_xyzw"]))
    });
    let axis = axis(idx, axis_el, name, jtype)?;
    let mimic = match mimic_el {
        None => None,
        Some(m) => Some(mimic(idx, &m, name)?),
    };
    let limit = limit(
        idx,
        limit_el.as_ref(),
        jtype,
        name,
        cx.version,
        &loc,
        warnings,
    )?;
    number_spacing(&kids, name, jtype, &loc, warnings);
    Ok(JointRaw {
        name: name.to_string(),
        jtype: JointType::from_name(jtype),
        parent,
        child,
        origin,
        origin_precision,
        axis,
        limit,
        mimic,
        loc,
        values,
    })
}

/// `<axis xyz>`, as urdfdom reads it: no `<axis>` is 1 0 0, an `<axis>`
/// without xyz is 0 0 0 (refused on a movable joint: KDL would divide by its
/// norm).
fn axis(idx: &Lines, a: Option<El>, name: &str, jtype: &str) -> Result<[f64; 3]> {
    let what = What {
        joint: name,
        tag: "axis",
        attr: "xyz",
    };
    match a.map(|a| (a, a.attr("xyz"))) {
        Some((a, Some(s))) => numbers_attr::<3>(s, what).map_err(|m| err_at(idx, &a, m)),
        Some((a, None)) if matches!(jtype, "revolute" | "continuous" | "prismatic") => {
            Err(err_at(
                idx,
                &a,
                format!("{jtype} joint '{name}': <axis> without xyz, which urdfdom reads as 0 0 0 (no motion; ROS would publish a non-finite pose): expected <axis xyz=\"x y z\"/>"),
            ))
        }
        Some((_, None)) => Ok([0.0; 3]),
        None => Ok([1.0, 0.0, 0.0]),
    }
}

/// `<limit lower upper>` of a revolute or prismatic joint: a bound not
/// written is 0, as in urdfdom. What urdfdom refuses without a pose being in
/// doubt (no `<limit>`; before URDF 1.2 no `effort` or `velocity`, from 1.2 no
/// `lower` or `upper`) is a `refused-by-ros` warning.
fn limit(
    idx: &Lines,
    l: Option<&El>,
    jtype: &str,
    name: &str,
    version: Version,
    loc: &Location,
    warnings: &mut Vec<Warning>,
) -> Result<Option<Limit>> {
    if !matches!(jtype, "revolute" | "prismatic") {
        return Ok(None);
    }
    let refused = |why: String| {
        Warning::new(
            Code::RefusedByRos,
            format!("{jtype} joint '{name}': {why}; ROS (urdfdom) refuses the file, the pose is read anyway"),
        )
        .at(loc)
    };
    let Some(l) = l else {
        warnings.push(refused(
            "no <limit> element (urdfdom requires one on revolute and prismatic joints)".into(),
        ));
        return Ok(None);
    };
    let required = if version.used >= UrdfVersion::V1_2 {
        ["lower", "upper"]
    } else {
        ["effort", "velocity"]
    };
    for attr in ["effort", "velocity"] {
        // Not used, but a malformed number is refused, as urdfdom refuses it.
        if let Some(s) = l.attr(attr) {
            numbers_attr::<1>(
                s,
                What {
                    joint: name,
                    tag: "limit",
                    attr,
                },
            )
            .map_err(|m| err_at(idx, l, m))?;
        }
    }
    let missing: Vec<&str> = required
        .into_iter()
        .filter(|a| l.attr(a).is_none())
        .collect();
    if !missing.is_empty() {
        warnings.push(refused(format!(
            "<limit> without {}",
            missing.join(" and ")
        )));
    }
    let bound = |attr: &str| -> Result<f64> {
        match l.attr(attr) {
            None => Ok(0.0),
            Some(s) => numbers_attr::<1>(
                s,
                What {
                    joint: name,
                    tag: "limit",
                    attr,
                },
            )
            .map(|v| v[0])
            .map_err(|m| err_at(idx, l, m)),
        }
    };
    let (line, _) = idx.pos(l.start);
    Ok(Some(Limit {
        lower: bound("lower")?,
        upper: bound("upper")?,
        line,
    }))
}

/// The child elements of a `<joint>` that are read (the first of each
/// name), in the order [`joint`] takes them.
const KIDS: [&str; 6] = ["parent", "child", "origin", "axis", "mimic", "limit"];

/// The numeric attributes urdfdom reads: (element, its place in [`KIDS`],
/// attribute, vector of numbers split at spaces, or one number).
const NUMERIC_ATTRS: &[(&str, usize, &str, bool)] = &[
    ("origin", 2, "xyz", true),
    ("origin", 2, "rpy", true),
    ("origin", 2, "quat_xyzw", true),
    ("axis", 3, "xyz", true),
    ("limit", 5, "lower", false),
    ("limit", 5, "upper", false),
    ("limit", 5, "effort", false),
    ("limit", 5, "velocity", false),
    ("mimic", 4, "multiplier", false),
    ("mimic", 4, "offset", false),
];

/// Whether urdfdom refuses a number's spacing: it splits vectors at spaces
/// only and reads each piece (or a lone number) with `operator>>`, which skips
/// leading whitespace but fails on anything after the number. So a tab or
/// line break between numbers, or trailing whitespace after a lone number, is
/// refused. XML parsers turn literal tabs and line breaks in attribute values
/// into spaces; urdfdom's does not, so the raw text is checked.
fn ros_refuses_spacing(raw: &str, vector: bool) -> bool {
    const C_SPACE: [char; 6] = [' ', '\t', '\n', '\r', '\u{b}', '\u{c}'];
    let bad = |piece: &str| piece.trim_start_matches(C_SPACE).contains(C_SPACE);
    if vector {
        raw.split(' ').any(bad)
    } else {
        bad(raw)
    }
}

/// A `refused-by-ros` warning for numbers urdfdom cannot split (see
/// [`ros_refuses_spacing`]); the tool reads them.
fn number_spacing(
    kids: &[Option<El>; KIDS.len()],
    name: &str,
    jtype: &str,
    loc: &Location,
    warnings: &mut Vec<Warning>,
) {
    let mut found = Vec::new();
    for (tag, kid, attr, vector) in NUMERIC_ATTRS {
        // urdfdom reads no axis on fixed and floating joints.
        if *tag == "axis" && matches!(jtype, "fixed" | "floating") {
            continue;
        }
        let Some(a) = kids[*kid]
            .as_ref()
            .and_then(|e| e.attrs.iter().find(|a| a.name == *attr))
        else {
            continue;
        };
        // Plain text holds no tab or line break (nor, once checked, any
        // other control character): only spaces separate its numbers.
        if a.plain && *vector {
            continue;
        }
        // The text as written; with entities, the decoded value.
        let raw = if a.raw.contains('&') {
            &*a.value
        } else {
            a.raw
        };
        if ros_refuses_spacing(raw, *vector) {
            found.push(format!("<{tag} {attr}={raw:?}>"));
        }
    }
    if !found.is_empty() {
        warnings.push(
            Warning::new(
                Code::RefusedByRos,
                format!(
                    "joint '{name}': {}: urdfdom separates numbers by spaces only and allows nothing after a number, so ROS refuses the file; read here with any whitespace as separator",
                    found.join(", ")
                ),
            )
            .at(loc),
        );
    }
}

fn mimic(idx: &Lines, m: &El, name: &str) -> Result<Mimic> {
    let master = m.attr("joint").ok_or_else(|| {
        err_at(
            idx,
            m,
            format!("joint '{name}': <mimic> without joint=\"...\""),
        )
    })?;
    let num = |attr: &str, def: f64| -> Result<f64> {
        match m.attr(attr) {
            None => Ok(def),
            Some(s) => numbers_attr::<1>(
                s,
                What {
                    joint: name,
                    tag: "mimic",
                    attr,
                },
            )
            .map(|v| v[0])
            .map_err(|msg| err_at(idx, m, msg)),
        }
    };
    Ok(Mimic {
        master: master.to_string(),
        multiplier: num("multiplier", 1.0)?,
        offset: num("offset", 0.0)?,
    })
}

#[cfg(test)]
mod tests {
    use super::{KIDS, NUMERIC_ATTRS};

    /// Each numeric attribute's element is found at its place in `KIDS`.
    #[test]
    fn numeric_attrs_name_their_kids() {
        assert!(NUMERIC_ATTRS.iter().all(|(tag, k, _, _)| KIDS[*k] == *tag));
    }
}
