//! A pull reader over the URDF text: the elements the reader needs, without a
//! document tree (issue 12: a `roxmltree` tree costs about 1 KB per link), in
//! one pass (issue 29: the text was read twice).
//!
//! Events come from quick-xml's plain `Reader`; element names are resolved
//! against their namespaces here ([`Scopes`]: the attributes are split once,
//! where quick-xml's `NsReader` splits them a second time to find the
//! declarations). Every element's start is a byte offset into the text (its
//! `<`), turned into line and column by [`Lines`] only when a message
//! needs one. Attribute values are decoded as XML reads them
//! ([`super::values`]): literal tabs and line breaks become spaces, then the
//! five predefined entities and character references are replaced; `raw`
//! keeps the text as written. Each element's attributes go into one buffer
//! reused from element to element, and a joint's elements into another
//! reused from joint to joint: reading allocates nothing per attribute.
//!
//! Errors stay those of `roxmltree`, word for word: quick-xml checks less
//! than roxmltree does, so anything unusual (a quick-xml error, a DOCTYPE, an
//! entity other than the five predefined, a character reference, a namespace
//! prefix on an attribute, a prefixed or empty namespace declaration, an
//! unknown prefix on an element, a non-ASCII or malformed name, a duplicated
//! attribute, a control character, a misplaced or unusual XML declaration, a
//! PI named `xml`, text or a second element outside the root, an element left
//! open at the end) makes the whole text be checked once by `roxmltree`
//! ([`crate::formats::xml`]), whose error is reported; its tree is dropped at
//! once. When roxmltree accepts the text, reading goes on (or, if quick-xml
//! cannot go on, its own error is reported at its position).

use super::lines::Lines;
use super::values::{decode, has_expr, scan};
use crate::diagnostic::{Error, Result};
use crate::formats::source::LineIndex;
use crate::formats::xacro::markers as xacro;
use crate::formats::xml;
use crate::tolerances::URDF_MAX_XML_DEPTH;
use quick_xml::events::{BytesStart, Event};
use quick_xml::reader::Reader;
use std::borrow::Cow;
use std::ops::Range;
use std::path::Path;

/// An attribute: local name, value as XML decodes it, text as written.
#[derive(Clone)]
pub(super) struct Attr<'a> {
    pub name: &'a str,
    pub value: Cow<'a, str>,
    pub raw: &'a str,
    /// Written with a namespace prefix (`a:b="..."`): not found by
    /// [`El::attr`], as roxmltree's `attribute(name)` does not find it.
    pub prefixed: bool,
    /// No entity, tab or line break: `value` is `raw`.
    pub plain: bool,
}

/// An element's start tag (its attributes live in the reader's buffers).
#[derive(Clone, Copy)]
pub(super) struct El<'e, 'a> {
    /// Local name (without prefix).
    pub name: &'a str,
    /// Byte offset of its `<`.
    pub start: usize,
    pub attrs: &'e [Attr<'a>],
    /// In a namespace whose name contains `xacro`.
    pub xacro_ns: bool,
}

impl<'e, 'a> El<'e, 'a> {
    /// The decoded value of the un-prefixed attribute `name`.
    pub fn attr(&self, name: &str) -> Option<&'e str> {
        self.attribute(name).map(|a| a.value.as_ref())
    }

    /// The un-prefixed attribute `name`.
    pub fn attribute(&self, name: &str) -> Option<&'e Attr<'a>> {
        self.attrs.iter().find(|a| !a.prefixed && a.name == name)
    }
}

/// An element of a joint: its attributes are a range of [`JointBuf::attrs`].
struct Head<'a> {
    name: &'a str,
    start: usize,
    xacro_ns: bool,
    attrs: Range<usize>,
}

/// The joint being read, kept in buffers reused from joint to joint.
#[derive(Default)]
struct JointBuf<'a> {
    heads: Vec<Head<'a>>,
    attrs: Vec<Attr<'a>>,
}

impl<'a> JointBuf<'a> {
    fn push(&mut self, el: &El<'_, 'a>) {
        let from = self.attrs.len();
        self.attrs.extend_from_slice(el.attrs);
        self.heads.push(Head {
            name: el.name,
            start: el.start,
            xacro_ns: el.xacro_ns,
            attrs: from..self.attrs.len(),
        });
    }

    fn clear(&mut self) {
        self.heads.clear();
        self.attrs.clear();
    }
}

/// A top-level `<joint>` and its child elements (their own children are not kept).
#[derive(Clone, Copy)]
pub(super) struct JointEl<'e, 'a> {
    pub el: El<'e, 'a>,
    buf: &'e JointBuf<'a>,
}

impl<'e, 'a> JointEl<'e, 'a> {
    fn new(buf: &'e JointBuf<'a>) -> Self {
        JointEl {
            el: buf.view(0),
            buf,
        }
    }

    /// The child elements, in file order.
    pub fn children(&self) -> impl Iterator<Item = El<'e, 'a>> + '_ {
        (1..self.buf.heads.len()).map(|i| self.buf.view(i))
    }

    /// The first child element named each of `tags`, in one pass over the
    /// children (a search per tag compared every child's name again).
    pub fn first_children<const N: usize>(&self, tags: [&str; N]) -> [Option<El<'e, 'a>>; N] {
        let mut out = [None; N];
        for c in self.children() {
            if let Some(k) = tags.iter().position(|t| *t == c.name) {
                if out[k].is_none() {
                    out[k] = Some(c);
                }
            }
        }
        out
    }
}

impl<'a> JointBuf<'a> {
    fn view(&self, i: usize) -> El<'_, 'a> {
        let h = &self.heads[i];
        El {
            name: h.name,
            start: h.start,
            attrs: &self.attrs[h.attrs.clone()],
            xacro_ns: h.xacro_ns,
        }
    }
}

/// The first element (document order) in a xacro namespace or with `${` /
/// `$(` in an attribute value.
pub(super) struct XacroAt<'a> {
    pub name: &'a str,
    pub xacro_ns: bool,
    pub start: usize,
}

/// What the pass hands on, in document order.
pub(super) enum Item<'e, 'a> {
    /// The root element (always the first item).
    Root(El<'e, 'a>),
    /// The first xacro element, before that element's own item.
    Xacro(XacroAt<'a>),
    /// A top-level `<link>`: its `name` attribute (if any) and start offset.
    Link(Option<&'e Attr<'a>>, usize),
    /// A top-level `<joint>` with its child elements.
    Joint(JointEl<'e, 'a>),
}

/// The one pass: the whole text checked, every item handed to `each` in
/// document order (a joint once its child elements are read).
pub(super) fn read<'a>(
    text: &'a str,
    path: &Path,
    mut each: impl FnMut(Item<'_, 'a>) -> Result<()>,
) -> Result<()> {
    let mut w = Walker::new(text, path);
    w.check_chars()?;
    let mut xacro_seen = false;
    let mut joint = JointBuf::default();
    let mut in_joint = false;
    w.walk(|depth, el, expr| {
        if !xacro_seen && (el.xacro_ns || expr) {
            xacro_seen = true;
            each(Item::Xacro(XacroAt {
                name: el.name,
                xacro_ns: el.xacro_ns,
                start: el.start,
            }))?;
        }
        if depth == 2 && in_joint {
            in_joint = false;
            each(Item::Joint(JointEl::new(&joint)))?;
        }
        match (depth, el.name) {
            (1, _) => each(Item::Root(el))?,
            (2, "link") => {
                each(Item::Link(el.attribute("name"), el.start))?;
            }
            (2, "joint") => {
                joint.clear();
                joint.push(&el);
                in_joint = true;
            }
            (3, _) if in_joint => joint.push(&el),
            _ => {}
        }
        Ok(())
    })?;
    if in_joint {
        each(Item::Joint(JointEl::new(&joint)))?;
    }
    Ok(())
}

/// `s` as a slice of `text` (quick-xml borrows every name and value from it).
fn sub<'a>(text: &'a str, s: &[u8]) -> Option<&'a str> {
    let off = (s.as_ptr() as usize).checked_sub(text.as_ptr() as usize)?;
    text.get(off..off.checked_add(s.len())?)
}

/// The namespace declarations in scope: (prefix, `None` for the default
/// namespace; its name contains `xacro`; its name is empty; element depth).
#[derive(Default)]
struct Scopes<'a> {
    bindings: Vec<(Option<&'a [u8]>, bool, bool, usize)>,
}

impl<'a> Scopes<'a> {
    /// An element's name resolved: (in a xacro namespace, undeclared prefix).
    fn resolve(&self, qname: &[u8]) -> (bool, bool) {
        let prefix = qname.iter().position(|&c| c == b':').map(|i| &qname[..i]);
        if prefix == Some(b"xml") {
            return (false, false);
        }
        match self.bindings.iter().rev().find(|b| b.0 == prefix) {
            Some(&(_, xacro, empty, _)) => (xacro && !empty, false),
            None => (false, prefix.is_some()),
        }
    }

    /// Leaves the element at `depth`: its declarations go out of scope.
    fn leave(&mut self, depth: usize) {
        while self.bindings.last().is_some_and(|b| b.3 >= depth) {
            self.bindings.pop();
        }
    }
}

/// Past this many attributes on one element, duplicates are left to roxmltree
/// (the pairwise comparison would be quadratic).
const PAIRWISE_ATTRS: usize = 32;

struct Walker<'a, 'p> {
    text: &'a str,
    path: &'p Path,
    /// roxmltree accepted the text: no more suspicion checks.
    validated: bool,
    /// The keys of the element's attributes so far (duplicates).
    keys: Vec<&'a str>,
}

impl<'a, 'p> Walker<'a, 'p> {
    fn new(text: &'a str, path: &'p Path) -> Self {
        Walker {
            text,
            path,
            validated: false,
            keys: Vec::new(),
        }
    }

    /// Something roxmltree may refuse: check the whole text with it once.
    fn suspect(&mut self) -> Result<()> {
        if self.validated {
            return Ok(());
        }
        match roxmltree::Document::parse_with_options(self.text, xml::parse_options()) {
            Ok(_) => {
                self.validated = true;
                Ok(())
            }
            Err(e) => Err(self.refusal(&e)),
        }
    }

    /// roxmltree's error, as the reader always reported it.
    fn refusal(&self, e: &roxmltree::Error) -> Error {
        if xacro::has_markers(self.text) {
            return Error::parse(format!(
                "this file holds un-expanded xacro, not URDF: {}",
                xacro::advice(self.path)
            ));
        }
        xml::error(e, self.text)
    }

    /// The text cannot be read on: roxmltree's error, else `what` at `at`.
    fn fail(&mut self, at: usize, what: &str) -> Error {
        self.validated = false;
        if let Err(e) = self.suspect() {
            return e;
        }
        let (l, c) = LineIndex::new(self.text).pos(at.min(self.text.len()));
        Error::parse(format!("not well-formed XML: {what}")).at_line(l, Some(c))
    }

    /// Elements nested deeper than [`URDF_MAX_XML_DEPTH`]: roxmltree's error
    /// if the text is not well-formed, else a limit error.
    fn too_deep(&mut self, at: usize) -> Error {
        if let Err(e) = self.suspect() {
            return e;
        }
        let (l, c) = LineIndex::new(self.text).pos(at.min(self.text.len()));
        Error::limit(format!(
            "XML elements nested deeper than {URDF_MAX_XML_DEPTH} levels: expected a URDF (its elements nest about five levels)"
        ))
        .at_line(l, Some(c))
    }

    /// Characters XML does not allow (controls other than tab, LF, CR;
    /// U+FFFE, U+FFFF), looked for a block at a time (a branch-free test
    /// the compiler vectorises), each flagged block then byte by byte.
    fn check_chars(&mut self) -> Result<()> {
        let b = self.text.as_bytes();
        let odd = |c: u8| (c < 0x20 && c != b'\t' && c != b'\n' && c != b'\r') || c == 0xEF;
        let bad_at = |i: usize| {
            let c = b[i];
            (c < 0x20 && !matches!(c, b'\t' | b'\n' | b'\r'))
                || (c == 0xEF
                    && b.get(i + 1) == Some(&0xBF)
                    && matches!(b.get(i + 2), Some(0xBE | 0xBF)))
        };
        let bad = b.chunks(64).enumerate().any(|(k, block)| {
            block.iter().fold(false, |acc, &c| acc | odd(c))
                && (k * 64..k * 64 + block.len()).any(bad_at)
        });
        if bad {
            self.suspect()?;
        }
        Ok(())
    }

    /// Every event in order; `f(depth, element, xacro expression in an
    /// attribute)` for each element (depth 1: the root), its attributes
    /// checked and decoded.
    fn walk<F>(&mut self, mut f: F) -> Result<()>
    where
        F: FnMut(usize, El<'_, 'a>, bool) -> Result<()>,
    {
        let text = self.text;
        let mut r = Reader::from_str(text);
        let cfg = r.config_mut();
        cfg.check_comments = true;
        cfg.check_end_names = true;
        cfg.expand_empty_elements = false;
        cfg.trim_text(false);
        let (mut depth, mut roots) = (0usize, 0usize);
        let mut attrs: Vec<Attr<'a>> = Vec::new();
        let mut scopes = Scopes::default();
        loop {
            let before = position(r.buffer_position());
            let ev = match r.read_event() {
                Ok(ev) => ev,
                Err(e) => {
                    let at = position(r.error_position());
                    return Err(self.fail(at, &e.to_string()));
                }
            };
            match ev {
                Event::Start(ref e) | Event::Empty(ref e) => {
                    if depth == 0 {
                        roots += 1;
                    }
                    if depth >= URDF_MAX_XML_DEPTH {
                        return Err(self.too_deep(before));
                    }
                    let qname = e.name();
                    if !self.validated && (roots > 1 || !qname_ok(qname.as_ref())) {
                        self.suspect()?;
                    }
                    let start = sub(text, qname.as_ref()).map_or(before, |s| {
                        (s.as_ptr() as usize - text.as_ptr() as usize).saturating_sub(1)
                    });
                    attrs.clear();
                    let expr = self.attributes(e, start, depth + 1, &mut attrs, &mut scopes)?;
                    let (xacro_ns, unknown) = scopes.resolve(qname.as_ref());
                    if unknown {
                        self.suspect()?;
                    }
                    let Some(name) = sub(text, e.local_name().into_inner()) else {
                        return Err(self.fail(start, "an element name"));
                    };
                    let el = El {
                        name,
                        start,
                        attrs: &attrs,
                        xacro_ns,
                    };
                    f(depth + 1, el, expr)?;
                    if matches!(ev, Event::Start(_)) {
                        depth += 1;
                    } else {
                        scopes.leave(depth + 1);
                    }
                }
                Event::End(_) => {
                    scopes.leave(depth);
                    depth = depth.saturating_sub(1);
                }
                Event::Text(_) if self.validated => {}
                Event::Text(ref t) => {
                    let s = sub(text, t).unwrap_or("");
                    let outside = depth == 0 && !s.bytes().all(|b| b.is_ascii_whitespace());
                    if outside || s.contains("]]>") {
                        self.suspect()?;
                    }
                }
                Event::CData(_) if depth == 0 => self.suspect()?,
                Event::CData(_) | Event::Comment(_) => {}
                Event::GeneralRef(ref g) => {
                    let predefined = matches!(&**g, b"lt" | b"gt" | b"amp" | b"apos" | b"quot");
                    if depth == 0 || !predefined {
                        self.suspect()?;
                    }
                }
                Event::Decl(_) if before == 0 && decl_ok(raw(text, before, &r)) => {}
                Event::Decl(_) | Event::DocType(_) => self.suspect()?,
                Event::PI(_) => {
                    let target = raw(text, before, &r)
                        .trim_start_matches("<?")
                        .split(|c: char| c.is_ascii_whitespace() || c == '?')
                        .next()
                        .unwrap_or("");
                    if target.eq_ignore_ascii_case("xml") || !qname_ok(target.as_bytes()) {
                        self.suspect()?;
                    }
                }
                Event::Eof => {
                    if depth != 0 {
                        return Err(self.fail(text.len(), "the file ends inside an element"));
                    }
                    if roots == 0 {
                        return Err(self.fail(text.len(), "no root element"));
                    }
                    return Ok(());
                }
            }
        }
    }

    /// The start tag's attributes (not the namespace declarations, which go
    /// into `scopes` at `depth`), checked, decoded and put in `out` in order;
    /// whether a value holds a xacro expression.
    fn attributes(
        &mut self,
        e: &BytesStart<'a>,
        start: usize,
        depth: usize,
        out: &mut Vec<Attr<'a>>,
        scopes: &mut Scopes<'a>,
    ) -> Result<bool> {
        let text = self.text;
        let mut expr = false;
        self.keys.clear();
        // Duplicates are checked here, pairwise, not by quick-xml, whose check
        // allocates a vector per element.
        for a in e.attributes().with_checks(false) {
            let a = match a {
                Ok(a) => a,
                Err(err) => return Err(self.fail(start, &err.to_string())),
            };
            let (Some(key), Some(raw)) = (sub(text, a.key.as_ref()), sub(text, &a.value)) else {
                return Err(self.fail(start, "an attribute"));
            };
            if !self.validated {
                let twice = self.keys.len() >= PAIRWISE_ATTRS || self.keys.contains(&key);
                self.keys.push(key);
                if twice || !qname_ok(key.as_bytes()) {
                    self.suspect()?;
                }
            }
            // The name split once at its first colon, as quick-xml splits it.
            // A byte search: `str::find(char)` cost 70 instructions a key.
            let (prefix, local) = match key.bytes().position(|c| c == b':') {
                Some(i) => (Some(&key[..i]), &key[i + 1..]),
                None => (None, key),
            };
            if key == "xmlns" || prefix == Some("xmlns") {
                // xmlns declarations are not attributes (roxmltree); a
                // prefixed one is left to roxmltree's checks.
                if raw.is_empty() || prefix.is_some() {
                    self.suspect()?;
                }
                let named = raw.contains("xacro");
                let declared = prefix.map(|_| local.as_bytes());
                scopes
                    .bindings
                    .push((declared, named, raw.is_empty(), depth));
                continue;
            }
            let prefixed = prefix.is_some();
            let s = scan(raw);
            if prefixed || s.lt || s.char_ref {
                self.suspect()?;
            }
            let value = if s.plain {
                expr |= s.expr;
                Cow::Borrowed(raw)
            } else {
                let Some(v) = decode(raw) else {
                    self.suspect()?;
                    return Err(self.fail(start, &format!("attribute {local}: an unknown entity")));
                };
                expr |= has_expr(&v);
                v
            };
            out.push(Attr {
                name: local,
                value,
                raw,
                prefixed,
                plain: s.plain,
            });
        }
        Ok(expr)
    }
}

/// quick-xml's position as an offset into the text.
fn position(p: u64) -> usize {
    usize::try_from(p).unwrap_or(usize::MAX)
}

/// The text of the event just read, from `before`.
fn raw<'a>(text: &'a str, before: usize, r: &Reader<&[u8]>) -> &'a str {
    text.get(before..position(r.buffer_position()))
        .unwrap_or("")
}

/// An ASCII XML name, or two joined by one `:` (a non-ASCII name is left to
/// roxmltree).
fn qname_ok(name: &[u8]) -> bool {
    match name.iter().position(|&c| c == b':') {
        None => ncname_ok(name),
        Some(i) => ncname_ok(&name[..i]) && ncname_ok(&name[i + 1..]),
    }
}

/// What an ASCII byte may be in a name without a colon: [`NAME_START`]
/// (a letter or `_`), [`NAME_CHAR`] (also a digit, `-` or `.`).
static NAME_BYTES: [u8; 256] = {
    let mut t = [0u8; 256];
    let mut c = 0;
    while c < 256 {
        let b = c as u8;
        if b.is_ascii_alphabetic() || b == b'_' {
            t[c] = NAME_START | NAME_CHAR;
        } else if b.is_ascii_digit() || b == b'-' || b == b'.' {
            t[c] = NAME_CHAR;
        }
        c += 1;
    }
    t
};
const NAME_START: u8 = 1;
const NAME_CHAR: u8 = 2;

/// A non-empty ASCII name without a colon. A table per byte: the tests
/// spelled out were a tenth of the pass over a 100,000-link URDF (issue 29).
fn ncname_ok(name: &[u8]) -> bool {
    match name.split_first() {
        Some((&first, rest)) => {
            NAME_BYTES[first as usize] & NAME_START != 0
                && rest
                    .iter()
                    .all(|&c| NAME_BYTES[c as usize] & NAME_CHAR != 0)
        }
        None => false,
    }
}

/// `<?xml version="1.x"( encoding="...")?( standalone="yes|no")??>`.
fn decl_ok(raw: &str) -> bool {
    let Some(inner) = raw.strip_prefix("<?xml").and_then(|s| s.strip_suffix("?>")) else {
        return false;
    };
    let mut rest = inner;
    let mut names = Vec::new();
    loop {
        let t = rest.trim_start_matches([' ', '\t', '\n', '\r']);
        if t.is_empty() {
            break;
        }
        if t.len() == rest.len() {
            return false;
        }
        let Some((name, v)) = t.split_once('=') else {
            return false;
        };
        let v = v.trim_start_matches([' ', '\t', '\n', '\r']);
        let Some(q) = v.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            return false;
        };
        let Some((value, after)) = v[1..].split_once(q) else {
            return false;
        };
        let ok = match name.trim_end() {
            "version" => {
                value.len() > 2
                    && value.starts_with("1.")
                    && value[2..].bytes().all(|b| b.is_ascii_digit())
            }
            "encoding" => {
                value
                    .bytes()
                    .next()
                    .is_some_and(|b| b.is_ascii_alphabetic())
                    && value
                        .bytes()
                        .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'.' | b'_' | b'-'))
            }
            "standalone" => matches!(value, "yes" | "no"),
            _ => false,
        };
        if !ok {
            return false;
        }
        names.push(name.trim_end());
        rest = after;
    }
    matches!(
        names[..],
        ["version"]
            | ["version", "encoding"]
            | ["version", "standalone"]
            | ["version", "encoding", "standalone"]
    )
}

/// A parse error at element `n`'s line and column.
pub(super) fn err_at(idx: &Lines, n: &El, msg: String) -> Error {
    fail_at(idx, n.start, msg)
}

/// A parse error at byte `start`'s line and column.
pub(super) fn fail_at(idx: &Lines, start: usize, msg: String) -> Error {
    let (l, c) = idx.pos(start);
    Error::parse(msg).at_line(l, Some(c))
}

#[cfg(test)]
mod tests {
    use super::{decl_ok, qname_ok, read, Item};
    use crate::formats::{xml, LoadOptions};
    use std::path::Path;

    /// The reader's error for `text`, and roxmltree's own for the same text.
    fn both(text: &str) -> (String, String) {
        let ours = match super::super::parse(text, Path::new("t.urdf"), &LoadOptions::default()) {
            Err(e) => e.to_string(),
            Ok(_) => "roxmltree accepts it".to_string(),
        };
        let theirs = match roxmltree::Document::parse_with_options(text, xml::parse_options()) {
            Err(e) => xml::error(&e, text).to_string(),
            Ok(_) => "roxmltree accepts it".to_string(),
        };
        (ours, theirs)
    }

    /// Malformed XML gets roxmltree's words and position, whichever check of
    /// the pull reader noticed it first.
    #[test]
    fn xml_errors_are_roxmltree_s() {
        let l = "<link name=\"a\"/>";
        for text in [
            format!("<robot name=\"r\">{l}</robt>"),
            format!("<robot name=\"r\">{l}"),
            format!("<robot name=\"r\">{l}</robot>trailing"),
            format!("<robot name=\"r\">{l}</robot><robot name=\"s\"/>"),
            format!("<robot name=\"r\">{l}<p:link name=\"a\"/></robot>"),
            format!("<robot name=\"r\">{l}<link name=a/></robot>"),
            format!("<robot name=\"r\">{l}<link name=\"a\" name=\"b\"/></robot>"),
            format!("<robot name=\"r\">{l}<link name=\"a&nbsp;\"/></robot>"),
            format!("<robot name=\"r\">{l}<link name=\"a&#0;\"/></robot>"),
            format!("<robot name=\"r\">{l}<link name=\"a<\"/></robot>"),
            format!("<robot name=\"r\">{l} & </robot>"),
            format!("<robot name=\"r\">{l}\u{1}</robot>"),
            format!("<!DOCTYPE robot [<!ENTITY a \"b\">]><robot name=\"r\">{l}</robot>"),
            format!("<robot name=\"r\"><?xml version=\"1.0\"?>{l}</robot>"),
            format!("<?xml version=\"2.0\"?><robot name=\"r\">{l}</robot>"),
            format!("<robot name=\"r\"><1a/>{l}</robot>"),
            format!("<robot name=\"r\"><!-- a -- b -->{l}</robot>"),
            format!("<robot name=\"r\"><?XML x?>{l}</robot>"),
            format!("<![CDATA[x]]><robot name=\"r\">{l}</robot>"),
            format!("<robot name=\"r\" p:x=\"1\">{l}</robot>"),
            format!("<robot name=\"r\" xmlns:p=\"\">{l}</robot>"),
            format!("<robot name=\"r\">&foo;{l}</robot>"),
            String::new() + "  ",
        ] {
            let (ours, theirs) = both(&text);
            assert_eq!(ours, theirs, "{text:?}");
        }
    }

    /// On valid XML the values read are roxmltree's: entities, character
    /// references, tabs and line breaks in attributes, namespaces, comments,
    /// CDATA, processing instructions, a declaration.
    #[test]
    fn values_are_roxmltree_s() {
        let text = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!-- c -->\n<?pi data?>\n\
            <robot name=\"r&amp;d\" xmlns:x=\"urn:other\">\n<x:note a=\"1\"/>\n\
            <link name=\"a&#x42;\tc\"/><link name='q&quot;&lt;&gt;&apos;'/>\n\
            <joint name=\"j\r\n1\" type=\"fixed\"><parent link=\"a&#x42;\tc\"/><child link='q&quot;&lt;&gt;&apos;'/>\
            <origin xyz=\"1\t2\n3\" rpy=\"0 0 0\"/><![CDATA[<x>]]></joint>\n</robot>\n";
        let doc = roxmltree::Document::parse(text).unwrap();
        let root = doc.root_element();
        let links: Vec<_> = root.children().filter(|n| n.has_tag_name("link")).collect();
        let j = root.children().find(|n| n.has_tag_name("joint")).unwrap();
        let (mut seen, mut roots, mut read_links) = (0, 0, 0);
        read(text, Path::new("t.urdf"), |item| {
            match item {
                Item::Root(r) => {
                    roots += 1;
                    assert_eq!(r.attr("name"), root.attribute("name"));
                    assert_eq!(r.start, root.range().start);
                }
                Item::Link(name, start) => {
                    let l = links[read_links];
                    read_links += 1;
                    assert_eq!(name.map(|a| a.value.as_ref()), l.attribute("name"));
                    assert_eq!(start, l.range().start);
                }
                Item::Joint(je) => {
                    seen += 1;
                    assert_eq!(je.el.attr("name"), j.attribute("name"));
                    assert_eq!(je.el.start, j.range().start);
                    let kids: Vec<_> = j.children().filter(|n| n.is_element()).collect();
                    assert_eq!(je.children().count(), kids.len());
                    for (c, k) in je.children().zip(&kids) {
                        assert_eq!(c.name, k.tag_name().name());
                        assert_eq!(c.start, k.range().start);
                        for a in k.attributes() {
                            assert_eq!(c.attr(a.name()), Some(a.value()), "{}", a.name());
                            assert_eq!(c.attribute(a.name()).unwrap().raw, &text[a.range_value()]);
                        }
                    }
                }
                Item::Xacro(_) => panic!("no xacro here"),
            }
            Ok(())
        })
        .unwrap();
        assert_eq!((roots, read_links), (1, links.len()));
        assert_eq!(seen, 1);
        let loaded =
            super::super::parse(text, Path::new("t.urdf"), &LoadOptions::default()).unwrap();
        // A literal tab in a value is a space, as XML reads it.
        assert_eq!(loaded.edges[0].parent, "aB c");
        assert_eq!(loaded.edges[0].child, "q\"<>'");
        assert_eq!(
            loaded.edges[0].transform.translation().as_slice(),
            &[1.0, 2.0, 3.0]
        );
    }

    /// Nesting past the limit is refused, not a panic of the 16-bit
    /// namespace level counter (65,536 levels).
    #[test]
    fn deep_nesting_is_refused() {
        for depth in [super::URDF_MAX_XML_DEPTH, 70_000] {
            let text = format!(
                "<robot name=\"r\">{}{}</robot>",
                "<a>".repeat(depth),
                "</a>".repeat(depth)
            );
            let e = super::super::parse(&text, Path::new("t.urdf"), &LoadOptions::default())
                .expect_err("deep");
            assert!(e.to_string().contains("nested deeper than 1000"), "{e}");
        }
    }

    /// A xacro namespace given as the default namespace puts the root itself
    /// in it: refused at the root, as before.
    #[test]
    fn default_xacro_namespace_is_xacro() {
        let text =
            "<robot name=\"r\" xmlns=\"http://www.ros.org/wiki/xacro\"><link name=\"a\"/></robot>";
        let mut first = None;
        read(text, Path::new("t.urdf"), |item| {
            if let (Item::Xacro(x), None) = (item, &first) {
                first = Some((x.name, x.xacro_ns));
            }
            Ok(())
        })
        .unwrap();
        assert_eq!(first, Some(("robot", true)));
    }

    #[test]
    fn names_and_declarations() {
        assert!(qname_ok(b"robot") && qname_ok(b"xacro:macro") && qname_ok(b"_a-1.b"));
        assert!(
            !qname_ok(b"1a") && !qname_ok(b"a:b:c") && !qname_ok(b"") && !qname_ok("é".as_bytes())
        );
        // The same answers as the one-pass test the table replaced, over
        // every name of up to three bytes from a set of telling ones.
        let reference = |name: &[u8]| {
            let (mut at_start, mut colons) = (true, 0);
            for &c in name {
                if at_start {
                    if !(c.is_ascii_alphabetic() || c == b'_') {
                        return false;
                    }
                    at_start = false;
                } else if c == b':' {
                    colons += 1;
                    at_start = true;
                    if colons > 1 {
                        return false;
                    }
                } else if !(c.is_ascii_alphanumeric() || matches!(c, b'_' | b'-' | b'.')) {
                    return false;
                }
            }
            !at_start
        };
        let set = b"aZ_0-.:\xc3 /";
        let mut names: Vec<Vec<u8>> = vec![vec![]];
        for _ in 0..3 {
            let longer: Vec<Vec<u8>> = names
                .iter()
                .flat_map(|n| set.iter().map(move |&c| [&n[..], &[c]].concat()))
                .collect();
            names.extend(longer);
        }
        names.dedup();
        for n in &names {
            assert_eq!(qname_ok(n), reference(n), "{n:?}");
        }
        assert!(decl_ok("<?xml version=\"1.0\"?>"));
        assert!(decl_ok(
            "<?xml version='1.0' encoding='UTF-8' standalone=\"yes\" ?>"
        ));
        assert!(!decl_ok("<?xml version=\"2.0\"?>"));
        assert!(!decl_ok("<?xml encoding=\"UTF-8\"?>"));
        assert!(!decl_ok("<?xml version=\"1.0\" foo=\"1\"?>"));
    }
}
