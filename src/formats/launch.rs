//! Static transforms as ROS launches them: `static_transform_publisher`.
//!
//! Meaning (ROS 1 tf / tf2_ros and ROS 2 tf2_ros): the transform published is
//! the pose of `child` in `parent` (`p_parent = R p_child + d`), edge
//! `parent -> child`. Argument forms read:
//!
//! - `x y z yaw pitch roll parent child [period_ms]` (note yaw first; the angles
//!   are URDF's fixed-axis roll-pitch-yaw, `R = Rz(yaw) Ry(pitch) Rx(roll)`);
//! - `x y z qx qy qz qw parent child [period_ms]` (quaternion x y z w);
//! - ROS 2 flags `--x --y --z --roll --pitch --yaw --qx --qy --qz --qw
//!   --frame-id --child-frame-id` (missing numbers are 0, qw 1; mixing angles and
//!   a quaternion is refused).
//!
//! ROS remappings (`__name:=...`, `name:=value`) and everything after
//! `--ros-args` are skipped. A number followed by a comma (`1.5707963,`, seen in
//! a real launch file) is read as ROS 1's `atof` reads it, with an `ignored`
//! warning. A leading `/` on a frame name is dropped (tf2 does the same).
//!
//! Where the transforms are found:
//! - launch XML (ROS 1 `<node pkg="tf|tf2_ros" type="static_transform_publisher"
//!   args="...">`, ROS 2 `exec="static_transform_publisher"`), anywhere in the
//!   tree (`<group>` included); `$(arg x)` / `$(var x)` resolved from the
//!   file's `<arg>` declarations and `--arg x=VALUE`, `if` / `unless` on the
//!   node and its groups evaluated (a node switched off is skipped with an
//!   `ignored` warning), other substitutions refused (see `launch_subst`);
//! - ROS 2 launch YAML (`node: {pkg, exec, args}`), `args` a string or a list,
//!   with `arg:` declarations, `$(var x)` and `if:` / `unless:` on the node
//!   and its groups decided as for launch XML;
//! - ROS 2 Python launch files, read statically by `launch_py` (literals,
//!   `LaunchConfiguration`, `PythonExpression`, conditions, and what the
//!   file's own helper functions and `for` loops build; never executed);
//! - command lines saved as text (`rosrun tf static_transform_publisher ...`,
//!   `ros2 run tf2_ros static_transform_publisher ...`), one a line, `\`
//!   continuations joined, `#` comments skipped.
//!
//! LIO-Livox launch files carry `<rosparam param="Extrinsic_Tlb">` with a
//! row-major 4x4 instead: `T_lb`, the pose of the IMU (b, body) in the LiDAR
//! (l), `p_lidar = R p_imu + t`, edge `lidar -> imu`, as LIO-Livox's code uses
//! it (Livox-SDK/LIO-Livox @ 2296e4bea59bcfec09624a6f052fd6bfbe2b1e6a):
//! `src/lio/PoseEstimation.cpp:576-593` loads `~Extrinsic_Tlb` row-major
//! (`R << vecTlb[0..2], [4..6], [8..10]; t << vecTlb[3], [7], [11]`,
//! `exRlb = R; exPlb = t; exRbl = R^T; exPbl = -R^T t`); `:354-355`
//! `P = Pwl + Qwl*exPlb; Q = Qwl * exRlb` (`T_wb = T_wl T_lb`); `:449-450`
//! `Qwl = Q * exRbl; Pwl = Q * exPbl + P` (`T_wl = T_wb T_bl`); and
//! `src/lio/Estimator.cpp:113-114` `Tbl = exTlb^-1`, with which LiDAR points
//! go to the map (`include/utils/ceresfunc.h:469-485`). LIO-Livox
//! re-orthonormalises the rotation (`Quaterniond(R).normalized()`); the
//! tool's rounding warning says when that matters. (The shipped
//! `mid360.launch` numbers carry FAST-LIO's LiDAR-in-IMU sign while
//! `horizon.launch` carries the negative: the code, not the numbers, decides
//! the reading; see calibrations/README.md.)

use super::launch_subst::{ArgDecl, Condition, LaunchArgs};
use super::source::LineIndex;
use super::spec::{
    check_metres, locate_warnings, parse_number, Confidence, FormatSpec, Input, LoadOptions, Parsed,
};
use super::xml;
use super::yaml::{self, Node, Value};
use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::frames::Edge;
use crate::geometry::se3::{QuatOrder, Transform};
use crate::geometry::uncertainty::{matrix4_precision, written_precision, Written};
use crate::sanitize::clip;
use std::path::Path;

const FLAGS: &[&str] = &[
    "--x",
    "--y",
    "--z",
    "--roll",
    "--pitch",
    "--yaw",
    "--qx",
    "--qy",
    "--qz",
    "--qw",
    "--frame-id",
    "--child-frame-id",
];

fn frame_name(s: &str) -> String {
    s.trim_start_matches('/').to_string()
}

fn number_arg(tok: &str, idx: usize, warnings: &mut Vec<Warning>, loc: &Location) -> Result<f64> {
    if let Some(x) = parse_number(tok) {
        return Ok(x);
    }
    if let Some(stripped) = tok.strip_suffix(',') {
        if let Some(x) = parse_number(stripped) {
            warnings.push(
                Warning::new(
                    Code::Ignored,
                    format!("argument {idx} {tok:?}: trailing comma ignored (ROS 1 reads it with atof, which stops there)"),
                )
                .at(loc),
            );
            return Ok(x);
        }
    }
    Err(Error::parse(format!(
        "static_transform_publisher argument {idx}: expected a number, found {:?}",
        clip(tok)
    ))
    .at(loc))
}

/// Read the arguments of one `static_transform_publisher` call.
pub fn parse_stp_args(
    args: &[String],
    loc: &Location,
    format: &'static str,
    context: &str,
    warnings: &mut Vec<Warning>,
) -> Result<Edge> {
    let toks = publisher_tokens(args);
    refuse_substitutions(&toks, loc)?;
    let mut ws = Vec::new();
    let (parent, child, read) = if toks.iter().any(|t| t.starts_with("--")) {
        flag_form(&toks, loc, &mut ws)?
    } else {
        positional_form(&toks, loc, &mut ws)?
    };
    let edge = Edge::new(
        frame_name(parent),
        frame_name(child),
        read.transform,
        loc.clone(),
        format,
        format!("{context}static_transform_publisher {}", read.form),
    )
    .with_precision(written_precision(read.written, read.d, 1.0));
    locate_warnings(ws, loc, warnings);
    Ok(edge)
}

/// A publisher's transform, the argument form it was written in, and its
/// numbers as written (for their rounding).
struct Published {
    transform: Transform,
    form: &'static str,
    written: Written,
    d: [f64; 3],
}

/// The arguments without ROS arguments (everything after `--ros-args`) and
/// remappings (`name:=value`, `__name:=...`).
fn publisher_tokens(args: &[String]) -> Vec<&str> {
    args.iter()
        .take_while(|a| *a != "--ros-args")
        .filter(|a| !(a.contains(":=") || a.starts_with("__")))
        .map(String::as_str)
        .collect()
}

/// A `$(...)` or `${...}` left in the arguments: the launch system would
/// substitute it, the tool does not.
fn refuse_substitutions(toks: &[&str], loc: &Location) -> Result<()> {
    let joined = toks.join(" ");
    let Some(at) = joined.find("$(").or_else(|| joined.find("${")) else {
        return Ok(());
    };
    let end = joined[at..]
        .find([')', '}'])
        .map(|e| at + e + 1)
        .unwrap_or(joined.len());
    Err(Error::parse(format!(
        "static_transform_publisher arguments hold the substitution {:?}: expected literal values; resolve it (roslaunch / ros2 launch --print) or write the value",
        &joined[at..end]
    ))
    .at(loc))
}

/// ROS 2 flags (`--x 1 --frame-id a ...`, or `--x=1`): each known, given once.
fn flag_values<'t>(
    toks: &[&'t str],
    loc: &Location,
) -> Result<std::collections::BTreeMap<&'t str, &'t str>> {
    let mut vals = std::collections::BTreeMap::new();
    let mut i = 0;
    while i < toks.len() {
        let t = toks[i];
        let (flag, inline) = match t.split_once('=') {
            Some((f, v)) if t.starts_with("--") => (f, Some(v)),
            _ => (t, None),
        };
        if !FLAGS.contains(&flag) {
            return Err(Error::parse(format!(
                "static_transform_publisher: expected one of {}, found {:?}",
                FLAGS.join(" "),
                clip(t)
            ))
            .at(loc));
        }
        let v = match inline {
            Some(v) => v,
            None => {
                i += 1;
                *toks.get(i).ok_or_else(|| {
                    Error::parse(format!(
                        "static_transform_publisher: expected a value after {flag}, found the end"
                    ))
                    .at(loc)
                })?
            }
        };
        if vals.insert(flag, v).is_some() {
            return Err(
                Error::parse(format!("static_transform_publisher: {flag} given twice")).at(loc),
            );
        }
        i += 1;
    }
    Ok(vals)
}

/// The ROS 2 flag form: frames from `--frame-id` / `--child-frame-id`,
/// missing numbers 0 (`--qw` 1), angles or a quaternion but not both.
fn flag_form<'t>(
    toks: &[&'t str],
    loc: &Location,
    ws: &mut Vec<Warning>,
) -> Result<(&'t str, &'t str, Published)> {
    let vals = flag_values(toks, loc)?;
    let num = |f: &str, def: f64, ws: &mut Vec<Warning>| -> Result<f64> {
        match vals.get(f) {
            None => Ok(def),
            Some(v) => number_arg(v, 0, ws, loc).map_err(|_| {
                Error::parse(format!(
                    "static_transform_publisher {f}: expected a number, found {:?}",
                    clip(v)
                ))
                .at(loc)
            }),
        }
    };
    let parent = vals.get("--frame-id").ok_or_else(|| {
        Error::parse("static_transform_publisher: expected --frame-id NAME, found none").at(loc)
    })?;
    let child = vals.get("--child-frame-id").ok_or_else(|| {
        Error::parse("static_transform_publisher: expected --child-frame-id NAME, found none")
            .at(loc)
    })?;
    let d = [
        num("--x", 0.0, ws)?,
        num("--y", 0.0, ws)?,
        num("--z", 0.0, ws)?,
    ];
    let given = |fs: &[&str]| fs.iter().any(|f| vals.contains_key(f));
    let (has_q, has_a) = (
        given(&["--qx", "--qy", "--qz", "--qw"]),
        given(&["--roll", "--pitch", "--yaw"]),
    );
    if has_q && has_a {
        return Err(Error::parse(
            "static_transform_publisher: expected either --roll/--pitch/--yaw or --qx/--qy/--qz/--qw, found both",
        )
        .at(loc));
    }
    let read = if has_q {
        let q = [
            num("--qx", 0.0, ws)?,
            num("--qy", 0.0, ws)?,
            num("--qz", 0.0, ws)?,
            num("--qw", 1.0, ws)?,
        ];
        Published {
            transform: Transform::from_quaternion(q, QuatOrder::Xyzw, d, ws)
                .map_err(|e| e.at(loc))?,
            form: "--x --y --z --qx --qy --qz --qw",
            written: Written::Quat(q, QuatOrder::Xyzw),
            d,
        }
    } else {
        let rpy = [
            num("--roll", 0.0, ws)?,
            num("--pitch", 0.0, ws)?,
            num("--yaw", 0.0, ws)?,
        ];
        Published {
            transform: Transform::from_rpy(rpy, d).map_err(|e| e.at(loc))?,
            form: "--x --y --z --roll --pitch --yaw",
            written: Written::Rpy(rpy),
            d,
        }
    };
    check_metres(&d, "static_transform_publisher --x --y --z", loc, ws);
    Ok((parent, child, read))
}

/// How many numbers lead the positional form: 6 (x y z yaw pitch roll) or 7
/// (x y z qx qy qz qw), then `parent child [period_ms]`.
fn positional_count(toks: &[&str], loc: &Location) -> Result<(usize, &'static str)> {
    let nnum = toks
        .iter()
        .take_while(|t| {
            parse_number(t).is_some() || t.strip_suffix(',').and_then(parse_number).is_some()
        })
        .count();
    let form = match nnum {
        6 => "x y z yaw pitch roll",
        7 => "x y z qx qy qz qw",
        n if n < 6 && toks.len() >= 8 => {
            return Err(Error::parse(format!(
                "static_transform_publisher argument {}: expected a number, found {:?}",
                n + 1,
                clip(toks[n])
            ))
            .at(loc))
        }
        _ => {
            return Err(Error::parse(format!(
                "static_transform_publisher: expected `x y z yaw pitch roll parent child [period_ms]` or `x y z qx qy qz qw parent child [period_ms]`, found {} leading numbers in {:?}",
                nnum,
                toks.join(" ")
            ))
            .at(loc))
        }
    };
    let rest = &toks[nnum..];
    match rest.len() {
        2 => {}
        3 if parse_number(rest[2]).is_some() => {}
        _ => {
            return Err(Error::parse(format!(
                "static_transform_publisher: expected `parent child [period_ms]` after the {nnum} numbers, found {:?}",
                clip(&rest.join(" "))
            ))
            .at(loc))
        }
    }
    Ok((nnum, form))
}

/// The positional form: `x y z yaw pitch roll parent child [period_ms]` (yaw
/// first) or `x y z qx qy qz qw parent child [period_ms]`.
fn positional_form<'t>(
    toks: &[&'t str],
    loc: &Location,
    ws: &mut Vec<Warning>,
) -> Result<(&'t str, &'t str, Published)> {
    let (nnum, form) = positional_count(toks, loc)?;
    let mut v = Vec::with_capacity(nnum);
    for (i, t) in toks[..nnum].iter().enumerate() {
        v.push(number_arg(t, i + 1, ws, loc)?);
    }
    let d = [v[0], v[1], v[2]];
    let (transform, written) = if nnum == 6 {
        let ypr = [v[3], v[4], v[5]];
        (
            Transform::from_ypr(ypr, d).map_err(|e| e.at(loc))?,
            Written::Ypr(ypr),
        )
    } else {
        let q = [v[3], v[4], v[5], v[6]];
        (
            Transform::from_quaternion(q, QuatOrder::Xyzw, d, ws).map_err(|e| e.at(loc))?,
            Written::Quat(q, QuatOrder::Xyzw),
        )
    };
    check_metres(&d, "static_transform_publisher x y z", loc, ws);
    let read = Published {
        transform,
        form,
        written,
        d,
    };
    Ok((toks[nnum], toks[nnum + 1], read))
}

fn xml_doc(text: &str) -> Result<roxmltree::Document<'_>> {
    xml::parse(text)
}

/// ROS 1 / ROS 2 launch XML: every `static_transform_publisher` node that
/// runs (see [`super::launch_subst`] for `$(arg ...)` and `if` / `unless`).
pub fn parse_launch_xml(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let doc = xml_doc(text)?;
    let idx = LineIndex::new(text);
    let args = LaunchArgs::new(&doc, &opts.xacro_args);
    let mut out = Parsed::default();
    // The first node switched off, for the error when none runs.
    let mut skipped: Option<(usize, String)> = None;
    for n in doc
        .descendants()
        .filter(|n| n.is_element() && n.tag_name().name() == "node")
    {
        let exe = n
            .attribute("type")
            .or_else(|| n.attribute("exec"))
            .unwrap_or("");
        if exe != "static_transform_publisher" {
            continue;
        }
        let (row, col) = xml::pos_of(&idx, n);
        let loc = Location::at(path, row, Some(col));
        if let Some(why) = args.switched_off(n, &loc)? {
            if skipped.is_none() {
                skipped = Some((row, why.clone()));
            }
            out.warnings.push(
                Warning::new(
                    Code::Ignored,
                    format!("static_transform_publisher <node> not started ({why}): its transform is not read"),
                )
                .at(&loc),
            );
            continue;
        }
        let raw = n.attribute("args").ok_or_else(|| {
            Error::parse("static_transform_publisher <node> without args=\"...\": expected the transform in args").at(&loc)
        })?;
        let toks: Vec<String> = args
            .resolve(raw, &loc)?
            .split_whitespace()
            .map(String::from)
            .collect();
        let name = n.attribute("name").unwrap_or("");
        let ctx = if name.is_empty() {
            "<node> ".to_string()
        } else {
            format!("<node name=\"{name}\"> ")
        };
        out.edges.push(parse_stp_args(
            &toks,
            &loc,
            LAUNCH_XML.id,
            &ctx,
            &mut out.warnings,
        )?);
    }
    if out.edges.is_empty() && text.contains("Extrinsic_Tlb") {
        return parse_lio_livox(text, path, opts);
    }
    if let (true, Some((line, why))) = (out.edges.is_empty(), skipped) {
        return Err(Error::parse(format!(
            "every static_transform_publisher <node> is switched off (the first by {why}): expected at least one that runs; set the arg it depends on with --arg NAME=VALUE"
        ))
        .at_line(line, None));
    }
    Ok(out)
}

/// LIO-Livox `<rosparam param="Extrinsic_Tlb">` (or the `--key` param).
pub fn parse_lio_livox(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let doc = xml_doc(text)?;
    let want = opts.key.as_deref().unwrap_or("Extrinsic_Tlb");
    let mut out = Parsed::default();
    for n in doc
        .descendants()
        .filter(|n| n.is_element() && n.tag_name().name() == "rosparam")
    {
        let param = n.attribute("param").unwrap_or("");
        if param != want {
            continue;
        }
        let (row, col) = xml::pos_of(&LineIndex::new(text), n);
        let loc = Location::at(path, row, Some(col));
        let body: String = n.text().unwrap_or("").to_string();
        let cleaned = body.replace(['[', ']', ','], " ");
        let mut v = Vec::new();
        for t in cleaned.split_whitespace() {
            v.push(parse_number(t).ok_or_else(|| {
                Error::parse(format!(
                    "<rosparam param=\"{}\">: expected 16 numbers, found {:?}",
                    clip(param),
                    clip(t)
                ))
                .at(&loc)
            })?);
        }
        if v.len() != 16 {
            return Err(Error::parse(format!(
                "<rosparam param=\"{param}\">: expected 16 numbers (row-major 4x4), found {}",
                v.len()
            ))
            .at(&loc));
        }
        let m = [
            [v[0], v[1], v[2], v[3]],
            [v[4], v[5], v[6], v[7]],
            [v[8], v[9], v[10], v[11]],
            [v[12], v[13], v[14], v[15]],
        ];
        let mut ws = Vec::new();
        let t = Transform::from_matrix4(m, &mut ws).map_err(|e| e.at(&loc))?;
        locate_warnings(ws, &loc, &mut out.warnings);
        check_metres(&[v[3], v[7], v[11]], param, &loc, &mut out.warnings);
        // T_lb: the IMU's pose in the LiDAR (PoseEstimation.cpp:354-355).
        out.edges.push(
            Edge::new(
                "lidar",
                "imu",
                t,
                loc,
                LIO_LIVOX_LAUNCH.id,
                format!("<rosparam param=\"{param}\">"),
            )
            .with_precision(matrix4_precision(m, 1.0)),
        );
    }
    if out.edges.is_empty() {
        return Err(Error::parse(format!(
            "expected a static_transform_publisher <node> or <rosparam param=\"{want}\">, found neither"
        )));
    }
    Ok(out)
}

/// A static_transform_publisher node of launch YAML with the `if` / `unless`
/// conditions on it and on the mappings enclosing it.
type YamlNode<'a> = (&'a Node, Vec<Condition>);

fn find_nodes<'a>(n: &'a Node, conds: &mut Vec<Condition>, out: &mut Vec<YamlNode<'a>>) {
    match &n.value {
        Value::Map(m) => {
            let exe = n
                .get("exec")
                .or_else(|| n.get("executable"))
                .or_else(|| n.get("type"))
                .and_then(|v| v.as_str());
            let is_node = exe.as_deref() == Some("static_transform_publisher");
            let before = conds.len();
            for attr in ["if", "unless"] {
                if let Some(raw) = n.get(attr).and_then(|v| v.as_str()) {
                    let place = if is_node {
                        ""
                    } else {
                        " on its enclosing group"
                    };
                    conds.push(Condition {
                        attr,
                        raw,
                        place: place.to_string(),
                    });
                }
            }
            if is_node {
                // The node's own conditions first.
                let mut own = conds[before..].to_vec();
                own.extend_from_slice(&conds[..before]);
                out.push((n, own));
            } else {
                for (_, v) in m {
                    find_nodes(v, conds, out);
                }
            }
            conds.truncate(before);
        }
        Value::Seq(s) => {
            for v in s {
                find_nodes(v, conds, out);
            }
        }
        _ => {}
    }
}

/// The `arg:` and `let:` declarations of a launch YAML document.
fn yaml_args(n: &Node, out: &mut Vec<ArgDecl>) {
    for (k, v) in n.entries() {
        let key = k.as_str().unwrap_or_default();
        if key == "arg" || key == "let" {
            if let Some(name) = v.get("name").and_then(|x| x.as_str()) {
                out.push(ArgDecl {
                    name,
                    value: v.get("value").and_then(|x| x.as_str()),
                    default: v.get("default").and_then(|x| x.as_str()),
                });
            }
        }
        yaml_args(v, out);
    }
    if let Value::Seq(s) = &n.value {
        for v in s {
            yaml_args(v, out);
        }
    }
}

/// ROS 2 launch YAML.
pub fn parse_launch_yaml(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let docs = yaml::parse_documents(text)?;
    let mut nodes = Vec::new();
    let mut decls = Vec::new();
    for d in &docs {
        find_nodes(d, &mut Vec::new(), &mut nodes);
        yaml_args(d, &mut decls);
    }
    let largs = LaunchArgs::from_decls(decls, &opts.xacro_args);
    let mut out = Parsed::default();
    let mut skipped: Option<(usize, String)> = None;
    for (n, conds) in nodes {
        let loc = Location::at(path, n.line.max(1), Some(n.column.max(1)));
        if let Some(why) = largs.first_off(&conds, &loc)? {
            skipped.get_or_insert((n.line.max(1), why.clone()));
            out.warnings.push(
                Warning::new(
                    Code::Ignored,
                    format!("static_transform_publisher node not started ({why}): its transform is not read"),
                )
                .at(&loc),
            );
            continue;
        }
        let args = n
            .get("args")
            .or_else(|| n.get("arguments"))
            .ok_or_else(|| {
                Error::parse(
                    "static_transform_publisher node without args: expected `args: \"...\"`",
                )
                .at(&loc)
            })?;
        let toks: Vec<String> = match &args.value {
            Value::Str(s) => largs
                .resolve(s, &loc)?
                .split_whitespace()
                .map(String::from)
                .collect(),
            Value::Seq(items) => {
                let mut v = Vec::new();
                for it in items {
                    let t = it.as_str().ok_or_else(|| {
                        Error::parse(format!(
                            "static_transform_publisher args: expected strings or numbers, found {}",
                            it.kind()
                        ))
                        .at(&loc)
                    })?;
                    v.push(largs.resolve(&t, &loc)?);
                }
                v
            }
            _ => {
                return Err(Error::parse(format!(
                    "static_transform_publisher args: expected a string or a list, found {}",
                    args.kind()
                ))
                .at(&loc))
            }
        };
        out.edges.push(parse_stp_args(
            &toks,
            &loc,
            LAUNCH_YAML.id,
            "node ",
            &mut out.warnings,
        )?);
    }
    if let (true, Some((line, why))) = (out.edges.is_empty(), skipped) {
        return Err(Error::parse(format!(
            "every static_transform_publisher node is switched off (the first by {why}): expected at least one that runs; set the arg it depends on with --arg NAME=VALUE"
        ))
        .at_line(line, None));
    }
    Ok(out)
}

/// Command lines saved as text.
pub fn parse_commands(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let _ = opts;
    let mut out = Parsed::default();
    let mut joined = String::new();
    let mut start_line = 0;
    // Length of the logical line's first physical line: columns are counted
    // there.
    let mut first_len = usize::MAX;
    for (i, raw) in text.lines().enumerate() {
        if joined.is_empty() {
            start_line = i + 1;
            first_len = usize::MAX;
        }
        let l = raw.trim_end();
        if let Some(x) = l.strip_suffix('\\') {
            if joined.is_empty() {
                first_len = x.len();
            }
            joined.push_str(x);
            joined.push(' ');
            continue;
        }
        joined.push_str(l);
        let line = std::mem::take(&mut joined);
        // One edge per publisher command: `&`, `;`, `&&`, `|`, subshells and
        // comments split the line (see `shell`).
        for cmd in super::shell::commands(&line) {
            let words = &cmd.words;
            let Some(pos) = words.iter().position(|w| w == "static_transform_publisher") else {
                continue;
            };
            let col = if cmd.offset < first_len {
                line[..cmd.offset].chars().count() + 1
            } else {
                1
            };
            let loc = Location::at(path, start_line, Some(col));
            out.edges.push(parse_stp_args(
                &words[pos + 1..],
                &loc,
                STATIC_TF_COMMANDS.id,
                "",
                &mut out.warnings,
            )?);
        }
    }
    Ok(out)
}

/// Whether XML text is a launch file, and whether it holds static transform
/// publishers or a LIO-Livox extrinsic.
fn launch_xml(i: &Input) -> Option<(bool, bool)> {
    (xml::candidate(i) && i.contains("<launch")).then(|| {
        (
            i.contains("static_transform_publisher"),
            i.contains("Extrinsic_Tlb"),
        )
    })
}

/// A file named like a launch file (`.launch`, `.launch.py`, `.launch.xml`,
/// `.launch.yaml`) that names neither `static_transform_publisher` nor
/// `Extrinsic_Tlb` holds no calibration: most launch files of a ROS package
/// start nodes. `false` when it cannot be read within `max_size` bytes (the
/// reader then says why).
pub(crate) fn holds_no_calibration(path: &Path, max_size: u64) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let launch = name.ends_with(".launch")
        || [".launch.py", ".launch.xml", ".launch.yaml", ".launch.yml"]
            .iter()
            .any(|x| name.ends_with(x));
    if !launch {
        return false;
    }
    crate::input::read_file(path, max_size).is_ok_and(|b| {
        let t = String::from_utf8_lossy(&b);
        !t.contains("static_transform_publisher") && !t.contains("Extrinsic_Tlb")
    })
}

/// ROS launch XML.
pub const LAUNCH_XML: FormatSpec = FormatSpec {
    id: "launch-xml",
    description: "ROS 1 / ROS 2 launch XML: static_transform_publisher nodes (x y z yaw pitch roll | x y z qx qy qz qw, or ROS 2 --flags): child pose in parent",
    extensions: &[],
    walk: &[".launch", ".xml"],
    magic: &[],
    sniff: |i| match launch_xml(i)? {
        (true, _) => Some(Confidence::Certain),
        (false, true) => None,
        (false, false) => Some(Confidence::Document),
    },
    parse: |i, o| parse_launch_xml(i.text()?, i.path(), o),
    checked: true,
};

/// LIO-Livox launch files with `Extrinsic_Tlb`.
pub const LIO_LIVOX_LAUNCH: FormatSpec = FormatSpec {
    id: "lio-livox-launch",
    description: "LIO-Livox launch `<rosparam param=\"Extrinsic_Tlb\">` 4x4 row-major (T_lb): the IMU pose in the LiDAR frame, as PoseEstimation.cpp composes it (T_wb = T_wl T_lb), edge lidar -> imu",
    extensions: &[],
    walk: &[".launch"],
    magic: &[],
    sniff: |i| matches!(launch_xml(i)?, (false, true)).then_some(Confidence::Certain),
    parse: |i, o| parse_lio_livox(i.text()?, i.path(), o),
    checked: true,
};

/// ROS 2 launch YAML.
pub const LAUNCH_YAML: FormatSpec = FormatSpec {
    id: "launch-yaml",
    description: "ROS 2 launch YAML: static_transform_publisher nodes with literal args; child pose in parent",
    extensions: &["launch.yaml", "launch.yml"],
    walk: &[".yaml", ".yml"],
    magic: &[],
    sniff: |i| {
        let node = i.has_key("exec") || i.has_key("- node") || i.has_key("node");
        (node && i.contains("static_transform_publisher")).then_some(Confidence::Keys)
    },
    parse: |i, o| parse_launch_yaml(i.text()?, i.path(), o),
    checked: true,
};

/// Command lines saved as text.
pub const STATIC_TF_COMMANDS: FormatSpec = FormatSpec {
    id: "static-tf-commands",
    description: "command lines saved as text or a shell script (rosrun tf / ros2 run tf2_ros static_transform_publisher ..., with `&`, `;`, `&&`, subshells, `\\` continuations, comments): child pose in parent, one edge per publisher command",
    extensions: &["sh", "bash"],
    // Not `.sh`: a directory walk (`audit check DIR`) would read every
    // script of a repository, most of which publish nothing.
    walk: &[".txt"],
    magic: &[],
    sniff: |i| {
        let commands = i.text().unwrap_or("").lines().any(|l| {
            let l = l.trim_start();
            !l.starts_with('#')
                && !l.starts_with('%')
                && (l.contains("rosrun") || l.contains("ros2 run"))
                && l.contains("static_transform_publisher")
        });
        (commands && !i.contains("!!opencv-matrix")).then_some(Confidence::Commands)
    },
    parse: |i, o| parse_commands(i.text()?, i.path(), o),
    checked: true,
};
