//! xacro: robot descriptions kept as macro files, expanded here without ROS
//! or Python, then read as URDF (see `formats::urdf` for what the numbers mean).
//!
//! The expander follows Python xacro 2.x (`pip install xacro`), the in-order
//! processing of ROS xacro: `xacro:property` (value, default, remove, blocks,
//! `scope`, lazy evaluation), `${...}` (the Python subset of [`expr`]),
//! `$(arg|find|env|optenv|dirname|cwd)` ([`subst`]), `xacro:arg`,
//! `xacro:include` (relative, `$(find pkg)`, `ns`, `optional`), `xacro:macro`
//! with defaults and `*`/`**` block parameters, `xacro:insert_block`,
//! `xacro:if`/`unless`, `xacro:element`/`attribute`, `xacro:call`,
//! `xacro.load_yaml`. Anything outside that is an error naming the file,
//! line and construct; expansion is bounded (`limits`, values in `crate::tolerances`).
//!
//! Provenance: every output element keeps the file, line and column of the
//! element it came from (a joint written inside a macro in an included file
//! points there, not at the call), so each edge names the line of the xacro
//! *source*; URDF errors found after expansion are placed the same way. When
//! the joint's `<origin>` was written elsewhere (a block passed to a macro,
//! where calibrations usually are), the edge's key names that place too.
//!
//! `--xacro external` runs the `xacro` program instead ([`external`]).
//!
//! Known differences from Python xacro 2.1.1 (the reference of the tests):
//! ints are 64-bit (beyond is an error); a complex intermediate (a negative
//! number to a fractional power) is an error; `load_yaml` numbers that are
//! whole become ints (`1.0` reads as `1`: the same number in an attribute);
//! `$(dirname)` gives the current file's directory (xacro 2.1.1 refuses it
//! for lack of context); wildcard includes, `$(eval)`, `xacro:message` and
//! Python outside the subset of [`expr`] are refused; comments are not copied.
//! YAML unit tags (`!degrees 90`) are converted before the YAML is read, the
//! scalar ending at a line end, comment or flow separator.

mod builtins;
mod eval;
mod expand;
mod expr;
pub mod external;
mod format;
mod include;
mod kwargs;
mod limits;
mod macros;
pub(crate) mod markers;
mod methods;
mod ops;
mod scope;
mod subscript;
pub mod subst;
mod tree;
mod value;

use crate::diagnostic::{Error, Location, Result, Warning};
use crate::formats::spec::{FormatSpec, LoadOptions, Parsed};
use crate::formats::urdf;
use std::path::Path;

/// The expanded URDF text and, per output line that starts an element, the
/// source location of that element.
pub struct Expanded {
    /// The expanded URDF.
    pub text: String,
    lines: Vec<(usize, Location)>,
    /// Joint output line -> where its `<origin>` was written.
    origins: std::collections::HashMap<usize, Location>,
    /// Constructs expanded as Python xacro does that are likely not meant.
    pub warnings: Vec<Warning>,
}

impl Expanded {
    /// The source location of output line `line` (the element starting at or
    /// before it).
    pub fn source_of(&self, line: usize) -> Option<&Location> {
        let i = self.lines.partition_point(|(l, _)| *l <= line);
        i.checked_sub(1).map(|i| &self.lines[i].1)
    }
}

/// Expand xacro `text` read from `path` into URDF text with a line map.
pub fn expand(text: &str, path: &Path, opts: &LoadOptions) -> Result<Expanded> {
    let run = || -> Result<Expanded> {
        let file = tree::file_ref(path);
        let doc = tree::parse(text, file)?;
        let mut ex = expand::Expander::new(opts, path);
        let root = ex.run(&doc)?;
        let w = tree::write(root, &ex.namespaces);
        Ok(Expanded {
            text: w.text,
            lines: w
                .lines
                .into_iter()
                .map(|(l, s)| (l, s.location()))
                .collect(),
            origins: w
                .origins
                .into_iter()
                .map(|(l, s)| (l, s.location()))
                .collect(),
            warnings: ex.warnings,
        })
    };
    crate::stack::deep("xacro", run)
}

/// Why an xacro file is an include, not a robot of its own.
#[derive(Debug, Clone, PartialEq)]
pub enum IncludeOnly {
    /// It only defines macros (their names): its root (and any
    /// `xacro:if`/`unless` at the top) holds `xacro:macro`,
    /// `xacro:property`, `xacro:arg` and `xacro:include` only, at least one
    /// macro, no element of its own and no macro call (TurtleBot4's sensor
    /// files).
    Macros(Vec<String>),
    /// Its `<robot>` has no name: ROS refuses a robot without one, so the
    /// file is only ever included (a Clearpath platform package's every
    /// file: materials, gazebo plugins, forwarding includes).
    Nameless,
}

impl IncludeOnly {
    /// Why, for messages.
    pub fn reason(&self) -> String {
        match self {
            IncludeOnly::Macros(m) => {
                let shown: Vec<&str> = m.iter().take(4).map(String::as_str).collect();
                let more = match m.len() {
                    n if n > 4 => format!(", and {} more", n - 4),
                    _ => String::new(),
                };
                format!("defines only macros ({}{more})", shown.join(", "))
            }
            IncludeOnly::Nameless => {
                "has a <robot> without a name (ROS refuses one: the file is only included)".into()
            }
        }
    }
}

/// Whether the xacro file `path` is an include ([`IncludeOnly`]): it has no
/// robot to read until another file includes it. `None`: a robot file, or
/// not an xacro file (not `.xacro`, unreadable, outside `--confine`, not
/// XML).
pub fn include_only(path: &Path, opts: &LoadOptions) -> Option<IncludeOnly> {
    if !path.to_string_lossy().ends_with(".xacro") || opts.check_confined(path).is_err() {
        return None;
    }
    let bytes = crate::input::read_file(path, opts.max_file_size).ok()?;
    let text = crate::input::decode(bytes).ok()?;
    include_kind(&text, path)
}

/// [`include_only`] on text read from `path`.
fn include_kind(text: &str, path: &Path) -> Option<IncludeOnly> {
    let doc = tree::parse(text, tree::file_ref(path)).ok()?;
    let mut macros = Vec::new();
    if library_body(&doc.root, &mut macros) && !macros.is_empty() {
        return Some(IncludeOnly::Macros(macros));
    }
    (doc.root.name == "robot" && doc.root.attr("name").is_none()).then_some(IncludeOnly::Nameless)
}

/// Whether `e`'s children only define things (see `macro_only`), the
/// macro names collected.
fn library_body(e: &tree::Elem, macros: &mut Vec<String>) -> bool {
    e.children.iter().all(|n| match n {
        tree::Node::Text(t) => t.trim().is_empty(),
        tree::Node::Elem(c) => match c.name.as_str() {
            "xacro:macro" => {
                macros.push(c.attr("name").unwrap_or("?").to_string());
                true
            }
            "xacro:property" | "xacro:arg" | "xacro:include" => true,
            "xacro:if" | "xacro:unless" => library_body(c, macros),
            _ => false,
        },
    })
}

/// Move a location in the expanded text to the source element it came from.
fn relocate(loc: &mut Location, x: &Expanded, path: &Path) {
    let ours = loc.file.as_deref().is_none_or(|f| f == path);
    if let (true, Some(l)) = (ours, loc.line) {
        if let Some(src) = x.source_of(l) {
            *loc = src.clone();
        }
    }
}

/// A `.xacro` file: expanded natively (or by the external program with
/// `--xacro external`), then read as URDF with source locations.
pub fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    if opts.xacro_external {
        return external::parse(path, opts);
    }
    if let Some(kind) = include_kind(text, path) {
        return Err(Error::parse(format!(
            "this xacro file {}: it is an include, with no robot of its own; read the file that includes it (`audit check` notes such files and checks them where they are included)",
            kind.reason()
        )));
    }
    let x = expand(text, path, opts)?;
    let mut loaded = urdf::parse(&x.text, path, opts).map_err(|mut e: Error| {
        relocate(&mut e.location, &x, path);
        e.message = format!(
            "{} (in the URDF expanded from {})",
            e.message,
            path.display()
        );
        e
    })?;
    for e in &mut loaded.edges {
        let origin = e.provenance.location.line.and_then(|l| x.origins.get(&l));
        relocate(&mut e.provenance.location, &x, path);
        if let Some(o) = origin {
            e.provenance.key = format!("{} (its <origin> written at {o})", e.provenance.key);
        }
        e.provenance.format = SPEC.id;
    }
    for w in &mut loaded.warnings {
        relocate(&mut w.location, &x, path);
    }
    loaded.warnings.extend(x.warnings);
    Ok(loaded)
}

/// xacro macro files.
pub const SPEC: FormatSpec = FormatSpec {
    id: "xacro",
    description: "xacro macro file: expanded by the built-in expander (--arg NAME=VALUE, --package-path DIR for $(find)), then read as URDF; edges point at the line in the xacro source",
    extensions: &["xacro", "urdf.xacro"],
    walk: &[".xacro"],
    magic: &[],
    sniff: |_| None,
    parse: |i, o| parse(i.text()?, i.path(), o),
    checked: true,
};
