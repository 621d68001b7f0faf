//! The XML tree the expander works on: owned elements that remember the file,
//! line and column they were written at (macro bodies and blocks are cloned
//! and evaluated many times), read with roxmltree and written back as text
//! with a map from each output line to the source element that produced it.
//!
//! Names: an element or attribute in the xacro namespace is named `xacro:x`
//! whatever prefix the file used (as Python xacro expects it to be spelled);
//! another namespace keeps its prefix, declared again on the output root.

use crate::diagnostic::{Error, Location, Result};
use crate::formats::source::LineIndex;
use crate::formats::xml;
use crate::tolerances::XACRO_MAX_ELEMENT_DEPTH;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// Where an element was written.
#[derive(Debug, Clone, PartialEq)]
pub struct Src {
    pub file: Rc<PathBuf>,
    pub line: usize,
    pub col: usize,
    /// Line of the element's end tag.
    pub end_line: usize,
}

impl Src {
    pub fn location(&self) -> Location {
        Location::at(self.file.as_path(), self.line, Some(self.col))
    }
}

#[derive(Debug, Clone)]
pub enum Node {
    Elem(Elem),
    Text(String),
}

#[derive(Debug, Clone)]
pub struct Elem {
    pub name: String,
    pub attrs: Vec<(String, String)>,
    pub children: Vec<Node>,
    pub src: Src,
}

impl Elem {
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// Set an attribute, keeping its place when it exists (as a DOM does).
    pub fn set_attr(&mut self, name: &str, value: String) {
        match self.attrs.iter_mut().find(|(k, _)| k == name) {
            Some(slot) => slot.1 = value,
            None => self.attrs.push((name.to_string(), value)),
        }
    }

    pub fn child_elements(&self) -> impl Iterator<Item = &Elem> {
        self.children.iter().filter_map(|n| match n {
            Node::Elem(e) => Some(e),
            _ => None,
        })
    }
}

/// A parsed file: its root element and the non-xacro namespaces it declares.
#[derive(Debug)]
pub struct Doc {
    pub root: Elem,
    pub namespaces: BTreeMap<String, String>,
}

/// Whether a namespace URI is xacro's (`http://www.ros.org/wiki/xacro`, also
/// spelled without `www.`).
pub fn is_xacro_ns(uri: &str) -> bool {
    uri.trim_end_matches('/').ends_with("ros.org/wiki/xacro")
}

/// The xacro namespace declaration added when a file uses the `xacro:` prefix
/// without declaring it (Python xacro does not check namespaces).
const XACRO_DECL: &str = " xmlns:xacro=\"http://www.ros.org/wiki/xacro\"";

/// Parse one file's text.
pub fn parse(text: &str, file: Rc<PathBuf>) -> Result<Doc> {
    let patched;
    let mut src_text = text;
    let doc = match roxmltree::Document::parse_with_options(text, xml::parse_options()) {
        Ok(d) => d,
        Err(roxmltree::Error::UnknownNamespace(p, _)) if p == "xacro" => {
            patched = declare_xacro(text).ok_or_else(|| {
                Error::parse("the `xacro:` prefix is used but never declared").in_file(&*file)
            })?;
            src_text = &patched;
            roxmltree::Document::parse_with_options(&patched, xml::parse_options())
                .map_err(|e| xml::error(&e, &patched).in_file(&*file))?
        }
        Err(e) => return Err(xml::error(&e, text).in_file(&*file)),
    };
    let idx = LineIndex::new(src_text);
    let mut namespaces = BTreeMap::new();
    let root = convert(doc.root_element(), &idx, &file, &mut namespaces, 1)
        .map_err(|e| e.in_file(&*file))?;
    Ok(Doc { root, namespaces })
}

/// Insert the xacro declaration after the root element's name (same line, so
/// line numbers stay).
fn declare_xacro(text: &str) -> Option<String> {
    let mut search = 0;
    loop {
        let lt = search + text[search..].find('<')?;
        let rest = &text[lt + 1..];
        if rest.starts_with('?') || rest.starts_with('!') {
            let close = if rest.starts_with("!--") { "-->" } else { ">" };
            search = lt + 1 + rest.find(close)? + close.len();
            continue;
        }
        let name_len = rest
            .find(|c: char| c.is_whitespace() || c == '>' || c == '/')
            .unwrap_or(rest.len());
        let at = lt + 1 + name_len;
        return Some(format!("{}{XACRO_DECL}{}", &text[..at], &text[at..]));
    }
}

fn qualified(
    node: roxmltree::Node,
    ns: Option<&str>,
    local: &str,
    namespaces: &mut BTreeMap<String, String>,
) -> String {
    match ns {
        Some(uri) if is_xacro_ns(uri) => format!("xacro:{local}"),
        Some(uri) => match node.lookup_prefix(uri) {
            Some(p) if !p.is_empty() => {
                namespaces.insert(p.to_string(), uri.to_string());
                format!("{p}:{local}")
            }
            _ => local.to_string(),
        },
        None => local.to_string(),
    }
}

/// One element and its children, at most `XACRO_MAX_ELEMENT_DEPTH` levels
/// (the tree is recursive: deeper would overflow the stack here and when
/// it is dropped).
fn convert(
    n: roxmltree::Node,
    idx: &LineIndex,
    file: &Rc<PathBuf>,
    namespaces: &mut BTreeMap<String, String>,
    depth: usize,
) -> Result<Elem> {
    if depth > XACRO_MAX_ELEMENT_DEPTH {
        let (line, col) = idx.pos(n.range().start);
        return Err(Error::limit(format!(
            "elements nested deeper than {XACRO_MAX_ELEMENT_DEPTH} levels: a URDF nests about five"
        ))
        .at(&Location::at(file.as_path(), line, Some(col))));
    }
    let tag = n.tag_name();
    let name = qualified(n, tag.namespace(), tag.name(), namespaces);
    let attrs = n
        .attributes()
        .map(|a| {
            (
                qualified(n, a.namespace(), a.name(), namespaces),
                a.value().to_string(),
            )
        })
        .collect();
    let mut children = Vec::new();
    for c in n.children() {
        if c.is_element() {
            children.push(Node::Elem(convert(c, idx, file, namespaces, depth + 1)?));
        } else if c.is_text() {
            children.push(Node::Text(c.text().unwrap_or("").to_string()));
        }
    }
    let (line, col) = idx.pos(n.range().start);
    let (end_line, _) = idx.pos(n.range().end);
    Ok(Elem {
        name,
        attrs,
        children,
        src: Src {
            file: file.clone(),
            line,
            col,
            end_line,
        },
    })
}

/// Output text and, for each output line that starts an element, where that
/// element was written (sorted by output line).
pub struct Written {
    pub text: String,
    pub lines: Vec<(usize, Src)>,
    /// For each `<joint>` (by output line) whose `<origin>` was not written
    /// inside it (a block passed to a macro, maybe from another file), where
    /// the `<origin>` was written.
    pub origins: Vec<(usize, Src)>,
}

/// Write the expanded tree: one element start per line, whitespace-only text
/// dropped, comments dropped.
pub fn write(mut root: Elem, namespaces: &BTreeMap<String, String>) -> Written {
    let mut w = Writer {
        out: String::from("<?xml version=\"1.0\"?>\n"),
        line: 2,
        lines: Vec::new(),
        origins: Vec::new(),
    };
    for (p, uri) in namespaces {
        root.set_attr(&format!("xmlns:{p}"), uri.clone());
    }
    w.elem(&root, 0);
    Written {
        text: w.out,
        lines: w.lines,
        origins: w.origins,
    }
}

struct Writer {
    out: String,
    line: usize,
    lines: Vec<(usize, Src)>,
    origins: Vec<(usize, Src)>,
}

impl Writer {
    fn push(&mut self, s: &str) {
        self.line += s.bytes().filter(|b| *b == b'\n').count();
        self.out.push_str(s);
    }

    fn elem(&mut self, e: &Elem, depth: usize) {
        self.lines.push((self.line, e.src.clone()));
        if e.name == "joint" {
            if let Some(o) = e.child_elements().find(|c| c.name == "origin") {
                let inside =
                    o.src.file == e.src.file && (e.src.line..=e.src.end_line).contains(&o.src.line);
                if !inside {
                    self.origins.push((self.line, o.src.clone()));
                }
            }
        }
        let mut head = format!("{}<{}", "  ".repeat(depth.min(64)), e.name);
        for (k, v) in &e.attrs {
            let _ = write!(head, " {k}=\"{}\"", escape(v, true));
        }
        let kids: Vec<&Node> = e
            .children
            .iter()
            .filter(|n| match n {
                Node::Elem(_) => true,
                Node::Text(t) => !t.trim().is_empty(),
            })
            .collect();
        if kids.is_empty() {
            head.push_str("/>\n");
            self.push(&head);
            return;
        }
        head.push('>');
        let only_text = kids.iter().all(|n| matches!(n, Node::Text(_)));
        if !only_text {
            head.push('\n');
        }
        self.push(&head);
        for k in kids {
            match k {
                Node::Elem(c) => self.elem(c, depth + 1),
                Node::Text(t) => self.push(&escape(t, false)),
            }
        }
        let indent = if only_text {
            String::new()
        } else {
            "  ".repeat(depth.min(64))
        };
        self.push(&format!("{indent}</{}>\n", e.name));
    }
}

fn escape(s: &str, attr: bool) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' if attr => out.push_str("&quot;"),
            '\n' if attr => out.push_str("&#10;"),
            '\t' if attr => out.push_str("&#9;"),
            '\r' => out.push_str("&#13;"),
            c => out.push(c),
        }
    }
    out
}

/// A file's path as given, for `Src` (shared by all its elements).
pub fn file_ref(p: &Path) -> Rc<PathBuf> {
    Rc::new(p.to_path_buf())
}

/// An error at an element, with the macro calls that led there (innermost
/// first, at most three).
pub fn err_at(src: &Src, msg: impl Into<String>, stack: &[String]) -> Error {
    let mut m = msg.into();
    if !stack.is_empty() {
        let shown: Vec<&str> = stack.iter().rev().take(3).map(String::as_str).collect();
        let more = stack.len().saturating_sub(3);
        m = format!(
            "{m} (in macro {}{})",
            shown.join(", from macro "),
            if more > 0 {
                format!(", and {more} outer macro call(s)")
            } else {
                String::new()
            }
        );
    }
    Error::parse(m).at(&src.location())
}
