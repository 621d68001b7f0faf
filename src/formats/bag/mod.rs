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

pub mod db3;
pub mod decode;
pub mod mcap_file;
pub mod ros1;

use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::{check_metres, locate_warnings, urdf, Edge, LoadOptions, Loaded};
use crate::frames::transforms_agree;
use crate::geometry::se3::{QuatOrder, Transform};
use crate::tolerances::{
    BAG_PROGRESS_MIN_BYTES, MAX_BAG_DECOMPRESSED_BYTES, MAX_BAG_METADATA_BYTES,
    MAX_BAG_RECORD_BYTES, MAX_TRANSLATION_M,
};
use decode::{Encoding, TfRecord};
use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};

/// `Provenance::format` of the transforms read from a bag.
pub const FORMAT: &str = "bag";

/// Which topics to read.
#[derive(Debug, Clone, PartialEq)]
pub struct BagOptions {
    /// Static transform topics (`tf2_msgs/TFMessage`): default `/tf_static`.
    pub static_topics: Vec<String>,
    /// Dynamic transform topics whose constant transforms are kept: default none
    /// (`/tf` on request).
    pub tf_topics: Vec<String>,
    /// Robot description topics (`std_msgs/String` with a URDF): default
    /// `/robot_description`.
    pub description_topics: Vec<String>,
    /// ROS 2 parameter event topics (`rcl_interfaces/msg/ParameterEvent`),
    /// searched for a string parameter `robot_description` (the way
    /// `robot_state_publisher` holds it): default `/parameter_events`.
    pub parameter_topics: Vec<String>,
}

impl Default for BagOptions {
    fn default() -> Self {
        BagOptions {
            static_topics: vec!["/tf_static".into()],
            tf_topics: Vec::new(),
            description_topics: vec!["/robot_description".into()],
            parameter_topics: vec!["/parameter_events".into()],
        }
    }
}

/// One message of a wanted topic, as a container yields it.
#[derive(Debug, Clone)]
pub struct RawMessage {
    /// The topic it was recorded on.
    pub topic: String,
    /// The message type as the container names it (`tf2_msgs/msg/TFMessage`,
    /// `tf2_msgs/TFMessage`); empty when it names none.
    pub type_name: String,
    /// How its bytes are serialised.
    pub encoding: Encoding,
    /// Log (receive) time, ns since the epoch.
    pub time_ns: u64,
    /// The serialised message.
    pub data: Vec<u8>,
    /// The file it was read from.
    pub file: PathBuf,
    /// Where in the file: `chunk at byte N`, `messages row id N`.
    pub place: String,
}

/// What a container yields: every topic it has, and the wanted messages.
#[derive(Debug, Clone, Default)]
pub struct Contents {
    /// Every topic the container holds.
    pub topics: Vec<String>,
    /// The messages of the wanted topics.
    pub messages: Vec<RawMessage>,
}

/// A one-line progress indicator on stderr, shown only on a terminal and for
/// reads of at least [`BAG_PROGRESS_MIN_BYTES`]; erased when dropped.
pub struct Progress {
    label: String,
    total: u64,
    on: bool,
    last: Option<u64>,
}

impl Progress {
    /// A progress line for reading `total` bytes of `path`.
    pub fn new(path: &Path, total: u64) -> Self {
        use std::io::IsTerminal;
        Progress {
            label: path.display().to_string(),
            total,
            on: total >= BAG_PROGRESS_MIN_BYTES && std::io::stderr().is_terminal(),
            last: None,
        }
    }

    /// `done` of the `total` bytes have been read.
    pub fn update(&mut self, done: u64) {
        if !self.on {
            return;
        }
        let pct = done.min(self.total) * 100 / self.total.max(1);
        if self.last != Some(pct) {
            self.last = Some(pct);
            eprint!(
                "\rreading {}: {pct:3}% of {} MiB",
                self.label,
                self.total >> 20
            );
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        if self.last.is_some() {
            eprint!("\r\x1b[K");
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Container {
    Mcap,
    Db3,
    Ros1,
    Folder,
}

fn magic(path: &Path) -> Option<Container> {
    let mut head = [0u8; 16];
    // Regular files only: opening a FIFO to sniff it would block (issue 12).
    let mut f = crate::input::open_regular(path).ok()?;
    let n = f.read(&mut head).ok()?;
    let head = &head[..n];
    if head.starts_with(mcap_file::MAGIC) {
        Some(Container::Mcap)
    } else if head.starts_with(db3::MAGIC) {
        Some(Container::Db3)
    } else if head.starts_with(b"#ROSBAG") {
        Some(Container::Ros1)
    } else {
        None
    }
}

fn container(path: &Path) -> Option<Container> {
    if path.is_dir() {
        return path
            .join("metadata.yaml")
            .is_file()
            .then_some(Container::Folder);
    }
    if let Some(c) = magic(path) {
        return Some(c);
    }
    let ext = path.extension()?.to_string_lossy().to_ascii_lowercase();
    match ext.as_str() {
        "mcap" => Some(Container::Mcap),
        "db3" => Some(Container::Db3),
        "bag" => Some(Container::Ros1),
        _ => None,
    }
}

/// Whether `path` is a bag: a `.mcap`, `.db3` or `.bag` file, a file starting
/// with one of their magic bytes, or a folder holding `metadata.yaml`.
pub fn is_bag(path: &Path) -> bool {
    container(path).is_some()
}

/// Read a bag's transform and description topics as `opts.bag` chooses
/// (default `/tf_static` and `/robot_description`; see the module docs).
pub fn load(path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    load_with(path, opts, &opts.bag)
}

/// [`load`] with the topics chosen by `bag`.
pub fn load_with(path: &Path, opts: &LoadOptions, bag: &BagOptions) -> Result<Loaded> {
    let wanted = |t: &str| {
        bag.static_topics.iter().any(|w| w == t)
            || bag.tf_topics.iter().any(|w| w == t)
            || bag.description_topics.iter().any(|w| w == t)
            || bag.parameter_topics.iter().any(|w| w == t)
    };
    let contents = read_container(path, &wanted)?;
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
    let mut out = Loaded::default();
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

fn read_container(path: &Path, wanted: &dyn Fn(&str) -> bool) -> Result<Contents> {
    match container(path) {
        Some(Container::Mcap) => mcap_file::read(path, wanted),
        Some(Container::Db3) => db3::read(path, wanted),
        Some(Container::Ros1) => ros1::read(path, wanted),
        Some(Container::Folder) => read_folder(path, wanted),
        None => Err(Error::parse(
            "expected a bag (.mcap, .db3, .bag, or a rosbag2 folder with metadata.yaml), found none of them",
        )
        .in_file(path)),
    }
}

#[derive(serde::Deserialize)]
struct Metadata {
    rosbag2_bagfile_information: BagInfo,
}

#[derive(serde::Deserialize)]
struct BagInfo {
    #[serde(default)]
    relative_file_paths: Vec<String>,
    #[serde(default)]
    compression_mode: String,
    #[serde(default)]
    compression_format: String,
}

/// rosbag2's `compression_mode` (rosbag2 writes `FILE`/`MESSAGE`, rosbags
/// `file`/`message`).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Compression {
    None,
    File,
    Message,
}

impl BagInfo {
    fn compression(&self, meta_path: &Path) -> Result<Compression> {
        let mode = match self.compression_mode.to_ascii_lowercase().as_str() {
            "" | "none" => return Ok(Compression::None),
            "file" => Compression::File,
            "message" => Compression::Message,
            other => {
                return Err(Error::parse(format!(
                    "rosbag2 metadata: compression_mode `{other}`: expected none, file or message"
                ))
                .in_file(meta_path))
            }
        };
        if !self.compression_format.eq_ignore_ascii_case("zstd") {
            return Err(Error::parse(format!(
                "rosbag2 metadata: compression_format `{}`: expected zstd (the only format rosbag2 ships)",
                self.compression_format
            ))
            .in_file(meta_path));
        }
        Ok(mode)
    }
}

/// A `compression_mode: FILE` split decompressed into a temporary file with
/// the inner extension (`x.db3.zstd` -> `x.db3`), bounded by
/// [`MAX_BAG_DECOMPRESSED_BYTES`]. The file is deleted when the guard drops.
fn decompress_split(f: &Path) -> Result<tempfile::TempPath> {
    let input = crate::input::open_regular(f)?;
    let inner = f.file_stem().map(Path::new).and_then(|s| s.extension());
    let suffix = format!(
        ".{}",
        inner.map(|e| e.to_string_lossy()).unwrap_or_default()
    );
    let mut tmp = tempfile::Builder::new()
        .prefix("audit-bag-")
        .suffix(&suffix)
        .tempfile()
        .map_err(|e| Error::io(Path::new("temporary file"), &e))?;
    let mut dec = zstd::stream::read::Decoder::new(input)
        .map_err(|e| Error::parse(format!("zstd: {e}")).in_file(f))?;
    let n = std::io::copy(
        &mut (&mut dec).take(MAX_BAG_DECOMPRESSED_BYTES + 1),
        tmp.as_file_mut(),
    )
    .map_err(|e| {
        Error::parse(format!(
            "expected a zstd-compressed rosbag2 file (compression_mode file): {e}"
        ))
        .in_file(f)
    })?;
    if n > MAX_BAG_DECOMPRESSED_BYTES {
        return Err(Error::limit(format!(
            "decompresses to more than {MAX_BAG_DECOMPRESSED_BYTES} bytes: expected a rosbag2 split of a few GiB"
        ))
        .in_file(f));
    }
    Ok(tmp.into_temp_path())
}

/// `compression_mode: MESSAGE`: each message's bytes are one zstd frame.
fn decompress_messages(c: &mut Contents) -> Result<()> {
    for m in &mut c.messages {
        let mut out = Vec::new();
        zstd::stream::read::Decoder::new(m.data.as_slice())
            .and_then(|d| {
                d.take(MAX_BAG_RECORD_BYTES as u64 + 1)
                    .read_to_end(&mut out)
            })
            .map_err(|e| {
                Error::parse(format!(
                    "{} message ({}): expected zstd-compressed bytes (compression_mode message): {e}",
                    m.topic, m.place
                ))
                .in_file(&m.file)
            })?;
        if out.len() > MAX_BAG_RECORD_BYTES {
            return Err(Error::limit(format!(
                "{} message ({}) decompresses to more than {MAX_BAG_RECORD_BYTES} bytes",
                m.topic, m.place
            ))
            .in_file(&m.file));
        }
        m.data = out;
    }
    Ok(())
}

/// A rosbag2 folder: the files its `metadata.yaml` lists, read in order.
fn read_folder(dir: &Path, wanted: &dyn Fn(&str) -> bool) -> Result<Contents> {
    let meta_path = dir.join("metadata.yaml");
    let size = std::fs::metadata(&meta_path)
        .map_err(|e| Error::io(&meta_path, &e))?
        .len();
    if size > MAX_BAG_METADATA_BYTES {
        return Err(Error::limit(format!(
            "metadata.yaml is {size} bytes: expected at most {MAX_BAG_METADATA_BYTES}"
        ))
        .in_file(&meta_path));
    }
    let text = std::fs::read_to_string(&meta_path).map_err(|e| Error::io(&meta_path, &e))?;
    let meta: Metadata = serde_saphyr::from_str(&text).map_err(|e| {
        Error::parse(format!(
            "rosbag2 metadata: expected `rosbag2_bagfile_information` with `relative_file_paths`: {e}"
        ))
        .in_file(&meta_path)
    })?;
    let info = meta.rosbag2_bagfile_information;
    if info.relative_file_paths.is_empty() {
        return Err(Error::parse(
            "rosbag2 metadata: `relative_file_paths` is empty: expected the bag's files",
        )
        .in_file(&meta_path));
    }
    let compression = info.compression(&meta_path)?;
    let mut out = Contents::default();
    for rel in &info.relative_file_paths {
        let f = dir.join(rel);
        // FILE mode: a split that is not itself a container is decompressed.
        let tmp = match compression {
            Compression::File if f.is_file() && magic(&f).is_none() => Some(decompress_split(&f)?),
            _ => None,
        };
        let read_from = tmp.as_deref().unwrap_or(&f);
        let mut c = match container(read_from) {
            Some(Container::Mcap) => mcap_file::read(read_from, wanted)?,
            Some(Container::Db3) => db3::read(read_from, wanted)?,
            _ => {
                return Err(Error::parse(format!(
                    "rosbag2 file {rel}: expected an .mcap or .db3 file{}, found {}",
                    if compression == Compression::File {
                        " (zstd-compressed)"
                    } else {
                        ""
                    },
                    if f.exists() {
                        "neither"
                    } else {
                        "no such file"
                    }
                ))
                .in_file(&meta_path))
            }
        };
        if tmp.is_some() {
            for m in &mut c.messages {
                m.file = f.clone();
                m.place = format!("{} of the decompressed file", m.place);
            }
        }
        if compression == Compression::Message {
            decompress_messages(&mut c)?;
        }
        for t in c.topics {
            if !out.topics.contains(&t) {
                out.topics.push(t);
            }
        }
        out.messages.extend(c.messages);
    }
    Ok(out)
}

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
) -> Result<Option<Loaded>> {
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
    desc: Loaded,
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
