//! A pull reader over the URDF text: the elements the reader needs, without a
//! document tree (issue 12: a `roxmltree` tree costs about 1 KB per link).
//!
//! Events come from quick-xml (`NsReader`, names resolved against their
//! namespaces). Every element's start is a byte offset into the text (its
//! `<`), turned into line and column by [`LineIndex`] only when a message
//! needs one. Attribute values are decoded as XML reads them: literal tabs
//! and line breaks become spaces, then the five predefined entities and
//! character references are replaced; `raw` keeps the text as written.
//!
//! Errors stay those of `roxmltree`, word for word: quick-xml checks less
//! than roxmltree does, so anything unusual (a quick-xml error, a DOCTYPE, an
//! entity other than the five predefined, a character reference, a namespace
//! prefix on an attribute or an unknown one on an element, a non-ASCII or
//! malformed name, a control character, a misplaced or unusual XML
//! declaration, a PI named `xml`, text or a second element outside the root,
//! an element left open at the end) makes the whole text be checked once by
//! `roxmltree` ([`crate::formats::xml`]), whose error is reported; its tree is
//! dropped at once. When roxmltree accepts the text, reading goes on (or, if
//! quick-xml cannot go on, its own error is reported at its position).

use crate::diagnostic::{Error, Result};
use crate::formats::source::LineIndex;
use crate::formats::xacro::markers as xacro;
use crate::formats::xml;
use crate::tolerances::URDF_MAX_XML_DEPTH;
use quick_xml::events::{BytesStart, Event};
use quick_xml::name::ResolveResult;
use quick_xml::reader::{NsReader, Reader};
use std::borrow::Cow;
use std::path::Path;

/// An attribute: local name, value as XML decodes it, text as written.
pub(super) struct Attr<'a> {
    pub name: &'a str,
    pub value: Cow<'a, str>,
    pub raw: &'a str,
    /// Written with a namespace prefix (`a:b="..."`): not found by
    /// [`El::attr`], as roxmltree's `attribute(name)` does not find it.
    pub prefixed: bool,
}

/// An element's start tag.
pub(super) struct El<'a> {
    /// Local name (without prefix).
    pub name: &'a str,
    /// Byte offset of its `<`.
    pub start: usize,
    pub attrs: Vec<Attr<'a>>,
    /// In a namespace whose name contains `xacro`.
    pub xacro_ns: bool,
}

impl<'a> El<'a> {
    /// The decoded value of the un-prefixed attribute `name`.
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attribute(name).map(|a| a.value.as_ref())
    }

    /// The un-prefixed attribute `name`.
    pub fn attribute(&self, name: &str) -> Option<&Attr<'a>> {
        self.attrs.iter().find(|a| !a.prefixed && a.name == name)
    }
}

/// A top-level `<joint>` and its child elements (their own children are not kept).
pub(super) struct JointEl<'a> {
    pub el: El<'a>,
    pub children: Vec<El<'a>>,
}

impl<'a> JointEl<'a> {
    /// The first child element named `tag`.
    pub fn child(&self, tag: &str) -> Option<&El<'a>> {
        self.children.iter().find(|c| c.name == tag)
    }
}

/// What the first pass keeps: the root, the first xacro element or
/// attribute, the links and the number of joints.
pub(super) struct Outline<'a> {
    pub root: El<'a>,
    /// The first element (document order) in a xacro namespace or with
    /// `${` / `$(` in an attribute value.
    pub xacro: Option<El<'a>>,
    /// Top-level `<link>`: name (if any) and start offset.
    pub links: Vec<(Option<Cow<'a, str>>, usize)>,
    /// Number of top-level `<joint>` elements.
    pub joints: usize,
}

/// The first pass: the whole text checked, the outline kept.
pub(super) fn outline<'a>(text: &'a str, path: &Path) -> Result<Outline<'a>> {
    let mut w = Walker::new(text, path);
    w.check_chars()?;
    let mut root = None;
    let mut first_xacro = None;
    let mut links = Vec::new();
    let mut joints = 0;
    w.walk(|w, depth, e, xacro_ns, start| {
        // Checked without collecting: only the root and the first xacro
        // element are kept whole.
        let (mut expr, mut name) = (false, None);
        w.attributes(e, start, |a| {
            expr |= a.value.contains("${") || a.value.contains("$(");
            if !a.prefixed && a.name == "name" {
                name = Some(a.value);
            }
        })?;
        if first_xacro.is_none() && (xacro_ns || expr) {
            first_xacro = Some(w.element(e, start, xacro_ns)?);
        }
        match (depth, local(w.text, e)) {
            (1, _) => root = Some(w.element(e, start, xacro_ns)?),
            (2, Some("link")) => links.push((name, start)),
            (2, Some("joint")) => joints += 1,
            _ => {}
        }
        Ok(())
    })?;
    let root = root.ok_or_else(|| w.fail(text.len(), "no root element"))?;
    Ok(Outline {
        root,
        xacro: first_xacro,
        links,
        joints,
    })
}

/// The second pass: each top-level `<joint>` with its child elements, in
/// file order (the text was checked by [`outline`]).
pub(super) fn joints<'a>(
    text: &'a str,
    path: &Path,
    mut f: impl FnMut(JointEl<'a>) -> Result<()>,
) -> Result<()> {
    let mut w = Walker::new(text, path);
    w.validated = true;
    let mut cur: Option<JointEl<'a>> = None;
    w.walk(|w, depth, e, xacro_ns, start| {
        match depth {
            2 => {
                if let Some(j) = cur.take() {
                    f(j)?;
                }
                if local(w.text, e) == Some("joint") {
                    let el = w.element(e, start, xacro_ns)?;
                    cur = Some(JointEl {
                        el,
                        children: Vec::new(),
                    });
                }
            }
            3 => {
                if let Some(j) = &mut cur {
                    j.children.push(w.element(e, start, xacro_ns)?);
                }
            }
            _ => {}
        }
        Ok(())
    })?;
    match cur {
        Some(j) => f(j),
        None => Ok(()),
    }
}

/// The element's local name, as a slice of the text.
fn local<'a>(text: &'a str, e: &BytesStart) -> Option<&'a str> {
    sub(text, e.local_name().into_inner())
}

/// `s` as a slice of `text` (quick-xml borrows every name and value from it).
fn sub<'a>(text: &'a str, s: &[u8]) -> Option<&'a str> {
    let off = (s.as_ptr() as usize).checked_sub(text.as_ptr() as usize)?;
    text.get(off..off.checked_add(s.len())?)
}

struct Walker<'a, 'p> {
    text: &'a str,
    path: &'p Path,
    /// roxmltree accepted the text: no more suspicion checks.
    validated: bool,
}

impl<'a, 'p> Walker<'a, 'p> {
    fn new(text: &'a str, path: &'p Path) -> Self {
        Walker {
            text,
            path,
            validated: false,
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
    /// U+FFFE, U+FFFF).
    fn check_chars(&mut self) -> Result<()> {
        let b = self.text.as_bytes();
        let bad = b.iter().enumerate().any(|(i, &c)| {
            (c < 0x20 && !matches!(c, b'\t' | b'\n' | b'\r'))
                || (c == 0xEF
                    && b.get(i + 1) == Some(&0xBF)
                    && matches!(b.get(i + 2), Some(0xBE | 0xBF)))
        });
        if bad {
            self.suspect()?;
        }
        Ok(())
    }

    /// Every event in order; `f(walker, depth, start tag, in a xacro
    /// namespace, offset of '<')` for each element (depth 1: the root).
    fn walk<F>(&mut self, mut f: F) -> Result<()>
    where
        F: FnMut(&mut Self, usize, &BytesStart<'a>, bool, usize) -> Result<()>,
    {
        let text = self.text;
        // Namespaces are resolved only while the text is not known to be
        // well-formed (the first pass): the second needs none.
        let mut r = Events::new(text, !self.validated);
        let (mut depth, mut roots) = (0usize, 0usize);
        loop {
            let before = r.position();
            let (xacro_ns, unknown, ev) = match r.next() {
                Ok(x) => x,
                Err(e) => {
                    let at = r.error_position();
                    return Err(self.fail(at, &e.to_string()));
                }
            };
            let after = r.position();
            let raw = text.get(before..after).unwrap_or("");
            match ev {
                Event::Start(ref e) | Event::Empty(ref e) => {
                    if depth == 0 {
                        roots += 1;
                    }
                    if depth >= URDF_MAX_XML_DEPTH {
                        return Err(self.too_deep(before));
                    }
                    if !self.validated && (unknown || roots > 1 || !qname_ok(e.name().as_ref())) {
                        self.suspect()?;
                    }
                    let start = sub(text, e.name().as_ref()).map_or(before, |s| {
                        (s.as_ptr() as usize - text.as_ptr() as usize).saturating_sub(1)
                    });
                    f(self, depth + 1, e, xacro_ns, start)?;
                    if matches!(ev, Event::Start(_)) {
                        depth += 1;
                    }
                }
                Event::End(_) => depth = depth.saturating_sub(1),
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
                Event::Decl(_) if before == 0 && decl_ok(raw) => {}
                Event::Decl(_) | Event::DocType(_) => self.suspect()?,
                Event::PI(_) => {
                    let target = raw
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

    /// The start tag's name and attributes, checked and decoded.
    fn element(&mut self, e: &BytesStart<'a>, start: usize, xacro_ns: bool) -> Result<El<'a>> {
        let name = match local(self.text, e) {
            Some(n) => n,
            None => return Err(self.fail(start, "an element name")),
        };
        let mut attrs = Vec::new();
        self.attributes(e, start, |a| attrs.push(a))?;
        Ok(El {
            name,
            start,
            attrs,
            xacro_ns,
        })
    }

    /// The start tag's attributes (not the namespace declarations), checked,
    /// decoded and handed to `each` in order.
    fn attributes(
        &mut self,
        e: &BytesStart<'a>,
        start: usize,
        mut each: impl FnMut(Attr<'a>),
    ) -> Result<()> {
        let text = self.text;
        for a in e.attributes() {
            let a = match a {
                Ok(a) => a,
                Err(err) => return Err(self.fail(start, &err.to_string())),
            };
            if !self.validated && !qname_ok(a.key.as_ref()) {
                self.suspect()?;
            }
            if a.key.as_namespace_binding().is_some() {
                // xmlns declarations are not attributes (roxmltree).
                if a.value.is_empty() || a.key.prefix().is_some() {
                    self.suspect()?;
                }
                continue;
            }
            let prefixed = a.key.prefix().is_some();
            let (Some(local), Some(raw)) = (
                sub(text, a.key.local_name().into_inner()),
                sub(text, &a.value),
            ) else {
                return Err(self.fail(start, "an attribute"));
            };
            if prefixed || raw.contains('<') || raw.contains("&#") {
                self.suspect()?;
            }
            let Some(value) = decode(raw) else {
                self.suspect()?;
                return Err(self.fail(start, &format!("attribute {local}: an unknown entity")));
            };
            each(Attr {
                name: local,
                value,
                raw,
                prefixed,
            });
        }
        Ok(())
    }
}

/// quick-xml events, with namespaces resolved (`xacro`: in a namespace whose
/// name contains `xacro`; `unknown`: an undeclared prefix) or not.
enum Events<'a> {
    Resolved(NsReader<&'a [u8]>),
    Plain(Reader<&'a [u8]>),
}

impl<'a> Events<'a> {
    fn new(text: &'a str, resolve: bool) -> Self {
        let mut r = if resolve {
            Events::Resolved(NsReader::from_str(text))
        } else {
            Events::Plain(Reader::from_str(text))
        };
        let cfg = match &mut r {
            Events::Resolved(r) => r.config_mut(),
            Events::Plain(r) => r.config_mut(),
        };
        cfg.check_comments = true;
        cfg.check_end_names = true;
        cfg.expand_empty_elements = false;
        cfg.trim_text(false);
        r
    }

    /// The next event: (in a xacro namespace, undeclared prefix, event).
    fn next(&mut self) -> quick_xml::Result<(bool, bool, Event<'a>)> {
        match self {
            Events::Resolved(r) => r.read_resolved_event().map(|(res, ev)| {
                (
                    matches!(&res, ResolveResult::Bound(ns) if contains(ns.as_ref(), b"xacro")),
                    matches!(res, ResolveResult::Unknown(_)),
                    ev,
                )
            }),
            Events::Plain(r) => r.read_event().map(|ev| (false, false, ev)),
        }
    }

    fn position(&self) -> usize {
        let p = match self {
            Events::Resolved(r) => r.buffer_position(),
            Events::Plain(r) => r.buffer_position(),
        };
        usize::try_from(p).unwrap_or(usize::MAX)
    }

    fn error_position(&self) -> usize {
        let p = match self {
            Events::Resolved(r) => r.error_position(),
            Events::Plain(r) => r.error_position(),
        };
        usize::try_from(p).unwrap_or(usize::MAX)
    }
}

fn contains(hay: &[u8], needle: &[u8]) -> bool {
    hay.windows(needle.len()).any(|w| w == needle)
}

/// An ASCII XML name, or two joined by one `:` (a non-ASCII name is left to
/// roxmltree).
fn qname_ok(name: &[u8]) -> bool {
    let part = |p: &[u8]| {
        p.first()
            .is_some_and(|&c| c.is_ascii_alphabetic() || c == b'_')
            && p.iter()
                .all(|&c| c.is_ascii_alphanumeric() || matches!(c, b'_' | b'-' | b'.'))
    };
    let mut it = name.splitn(2, |&c| c == b':');
    match (it.next(), it.next()) {
        (Some(a), None) => part(a),
        (Some(a), Some(b)) => part(a) && part(b),
        _ => false,
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

/// The character an entity or character reference stands for.
fn entity(name: &str) -> Option<char> {
    let code = if let Some(h) = name.strip_prefix("#x") {
        u32::from_str_radix(h, 16).ok()?
    } else if let Some(d) = name.strip_prefix('#') {
        d.parse().ok()?
    } else {
        return match name {
            "lt" => Some('<'),
            "gt" => Some('>'),
            "amp" => Some('&'),
            "apos" => Some('\''),
            "quot" => Some('"'),
            _ => None,
        };
    };
    char::from_u32(code)
}

/// An attribute value as XML reads it: literal tab, CR, LF (a CR LF pair
/// counting once) become spaces; the five predefined entities and character
/// references are replaced (a reference's character is kept as is). `None`
/// for any other entity.
fn decode(raw: &str) -> Option<Cow<'_, str>> {
    if !raw.contains(['&', '\t', '\n', '\r']) {
        return Some(Cow::Borrowed(raw));
    }
    let mut out = String::with_capacity(raw.len());
    let mut rest = raw;
    while let Some(i) = rest.find(['&', '\t', '\n', '\r']) {
        out.push_str(&rest[..i]);
        let tail = &rest[i..];
        if let Some(t) = tail.strip_prefix("\r\n") {
            out.push(' ');
            rest = t;
        } else if tail.starts_with('&') {
            let end = tail.find(';')?;
            out.push(entity(&tail[1..end])?);
            rest = &tail[end + 1..];
        } else {
            out.push(' ');
            rest = &tail[1..];
        }
    }
    out.push_str(rest);
    Some(Cow::Owned(out))
}

#[cfg(test)]
mod tests {
    use super::{decl_ok, decode, joints, outline, qname_ok};
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
        let o = outline(text, Path::new("t.urdf")).unwrap();
        let root = doc.root_element();
        assert_eq!(o.root.attr("name"), root.attribute("name"));
        assert_eq!(o.root.start, root.range().start);
        let links: Vec<_> = root.children().filter(|n| n.has_tag_name("link")).collect();
        assert_eq!(o.links.len(), links.len());
        for ((name, start), l) in o.links.iter().zip(&links) {
            assert_eq!(name.as_deref(), l.attribute("name"));
            assert_eq!(*start, l.range().start);
        }
        let j = root.children().find(|n| n.has_tag_name("joint")).unwrap();
        let mut seen = 0;
        joints(text, Path::new("t.urdf"), |je| {
            seen += 1;
            assert_eq!(je.el.attr("name"), j.attribute("name"));
            assert_eq!(je.el.start, j.range().start);
            let kids: Vec<_> = j.children().filter(|n| n.is_element()).collect();
            assert_eq!(je.children.len(), kids.len());
            for (c, k) in je.children.iter().zip(&kids) {
                assert_eq!(c.name, k.tag_name().name());
                assert_eq!(c.start, k.range().start);
                for a in k.attributes() {
                    assert_eq!(c.attr(a.name()), Some(a.value()), "{}", a.name());
                    assert_eq!(c.attribute(a.name()).unwrap().raw, &text[a.range_value()]);
                }
            }
            Ok(())
        })
        .unwrap();
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
        let o = outline(text, Path::new("t.urdf")).unwrap();
        assert!(o.xacro.is_some_and(|e| e.name == "robot" && e.xacro_ns));
    }

    #[test]
    fn attribute_values_decode_as_xml_reads_them() {
        assert_eq!(decode("a b").unwrap(), "a b");
        assert_eq!(decode("a\tb\r\nc\rd\ne").unwrap(), "a b c d e");
        assert_eq!(decode("&lt;&amp;&gt;&apos;&quot;").unwrap(), "<&>'\"");
        assert_eq!(decode("a&#9;b&#x41;").unwrap(), "a\tbA");
        assert!(decode("&nbsp;").is_none());
        assert!(decode("a & b").is_none());
    }

    #[test]
    fn names_and_declarations() {
        assert!(qname_ok(b"robot") && qname_ok(b"xacro:macro") && qname_ok(b"_a-1.b"));
        assert!(
            !qname_ok(b"1a") && !qname_ok(b"a:b:c") && !qname_ok(b"") && !qname_ok("é".as_bytes())
        );
        assert!(decl_ok("<?xml version=\"1.0\"?>"));
        assert!(decl_ok(
            "<?xml version='1.0' encoding='UTF-8' standalone=\"yes\" ?>"
        ));
        assert!(!decl_ok("<?xml version=\"2.0\"?>"));
        assert!(!decl_ok("<?xml encoding=\"UTF-8\"?>"));
        assert!(!decl_ok("<?xml version=\"1.0\" foo=\"1\"?>"));
    }
}
