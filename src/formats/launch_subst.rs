//! Launch XML substitutions and conditions: what roslaunch (ROS 1) and
//! `ros2 launch` (XML) would decide before starting a node, where the file
//! alone (and `--arg NAME=VALUE`) says it.
//!
//! - `<arg name="x" default="v"/>` declares `x` with a default that
//!   `--arg x=...` overrides; `<arg name="x" value="v"/>` (and ROS 2
//!   `<let name="x" value="v"/>`) fixes it; launch YAML's
//!   `arg: {name, default}` / `let: {name, value}` the same. Args are
//!   file-wide.
//! - `$(arg x)` (ROS 1) and `$(var x)` (ROS 2) are replaced by that value; a
//!   default may itself use `$(arg y)`. `$(eval ...)` is evaluated as
//!   roslaunch (ROS 1) or `ros2 launch` (ROS 2) evaluates it, statically (see
//!   `launch_eval`); the file is ROS 2 when it declares `<let>`, starts a
//!   node with `exec=` or uses `$(var ...)`, and launch YAML and Python files
//!   always are. Any other substitution (`$(find ...)`, `$(env ...)`) is left
//!   for the caller to refuse.
//! - `if="..."` / `unless="..."` on a node or on any enclosing element
//!   (`<group>`, `<include>`; in launch YAML an `if:` / `unless:` key on the
//!   node or an enclosing mapping): the value, once substituted, must be `true`,
//!   `false`, `1` or `0` (any case, as roslaunch reads them); a node whose
//!   condition is off is not started.
//!
//! A value that cannot be known from the file is refused, naming the
//! `--arg` to pass.

use super::launch_eval::{closing, eval_ros1, eval_ros2, ArgSource};
use crate::diagnostic::{Error, Location, Result};
use crate::sanitize::quote;
use std::collections::BTreeMap;

/// Nesting of `$(arg ...)` inside arg defaults followed before giving up (a
/// default that names itself would loop).
const MAX_ARG_DEPTH: usize = 16;

/// One `<arg>` / `<let>` (or launch YAML `arg:`) declaration.
#[derive(Debug, Clone)]
pub struct ArgDecl {
    /// The arg's name.
    pub name: String,
    /// `value=`: fixed.
    pub value: Option<String>,
    /// `default=`: overridden by `--arg`.
    pub default: Option<String>,
}

/// One `if` / `unless` condition on a node or an enclosing group.
#[derive(Debug, Clone)]
pub struct Condition {
    /// `if` or `unless`.
    pub attr: &'static str,
    /// The value as written.
    pub raw: String,
    /// Where it sits, for the message: empty on the node itself, else
    /// ` on its enclosing ...`.
    pub place: String,
}

/// How an arg is declared in the file.
#[derive(Debug, Clone)]
enum Decl {
    /// `value=` (or `<let>`): fixed.
    Value(String),
    /// `default=`: `--arg` overrides it.
    Default(String),
    /// Declared without a value: only `--arg` gives one.
    Free,
}

/// The args of one launch file, with the values given on the command line.
pub struct LaunchArgs<'a> {
    declared: BTreeMap<String, Decl>,
    given: &'a BTreeMap<String, String>,
    /// ROS 2 substitution rules (`$(eval)` anywhere, inner substitutions
    /// first); else roslaunch's.
    ros2: bool,
}

impl<'a> LaunchArgs<'a> {
    /// Collect the `<arg>` and `<let>` declarations of `doc`.
    pub fn new(doc: &roxmltree::Document, given: &'a BTreeMap<String, String>) -> Self {
        let decls = doc
            .descendants()
            .filter(|n| n.is_element() && matches!(n.tag_name().name(), "arg" | "let"))
            .filter_map(|n| {
                let name = n.attribute("name")?;
                Some(ArgDecl {
                    name: name.to_string(),
                    value: n.attribute("value").map(String::from),
                    default: n.attribute("default").map(String::from),
                })
            });
        let ros2 = doc.descendants().any(|n| {
            n.is_element() && (n.tag_name().name() == "let" || n.attribute("exec").is_some())
        }) || doc.input_text().contains("$(var ");
        LaunchArgs {
            ros2,
            ..Self::from_decls(decls, given)
        }
    }

    /// Args from their declarations (the first declaration of a name counts).
    pub fn from_decls(
        decls: impl IntoIterator<Item = ArgDecl>,
        given: &'a BTreeMap<String, String>,
    ) -> Self {
        let mut declared = BTreeMap::new();
        for d in decls {
            let decl = match (d.value, d.default) {
                (Some(v), _) => Decl::Value(v),
                (None, Some(x)) => Decl::Default(x),
                (None, None) => Decl::Free,
            };
            declared.entry(d.name).or_insert(decl);
        }
        LaunchArgs {
            declared,
            given,
            ros2: true,
        }
    }

    /// `s` with every `$(arg x)` / `$(var x)` replaced by its value.
    pub fn resolve(&self, s: &str, loc: &Location) -> Result<String> {
        self.resolve_depth(s, loc, 0)
    }

    fn resolve_depth(&self, s: &str, loc: &Location, depth: usize) -> Result<String> {
        if depth > MAX_ARG_DEPTH {
            return Err(Error::parse(format!(
                "launch arg defaults nest more than {MAX_ARG_DEPTH} deep at {}: expected a default that does not refer to itself",
                quote(s)
            ))
            .at(loc));
        }
        // roslaunch: `$(eval ...)` only as the whole value.
        if !self.ros2 && s.starts_with("$(eval ") && s.ends_with(')') {
            return eval_ros1(&s[7..s.len() - 1], self, loc, depth);
        }
        let mut out = String::with_capacity(s.len());
        let mut rest = s;
        while let Some(at) = rest.find("$(") {
            out.push_str(&rest[..at]);
            if rest[at..].starts_with("$(eval ") || rest[at..].starts_with("$(eval)") {
                let Some(close) = closing(rest, at) else {
                    return Err(Error::parse(format!(
                        "{}: `$(eval` without its closing `)`",
                        quote(s)
                    ))
                    .at(loc));
                };
                if !self.ros2 {
                    return Err(Error::parse(format!(
                        "{}: roslaunch evaluates $(eval ...) only when it is the whole attribute value; inside other text `eval` is an unknown substitution command and roslaunch refuses the file",
                        quote(s)
                    ))
                    .at(loc));
                }
                let inner = self.resolve_depth(&rest[at + 7..close], loc, depth + 1)?;
                out.push_str(&eval_ros2(&inner, loc)?);
                rest = &rest[close + 1..];
                continue;
            }
            let after = &rest[at + 2..];
            let Some(close) = after.find(')') else {
                out.push_str(&rest[at..]);
                return Ok(out);
            };
            let inner = after[..close].trim();
            let mut words = inner.split_whitespace();
            match (words.next(), words.next(), words.next()) {
                (Some("arg" | "var"), Some(name), None) => {
                    let v = self.value(name, loc)?;
                    out.push_str(&self.resolve_depth(&v, loc, depth + 1)?);
                }
                // Another substitution: kept, for the caller to refuse.
                _ => out.push_str(&rest[at..at + 3 + close]),
            }
            rest = &after[close + 1..];
        }
        out.push_str(rest);
        Ok(out)
    }

    /// The value of arg `name`: fixed in the file, else given, else the default.
    fn value(&self, name: &str, loc: &Location) -> Result<String> {
        match (self.declared.get(name), self.given.get(name)) {
            (Some(Decl::Value(v)), _) => Ok(v.clone()),
            (_, Some(v)) => Ok(v.clone()),
            (Some(Decl::Default(d)), None) => Ok(d.clone()),
            (Some(Decl::Free), None) => Err(Error::parse(format!(
                "$(arg {}) is declared without a default: its value is not known from the file; pass --arg {}=VALUE",
                quote(name),
                quote(name)
            ))
            .at(loc)),
            (None, None) => Err(Error::parse(format!(
                "$(arg {}) is not declared in this file (it comes from an including launch file); pass --arg {}=VALUE",
                quote(name),
                quote(name)
            ))
            .at(loc)),
        }
    }

    /// Why `node` is not started, when an `if` / `unless` on it or on an
    /// enclosing element is off; `None` when it runs.
    pub fn switched_off(&self, node: roxmltree::Node, loc: &Location) -> Result<Option<String>> {
        let mut conds = Vec::new();
        for n in node.ancestors().filter(|n| n.is_element()) {
            let place = if n == node {
                String::new()
            } else {
                format!(" on its enclosing <{}>", n.tag_name().name())
            };
            for attr in ["if", "unless"] {
                if let Some(raw) = n.attribute(attr) {
                    conds.push(Condition {
                        attr,
                        raw: raw.to_string(),
                        place: place.clone(),
                    });
                }
            }
        }
        self.first_off(&conds, loc)
    }

    /// The first condition that is off, described; `None` when all hold.
    pub fn first_off(&self, conds: &[Condition], loc: &Location) -> Result<Option<String>> {
        for c in conds {
            let runs_when = c.attr == "if";
            if self.truth(&c.raw, c.attr, loc)? != runs_when {
                return Ok(Some(format!("{}=\"{}\"{}", c.attr, quote(&c.raw), c.place)));
            }
        }
        Ok(None)
    }

    /// The truth of a condition attribute, as roslaunch reads it.
    fn truth(&self, raw: &str, attr: &str, loc: &Location) -> Result<bool> {
        let v = self.resolve(raw, loc)?;
        match v.trim().to_ascii_lowercase().as_str() {
            "true" | "1" => Ok(true),
            "false" | "0" => Ok(false),
            _ if v.contains("$(") => Err(Error::parse(format!(
                "{attr}=\"{}\": the substitution cannot be evaluated here: expected true, false, 1, 0 or $(arg NAME) with a known value",
                quote(raw)
            ))
            .at(loc)),
            _ => Err(Error::parse(format!(
                "{attr}=\"{}\" is {}: expected true, false, 1 or 0",
                quote(raw),
                quote(&v)
            ))
            .at(loc)),
        }
    }
}

/// What `$(eval ...)` reads of the args (ROS 1 names them bare).
impl ArgSource for LaunchArgs<'_> {
    /// Whether the file declares arg `name` or `--arg` gives it.
    fn declares(&self, name: &str) -> bool {
        self.declared.contains_key(name) || self.given.contains_key(name)
    }

    /// The value of arg `name`, its own substitutions resolved.
    fn arg_value(&self, name: &str, loc: &Location, depth: usize) -> Result<String> {
        let v = self.value(name, loc)?;
        self.resolve_depth(&v, loc, depth + 1)
    }
}
