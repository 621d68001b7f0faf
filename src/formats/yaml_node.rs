//! The YAML tree both readers build (`yaml`'s serde-saphyr path and
//! `yaml_subset`'s fast one): a leaf module, so that the subset reader, which
//! `yaml` calls, needs nothing from `yaml` (no import cycle). Its methods are
//! in `yaml`.

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
