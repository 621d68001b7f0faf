//! URDF: the kinematic tree of a robot description.
//!
//! Meaning: every top-level `<joint>` is an edge `parent link -> child link`
//! whose transform is the child's pose in the parent: `<origin xyz rpy>` with
//! fixed-axis roll-pitch-yaw, `R = Rz(yaw) Ry(pitch) Rx(roll)`, then the joint's
//! motion. A missing `<origin>` is the identity; a missing `rpy` or `xyz` is zero.
//! URDF 1.1's `quat_xyzw` attribute is read, in x y z w order (a file giving both
//! `rpy` and `quat_xyzw` is refused).
//!
//! Joints: `fixed` as given. `revolute` / `continuous` rotate about `<axis>`
//! (default `1 0 0`, normalised with a `non-unit-axis` warning when it is not a
//! unit vector; a zero axis on a movable joint is an error, on a fixed joint it
//! is ignored), `prismatic` translates along it. They sit at position 0 unless
//! `--joint NAME=VALUE` (rad or m) sets them; paths through joints at 0 carry a
//! `joint-at-default` warning. `<mimic joint multiplier offset>` joints follow
//! their master: `value = multiplier * master + offset`. `floating` and
//! `planar` joints have no pose in the file: a path through one is refused
//! unless `--joint NAME=0` puts it at its origin (a floating pose needs six
//! numbers: give it as a static transform instead).
//!
//! Reader: the tree is read with roxmltree, so every edge knows the line and
//! column of its `<joint>` element. Only top-level `<link>` and `<joint>` count
//! (Husky's `<transmission>` blocks hold decoy `<joint>` elements). Several
//! `<material>` in one `<visual>` (Unitree B2/Go2) do not matter. Checked: the
//! root element is `<robot>` (an `<sdf>` root is refused), names are unique,
//! joints name declared links, numbers are finite, the joints form a tree (no
//! cycle, one parent per link).
//!
//! Why not urdf-rs for reading: urdf-rs 0.10 keeps no positions, hides the XML
//! parser's errors, rejects files ROS reads (duplicate `<material>`), drops
//! `quat_xyzw` silently and accepts NaN, cycles, duplicate links and two parents.
//! The test suite uses it as an independent cross-check on the corpus files it
//! reads.
//!
//! xacro: a `.xacro` file is expanded by the `xacro` program when it is on PATH
//! (`xacro FILE`, its standard output parsed as URDF; line numbers then refer to
//! the expanded text), otherwise refused with the command to run. A file named
//! `.urdf` that still holds xacro (`xacro:` elements or namespace, `${...}`,
//! `$(...)`) is refused with the same advice: it is never parsed as URDF.

use crate::error::{Error, Location, Result, Warning, WarningCode};
use crate::formats::{locate_warnings, Edge, Format, JointState, LineIndex, LoadOptions, Loaded};
use crate::graph::FrameGraph;
use crate::se3::{QuatOrder, Transform};
use std::collections::HashMap;
use std::path::Path;

const JOINT_TYPES: &[&str] = &[
    "fixed",
    "revolute",
    "continuous",
    "prismatic",
    "floating",
    "planar",
];

fn xacro_advice(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_else(|| "robot.urdf.xacro".to_string());
    let out = name
        .strip_suffix(".xacro")
        .map(|s| {
            if s.ends_with(".urdf") {
                s.to_string()
            } else {
                format!("{s}.urdf")
            }
        })
        .unwrap_or_else(|| "robot.urdf".to_string());
    let out = if out == name {
        "expanded.urdf".to_string()
    } else {
        out
    };
    format!("expand it first: `xacro {name} > {out}` (pip install xacro), then pass {out}")
}

fn find_on_path(prog: &str) -> Option<std::path::PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join(prog))
        .find(|p| p.is_file())
}

/// A `.xacro` file: expand with the `xacro` program if present, else refuse.
pub fn parse_xacro(text: &str, path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    let _ = text;
    let Some(xacro) = find_on_path("xacro") else {
        return Err(Error::parse(format!(
            "this is a xacro file, not URDF, and the `xacro` program is not on PATH: {}",
            xacro_advice(path)
        )));
    };
    let out = std::process::Command::new(&xacro)
        .arg(path)
        .output()
        .map_err(|e| Error::parse(format!("running {}: {e}", xacro.display())))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(Error::parse(format!(
            "xacro could not expand this file ({}): {}",
            out.status,
            err.lines().last().unwrap_or("").trim()
        )));
    }
    let expanded = String::from_utf8(out.stdout)
        .map_err(|_| Error::parse("xacro printed something that is not UTF-8"))?;
    let mut loaded = parse(&expanded, path, opts)?;
    for e in &mut loaded.edges {
        e.provenance.key = format!("{} (line in xacro's expanded output)", e.provenance.key);
    }
    Ok(loaded)
}

/// An XML error at its position; at the end of the text when the input stops early.
pub(crate) fn xml_err_at(e: &roxmltree::Error, row: usize, col: usize, text: &str) -> Error {
    if matches!(e, roxmltree::Error::UnexpectedEndOfStream) {
        let lines = text.lines().count().max(1);
        let last = text
            .lines()
            .last()
            .map(|l| l.chars().count() + 1)
            .unwrap_or(1);
        return Error::parse("not well-formed XML: the file ends inside an element (truncated?)")
            .at_line(lines, Some(last));
    }
    if matches!(e, roxmltree::Error::DtdDetected) {
        // Refused on purpose: DTD entities can expand exponentially ("billion
        // laughs") and no URDF or launch file needs them.
        let line = text
            .lines()
            .position(|l| l.contains("<!DOCTYPE"))
            .map(|i| i + 1)
            .unwrap_or(row);
        return Error::limit(
            "XML with a <!DOCTYPE> (DTD / entity declarations): not read, entities can expand without bound; expected a plain URDF or launch file: remove the DOCTYPE block and write the values out",
        )
        .at_line(line, None);
    }
    Error::parse(format!("not well-formed XML: {e}")).at_line(row, Some(col))
}

fn xml_error(e: &roxmltree::Error, text: &str) -> Error {
    let pos = e.pos();
    xml_err_at(e, pos.row as usize, pos.col as usize, text)
}

fn pos_of(idx: &LineIndex, node: roxmltree::Node) -> (usize, usize) {
    idx.pos(node.range().start)
}

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

struct JointRaw<'a> {
    name: String,
    jtype: String,
    parent: String,
    child: String,
    origin: Transform,
    axis: [f64; 3],
    mimic: Option<(String, f64, f64)>,
    loc: Location,
    node: roxmltree::Node<'a, 'a>,
}

/// Parse URDF text.
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    let has_xacro_markers = text.contains("xmlns:xacro")
        || text.contains("<xacro:")
        || text.contains("${")
        || text.contains("$(");
    let opt = roxmltree::ParsingOptions {
        allow_dtd: false,
        ..Default::default()
    };
    let doc = match roxmltree::Document::parse_with_options(text, opt) {
        Ok(d) => d,
        Err(e) => {
            if has_xacro_markers {
                return Err(Error::parse(format!(
                    "this file holds un-expanded xacro, not URDF: {}",
                    xacro_advice(path)
                )));
            }
            return Err(xml_error(&e, text));
        }
    };
    let idx = LineIndex::new(text);
    let root = doc.root_element();
    let (rl, rc) = pos_of(&idx, root);
    match root.tag_name().name() {
        "robot" => {}
        "sdf" => {
            return Err(Error::parse(
                "root element is <sdf>: this is an SDF (Gazebo) file, expected a URDF <robot>; convert it to URDF first",
            )
            .at_line(rl, Some(rc)))
        }
        other => {
            return Err(Error::parse(format!(
                "root element is <{other}>: expected a URDF <robot>"
            ))
            .at_line(rl, Some(rc)))
        }
    }
    // Un-expanded xacro: namespace, elements or ${...} / $(...) in attributes.
    for n in doc.descendants().filter(|n| n.is_element()) {
        let is_xacro_el = n
            .tag_name()
            .namespace()
            .map(|ns| ns.contains("xacro"))
            .unwrap_or(false);
        let has_expr = n
            .attributes()
            .any(|a| a.value().contains("${") || a.value().contains("$("));
        if is_xacro_el || has_expr {
            let (l, c) = pos_of(&idx, n);
            return Err(Error::parse(format!(
                "this file holds un-expanded xacro (<{}{}>), not URDF: {}",
                if is_xacro_el { "xacro:" } else { "" },
                n.tag_name().name(),
                xacro_advice(path)
            ))
            .at_line(l, Some(c)));
        }
    }
    let loc_of = |n: roxmltree::Node| {
        let (l, c) = pos_of(&idx, n);
        Location::at(path, l, Some(c))
    };
    let err_at = |n: roxmltree::Node, msg: String| {
        let (l, c) = pos_of(&idx, n);
        Error::parse(msg).at_line(l, Some(c))
    };

    let mut warnings = Vec::new();
    let mut links: HashMap<String, roxmltree::Node> = HashMap::new();
    for l in root
        .children()
        .filter(|n| n.is_element() && n.tag_name().name() == "link")
    {
        let Some(name) = l.attribute("name") else {
            return Err(err_at(
                l,
                "<link> without a name: expected name=\"...\"".into(),
            ));
        };
        if let Some(prev) = links.get(name) {
            let (pl, _) = pos_of(&idx, *prev);
            return Err(err_at(
                l,
                format!(
                    "link '{name}' declared twice: expected unique link names, first at line {pl}"
                ),
            ));
        }
        links.insert(name.to_string(), l);
    }

    let mut joints: Vec<JointRaw> = Vec::new();
    let mut seen: HashMap<String, usize> = HashMap::new();
    for j in root
        .children()
        .filter(|n| n.is_element() && n.tag_name().name() == "joint")
    {
        let Some(name) = j.attribute("name") else {
            return Err(err_at(
                j,
                "<joint> without a name: expected name=\"...\"".into(),
            ));
        };
        if let Some(&prev) = seen.get(name) {
            return Err(err_at(
                j,
                format!(
                    "joint '{name}' declared twice: expected unique joint names, first at line {}",
                    joints[prev].loc.line.unwrap_or(0)
                ),
            ));
        }
        let jtype = j.attribute("type").unwrap_or("");
        if !JOINT_TYPES.contains(&jtype) {
            return Err(err_at(
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
                    j,
                    format!("joint '{name}': expected a <{tag} link=\"...\"/>, found none"),
                )
            })?;
            let l = el.attribute("link").ok_or_else(|| {
                err_at(el, format!("joint '{name}': <{tag}> without link=\"...\""))
            })?;
            if !links.contains_key(l) {
                return Err(err_at(
                    el,
                    format!("joint '{name}': {tag} link '{l}' is not declared as a <link>"),
                ));
            }
            Ok(l.to_string())
        };
        let parent = link_of("parent")?;
        let child = link_of("child")?;
        let origin = match child_el("origin") {
            None => Transform::identity(),
            Some(o) => {
                let xyz = match o.attribute("xyz") {
                    Some(s) => numbers_attr::<3>(s, &format!("joint '{name}' <origin xyz>"))
                        .map_err(|m| err_at(o, m))?,
                    None => [0.0; 3],
                };
                let rpy = o.attribute("rpy");
                let quat = o.attribute("quat_xyzw");
                match (rpy, quat) {
                    (Some(_), Some(_)) => {
                        return Err(err_at(
                            o,
                            format!(
                            "joint '{name}' <origin>: expected either rpy or quat_xyzw, found both"
                        ),
                        ))
                    }
                    (None, Some(q)) => {
                        let q = numbers_attr::<4>(q, &format!("joint '{name}' <origin quat_xyzw>"))
                            .map_err(|m| err_at(o, m))?;
                        let mut ws = Vec::new();
                        let t = Transform::from_quaternion(q, QuatOrder::Xyzw, xyz, &mut ws)
                            .map_err(|e| {
                                err_at(
                                    o,
                                    format!("joint '{name}' <origin quat_xyzw>: {}", e.message),
                                )
                            })?;
                        locate_warnings(ws, &loc_of(o), &mut warnings);
                        warnings.push(
                            Warning::new(
                                WarningCode::AssumedConvention,
                                format!("joint '{name}': URDF 1.1 quat_xyzw read in x y z w order (urdf-rs and ROS parsers before URDF 1.1 ignore it and use the identity)"),
                            )
                            .at(&loc_of(o)),
                        );
                        t
                    }
                    (r, None) => {
                        let rpy = match r {
                            Some(s) => {
                                numbers_attr::<3>(s, &format!("joint '{name}' <origin rpy>"))
                                    .map_err(|m| err_at(o, m))?
                            }
                            None => [0.0; 3],
                        };
                        Transform::from_rpy(rpy, xyz).map_err(|e| err_at(o, e.message))?
                    }
                }
            }
        };
        let axis = match child_el("axis").and_then(|a| a.attribute("xyz").map(|s| (a, s))) {
            Some((a, s)) => numbers_attr::<3>(s, &format!("joint '{name}' <axis xyz>"))
                .map_err(|m| err_at(a, m))?,
            None => [1.0, 0.0, 0.0],
        };
        let mimic = match child_el("mimic") {
            None => None,
            Some(m) => {
                let master = m.attribute("joint").ok_or_else(|| {
                    err_at(m, format!("joint '{name}': <mimic> without joint=\"...\""))
                })?;
                let num = |attr: &str, def: f64| -> Result<f64> {
                    match m.attribute(attr) {
                        None => Ok(def),
                        Some(s) => numbers_attr::<1>(s, &format!("joint '{name}' <mimic {attr}>"))
                            .map(|v| v[0])
                            .map_err(|msg| err_at(m, msg)),
                    }
                };
                Some((
                    master.to_string(),
                    num("multiplier", 1.0)?,
                    num("offset", 0.0)?,
                ))
            }
        };
        seen.insert(name.to_string(), joints.len());
        joints.push(JointRaw {
            name: name.to_string(),
            jtype: jtype.to_string(),
            parent,
            child,
            origin,
            axis,
            mimic,
            loc: loc_of(j),
            node: j,
        });
    }

    // Joint values: --joint, else mimic of the master, else 0.
    let by_name: HashMap<&str, &JointRaw> = joints.iter().map(|j| (j.name.as_str(), j)).collect();
    let mut edges = Vec::with_capacity(joints.len());
    for j in &joints {
        let movable = matches!(j.jtype.as_str(), "revolute" | "continuous" | "prismatic");
        let set = opts.joints.get(&j.name).copied();
        let key = format!("joint \"{}\" <origin>", j.name);
        if j.jtype == "fixed" {
            if set.is_some() {
                warnings.push(
                    Warning::new(
                        WarningCode::Ignored,
                        format!("--joint {}: a fixed joint has no position; ignored", j.name),
                    )
                    .at(&j.loc),
                );
            }
            edges.push(Edge::new(
                &j.parent,
                &j.child,
                j.origin,
                j.loc.clone(),
                Format::Urdf,
                key,
            ));
            continue;
        }
        if !movable {
            // floating, planar
            let value = match set {
                None => None,
                Some(v) if v.abs() < f64::MIN_POSITIVE => Some(0.0),
                Some(v) => {
                    return Err(Error::usage(format!(
                        "--joint {}={v}: joint '{}' is {}; only 0 (the joint at its origin) is accepted, a {} pose needs more than one number: give it as a static transform instead",
                        j.name, j.name, j.jtype, j.jtype
                    ))
                    .at(&j.loc))
                }
            };
            let mut e = Edge::new(
                &j.parent,
                &j.child,
                j.origin,
                j.loc.clone(),
                Format::Urdf,
                key,
            );
            e.joint = Some(JointState {
                name: j.name.clone(),
                joint_type: j.jtype.clone(),
                value,
                defaulted: false,
            });
            edges.push(e);
            continue;
        }
        let (value, defaulted) = match (set, &j.mimic) {
            (Some(v), _) => (v, false),
            (None, Some((master, mult, off))) => {
                let Some(m) = by_name.get(master.as_str()) else {
                    return Err(Error::parse(format!(
                        "joint '{}': <mimic joint=\"{master}\"> names no joint in this file",
                        j.name
                    ))
                    .at(&j.loc));
                };
                match opts.joints.get(&m.name) {
                    Some(mv) => (mult * mv + off, false),
                    None => (*off, true),
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
        // Scaled norm: an axis like [1e300, 1e300, 0] must not square to inf
        // (dividing by it would give a zero axis and, for a prismatic joint, a
        // silently zero motion).
        let scale = j.axis.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let n = if scale > 0.0 {
            scale
                * ((j.axis[0] / scale).powi(2)
                    + (j.axis[1] / scale).powi(2)
                    + (j.axis[2] / scale).powi(2))
                .sqrt()
        } else {
            0.0
        };
        if n.is_nan() || n < 1e-12 {
            let (l, c) = pos_of(&idx, j.node);
            return Err(Error::invalid(format!(
                "{} joint '{}': expected a non-zero <axis xyz>, found {:?}",
                j.jtype, j.name, j.axis
            ))
            .at_line(l, Some(c)));
        }
        if (n - 1.0).abs() > 1e-9 {
            warnings.push(
                Warning::new(
                    WarningCode::NonUnitAxis,
                    format!(
                        "{} joint '{}': axis {:?} has norm {}, expected 1; normalised",
                        j.jtype,
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
        let e_axis = if n.is_finite() {
            [j.axis[0] / n, j.axis[1] / n, j.axis[2] / n]
        } else {
            let a = [j.axis[0] / scale, j.axis[1] / scale, j.axis[2] / scale];
            let m = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            [a[0] / m, a[1] / m, a[2] / m]
        };
        let motion = if j.jtype == "prismatic" {
            Transform::from_translation([e_axis[0] * value, e_axis[1] * value, e_axis[2] * value])?
        } else {
            Transform::from_axis_angle(e_axis, value, [0.0; 3])?
        };
        let mut e = Edge::new(
            &j.parent,
            &j.child,
            j.origin.compose(&motion),
            j.loc.clone(),
            Format::Urdf,
            format!("joint \"{}\" <origin> + {} motion", j.name, j.jtype),
        );
        e.joint = Some(JointState {
            name: j.name.clone(),
            joint_type: j.jtype.clone(),
            value: Some(value),
            defaulted,
        });
        edges.push(e);
    }

    // The joints must form a tree: check now, with the file's positions.
    let mut g = FrameGraph::new();
    for e in &edges {
        g.add_edge(e.clone())?;
    }
    Ok(Loaded {
        edges,
        warnings,
        rig: None,
    })
}
