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

/// A YAML value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A mapping: `(key, value)` pairs in file order, duplicate keys kept.
    Map(Vec<(Node, Node)>),
    /// A sequence, in file order.
    Seq(Vec<Node>),
    /// A number (integers converted to `f64`).
    Num(f64),
    /// A string scalar.
    Str(String),
    /// `true` or `false`.
    Bool(bool),
    /// A YAML null.
    Null,
}

/// A YAML value with its 1-based line and column (0 when unknown).
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// The value, with its children.
    pub value: Value,
    /// 1-based line of the node's first character (0 when unknown).
    pub line: usize,
    /// 1-based column of the node's first character (0 when unknown).
    pub column: usize,
}

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
/// Runs on a large stack ([`crate::stack::deep`]), so the nesting limits hold
/// whatever stack the caller has.
pub fn parse_documents(text: &str) -> Result<Vec<Node>> {
    let text = strip_opencv_directive(text);
    let parse = |t: &str| -> Result<Vec<Node>> {
        let docs: Vec<Spanned<Raw>> =
            serde_saphyr::from_multiple_with_options(t, options()).map_err(yaml_error)?;
        Ok(docs.into_iter().map(node).collect())
    };
    crate::stack::deep("yaml", || parse(&text))
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
