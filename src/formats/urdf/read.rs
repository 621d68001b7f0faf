//! From XML to links and raw joints: the URDF version, names, types, origins
//! (`rpy`, or `quat_xyzw` from URDF 1.1), axes, limits and mimic tags, each
//! checked where it is written. The elements come from [`super::stream`],
//! one joint at a time.

use super::stream::{self, El, JointEl};
use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::source::LineIndex;
use crate::formats::spec::{locate_warnings, LoadOptions, UrdfVersion};
use crate::frames::JointType;
use crate::geometry::uncertainty::{rounding_covariance, rounding_std, tuple_half_units};
use crate::geometry::{Precision, QuatOrder, Transform};
use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;

/// Links by name (start offsets), for the joints' parent and child checks.
pub(crate) type Links<'a> = HashMap<Cow<'a, str>, usize>;

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

/// The rounding of `<origin>`'s numbers as written (conventions in
/// [`crate::geometry::uncertainty`]): each attribute is one tuple. Called after
/// [`origin`] accepted the element, so the numbers parse.
fn origin_precision(o: &El, version: Version) -> Precision {
    let tokens = |a: &str| -> Vec<&str> {
        o.attr(a)
            .map(|s| s.split_ascii_whitespace().collect())
            .unwrap_or_default()
    };
    let xyz = tokens("xyz");
    let (rot, quat) = match (o.attr("rpy"), version.used >= UrdfVersion::V1_1) {
        (None, true) if o.attr("quat_xyzw").is_some() => (tokens("quat_xyzw"), true),
        _ => (tokens("rpy"), false),
    };
    let mut texts = if xyz.is_empty() {
        vec!["0"; 3]
    } else {
        xyz.clone()
    };
    let mut halves = tuple_half_units(&texts);
    let rot = if rot.is_empty() { vec!["0"; 3] } else { rot };
    halves.extend(tuple_half_units(&rot));
    texts.extend(rot);
    let params: Vec<f64> = texts.iter().map(|t| t.parse().unwrap_or(0.0)).collect();
    if !quat {
        // Kept compact: the covariance is rpy_covariance of these, computed
        // where it is used.
        let u = |i: usize| [0, 1, 2].map(|k| rounding_std(halves[i + k]));
        return Precision::rpy([params[3], params[4], params[5]], u(0), u(3));
    }
    let build = |p: &[f64]| {
        let d = [p[0], p[1], p[2]];
        if quat {
            Transform::from_quaternion(
                [p[3], p[4], p[5], p[6]],
                QuatOrder::Xyzw,
                d,
                &mut Vec::new(),
            )
        } else {
            Transform::from_rpy([p[3], p[4], p[5]], d)
        }
    };
    match rounding_covariance(&params, &halves, build) {
        Ok(c) => crate::geometry::EdgePrecision {
            rounding: Some(c),
            user: None,
        }
        .into(),
        Err(_) => Precision::default(),
    }
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

/// The version a file is read as: declared (`None` when absent) and used.
#[derive(Debug, Clone, Copy)]
pub(super) struct Version {
    pub declared: Option<UrdfVersion>,
    pub used: UrdfVersion,
}

impl Version {
    fn declared_text(&self) -> String {
        match self.declared {
            Some(v) => format!("declares version {v}"),
            None => "declares no version (1.0)".to_string(),
        }
    }
}

/// `<robot version>` read as urdfdom reads it (refused at the `<robot>` line
/// when malformed or unsupported), then `--urdf-version` if given.
pub(super) fn version(idx: &LineIndex, root: &El, opts: &LoadOptions) -> Result<Version> {
    let declared = match root.attr("version") {
        None => None,
        Some(s) => Some(UrdfVersion::parse(s).map_err(|m| {
            err_at(
                idx,
                root,
                format!("<robot version>: {m}; ROS (urdfdom) refuses this file"),
            )
        })?),
    };
    let used = opts.urdf_version.or(declared).unwrap_or(UrdfVersion::V1_0);
    Ok(Version { declared, used })
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
}

/// `N` finite numbers separated by whitespace.
fn numbers_attr<const N: usize>(s: &str, what: &str) -> std::result::Result<[f64; N], String> {
    // ASCII whitespace only: a no-break space is no separator for urdfdom.
    let parts: Vec<&str> = s.split_ascii_whitespace().collect();
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

fn err_at(idx: &LineIndex, n: &El, msg: String) -> Error {
    let (l, c) = idx.pos(n.start);
    Error::parse(msg).at_line(l, Some(c))
}

/// Top-level `<link>` elements by name (names unique): their start offsets.
pub(super) fn links<'a>(
    idx: &LineIndex,
    decls: &[(Option<Cow<'a, str>>, usize)],
) -> Result<Links<'a>> {
    let mut links: Links = HashMap::with_capacity(decls.len());
    for (name, start) in decls {
        let at = |msg: String| {
            let (l, c) = idx.pos(*start);
            Error::parse(msg).at_line(l, Some(c))
        };
        let Some(name) = name else {
            return Err(at("<link> without a name: expected name=\"...\"".into()));
        };
        if let Some(prev) = links.get(name.as_ref()) {
            let (pl, _) = idx.pos(*prev);
            return Err(at(format!(
                "link '{name}' declared twice: expected unique link names, first at line {pl}"
            )));
        }
        links.insert(name.clone(), *start);
    }
    Ok(links)
}

/// Top-level `<joint>` elements (names unique, links declared), read one at
/// a time and handed to `each`; returns the joint names with their lines.
pub(super) fn joints<'a>(
    text: &'a str,
    idx: &LineIndex,
    links: &Links,
    version: Version,
    path: &Path,
    warnings: &mut Vec<Warning>,
    mut each: impl FnMut(JointRaw) -> Result<()>,
) -> Result<HashMap<Cow<'a, str>, usize>> {
    let mut seen: HashMap<Cow<'a, str>, usize> = HashMap::new();
    stream::joints(text, path, |j| {
        let name = j.el.attribute("name").map(|a| a.value.clone());
        if let Some(&prev) = name.as_ref().and_then(|n| seen.get(n.as_ref())) {
            return Err(err_at(
                idx,
                &j.el,
                format!(
                    "joint '{}' declared twice: expected unique joint names, first at line {}",
                    name.as_deref().unwrap_or(""),
                    prev
                ),
            ));
        }
        let raw = joint(idx, &j, links, version, path, warnings)?;
        if let Some(n) = name {
            seen.insert(n, raw.loc.line.unwrap_or(0));
        }
        each(raw)
    })?;
    Ok(seen)
}

fn joint(
    idx: &LineIndex,
    jel: &JointEl,
    links: &Links,
    version: Version,
    path: &Path,
    warnings: &mut Vec<Warning>,
) -> Result<JointRaw> {
    let j = &jel.el;
    let Some(name) = j.attr("name") else {
        return Err(err_at(
            idx,
            j,
            "<joint> without a name: expected name=\"...\"".into(),
        ));
    };
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
    let child_el = |tag: &str| jel.child(tag);
    let link_of = |tag: &str| -> Result<String> {
        let el = child_el(tag).ok_or_else(|| {
            err_at(
                idx,
                j,
                format!("joint '{name}': expected a <{tag} link=\"...\"/>, found none"),
            )
        })?;
        let l = el.attr("link").ok_or_else(|| {
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
    let loc_of = |n: &El| {
        let (l, c) = idx.pos(n.start);
        Location::at(path, l, Some(c))
    };
    let (origin, origin_precision) = match child_el("origin") {
        None => (
            Transform::identity(),
            crate::geometry::EdgePrecision::exact().into(),
        ),
        Some(o) => (
            origin(idx, o, name, version, &loc_of(o), warnings)?,
            origin_precision(o, version),
        ),
    };
    // As urdfdom: no <axis> is 1 0 0, an <axis> without xyz is 0 0 0 (refused
    // on a movable joint: KDL would divide by its norm).
    let axis = match child_el("axis").map(|a| (a, a.attr("xyz"))) {
        Some((a, Some(s))) => numbers_attr::<3>(s, &format!("joint '{name}' <axis xyz>"))
            .map_err(|m| err_at(idx, a, m))?,
        Some((a, None)) if matches!(jtype, "revolute" | "continuous" | "prismatic") => {
            return Err(err_at(
                idx,
                a,
                format!("{jtype} joint '{name}': <axis> without xyz, which urdfdom reads as 0 0 0 (no motion; ROS would publish a non-finite pose): expected <axis xyz=\"x y z\"/>"),
            ))
        }
        Some((_, None)) => [0.0; 3],
        None => [1.0, 0.0, 0.0],
    };
    let mimic = match child_el("mimic") {
        None => None,
        Some(m) => Some(mimic(idx, m, name)?),
    };
    let limit = limit(
        idx,
        child_el("limit"),
        jtype,
        name,
        version,
        &loc_of(j),
        warnings,
    )?;
    number_spacing(jel, name, jtype, &loc_of(j), warnings);
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
        loc: loc_of(j),
    })
}

/// `<origin xyz rpy>` or, from URDF 1.1, `<origin xyz quat_xyzw>`; both is
/// an error in every version.
fn origin(
    idx: &LineIndex,
    o: &El,
    name: &str,
    version: Version,
    loc: &Location,
    warnings: &mut Vec<Warning>,
) -> Result<Transform> {
    let xyz = match o.attr("xyz") {
        Some(s) => numbers_attr::<3>(s, &format!("joint '{name}' <origin xyz>"))
            .map_err(|m| err_at(idx, o, m))?,
        None => [0.0; 3],
    };
    let rpy = |r: Option<&str>| -> Result<Transform> {
        let rpy = match r {
            Some(s) => numbers_attr::<3>(s, &format!("joint '{name}' <origin rpy>"))
                .map_err(|m| err_at(idx, o, m))?,
            None => [0.0; 3],
        };
        Transform::from_rpy(rpy, xyz).map_err(|e| err_at(idx, o, e.message))
    };
    match (o.attr("rpy"), o.attr("quat_xyzw")) {
        (Some(_), Some(_)) => Err(err_at(
            idx,
            o,
            format!("joint '{name}' <origin>: expected either rpy or quat_xyzw, found both"),
        )),
        (None, Some(q)) if version.used < UrdfVersion::V1_1 => {
            let msg = if version.declared.unwrap_or(UrdfVersion::V1_0) < UrdfVersion::V1_1 {
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
            };
            warnings.push(Warning::new(Code::QuatXyzwIgnored, msg).at(loc));
            rpy(None)
        }
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
                    .at(loc),
                );
            }
            Ok(t)
        }
        (r, None) => rpy(r),
    }
}

/// `<limit lower upper>` of a revolute or prismatic joint: a bound not
/// written is 0, as in urdfdom. What urdfdom refuses without a pose being in
/// doubt (no `<limit>`; before URDF 1.2 no `effort` or `velocity`, from 1.2 no
/// `lower` or `upper`) is a `refused-by-ros` warning.
fn limit(
    idx: &LineIndex,
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
            numbers_attr::<1>(s, &format!("joint '{name}' <limit {attr}>"))
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
            Some(s) => numbers_attr::<1>(s, &format!("joint '{name}' <limit {attr}>"))
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

/// The numeric attributes urdfdom reads: (element, attribute, vector of
/// numbers split at spaces, or one number).
const NUMERIC_ATTRS: &[(&str, &str, bool)] = &[
    ("origin", "xyz", true),
    ("origin", "rpy", true),
    ("origin", "quat_xyzw", true),
    ("axis", "xyz", true),
    ("limit", "lower", false),
    ("limit", "upper", false),
    ("limit", "effort", false),
    ("limit", "velocity", false),
    ("mimic", "multiplier", false),
    ("mimic", "offset", false),
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
    j: &JointEl,
    name: &str,
    jtype: &str,
    loc: &Location,
    warnings: &mut Vec<Warning>,
) {
    let mut found = Vec::new();
    for (tag, attr, vector) in NUMERIC_ATTRS {
        // urdfdom reads no axis on fixed and floating joints.
        if *tag == "axis" && matches!(jtype, "fixed" | "floating") {
            continue;
        }
        let Some(a) = j
            .child(tag)
            .and_then(|e| e.attrs.iter().find(|a| a.name == *attr))
        else {
            continue;
        };
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

fn mimic(idx: &LineIndex, m: &El, name: &str) -> Result<Mimic> {
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
