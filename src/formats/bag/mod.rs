//! Bags: the transforms a robot ran with, as recorded.
//!
//! Reads `/tf_static` (`tf2_msgs/TFMessage`), on request `/tf`, and
//! `/robot_description` (`std_msgs/String` holding a URDF) from ROS 2 bags
//! (MCAP files; rosbag2 sqlite3 `.db3` files; a rosbag2 folder with its
//! `metadata.yaml`, also zstd-compressed per file or per message) and ROS 1
//! `.bag` files (format 2.0). Each container reader
//! uses the container's index to read only the wanted topics
//! ([`mcap_file`], [`db3`], [`ros1`]); [`decode`] turns CDR and ROS 1 messages
//! into transforms and strings.
//!
//! Meaning: each `TransformStamped` is an edge `header.frame_id ->
//! child_frame_id`, the child's pose in the parent (`p_parent = R p_child + d`,
//! quaternion x y z w), as tf2 reads it. Leading `/` (ROS 1 `tf_prefix` style)
//! is dropped from frame names. A bag carries the whole tf tree: a transform
//! with a translation beyond `MAX_TRANSLATION_M` (a geodetic `utm -> map`) is
//! left out with an `ignored` warning instead of refusing the bag.
//!
//! Several messages: messages of a topic are taken in log-time order (ties in
//! file order). For `/tf_static` the latest transform per child frame wins, as
//! in tf2's static buffer; an earlier one that disagrees (another parent, or
//! beyond the duplicate-edge tolerances) is reported as an `ignored` warning
//! naming both messages. `/tf` (only when asked, [`BagOptions::tf_topics`]) is
//! dynamic: a child whose transform never changes over the bag becomes an edge;
//! one that moves is reported (`ignored`) and left out; a child already on
//! `/tf_static` keeps its static transform.
//!
//! `/robot_description`: the latest message, or the latest ROS 2
//! `/parameter_events` message that sets the string parameter
//! `robot_description` (as `robot_state_publisher` holds it), is parsed with
//! [`crate::formats::urdf::parse`]. Its fixed joints are what
//! `robot_state_publisher` puts on `/tf_static`, so a URDF edge whose child is
//! also on `/tf_static` is dropped; when the two disagree the `/tf_static` one
//! is kept (it is what ran) with an `ignored` warning.
//!
//! Provenance: `Location` names the bag file (the `.db3`/`.mcap` inside a
//! folder); `Provenance::key` names the topic, the message index within the
//! topic (0-based, log-time order), its log time in seconds, where in the file
//! it was (chunk offset or row id) and the entry (`transforms[i]`, or the URDF
//! joint and its line in the description). `Provenance::format` is `bag` for
//! transforms and `urdf` for the description's joints.

mod container;
mod contents;
mod db3;
pub mod decode;
mod folder;
mod inflate;
mod kind;
mod mcap_file;
pub mod pointcloud2;
mod progress;
mod ros1;

pub use crate::formats::spec::BagOptions;
pub use contents::{Contents, Flow, Listing, RawMessage, TopicInfo};
pub use inflate::BagLimits;
pub use progress::Progress;

use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::spec::{
    check_metres, locate_warnings, Confidence, FormatSpec, Input, LoadOptions, Parsed,
};
use crate::formats::urdf;
use crate::frames::{transforms_agree, Edge};
use crate::geometry::se3::{QuatOrder, Transform};
use crate::tolerances::MAX_TRANSLATION_M;
use decode::{Encoding, TfRecord};
use std::collections::BTreeMap;
use std::path::Path;

/// `Provenance::format` of the transforms read from a bag (and the format's id).
pub const FORMAT: &str = "bag";

/// Bags: MCAP, rosbag2 (`.db3`, folders), ROS 1.
pub const SPEC: FormatSpec = FormatSpec {
    id: FORMAT,
    description: "ROS bags (MCAP, rosbag2 .db3 or folder with metadata.yaml, ROS 1 .bag), read through their index: /tf_static (child_frame_id pose in header.frame_id, the latest per child), on request /tf transforms that never change, and the URDF on /robot_description",
    extensions: &["bag", "mcap", "db3"],
    walk: &[".bag", ".db3", ".mcap"],
    magic: kind::MAGIC,
    sniff: |i| i.folder_holds("metadata.yaml").then_some(Confidence::Certain),
    parse: |i, o| {
        refuse_invert(i.path(), o)?;
        read(i, o, &o.bag)
    },
    // The common checks (names, translations, --joint) as for every format;
    // `--invert` is refused above, never applied.
    checked: true,
};

/// `--invert` says a file stores the pose of the parent in the child. A
/// bag's transforms are tf2's, the child's pose in the parent, by
/// definition: inverting them would be a silent wrong answer, so a bag with
/// `--invert` is refused by name.
fn refuse_invert(path: &Path, o: &LoadOptions) -> Result<()> {
    if o.invert {
        return Err(Error::usage(
            "--invert: a bag's transforms are tf2's (the child frame's pose in header.frame_id), never stored inverted; read the bag without --invert (and the files that need it in a separate command)",
        )
        .in_file(path));
    }
    Ok(())
}

/// Whether `path` is a bag: a `.mcap`, `.db3` or `.bag` file, a file starting
/// with one of their magic bytes, or a folder holding `metadata.yaml`.
pub fn is_bag(path: &Path) -> bool {
    kind::container_at(path).is_some()
}

/// Read a bag's transform and description topics as `opts.bag` chooses
/// (default `/tf_static` and `/robot_description`; see the module docs).
pub fn load(path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    load_with(path, opts, &opts.bag)
}

/// [`load`] with the topics chosen by `bag`.
pub fn load_with(path: &Path, opts: &LoadOptions, bag: &BagOptions) -> Result<Parsed> {
    read(&Input::open(path, opts.max_file_size)?, opts, bag)
}

/// Every topic of the bag at `path` with its type and, where the index
/// counts them, its message count; nothing else is read from an indexed
/// bag (one without an index is read through to list its topics). A damaged
/// bag lists the topics of the messages read before the damage (its read
/// will stop there too), or fails when none reads.
pub fn topics(path: &Path) -> Result<Listing> {
    let limits = BagLimits::default();
    let e = match stream(path, &|_| false, limits, &mut |_| Ok(Flow::Continue)) {
        Ok(l) => return Ok(l),
        Err(e) => e,
    };
    let mut seen: Vec<TopicInfo> = Vec::new();
    let mut note = |m: RawMessage| {
        if !seen.iter().any(|t| t.name == m.topic) {
            seen.push(TopicInfo {
                name: m.topic,
                type_name: m.type_name,
                count: None,
            });
        }
        Ok(Flow::Continue)
    };
    let warnings = match stream(path, &|_| true, limits, &mut note) {
        Ok(l) => l.warnings,
        Err(_) => Vec::new(),
    };
    if seen.is_empty() {
        return Err(e);
    }
    seen.sort();
    Ok(Listing {
        topics: seen,
        warnings,
    })
}

/// Hand the messages of the topics `wanted` accepts, from the bag at `path`,
/// to `each` one at a time, in file order (the order the recorder wrote),
/// through the container's index, every decompression within `limits`. A
/// ROS 1 bag without an index is read from the start (a named warning in the
/// listing). On damage (a truncated or corrupt file) the messages before it
/// have been handed out when the error is returned.
pub fn stream(
    path: &Path,
    wanted: &dyn Fn(&str) -> bool,
    limits: BagLimits,
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Listing> {
    let input = Input::open(path, 0)?;
    let ask = contents::Ask {
        wanted,
        limits,
        recover: true,
    };
    container::stream(&input, ask, each)
}

/// The bag `input`, its topics chosen by `bag`.
fn read(input: &Input, opts: &LoadOptions, bag: &BagOptions) -> Result<Parsed> {
    let path = input.path();
    let wanted = |t: &str| {
        bag.static_topics.iter().any(|w| w == t)
            || bag.tf_topics.iter().any(|w| w == t)
            || bag.description_topics.iter().any(|w| w == t)
            || bag.parameter_topics.iter().any(|w| w == t)
    };
    let contents = container::read(input, &wanted)?;
    let mut by_topic: BTreeMap<&str, Vec<&RawMessage>> = BTreeMap::new();
    for m in &contents.messages {
        by_topic.entry(m.topic.as_str()).or_default().push(m);
    }
    for v in by_topic.values_mut() {
        v.sort_by_key(|m| m.time_ns); // stable: ties stay in file order
    }
    let pick = |names: &[String]| -> Vec<Msg> {
        let mut v: Vec<Msg> = Vec::new();
        for n in names {
            if let Some(ms) = by_topic.get(n.as_str()) {
                v.extend(ms.iter().enumerate().map(|(i, m)| Msg { index: i, raw: m }));
            }
        }
        v.sort_by_key(|m| m.raw.time_ns);
        v
    };
    let mut out = Parsed::default();
    let statics = static_transforms(&pick(&bag.static_topics), &mut out.warnings)?;
    let mut edges: Vec<Edge> = statics.values().map(|s| s.edge.clone()).collect();
    edges.extend(constant_transforms(
        &pick(&bag.tf_topics),
        &statics,
        &mut out.warnings,
    )?);
    let texts = description_texts(&pick(&bag.description_topics), &pick(&bag.parameter_topics))?;
    if let Some(desc) = description(&texts, opts, &mut out.warnings)? {
        edges.extend(merge_description(desc, &statics, &mut out.warnings));
    }
    if edges.is_empty() {
        return Err(Error::parse(format!(
            "bag: expected transforms on {} or a URDF on {}, found {} (topics: {})",
            bag.static_topics.join(", "),
            bag.description_topics.join(", "),
            if contents.messages.is_empty() {
                "no message on them"
            } else {
                "no transform"
            },
            if contents.topics.is_empty() {
                "none".to_string()
            } else {
                contents.topics.join(", ")
            }
        ))
        .in_file(path));
    }
    out.edges = edges;
    Ok(out)
}

/// A message with its index within its topic.
#[derive(Clone, Copy)]
struct Msg<'a> {
    index: usize,
    raw: &'a RawMessage,
}

impl Msg<'_> {
    /// `/tf_static message #2 at t=1700000000.000000000 s (chunk at byte 1234)`.
    fn describe(&self) -> String {
        format!(
            "{} message #{} at t={} s ({})",
            self.raw.topic,
            self.index,
            fmt_time(self.raw.time_ns),
            self.raw.place
        )
    }

    fn err(&self, msg: impl std::fmt::Display) -> Error {
        Error::parse(format!("{}: {msg}", self.describe())).in_file(&self.raw.file)
    }

    fn check_type(&self, accepted: &[&str]) -> Result<()> {
        let t = self.raw.type_name.as_str();
        if t.is_empty() || accepted.contains(&t) {
            return Ok(());
        }
        Err(self.err(format!(
            "message type '{t}': expected {}",
            accepted.join(" or ")
        )))
    }
}

fn fmt_time(ns: u64) -> String {
    format!("{}.{:09}", ns / 1_000_000_000, ns % 1_000_000_000)
}

const TF_TYPES: &[&str] = &[
    "tf2_msgs/msg/TFMessage",
    "tf2_msgs/TFMessage",
    "tf/tfMessage",
    "tf/msg/tfMessage",
];
const STRING_TYPES: &[&str] = &["std_msgs/msg/String", "std_msgs/String"];
const PARAMETER_EVENT_TYPES: &[&str] = &["rcl_interfaces/msg/ParameterEvent"];
/// The parameter that holds the URDF in ROS 2 (`robot_state_publisher`).
const DESCRIPTION_PARAMETER: &str = "robot_description";

/// One transform read from a message, with where it came from.
#[derive(Clone)]
struct Seen {
    edge: Edge,
    what: String,
}

/// Decode every transform in `msgs` into an edge (checked like any file's).
fn transforms(msgs: &[Msg], mut each: impl FnMut(Seen) -> Result<()>) -> Result<Vec<Warning>> {
    let mut warnings = Vec::new();
    for m in msgs {
        m.check_type(TF_TYPES)?;
        let recs = decode::tf_message(&m.raw.data, m.raw.encoding)
            .map_err(|e| m.err(format!("tf2_msgs/TFMessage: {e}")))?;
        for (j, r) in recs.into_iter().enumerate() {
            let what = format!("{} transforms[{j}]", m.describe());
            let edge = edge(&r, &what, &m.raw.file, &mut warnings)
                .map_err(|e| m.err(format!("transforms[{j}]: {}", e.message)))?;
            if let Some(edge) = edge {
                each(Seen { edge, what })?;
            }
        }
    }
    Ok(warnings)
}

/// The edge of one transform; `None` (with a warning) for a translation beyond
/// [`MAX_TRANSLATION_M`]: a bag carries the whole tf tree, and a geodetic frame
/// (`utm -> map`, millions of metres) is no sensor extrinsic; refusing it would
/// refuse the bag.
fn edge(
    r: &TfRecord,
    what: &str,
    file: &Path,
    warnings: &mut Vec<Warning>,
) -> Result<Option<Edge>> {
    let parent = r.parent.trim_start_matches('/');
    let child = r.child.trim_start_matches('/');
    let loc = Location::file(file);
    let mut ws = Vec::new();
    let tf = Transform::from_quaternion(r.rotation, QuatOrder::Xyzw, r.translation, &mut ws)?;
    if let Some(x) = r.translation.iter().find(|x| x.abs() > MAX_TRANSLATION_M) {
        warnings.push(Warning::new(
            Code::Ignored,
            format!("{what} {parent} -> {child}: translation component {x:e} m, beyond {MAX_TRANSLATION_M:e} m: not a sensor extrinsic (a geodetic frame?), left out"),
        ).at(&loc));
        return Ok(None);
    }
    let ws: Vec<Warning> = ws
        .into_iter()
        .map(|w| Warning {
            message: format!("{what}: {}", w.message),
            ..w
        })
        .collect();
    check_metres(
        &r.translation,
        &format!("{what} translation"),
        &loc,
        warnings,
    );
    locate_warnings(ws, &loc, warnings);
    Ok(Some(Edge::new(
        parent,
        child,
        tf,
        loc,
        FORMAT,
        format!("{what} {parent} -> {child}"),
    )))
}

/// How far apart two transforms are, for messages.
fn difference(a: &Transform, b: &Transform) -> String {
    let dt = (a.translation() - b.translation()).norm();
    let dr = a.inverse().compose(b).rotation_angle_axis().0;
    format!("{dt:.3e} m and {:.3e} deg apart", dr.to_degrees())
}

fn same(a: &Edge, b: &Edge) -> bool {
    a.parent == b.parent && transforms_agree(&a.transform, &b.transform)
}

/// `/tf_static`: the latest transform per child frame.
fn static_transforms(msgs: &[Msg], warnings: &mut Vec<Warning>) -> Result<BTreeMap<String, Seen>> {
    let mut latest: BTreeMap<String, Seen> = BTreeMap::new();
    let mut ws = Vec::new();
    let decoded = transforms(msgs, |s| {
        if let Some(old) = latest.get(&s.edge.child) {
            if !same(&old.edge, &s.edge) {
                ws.push(superseded(&old.edge, &old.what, &s.edge, &s.what));
            }
        }
        latest.insert(s.edge.child.clone(), s);
        Ok(())
    })?;
    warnings.extend(decoded);
    warnings.extend(ws);
    Ok(latest)
}

fn superseded(old: &Edge, old_what: &str, new: &Edge, new_what: &str) -> Warning {
    let how = if old.parent == new.parent {
        difference(&old.transform, &new.transform)
    } else {
        format!("parent '{}' then '{}'", old.parent, new.parent)
    };
    Warning::new(
        Code::Ignored,
        format!(
            "frame '{}' is set twice with different values ({how}): {old_what} is superseded by {new_what}, which is used (the latest wins, as in tf2)",
            new.child
        ),
    )
    .at(&new.provenance.location)
}

/// Dynamic topics: children whose transform never changes.
fn constant_transforms(
    msgs: &[Msg],
    statics: &BTreeMap<String, Seen>,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<Edge>> {
    let mut first: BTreeMap<String, (Seen, usize, bool)> = BTreeMap::new();
    let ws = transforms(msgs, |s| {
        match first.get_mut(&s.edge.child) {
            Some((f, n, moves)) => {
                *n += 1;
                *moves |= !same(&f.edge, &s.edge);
            }
            None => {
                first.insert(s.edge.child.clone(), (s, 1, false));
            }
        }
        Ok(())
    })?;
    warnings.extend(ws);
    let mut out = Vec::new();
    for (child, (s, n, moves)) in first {
        if statics.contains_key(&child) {
            continue;
        }
        if moves {
            warnings.push(
                Warning::new(
                    Code::Ignored,
                    format!(
                        "frame '{child}' moves (parent '{}', {n} samples, the first {}): not a static transform, left out",
                        s.edge.parent, s.what
                    ),
                )
                .at(&s.edge.provenance.location),
            );
            continue;
        }
        let mut e = s.edge;
        e.provenance.key = format!("{} (constant over {n} samples)", e.provenance.key);
        out.push(e);
    }
    Ok(out)
}

/// A robot description found in the bag, and where.
struct DescriptionText<'a> {
    msg: Msg<'a>,
    what: String,
    text: String,
}

/// Every robot description the bag holds: `std_msgs/String` messages on the
/// description topics and `robot_description` string parameters set in ROS 2
/// parameter events, in log-time order.
fn description_texts<'a>(
    topics: &[Msg<'a>],
    events: &[Msg<'a>],
) -> Result<Vec<DescriptionText<'a>>> {
    let mut out = Vec::new();
    for m in topics {
        m.check_type(STRING_TYPES)?;
        let text = decode::string_message(&m.raw.data, m.raw.encoding)
            .map_err(|e| m.err(format!("std_msgs/String: {e}")))?;
        out.push(DescriptionText {
            msg: *m,
            what: m.describe(),
            text,
        });
    }
    for m in events {
        m.check_type(PARAMETER_EVENT_TYPES)?;
        if m.raw.encoding != Encoding::Cdr {
            return Err(m.err("parameter events: expected CDR (ROS 2), found ROS 1 serialization"));
        }
        let params = decode::parameter_event(&m.raw.data)
            .map_err(|e| m.err(format!("rcl_interfaces/msg/ParameterEvent: {e}")))?;
        for (node, name, text) in params {
            if name == DESCRIPTION_PARAMETER {
                let what = format!("{} (parameter {name} of node {node})", m.describe());
                out.push(DescriptionText {
                    msg: *m,
                    what,
                    text,
                });
            }
        }
    }
    out.sort_by_key(|d| d.msg.raw.time_ns);
    Ok(out)
}

/// The latest robot description, parsed, its edges pointing at the bag.
fn description(
    texts: &[DescriptionText],
    opts: &LoadOptions,
    warnings: &mut Vec<Warning>,
) -> Result<Option<Parsed>> {
    let Some(latest) = texts.last() else {
        return Ok(None);
    };
    let file = Location::file(&latest.msg.raw.file);
    for old in &texts[..texts.len() - 1] {
        if old.text != latest.text {
            warnings.push(
                Warning::new(
                    Code::Ignored,
                    format!("the robot description of {} differs from the latest, {}: the latest is used", old.what, latest.what),
                )
                .at(&file),
            );
        }
    }
    let urdf_opts = LoadOptions {
        invert: false,
        format: None,
        ..opts.clone()
    };
    let what = &latest.what;
    let mut loaded = urdf::parse(&latest.text, &latest.msg.raw.file, &urdf_opts).map_err(|e| {
        let line = e
            .location
            .line
            .map(|l| format!(" (line {l} of the description)"))
            .unwrap_or_default();
        Error::parse(format!("{what}: URDF: {}{line}", e.message)).in_file(&latest.msg.raw.file)
    })?;
    for e in &mut loaded.edges {
        let line = e
            .provenance
            .location
            .line
            .map(|l| format!(", description line {l}"))
            .unwrap_or_default();
        e.provenance.key = format!("{what}: {}{line}", e.provenance.key);
        e.provenance.location = file.clone();
    }
    for w in &mut loaded.warnings {
        let line = w
            .location
            .line
            .map(|l| format!(" (description line {l})"))
            .unwrap_or_default();
        w.message = format!("{what}: {}{line}", w.message);
        w.location = file.clone();
    }
    Ok(Some(loaded))
}

/// The description's edges less those `/tf_static` carries.
fn merge_description(
    desc: Parsed,
    statics: &BTreeMap<String, Seen>,
    warnings: &mut Vec<Warning>,
) -> Vec<Edge> {
    warnings.extend(desc.warnings);
    let mut out = Vec::new();
    for e in desc.edges {
        match statics.get(&e.child) {
            None => out.push(e),
            Some(s) if same(&s.edge, &e) => {}
            Some(s) => warnings.push(
                Warning::new(
                    Code::Ignored,
                    format!(
                        "{} -> {} from {} differs from {} ({}): the /tf_static transform is used (it is what ran)",
                        e.parent,
                        e.child,
                        e.provenance.key,
                        s.what,
                        if e.parent == s.edge.parent { difference(&e.transform, &s.edge.transform) } else { format!("parent '{}' vs '{}'", e.parent, s.edge.parent) }
                    ),
                )
                .at(&s.edge.provenance.location),
            ),
        }
    }
    out
}
