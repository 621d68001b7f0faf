//! YAML with positions: every node keeps the line and column it was read from.
//!
//! Built on serde-saphyr (chosen over the `saphyr` crate because it already is
//! the project's YAML dependency, has budgets against alias bombs and deep
//! nesting, a multi-document API and `Spanned<T>` locations). OpenCV FileStorage
//! files start with `%YAML:1.0`, which is not a valid YAML directive: that line is
//! blanked (line numbers stay) before parsing. Tags such as `!!opencv-matrix` are
//! ignored by the parser; the matrix is read from its `rows`, `cols`, `data`.
//! Duplicate keys are kept in order (policy "pass through") so that a loader can
//! say where both copies are.

use crate::diagnostic::{Error, Result};
use crate::tolerances::MAX_YAML_DEPTH;
use serde::de::{Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_saphyr::Spanned;
use std::cell::RefCell;
use std::rc::Rc;

pub use super::yaml_node::{Node, Value};

struct Raw(Value);

impl<'de> Deserialize<'de> for Raw {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Raw;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("any YAML value")
            }
            fn visit_bool<E>(self, v: bool) -> std::result::Result<Raw, E> {
                Ok(Raw(Value::Bool(v)))
            }
            fn visit_i64<E>(self, v: i64) -> std::result::Result<Raw, E> {
                Ok(Raw(Value::Num(v as f64)))
            }
            fn visit_u64<E>(self, v: u64) -> std::result::Result<Raw, E> {
                Ok(Raw(Value::Num(v as f64)))
            }
            fn visit_i128<E>(self, v: i128) -> std::result::Result<Raw, E> {
                Ok(Raw(Value::Num(v as f64)))
            }
            fn visit_u128<E>(self, v: u128) -> std::result::Result<Raw, E> {
                Ok(Raw(Value::Num(v as f64)))
            }
            fn visit_f64<E>(self, v: f64) -> std::result::Result<Raw, E> {
                Ok(Raw(Value::Num(v)))
            }
            fn visit_str<E>(self, v: &str) -> std::result::Result<Raw, E> {
                Ok(Raw(Value::Str(v.to_string())))
            }
            fn visit_string<E>(self, v: String) -> std::result::Result<Raw, E> {
                Ok(Raw(Value::Str(v)))
            }
            fn visit_unit<E>(self) -> std::result::Result<Raw, E> {
                Ok(Raw(Value::Null))
            }
            fn visit_none<E>(self) -> std::result::Result<Raw, E> {
                Ok(Raw(Value::Null))
            }
            fn visit_some<D2: Deserializer<'de>>(
                self,
                d: D2,
            ) -> std::result::Result<Raw, D2::Error> {
                Raw::deserialize(d)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut a: A) -> std::result::Result<Raw, A::Error> {
                let mut v = Vec::new();
                while let Some(x) = a.next_element::<Spanned<Raw>>()? {
                    v.push(node(x));
                }
                Ok(Raw(Value::Seq(v)))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut a: A) -> std::result::Result<Raw, A::Error> {
                let mut v = Vec::new();
                while let Some(k) = a.next_key::<Spanned<Raw>>()? {
                    let val = a.next_value::<Spanned<Raw>>()?;
                    v.push((node(k), node(val)));
                }
                Ok(Raw(Value::Map(v)))
            }
        }
        d.deserialize_any(V)
    }
}

fn node(s: Spanned<Raw>) -> Node {
    Node {
        value: s.value.0,
        line: s.referenced.line() as usize,
        column: s.referenced.column() as usize,
    }
}

/// Blank a leading OpenCV `%YAML:1.0` line (keeps line numbers).
pub fn strip_opencv_directive(text: &str) -> std::borrow::Cow<'_, str> {
    let first = text.lines().next().unwrap_or("");
    if first.trim_start().starts_with("%YAML:") {
        let rest = &text[first.len()..];
        std::borrow::Cow::Owned(rest.to_string())
    } else {
        std::borrow::Cow::Borrowed(text)
    }
}

fn options() -> serde_saphyr::options::Options {
    let mut o = serde_saphyr::options::Options::default();
    let mut budget = o.budget.clone().unwrap_or_default();
    budget.max_depth = MAX_YAML_DEPTH;
    budget.flow_nesting_limit = MAX_YAML_DEPTH;
    o.budget = Some(budget);
    o.duplicate_keys = serde_saphyr::options::DuplicateKeyPolicy::PassThrough;
    // `y:` is a coordinate key in tf dumps, not YAML 1.1's boolean.
    o.strict_booleans = true;
    o
}

fn yaml_error(e: serde_saphyr::Error) -> Error {
    // The crate's Display carries a source snippet; keep the first line.
    let full = e.to_string();
    let first = full.lines().next().unwrap_or("").trim().to_string();
    let (line, col, msg) = split_position(&first);
    let mut err = if msg.contains("budget") || msg.contains("recursion limit") {
        Error::limit(format!(
            "YAML beyond the reader's limits ({msg}): expected a calibration file, found an alias bomb or deep nesting"
        ))
    } else {
        Error::parse(format!("not valid YAML: {msg}"))
    };
    if let Some(l) = line {
        err = err.at_line(l, col);
    }
    err
}

/// `error: line 6 column 1: message` -> (6, 1, message).
fn split_position(s: &str) -> (Option<usize>, Option<usize>, String) {
    let s = s.strip_prefix("error: ").unwrap_or(s);
    if let Some(rest) = s.strip_prefix("line ") {
        let mut it = rest.splitn(2, ':');
        let pos = it.next().unwrap_or("");
        let msg = it.next().unwrap_or("").trim().to_string();
        let mut p = pos.split_whitespace();
        let line = p.next().and_then(|x| x.parse().ok());
        let col = match (p.next(), p.next()) {
            (Some("column"), Some(c)) => c.parse().ok(),
            _ => None,
        };
        return (line, col, msg);
    }
    (None, None, s.to_string())
}

/// Parse every document of a YAML stream.
///
/// Text in the plain subset most calibration files are written in is read by
/// [`super::yaml_subset`] (the same tree, several times faster); anything
/// else by serde-saphyr, on a large stack ([`crate::stack::deep`]), so the
/// nesting limits hold whatever stack the caller has.
pub fn parse_documents(text: &str) -> Result<Vec<Node>> {
    let text = strip_opencv_directive(text);
    if let Some(docs) = super::yaml_subset::parse(&text) {
        return Ok(docs);
    }
    parse_saphyr(&text)
}

/// The serde-saphyr reader alone (the reference the subset reader is
/// compared with).
fn parse_saphyr(text: &str) -> Result<Vec<Node>> {
    let parse = |t: &str| -> Result<Vec<Node>> {
        let docs: Vec<Spanned<Raw>> =
            serde_saphyr::from_multiple_with_options(t, options()).map_err(yaml_error)?;
        Ok(docs.into_iter().map(node).collect())
    };
    crate::stack::deep("yaml", || parse(text))
}

/// Texts up to this size are kept with their documents by
/// [`parse_documents_shared`] (a calibration file; a larger text is parsed
/// again rather than held twice).
const SHARED_MAX: usize = 1 << 20;

type Shared = Option<(String, Result<Rc<Vec<Node>>>)>;

thread_local! {
    /// The last text [`parse_documents_shared`] read on this thread, and what
    /// it read.
    static LAST: RefCell<Shared> = const { RefCell::new(None) };
}

/// [`parse_documents`], read once per text on each thread: a file is read
/// by the dialect sniffers and then by the dialect that claims it, on the
/// same thread and in a row; the second read is the first's documents.
pub fn parse_documents_shared(text: &str) -> Result<Rc<Vec<Node>>> {
    let hit = LAST.with(|l| match &*l.borrow() {
        Some((t, r)) if t == text => Some(r.clone()),
        _ => None,
    });
    if let Some(r) = hit {
        return r;
    }
    let r = parse_documents(text).map(Rc::new);
    if text.len() <= SHARED_MAX {
        LAST.with(|l| *l.borrow_mut() = Some((text.to_string(), r.clone())));
    }
    r
}

impl Node {
    /// The string form of a scalar key or value.
    pub fn as_str(&self) -> Option<String> {
        match &self.value {
            Value::Str(s) => Some(s.clone()),
            Value::Num(n) => Some(format!("{n}")),
            Value::Bool(b) => Some(format!("{b}")),
            _ => None,
        }
    }
    /// The number a scalar holds: a plain number, or a string that
    /// [`parse_number`](crate::formats::spec::parse_number) reads; `None` otherwise.
    pub fn as_f64(&self) -> Option<f64> {
        match &self.value {
            Value::Num(n) => Some(*n),
            Value::Str(s) => crate::formats::spec::parse_number(s),
            _ => None,
        }
    }
    /// All values under `key` in a map, in file order (duplicates kept).
    pub fn get_all<'a>(&'a self, key: &str) -> Vec<&'a Node> {
        match &self.value {
            Value::Map(m) => m
                .iter()
                .filter(|(k, _)| k.as_str().as_deref() == Some(key))
                .map(|(_, v)| v)
                .collect(),
            _ => vec![],
        }
    }
    /// The last value under `key` (what a YAML reader that keeps the last
    /// duplicate would return).
    pub fn get(&self, key: &str) -> Option<&Node> {
        self.get_all(key).into_iter().last()
    }
    /// The `(key, value)` pairs of a mapping in file order; empty for any other
    /// value.
    pub fn entries(&self) -> &[(Node, Node)] {
        match &self.value {
            Value::Map(m) => m,
            _ => &[],
        }
    }
    /// A short description of the value's type, for messages.
    pub fn kind(&self) -> &'static str {
        match &self.value {
            Value::Map(_) => "a mapping",
            Value::Seq(_) => "a list",
            Value::Num(_) => "a number",
            Value::Str(_) => "a string",
            Value::Bool(_) => "a boolean",
            Value::Null => "nothing",
        }
    }
    /// Flatten a list (possibly nested, e.g. a 4x4 list of rows) into numbers.
    pub fn numbers(&self, what: &str) -> Result<Vec<f64>> {
        let mut out = Vec::new();
        self.collect_numbers(what, &mut out, 0)?;
        Ok(out)
    }
    fn collect_numbers(&self, what: &str, out: &mut Vec<f64>, depth: usize) -> Result<()> {
        match &self.value {
            Value::Seq(items) if depth < 3 => {
                for it in items {
                    it.collect_numbers(what, out, depth + 1)?;
                }
                Ok(())
            }
            _ => match self.as_f64() {
                Some(x) if depth > 0 => {
                    out.push(x);
                    Ok(())
                }
                _ => Err(Error::parse(format!(
                    "{what}: expected a list of numbers, found {}{}",
                    self.kind(),
                    match &self.value {
                        Value::Str(s) => format!(" {:?}", crate::sanitize::clip(s)),
                        _ => String::new(),
                    }
                ))
                .at_line(self.line.max(1), Some(self.column.max(1)))),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::{Path, PathBuf};

    /// Whether the subset reader took `t`; when it did, serde-saphyr must
    /// read the same tree (values by their `Debug` form, so that `-0` and
    /// `0` differ), positions included.
    fn same_as_saphyr(t: &str) -> bool {
        let t = strip_opencv_directive(t);
        let Some(got) = super::super::yaml_subset::parse(&t) else {
            return false;
        };
        match parse_saphyr(&t) {
            Ok(want) => assert_eq!(format!("{got:?}"), format!("{want:?}"), "{t}"),
            Err(e) => panic!("the subset reader took what serde-saphyr refuses ({e:?}):\n{t}"),
        }
        true
    }

    fn yaml_files(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(rd) = std::fs::read_dir(dir) else {
            return;
        };
        for e in rd {
            let p = e.unwrap().path();
            if p.is_dir() {
                yaml_files(&p, out);
            } else if p.extension().is_some_and(|x| x == "yaml" || x == "yml") {
                out.push(p);
            }
        }
    }

    /// Every YAML file shipped (calibrations/) and under tests/fixtures, and
    /// the test data's when EXTRINSIC_AUDIT_TEST_DATA names it.
    fn shipped_yaml() -> Vec<String> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut paths = Vec::new();
        yaml_files(&root.join("calibrations"), &mut paths);
        yaml_files(&root.join("tests/fixtures"), &mut paths);
        if let Some(d) = std::env::var_os("EXTRINSIC_AUDIT_TEST_DATA") {
            yaml_files(Path::new(&d), &mut paths);
        }
        paths.sort();
        paths
            .iter()
            .filter_map(|p| std::fs::read_to_string(p).ok())
            .collect()
    }

    /// Each line's indent doubled (a deeper but consistent layout).
    fn reindent(t: &str) -> String {
        t.split('\n')
            .map(|l| {
                let n = l.len() - l.trim_start_matches(' ').len();
                format!("{}{l}", " ".repeat(n))
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    fn fleet_file() -> &'static str {
        "base_link:\n  velodyne_top:\n    x: 0.8988561\n    y: 0.0008623\n    z: 2.0011099\n    roll: -0.0000680\n    pitch: 0.0177219\n    yaw: -0.0001115\n"
    }

    #[test]
    fn the_subset_reader_reads_the_files_as_serde_saphyr() {
        let mut files = shipped_yaml();
        files.push(fleet_file().to_string());
        let (mut taken, mut tried) = (0, 0);
        for t in &files {
            let variants = [
                t.clone(),
                t.replace('\n', " # end\n"),
                t.replace(": ", ":   "),
                t.replace(", ", " ,  ").replace('[', "[ "),
                reindent(t),
                t.replace('\n', "\n\n# c\n"),
                t.replace('\n', "\r\n"),
                format!("# head\n{t}"),
                t.replace(" 0.", " -0.").replace(" 1\n", " 1e0\n"),
            ];
            for v in &variants {
                taken += usize::from(same_as_saphyr(v));
                tried += 1;
            }
        }
        // The fleet's file and a good part of the others are in the subset
        // (not the OpenCV files, their tags, block lists, inline maps, CRLF).
        assert!(same_as_saphyr(fleet_file()));
        eprintln!("{taken} of {tried} taken");
        assert!(taken > tried / 6, "{taken} of {tried}");
    }

    #[test]
    fn the_subset_reader_takes_no_edit_serde_saphyr_reads_otherwise() {
        // Single edits at pseudo-random places, with the characters YAML
        // turns on: each either left to serde-saphyr or read exactly as it
        // reads it.
        const EDITS: [&str; 40] = [
            ":", " ", "  ", "#", "-", "- ", ".", "e", "E", "0", "1", "9", "+", "[", "]", ",", "{",
            "}", "\n", "\t", "\r", "'", "\"", "~", "y", "n", "t", "_", "&", "*", "!", "|", ">",
            "?", "%", "@", "x: 1\n", "---\n", "null", "\u{e9}",
        ];
        let mut edits = crate::formats::test_edits::Edits::new();
        let mut files = shipped_yaml();
        files.truncate(40);
        files.push(fleet_file().to_string());
        let (mut taken, mut tried) = (0, 0);
        for t in files {
            let rounds = if t == fleet_file() { 2000 } else { 100 };
            for _ in 0..rounds {
                let v = edits.edit(&t, &EDITS);
                taken += usize::from(same_as_saphyr(&v));
                tried += 1;
            }
        }
        // Many edits keep the file in the subset (a digit, a space): those
        // are the ones compared.
        eprintln!("{taken} of {tried} taken");
        assert!(taken > tried / 10, "{taken} of {tried}");
    }

    #[test]
    fn the_subset_reader_leaves_the_rest_to_serde_saphyr() {
        for t in [
            "a: 01\n",
            "a: 1_000\n",
            "a: .5\n",
            "a: 1.\n",
            "a: +1\n",
            "a: 0x1f\n",
            "a: ~\n",
            "a: True\n",
            "a: \"x\\ty\"\n",
            "a: 'it''s'\n",
            "a: \"\u{e9}\"\n",
            "a: b # \u{2028} c: d\n",
            "a: NaN\n",
            "a:\n",
            "a: b c\n",
            "a: [1, [2]]\n",
            "a: [1,]\n",
            "a: [1,\n2]\n",
            "a: [1,#c\n  2]\n",
            "- 1\n",
            "---\na: 1\n",
            "a: 1\n  b: 2\n",
            "  a: 1\n",
            "a:\tb\n",
            "a: b#c\n",
            "a: &x 1\n",
            "a: 12345678901234567890\n",
            "a: 1e999\n",
            "# only a comment\n",
            "",
        ] {
            assert!(super::super::yaml_subset::parse(t).is_none(), "{t:?}");
        }
        // Every one of them is still read (or refused) as before.
        assert!(parse_documents("a: 01\n").is_ok());
        assert!(parse_documents("a: b\n  c: d\n").is_err());
        let quoted = super::super::yaml_subset::parse("a: 'q # r'\nb: [\"s\", t]\n");
        assert_eq!(quoted, parse_saphyr("a: 'q # r'\nb: [\"s\", t]\n").ok());
        assert!(quoted.is_some());
    }

    #[test]
    fn a_text_is_parsed_once_per_thread() {
        let a = parse_documents_shared(fleet_file()).unwrap();
        let b = parse_documents_shared(fleet_file()).unwrap();
        assert!(Rc::ptr_eq(&a, &b));
        let c = parse_documents_shared("a: 1\n").unwrap();
        assert!(!Rc::ptr_eq(&a, &c));
        assert_eq!(*a, parse_saphyr(fleet_file()).unwrap());
        // An error is kept as well, and is serde-saphyr's.
        let e = parse_documents_shared("a: b\n  c: d\n").unwrap_err();
        assert_eq!(e, parse_documents_shared("a: b\n  c: d\n").unwrap_err());
        assert_eq!(e, parse_saphyr("a: b\n  c: d\n").unwrap_err());
    }
}
