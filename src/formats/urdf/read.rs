//! From XML to links and raw joints: names, types, origins (`rpy` or URDF 1.1
//! `quat_xyzw`), axes and mimic tags, each checked where it is written.

use super::Links;
use crate::diagnostic::{Error, Location, Result, Warning, WarningCode};
use crate::formats::source::LineIndex;
use crate::formats::{locate_warnings, xml};
use crate::frames::JointType;
use crate::geometry::{QuatOrder, Transform};
use std::collections::HashMap;
use std::path::Path;

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

/// A joint as written, before any value is applied.
pub(super) struct JointRaw<'a> {
    pub name: String,
    /// `None` for a fixed joint.
    pub jtype: Option<JointType>,
    pub parent: String,
    pub child: String,
    pub origin: Transform,
    pub axis: [f64; 3],
    pub mimic: Option<Mimic>,
    pub loc: Location,
    pub node: roxmltree::Node<'a, 'a>,
}

/// `N` finite numbers separated by whitespace.
fn numbers_attr<const N: usize>(s: &str, what: &str) -> std::result::Result<[f64; N], String> {
    let parts: Vec<&str> = s.split_whitespace().collect();
    if parts.len() != N {
        return Err(format!(
            "{what}: expected {N} numbers, found {} ({s:?})",
            parts.len()
        ));
    }
    let mut out = [0.0; N];
    for (i, p) in parts.iter().enumerate() {
        out[i] = p
            .parse::<f64>()
            .map_err(|_| format!("{what}: expected {N} numbers, found {p:?} in {s:?}"))?;
        if !out[i].is_finite() {
            return Err(format!("{what}: expected finite numbers, found {p:?}"));
        }
    }
    Ok(out)
}

fn err_at(idx: &LineIndex, n: roxmltree::Node, msg: String) -> Error {
    let (l, c) = xml::pos_of(idx, n);
    Error::parse(msg).at_line(l, Some(c))
}

fn elements<'a>(
    root: roxmltree::Node<'a, 'a>,
    tag: &'static str,
) -> impl Iterator<Item = roxmltree::Node<'a, 'a>> {
    root.children()
        .filter(move |n| n.is_element() && n.tag_name().name() == tag)
}

/// Top-level `<link>` elements by name (names unique).
pub(super) fn links<'a>(idx: &LineIndex, root: roxmltree::Node<'a, 'a>) -> Result<Links<'a>> {
    let mut links: Links = HashMap::new();
    for l in elements(root, "link") {
        let Some(name) = l.attribute("name") else {
            return Err(err_at(
                idx,
                l,
                "<link> without a name: expected name=\"...\"".into(),
            ));
        };
        if let Some(prev) = links.get(name) {
            let (pl, _) = xml::pos_of(idx, *prev);
            return Err(err_at(
                idx,
                l,
                format!(
                    "link '{name}' declared twice: expected unique link names, first at line {pl}"
                ),
            ));
        }
        links.insert(name.to_string(), l);
    }
    Ok(links)
}

/// Top-level `<joint>` elements (names unique, links declared).
pub(super) fn joints<'a>(
    idx: &LineIndex,
    root: roxmltree::Node<'a, 'a>,
    links: &Links,
    path: &Path,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<JointRaw<'a>>> {
    let mut joints: Vec<JointRaw> = Vec::new();
    let mut seen: HashMap<String, usize> = HashMap::new();
    for j in elements(root, "joint") {
        if let Some(&prev) = j.attribute("name").and_then(|n| seen.get(n)) {
            return Err(err_at(
                idx,
                j,
                format!(
                    "joint '{}' declared twice: expected unique joint names, first at line {}",
                    joints[prev].name,
                    joints[prev].loc.line.unwrap_or(0)
                ),
            ));
        }
        let raw = joint(idx, j, links, path, warnings)?;
        seen.insert(raw.name.clone(), joints.len());
        joints.push(raw);
    }
    Ok(joints)
}

fn joint<'a>(
    idx: &LineIndex,
    j: roxmltree::Node<'a, 'a>,
    links: &Links,
    path: &Path,
    warnings: &mut Vec<Warning>,
) -> Result<JointRaw<'a>> {
    let Some(name) = j.attribute("name") else {
        return Err(err_at(
            idx,
            j,
            "<joint> without a name: expected name=\"...\"".into(),
        ));
    };
    let jtype = j.attribute("type").unwrap_or("");
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
    let child_el = |tag: &str| {
        j.children()
            .find(|n| n.is_element() && n.tag_name().name() == tag)
    };
    let link_of = |tag: &str| -> Result<String> {
        let el = child_el(tag).ok_or_else(|| {
            err_at(
                idx,
                j,
                format!("joint '{name}': expected a <{tag} link=\"...\"/>, found none"),
            )
        })?;
        let l = el.attribute("link").ok_or_else(|| {
            err_at(
                idx,
                el,
                format!("joint '{name}': <{tag}> without link=\"...\""),
            )
        })?;
        if !links.contains_key(l) {
            return Err(err_at(
                idx,
                el,
                format!("joint '{name}': {tag} link '{l}' is not declared as a <link>"),
            ));
        }
        Ok(l.to_string())
    };
    let parent = link_of("parent")?;
    let child = link_of("child")?;
    let loc_of = |n: roxmltree::Node| {
        let (l, c) = xml::pos_of(idx, n);
        Location::at(path, l, Some(c))
    };
    let origin = match child_el("origin") {
        None => Transform::identity(),
        Some(o) => origin(idx, o, name, &loc_of(o), warnings)?,
    };
    let axis = match child_el("axis").and_then(|a| a.attribute("xyz").map(|s| (a, s))) {
        Some((a, s)) => numbers_attr::<3>(s, &format!("joint '{name}' <axis xyz>"))
            .map_err(|m| err_at(idx, a, m))?,
        None => [1.0, 0.0, 0.0],
    };
    let mimic = match child_el("mimic") {
        None => None,
        Some(m) => Some(mimic(idx, m, name)?),
    };
    Ok(JointRaw {
        name: name.to_string(),
        jtype: JointType::from_name(jtype),
        parent,
        child,
        origin,
        axis,
        mimic,
        loc: loc_of(j),
        node: j,
    })
}

/// `<origin xyz rpy>` or `<origin xyz quat_xyzw>` (both is an error).
fn origin(
    idx: &LineIndex,
    o: roxmltree::Node,
    name: &str,
    loc: &Location,
    warnings: &mut Vec<Warning>,
) -> Result<Transform> {
    let xyz = match o.attribute("xyz") {
        Some(s) => numbers_attr::<3>(s, &format!("joint '{name}' <origin xyz>"))
            .map_err(|m| err_at(idx, o, m))?,
        None => [0.0; 3],
    };
    match (o.attribute("rpy"), o.attribute("quat_xyzw")) {
        (Some(_), Some(_)) => Err(err_at(
            idx,
            o,
            format!("joint '{name}' <origin>: expected either rpy or quat_xyzw, found both"),
        )),
        (None, Some(q)) => {
            let q = numbers_attr::<4>(q, &format!("joint '{name}' <origin quat_xyzw>"))
                .map_err(|m| err_at(idx, o, m))?;
            let mut ws = Vec::new();
            let t = Transform::from_quaternion(q, QuatOrder::Xyzw, xyz, &mut ws).map_err(|e| {
                err_at(
                    idx,
                    o,
                    format!("joint '{name}' <origin quat_xyzw>: {}", e.message),
                )
            })?;
            locate_warnings(ws, loc, warnings);
            warnings.push(
                Warning::new(
                    WarningCode::AssumedConvention,
                    format!("joint '{name}': URDF 1.1 quat_xyzw read in x y z w order (urdf-rs and ROS parsers before URDF 1.1 ignore it and use the identity)"),
                )
                .at(loc),
            );
            Ok(t)
        }
        (r, None) => {
            let rpy = match r {
                Some(s) => numbers_attr::<3>(s, &format!("joint '{name}' <origin rpy>"))
                    .map_err(|m| err_at(idx, o, m))?,
                None => [0.0; 3],
            };
            Transform::from_rpy(rpy, xyz).map_err(|e| err_at(idx, o, e.message))
        }
    }
}

fn mimic(idx: &LineIndex, m: roxmltree::Node, name: &str) -> Result<Mimic> {
    let master = m.attribute("joint").ok_or_else(|| {
        err_at(
            idx,
            m,
            format!("joint '{name}': <mimic> without joint=\"...\""),
        )
    })?;
    let num = |attr: &str, def: f64| -> Result<f64> {
        match m.attribute(attr) {
            None => Ok(def),
            Some(s) => numbers_attr::<1>(s, &format!("joint '{name}' <mimic {attr}>"))
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
