//! The document, read in one pass (issue 29): what each item of
//! [`super::stream::read`] adds, and at the end which error, if any, the file gets.
//!
//! The text is read once, so an error met early is kept, not raised: a later
//! part of the file may hold one that comes first in the order the checks
//! have always been made (the XML anywhere, the root element, un-expanded
//! xacro, the version, the links in file order, then the joints in file
//! order, then the tree), and a joint may name a link declared after it
//! ([`PendingLink`]). Once an error is certain to be reported (or one that
//! comes before it), the items it makes irrelevant are no longer read.

use super::joints::Builder;
use super::read::{self, Context, JointRaw, Links, PendingLink, Version};
use super::stream::{El, Item, JointEl, XacroAt};
use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::source::LineIndex;
use crate::formats::spec::{LoadOptions, Loaded};
use crate::formats::xacro::markers as xacro;
use crate::frames::{Edge, FrameDecl};
use foldhash::{HashMap, HashMapExt};
use std::borrow::Cow;
use std::collections::VecDeque;
use std::path::Path;

pub(super) struct Document<'c, 'a> {
    idx: &'c LineIndex<'a>,
    path: &'c Path,
    opts: &'c LoadOptions,
    root_error: Option<Error>,
    xacro: Option<XacroAt<'a>>,
    version: Option<Result<Version>>,
    /// Top-level `<link>`s in file order: name and start offset.
    decls: Vec<(Cow<'a, str>, usize)>,
    links: Links<'a>,
    link_error: Option<Error>,
    /// Joint names and their lines (duplicates, mimic masters).
    names: HashMap<Cow<'a, str>, usize>,
    builder: Builder<'c>,
    warnings: Vec<Warning>,
    joints_read: usize,
    /// The first joint that could not be read: its index and error.
    joint_error: Option<(usize, Error)>,
    /// Links named by joints before any `<link>` declared them, oldest
    /// first (dropped from the front as they are declared).
    pending: VecDeque<PendingLink<'a>>,
}

impl<'c, 'a> Document<'c, 'a> {
    pub(super) fn new(
        text: &'a str,
        idx: &'c LineIndex<'a>,
        path: &'c Path,
        opts: &'c LoadOptions,
        format: &'static str,
    ) -> Self {
        // Capacities from a count of the tags (a vector or map grown by
        // doubling would hold up to twice the memory per link: issue 12).
        let (links, joints) = (tags(text, b"<link"), tags(text, b"<joint"));
        Document {
            idx,
            path,
            opts,
            root_error: None,
            xacro: None,
            version: None,
            decls: Vec::with_capacity(links),
            links: Links::with_capacity(links),
            link_error: None,
            names: HashMap::with_capacity(joints),
            builder: Builder::new(opts, joints, format),
            warnings: Vec::new(),
            joints_read: 0,
            joint_error: None,
            pending: VecDeque::new(),
        }
    }

    /// An error is certain that comes before any link's or joint's.
    fn settled(&self) -> bool {
        self.root_error.is_some()
            || self.xacro.is_some()
            || matches!(self.version, Some(Err(_)))
            || self.link_error.is_some()
    }

    /// The next item of the pass.
    pub(super) fn add(&mut self, item: Item<'_, 'a>) {
        match item {
            Item::Root(el) => match check_root(self.idx, &el) {
                Err(e) => self.root_error = Some(e),
                Ok(()) => self.version = Some(read::version(self.idx, &el, self.opts)),
            },
            Item::Xacro(x) => self.xacro = Some(x),
            Item::Link(name, start) if !self.settled() => self.link(name, start),
            Item::Joint(j) if !self.settled() && self.joint_error.is_none() => self.joint(&j),
            Item::Link(..) | Item::Joint(_) => {}
        }
    }

    fn link(&mut self, name: Option<Cow<'a, str>>, start: usize) {
        let at = |msg: String| {
            let (l, c) = self.idx.pos(start);
            Error::parse(msg).at_line(l, Some(c))
        };
        let Some(name) = name else {
            self.link_error = Some(at("<link> without a name: expected name=\"...\"".into()));
            return;
        };
        if let Some(prev) = self.links.get(name.as_ref()) {
            let (pl, _) = self.idx.pos(*prev);
            self.link_error = Some(at(format!(
                "link '{name}' declared twice: expected unique link names, first at line {pl}"
            )));
            return;
        }
        self.links.insert(name.clone(), start);
        self.decls.push((name, start));
        while let Some(p) = self.pending.front() {
            if !self.links.contains_key(p.link.as_ref()) {
                break;
            }
            self.pending.pop_front();
        }
    }

    fn joint(&mut self, j: &JointEl<'_, 'a>) {
        let k = self.joints_read;
        self.joints_read += 1;
        let name = j.el.attribute("name").map(|a| a.value.clone());
        if let Some(&prev) = name.as_ref().and_then(|n| self.names.get(n.as_ref())) {
            let msg = format!(
                "joint '{}' declared twice: expected unique joint names, first at line {}",
                name.as_deref().unwrap_or(""),
                prev
            );
            self.joint_error = Some((k, read::err_at(self.idx, &j.el, msg)));
            return;
        }
        // Joints are read only once the root gave the version.
        let Some(Ok(version)) = self.version else {
            return;
        };
        let cx = Context {
            idx: self.idx,
            path: self.path,
            version,
            links: &self.links,
        };
        match read::joint(&cx, j, k, &mut self.pending, &mut self.warnings) {
            Err(e) => self.joint_error = Some((k, e)),
            Ok(raw) => self.push(name, raw),
        }
    }

    fn push(&mut self, name: Option<Cow<'a, str>>, raw: JointRaw) {
        if let Some(n) = name {
            self.names.insert(n, raw.loc.line.unwrap_or(0));
        }
        self.builder.push(raw);
    }

    /// The file's edges, frames and warnings, or its first error.
    pub(super) fn finish(self) -> Result<Loaded> {
        let idx = self.idx;
        if let Some(e) = self.root_error {
            return Err(e);
        }
        refuse_xacro(idx, self.xacro.as_ref(), self.path)?;
        if let Some(Err(e)) = self.version {
            return Err(e);
        }
        if let Some(e) = self.link_error {
            return Err(e);
        }
        let undeclared = self
            .pending
            .iter()
            .find(|p| !self.links.contains_key(p.link.as_ref()));
        match (undeclared, self.joint_error) {
            (Some(p), Some((k, _))) if p.joint <= k => return Err(p.error(idx)),
            (Some(p), None) => return Err(p.error(idx)),
            (_, Some((_, e))) => return Err(e),
            (None, None) => {}
        }
        let (edges, edge_warnings) = self.builder.finish(&self.names)?;
        drop((self.names, self.links, self.pending));
        let mut warnings = self.warnings;
        warnings.extend(edge_warnings);
        // The joints must form a tree: checked now, with the file's positions,
        // without a second copy of the edges.
        crate::frames::check_tree(&edges)?;
        let (frames, roots) = link_frames(idx, &self.decls, &edges, self.path);
        drop(self.decls);
        root_links(&roots, self.path, &mut warnings);
        Ok(Loaded {
            edges,
            frames,
            warnings,
            ..Loaded::default()
        })
    }
}

/// How many times `tag` occurs in `text` (a capacity hint: it also counts
/// tags in comments and nested elements).
fn tags(text: &str, tag: &[u8]) -> usize {
    memchr::memmem::find_iter(text.as_bytes(), tag).count()
}

/// The links no joint names, as declared frames (a link a joint names is
/// known to the graph through its edge: issue 12, memory per link), and the
/// links without a parent joint with their lines, both in file order.
fn link_frames(
    idx: &LineIndex,
    links: &[(Cow<'_, str>, usize)],
    edges: &[Edge],
    path: &Path,
) -> (Vec<FrameDecl>, Vec<(String, usize)>) {
    const CHILD: u8 = 1;
    const PARENT: u8 = 2;
    let mut named: HashMap<&str, u8> = HashMap::with_capacity(edges.len() + 1);
    for e in edges {
        *named.entry(e.parent.as_str()).or_default() |= PARENT;
        *named.entry(e.child.as_str()).or_default() |= CHILD;
    }
    let (mut frames, mut roots) = (Vec::new(), Vec::new());
    for (name, start) in links {
        let flags = named.get(name.as_ref()).copied().unwrap_or(0);
        if flags & CHILD != 0 {
            continue;
        }
        let (l, c) = idx.pos(*start);
        roots.push((name.to_string(), l));
        if flags == 0 {
            frames.push(FrameDecl {
                name: name.to_string(),
                location: Location::at(path, l, Some(c)),
            });
        }
    }
    (frames, roots)
}

/// More than one link without a parent joint: ROS refuses the file.
fn root_links(roots: &[(String, usize)], path: &Path, warnings: &mut Vec<Warning>) {
    if roots.len() < 2 {
        return;
    }
    let names: Vec<String> = roots
        .iter()
        .map(|(name, line)| format!("'{name}' (line {line})"))
        .collect();
    warnings.push(
        Warning::new(
            Code::RefusedByRos,
            format!(
                "{} links have no parent joint: {}; ROS (urdfdom) refuses a URDF with more than one root link (\"Two root links found\"); each is listed as its own tree and only links joined by joints can be audited",
                roots.len(),
                names.join(", ")
            ),
        )
        .at(&Location::file(path)),
    );
}

/// The root element must be `<robot>`; an `<sdf>` root gets its own advice.
fn check_root(idx: &LineIndex, root: &El) -> Result<()> {
    let (rl, rc) = idx.pos(root.start);
    match root.name {
        "robot" if root.attr("name").is_none() => Err(Error::parse(
            "<robot> without a name: expected <robot name=\"...\"> (ROS refuses a robot without a name)",
        )
        .at_line(rl, Some(rc))),
        "robot" => Ok(()),
        "sdf" => Err(Error::parse(
            "root element is <sdf>: this is an SDF (Gazebo) file, expected a URDF <robot>; convert it to URDF first",
        )
        .at_line(rl, Some(rc))),
        other => Err(Error::parse(format!(
            "root element is <{other}>: expected a URDF <robot>"
        ))
        .at_line(rl, Some(rc))),
    }
}

/// Un-expanded xacro: namespace, elements or `${...}` / `$(...)` in
/// attributes (the first such element, noted by [`super::stream::read`]).
fn refuse_xacro(idx: &LineIndex, first: Option<&XacroAt>, path: &Path) -> Result<()> {
    let Some(n) = first else { return Ok(()) };
    let (l, c) = idx.pos(n.start);
    Err(Error::parse(format!(
        "this file holds un-expanded xacro (<{}{}>), not URDF: {}",
        if n.xacro_ns { "xacro:" } else { "" },
        n.name,
        xacro::advice(path)
    ))
    .at_line(l, Some(c)))
}
