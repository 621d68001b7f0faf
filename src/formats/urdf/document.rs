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
use super::lines::Lines;
use super::names::{JointNames, Links};
use super::read::{self, Context, JointRaw, PendingLink};
use super::stream::err_at;
use super::stream::Attr;
use super::stream::{El, Item, JointEl, XacroAt};
use super::version::{self, Version};
use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::spec::{LoadOptions, Parsed};
use crate::formats::xacro::markers as xacro;
use crate::frames::{Edge, FrameDecl};
use std::collections::VecDeque;
use std::path::Path;
use std::sync::Arc;

pub(super) struct Document<'c, 'a> {
    idx: &'c Lines<'a>,
    path: &'c Path,
    /// `path`, shared by the locations of every joint's edge.
    file: Arc<Path>,
    opts: &'c LoadOptions,
    root_error: Option<Error>,
    /// `<robot name>`: the platform the survey names.
    robot: Option<String>,
    xacro: Option<XacroAt<'a>>,
    version: Option<Result<Version>>,
    /// Top-level `<link>`s in file order (name and start offset), by name.
    links: Links<'a>,
    link_error: Option<Error>,
    /// Joint names and their lines (duplicates, mimic masters).
    names: JointNames<'a>,
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
        idx: &'c Lines<'a>,
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
            file: path.into(),
            opts,
            root_error: None,
            robot: None,
            xacro: None,
            version: None,
            links: Links::with_capacity(text, links),
            link_error: None,
            names: JointNames::with_capacity(text, joints),
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
                Ok(()) => {
                    self.robot = el.attr("name").map(str::to_string);
                    self.version = Some(version::version(self.idx, &el, self.opts));
                }
            },
            Item::Xacro(x) => self.xacro = Some(x),
            Item::Link(name, start) if !self.settled() => self.link(name, start),
            Item::Joint(j) if !self.settled() && self.joint_error.is_none() => self.joint(&j),
            Item::Link(..) | Item::Joint(_) => {}
        }
    }

    fn link(&mut self, name: Option<&Attr<'a>>, start: usize) {
        let at = |msg: String| {
            let (l, c) = self.idx.pos(start);
            Error::parse(msg).at_line(l, Some(c))
        };
        let Some(attr) = name else {
            self.link_error = Some(at("<link> without a name: expected name=\"...\"".into()));
            return;
        };
        let name = attr.value.as_ref();
        if let Some(prev) = self.links.get(name) {
            let (pl, _) = self.idx.pos(prev);
            self.link_error = Some(at(format!(
                "link '{name}' declared twice: expected unique link names, first at line {pl}"
            )));
            return;
        }
        self.links.push(name, attr.raw, start);
        while let Some(p) = self.pending.front() {
            if !self.links.contains(p.link.as_ref()) {
                break;
            }
            self.pending.pop_front();
        }
    }

    fn joint(&mut self, j: &JointEl<'_, 'a>) {
        let k = self.joints_read;
        self.joints_read += 1;
        let name = j.el.attribute("name");
        if let Some(prev) = name.and_then(|a| self.names.get(&a.value)) {
            let msg = format!(
                "joint '{}' declared twice: expected unique joint names, first at line {}",
                name.map_or("", |a| a.value.as_ref()),
                prev
            );
            self.joint_error = Some((k, err_at(self.idx, &j.el, msg)));
            return;
        }
        // Joints are read only once the root gave the version.
        let Some(Ok(version)) = self.version else {
            return;
        };
        let cx = Context {
            idx: self.idx,
            file: &self.file,
            version,
            links: &self.links,
        };
        match read::joint(&cx, j, k, &mut self.pending, &mut self.warnings) {
            Err(e) => self.joint_error = Some((k, e)),
            Ok(raw) => self.push(name, raw),
        }
    }

    fn push(&mut self, name: Option<&Attr<'a>>, raw: JointRaw) {
        if let Some(a) = name {
            self.names.push(&a.value, a.raw, raw.loc.line.unwrap_or(0));
        }
        self.builder.push(raw);
    }

    /// The file's edges, frames and warnings, or its first error.
    pub(super) fn finish(self) -> Result<Parsed> {
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
            .find(|p| !self.links.contains(p.link.as_ref()));
        match (undeclared, self.joint_error) {
            (Some(p), Some((k, _))) if p.joint <= k => return Err(p.error(idx)),
            (Some(p), None) => return Err(p.error(idx)),
            (_, Some((_, e))) => return Err(e),
            (None, None) => {}
        }
        let names = &self.names;
        let (edges, edge_warnings) = self.builder.finish(|n| names.contains(n))?;
        drop((self.names, self.pending));
        let mut warnings = self.warnings;
        warnings.extend(edge_warnings);
        // The links' frames first (no error can come of them), so that the
        // links are dropped before the tree check's tables are built.
        let (frames, roots) = link_frames(idx, &self.links, &edges, self.path);
        drop(self.links);
        root_links(&roots, self.path, &mut warnings);
        // The joints must form a tree: checked now, with the file's positions,
        // without a second copy of the edges.
        crate::frames::check_tree(&edges)?;
        Ok(Parsed {
            edges,
            frames,
            warnings,
            platform: self.robot,
            ..Parsed::default()
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
    idx: &Lines,
    links: &Links,
    edges: &[Edge],
    path: &Path,
) -> (Vec<FrameDecl>, Vec<(String, usize)>) {
    const CHILD: u8 = 1;
    const PARENT: u8 = 2;
    // Every joint names declared links (checked before): a flag per link,
    // found through the links' own index.
    let mut named = vec![0u8; links.len()];
    for e in edges {
        for (name, flag) in [(&e.parent, PARENT), (&e.child, CHILD)] {
            if let Some(i) = links.index_of(name) {
                named[i] |= flag;
            }
        }
    }
    let (mut frames, mut roots) = (Vec::new(), Vec::new());
    for (&flags, (name, start)) in named.iter().zip(links.iter()) {
        if flags & CHILD != 0 {
            continue;
        }
        let (l, c) = idx.pos(start);
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
fn check_root(idx: &Lines, root: &El) -> Result<()> {
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
fn refuse_xacro(idx: &Lines, first: Option<&XacroAt>, path: &Path) -> Result<()> {
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

#[cfg(test)]
mod tests {
    use crate::formats::{xml, LoadOptions};
    use std::path::Path;

    fn load(text: &str) -> crate::diagnostic::Result<crate::formats::Parsed> {
        super::super::parse(text, Path::new("t.urdf"), &LoadOptions::default())
    }

    fn error(text: &str) -> String {
        match load(text) {
            Err(e) => e.to_string(),
            Ok(_) => "accepted".into(),
        }
    }

    /// The error's message and line (`accepted`, no line, when there is none).
    fn line_of(text: &str) -> (String, Option<usize>) {
        match load(text) {
            Err(e) => (e.message.clone(), e.location.line),
            Ok(_) => ("accepted".into(), None),
        }
    }

    fn joint(name: &str, parent: &str, child: &str, xyz: &str) -> String {
        format!(
            "<joint name=\"{name}\" type=\"fixed\"><parent link=\"{parent}\"/><child link=\"{child}\"/><origin xyz=\"{xyz}\"/></joint>\n"
        )
    }

    fn robot(body: &str) -> String {
        format!("<robot name=\"r\">\n{body}</robot>\n")
    }

    /// Links may follow the joints that name them, in any order: the edges
    /// are those of the file written links first.
    #[test]
    fn links_declared_after_their_joints() {
        let (ja, jb) = (
            joint("ja", "a", "b", "1 2 3"),
            joint("jb", "b", "c", "4 5 6"),
        );
        let links = "<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n";
        let first = load(&robot(&format!("{links}{ja}{jb}"))).unwrap();
        for body in [
            format!("{ja}{jb}{links}"),
            format!("<link name=\"a\"/>\n{ja}<link name=\"b\"/>\n{jb}<link name=\"c\"/>\n"),
            format!("{jb}<link name=\"c\"/>\n{ja}<link name=\"b\"/>\n<link name=\"a\"/>\n"),
        ] {
            let l = load(&robot(&body)).unwrap();
            let pairs = |l: &crate::formats::Parsed| {
                let mut v: Vec<_> = l
                    .edges
                    .iter()
                    .map(|e| {
                        (
                            e.parent.clone(),
                            e.child.clone(),
                            *e.transform.translation(),
                        )
                    })
                    .collect();
                v.sort_by(|a, b| a.0.cmp(&b.0));
                v
            };
            assert_eq!(pairs(&l), pairs(&first), "{body}");
        }
    }

    /// The error reported is the first in the order of the checks, wherever
    /// in the file the pass met it.
    #[test]
    fn the_first_error_in_check_order_wins() {
        let links = "<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n";
        let bad_xyz = joint("j1", "a", "b", "1 2");
        let undeclared = joint("j2", "b", "nowhere", "0 0 0");
        let xyz_msg = "joint 'j1' <origin xyz>: expected 3 numbers, found 2 (\"1 2\")";
        let link_msg = "joint 'j2': child link 'nowhere' is not declared as a <link>";
        // Joints in file order: the earlier joint's error, of either kind.
        assert!(error(&robot(&format!("{links}{bad_xyz}{undeclared}"))).contains(xyz_msg));
        assert!(error(&robot(&format!("{undeclared}{bad_xyz}{links}"))).contains(link_msg));
        // In one joint, an undeclared parent comes before a bad origin.
        let both = joint("j3", "gone", "b", "1 2");
        let e = error(&robot(&format!("{both}{links}")));
        assert!(
            e.contains("joint 'j3': parent link 'gone' is not declared"),
            "{e}"
        );
        // A duplicate link, declared after the bad joint, comes first.
        let e = line_of(&robot(&format!("{links}{bad_xyz}<link name=\"a\"/>\n")));
        assert!(
            e.0.contains("link 'a' declared twice") && e.1 == Some(6),
            "{e:?}"
        );
        // Un-expanded xacro late in the file comes before both.
        let e = line_of(&robot(&format!(
            "{links}{bad_xyz}<link name=\"${{x}}\"/>\n"
        )));
        assert!(
            e.0.contains("un-expanded xacro (<link>)") && e.1 == Some(6),
            "{e:?}"
        );
        // And malformed XML anywhere comes first: roxmltree's words.
        let text = format!("<robot name=\"r\">\n{links}{bad_xyz}</robt>\n");
        let want = xml::error(
            &roxmltree::Document::parse_with_options(&text, xml::parse_options()).unwrap_err(),
            &text,
        )
        .to_string();
        assert_eq!(error(&text), want);
        // A bad version at the root comes before the joints.
        let text = format!("<robot name=\"r\" version=\"2\">\n{links}{bad_xyz}</robot>");
        assert!(error(&text).contains("<robot version>"), "{}", error(&text));
    }

    /// An error at the end of a long file names its line.
    #[test]
    fn a_late_error_names_its_line() {
        let n = 20_000;
        let mut body = String::from("<link name=\"l0\"/>\n");
        for k in 1..n {
            body.push_str(&format!("<link name=\"l{k}\"/>\n"));
            body.push_str(&joint(
                &format!("j{k}"),
                &format!("l{}", k - 1),
                &format!("l{k}"),
                "0.1 0 0",
            ));
        }
        let ok = load(&robot(&body)).unwrap();
        assert_eq!(ok.edges.len(), n - 1);
        body.push_str(&joint("last", &format!("l{}", n - 1), "l0", "0.1 0 nan"));
        let e = load(&robot(&body)).unwrap_err();
        // Line 1 is <robot>, then two lines per link and joint but the first.
        assert_eq!(e.location.line, Some(2 * n + 1), "{e}");
        assert!(
            e.to_string()
                .contains("joint 'last' <origin xyz>: expected finite numbers, found \"nan\""),
            "{e}"
        );
    }

    /// Numbers with signs and exponents, entities and character references
    /// in values, comments and CDATA inside a joint: read as XML and urdfdom
    /// read them.
    #[test]
    fn values_signs_exponents_entities() {
        let text = robot(
            "<link name=\"a&amp;b\"/><link name=\"c\"/>\n\
             <joint name=\"j\" type=\"fixed\"><!-- <origin xyz=\"9 9 9\"/> -->\
             <parent link=\"a&amp;b\"/><![CDATA[<child link=\"x\"/>]]><child link='c'/>\
             <origin xyz=\"+1e-3&#32;-2.5E+2 .5\" rpy=\"-0 +0.0 1e0\"/></joint>\n",
        );
        let l = load(&text).unwrap();
        let e = &l.edges[0];
        assert_eq!((e.parent.as_str(), e.child.as_str()), ("a&b", "c"));
        assert_eq!(e.transform.translation().as_slice(), &[0.001, -250.0, 0.5]);
        let want = crate::geometry::Transform::from_rpy([-0.0, 0.0, 1.0], [0.0; 3]).unwrap();
        assert_eq!(e.transform.rotation(), want.rotation());
    }

    /// `${` and `$(` anywhere in a value, as written or once decoded, are
    /// xacro; a `$` alone is not.
    #[test]
    fn xacro_expressions_in_values() {
        for (value, xacro) in [
            ("${pi}", true),
            ("$(find pkg)", true),
            ("a$&#123;b}", true),
            ("$&#40;arg x)", true),
            ("a$b", false),
            ("$ {x}", false),
        ] {
            let text = robot(&format!(
                "<link name=\"a\"/>\n<link name=\"b\" note=\"{value}\"/>\n"
            ));
            let e = line_of(&text);
            assert_eq!(
                e.0.contains("un-expanded xacro (<link>)"),
                xacro,
                "{value}: {e:?}"
            );
            if xacro {
                assert_eq!(e.1, Some(3), "{e:?}");
            }
        }
    }

    /// Duplicated attributes past the pairwise limit, and namespace scopes,
    /// get roxmltree's error; a xacro prefix in scope is xacro.
    #[test]
    fn duplicates_and_namespace_scopes() {
        let attrs: String = (0..40).map(|i| format!(" a{i}=\"{i}\"")).collect();
        for text in [
            robot(&format!("<link name=\"a\"{attrs} a39=\"x\"/>\n")),
            robot(&format!("<link name=\"a\"{attrs} a3=\"x\"/>\n")),
            robot("<a xmlns:x=\"urn:x\"><x:b/></a><x:c/>\n<link name=\"a\"/>\n"),
        ] {
            let want = xml::error(
                &roxmltree::Document::parse_with_options(&text, xml::parse_options()).unwrap_err(),
                &text,
            )
            .to_string();
            assert_eq!(error(&text), want, "{text}");
        }
        let text = robot(
            "<link name=\"a\"/>\n<a xmlns:x=\"urn:other\"><x:b/></a>\n\
             <c xmlns:x=\"http://www.ros.org/wiki/xacro\">\n<x:d/></c>\n",
        );
        let e = line_of(&text);
        assert!(
            e.0.contains("un-expanded xacro (<xacro:d>)") && e.1 == Some(5),
            "{e:?}"
        );
    }
}
