//! `xacro:include` (relative to the including file, `$(find pkg)/...`, `ns`,
//! `optional`), `xacro:property` (value, default, remove, block, `scope`,
//! `lazy_eval`) and `xacro.load_yaml`.

use super::expand::Expander;
use super::limits::Meter;
use super::scope::{MacroEntry, MacroScope, MacroTable};
use super::tree::{self, Elem, Node, Src};
use super::value::{eval_literal, Bindings, Res, Scope, Slot, Value};
use crate::diagnostic::{Error, Result};
use crate::formats::yaml;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// YAML unit tags Python xacro converts (`!degrees 90` is `90 * pi / 180`):
/// the tag and the factor it multiplies by (CPython's constants).
const YAML_UNIT_TAGS: &[(&str, f64)] = &[
    ("!radians", 1.0),
    ("!degrees", std::f64::consts::PI / 180.0),
    ("!meters", 1.0),
    ("!millimeters", 0.001),
    ("!foot", 0.3048),
    ("!inches", 0.0254),
];

/// No names: the unit tags' expressions see only xacro's globals (`pi`,
/// ...); the expansion's meter.
struct NoNames<'m>(&'m mut Meter);

impl super::eval::Env for NoNames<'_> {
    fn lookup(&mut self, _: &str) -> Res<Option<Value>> {
        Ok(None)
    }
    fn lookup_in(&mut self, _: &Scope, _: &str) -> Res<Option<Value>> {
        Ok(None)
    }
    fn load_yaml(&mut self, _: &str) -> Res<Value> {
        Err("load_yaml inside a YAML unit tag".into())
    }
    fn arg(&mut self, _: &str) -> Res<Value> {
        Err("xacro.arg inside a YAML unit tag".into())
    }
    fn abs_filename(&mut self, _: &str) -> Res<String> {
        Err("xacro.abs_filename inside a YAML unit tag".into())
    }
    fn message(&mut self, _: &'static str, _: String) {}
    fn meter(&mut self) -> &mut Meter {
        self.0
    }
}

/// Replace `!degrees EXPR` (and the other unit tags) by the number they
/// stand for, written out in full precision; the scalar ends at the end of
/// the line, a comment or a flow separator. Line numbers stay.
fn convert_unit_tags(text: &str, m: &mut Meter) -> Res<String> {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    loop {
        let next = YAML_UNIT_TAGS
            .iter()
            .filter_map(|(t, f)| rest.find(&format!("{t} ")).map(|i| (i, *t, *f)))
            .min_by_key(|(i, _, _)| *i);
        let Some((i, tag, factor)) = next else {
            out.push_str(rest);
            return Ok(out);
        };
        out.push_str(&rest[..i]);
        let after = &rest[i + tag.len()..];
        let end = after
            .find(['\n', '#', ',', ']', '}'])
            .unwrap_or(after.len());
        let expr = after[..end].trim().trim_matches(['"', '\'']);
        let v =
            super::eval::eval(expr, &mut NoNames(m)).map_err(|e| format!("{tag} {expr}: {e}"))?;
        let x = v
            .as_f64()
            .ok_or_else(|| format!("{tag} {expr}: expected a number, found a {}", v.type_name()))?;
        out.push_str(&super::value::float_repr(x * factor));
        rest = &after[end..];
    }
}

impl Expander<'_> {
    /// A path as written in the current file: relative to its directory.
    fn resolve_path(&self, spec: &str) -> PathBuf {
        let p = Path::new(spec);
        if p.is_absolute() {
            // Below the working directory: relative, so locations print short
            // (the process does not change directory).
            return match self.cwd.as_ref().and_then(|c| p.strip_prefix(c).ok()) {
                Some(rel) if !rel.as_os_str().is_empty() => rel.to_path_buf(),
                _ => p.to_path_buf(),
            };
        }
        let cur = self.current_file();
        normalize(&cur.parent().unwrap_or(Path::new("")).join(p))
    }

    /// A regular file's text, at most `--max-file-size` bytes (a device or
    /// FIFO named by an include would never end), read through
    /// `crate::input`.
    fn read_text(&self, path: &Path, src: &Src, what: &str) -> Result<String> {
        use crate::input::ReadError;
        let fail = |e: String| self.err(src, format!("{what} {}: {e}", path.display()));
        if let Err(why) = self.opts.check_confined(path) {
            let e = self.err(src, format!("{what} {why}"));
            return Err(Error::limit(e.message).at(&e.location));
        }
        let cap = self.opts.max_file_size;
        let bytes = crate::input::read_file(path, cap).map_err(|e| {
            fail(match e {
                ReadError::Io(e) => e.to_string(),
                ReadError::Directory | ReadError::NotRegular(_) => "not a regular file".into(),
                ReadError::TooLarge { .. } => {
                    format!("more than {cap} bytes (the --max-file-size cap)")
                }
            })
        })?;
        String::from_utf8(bytes).map_err(|_| fail("stream did not contain valid UTF-8".into()))
    }

    pub fn include(
        &mut self,
        e: &Elem,
        syms: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
    ) -> Result<()> {
        let spec = self.req(e, "filename")?;
        let spec = self.eval_str(spec, syms, &e.src)?;
        let optional = match e.attr("optional") {
            Some(o) => {
                let v = self.eval_text(o, syms, &e.src)?;
                self.boolean(&v, o, &e.src)?
            }
            None => false,
        };
        if spec.contains(['*', '?', '[']) {
            return Err(self.err(
                &e.src,
                format!("xacro:include filename=\"{spec}\": wildcard includes are not supported; include each file"),
            ));
        }
        let (ns_syms, ns_macros) = match e.attr("ns") {
            Some(ns) => {
                let ns = self.eval_str(ns, syms, &e.src)?;
                let s = Bindings::child(syms, true);
                let m = MacroTable::root();
                syms.set(&ns, Slot::Val(Value::Ns(s.clone())));
                macros.set(&ns, MacroEntry::Ns(m.clone()));
                (s, m)
            }
            None => (syms.clone(), macros.clone()),
        };
        let path = self.resolve_path(&spec);
        if optional && !path.exists() {
            return Ok(());
        }
        let doc = match self.docs.get(&path) {
            Some(d) => d.clone(),
            None => {
                let text = self.read_text(&path, &e.src, "xacro:include: cannot read")?;
                let d = Rc::new(tree::parse(&text, tree::file_ref(&path))?);
                self.docs.insert(path.clone(), d.clone());
                d
            }
        };
        self.budget
            .enter_include(&path.display().to_string(), &e.src, &self.macro_stack)?;
        self.files.push(tree::file_ref(&path));
        self.namespaces.extend(doc.namespaces.clone());
        let mut scratch = Vec::new();
        // The included root's attributes are evaluated (and dropped), as xacro does.
        for (k, v) in &doc.root.attrs {
            if !k.starts_with("xacro:") {
                self.eval_text(v, &ns_syms, &doc.root.src)?;
            }
        }
        let r = self.children(&doc.root.children, &ns_syms, &ns_macros, out, &mut scratch);
        self.files.pop();
        self.budget.include_depth -= 1;
        r
    }

    pub fn property(&mut self, e: &Elem, syms: &Scope) -> Result<()> {
        let name = self.req(e, "name")?;
        let name = self.eval_str(name, syms, &e.src)?;
        if !is_identifier(&name) {
            return Err(self.err(
                &e.src,
                format!("property names must be valid python identifiers: {name}"),
            ));
        }
        if name.starts_with("__") {
            return Err(self.err(
                &e.src,
                format!("property names must not start with double underscore: {name}"),
            ));
        }
        let remove = match e.attr("remove") {
            Some(r) => {
                let v = self.eval_text(r, syms, &e.src)?;
                self.boolean(&v, r, &e.src)?
            }
            None => false,
        };
        let (value, default) = (e.attr("value"), e.attr("default"));
        if usize::from(value.is_some()) + usize::from(default.is_some()) + usize::from(remove) > 1 {
            return Err(self.err(
                &e.src,
                format!(
                    "property attributes default, value, and remove are mutually exclusive: {name}"
                ),
            ));
        }
        if remove {
            syms.remove(&name);
            return Ok(());
        }
        let (key, stored) = match (value, default) {
            (Some(v), _) => (name.clone(), Value::str(v)),
            (None, Some(d)) => {
                if syms.contains(&name) {
                    return Ok(());
                }
                (name.clone(), Value::str(d))
            }
            (None, None) => (format!("**{name}"), Value::Block(Rc::new(e.clone()))),
        };
        let mut lazy = match e.attr("lazy_eval") {
            Some(l) => {
                let v = self.eval_text(l, syms, &e.src)?;
                self.boolean(&v, l, &e.src)?
            }
            None => true,
        };
        let target = match e.attr("scope") {
            Some("global") => {
                lazy = false;
                syms.top()
            }
            Some("parent") => {
                let Some(mut t) = syms.parent.clone() else {
                    // xacro warns and drops it: there is no parent of the top scope.
                    return Ok(());
                };
                lazy = false;
                if !syms.is_ns {
                    while t.is_ns {
                        match t.parent.clone() {
                            Some(p) => t = p,
                            None => break,
                        }
                    }
                }
                t
            }
            _ => syms.clone(),
        };
        let stored = match stored {
            Value::Str(s) if !lazy => self.eval_text(&s, syms, &e.src)?,
            other => other,
        };
        let stored = eval_literal(stored);
        let slot = match stored {
            Value::Str(s) if lazy => Slot::Lazy(s.to_string(), e.src.clone()),
            v => Slot::Val(v),
        };
        target.set(&key, slot);
        Ok(())
    }

    /// `xacro.load_yaml(file)`: a YAML file relative to the current file, as
    /// dicts and lists (integral numbers become ints).
    pub fn load_yaml(&mut self, spec: &str, src: &Src) -> Result<Value> {
        let path = self.resolve_path(spec);
        let text = self.read_text(&path, src, "load_yaml: cannot read")?;
        let text = convert_unit_tags(&text, &mut self.budget.meter)
            .map_err(|m| self.limit(src, format!("load_yaml {}: {m}", path.display())))?;
        let docs = yaml::parse_documents(&text).map_err(|e| e.in_file(&path))?;
        let Some(n) = docs.into_iter().next() else {
            return Ok(Value::None);
        };
        yaml_value(&n.value, &mut self.budget.meter)
            .map_err(|m| self.limit(src, format!("load_yaml {}: {m}", path.display())))
    }
}

/// A YAML value as an expression value, each string and list charged to the
/// meter.
fn yaml_value(v: &yaml::Value, m: &mut Meter) -> Res<Value> {
    m.step()?;
    Ok(match v {
        yaml::Value::Null => Value::None,
        yaml::Value::Bool(b) => Value::Bool(*b),
        yaml::Value::Num(f) => {
            if f.fract() == 0.0 && f.abs() <= 9_007_199_254_740_992.0 {
                Value::Int(*f as i64)
            } else {
                Value::Float(*f)
            }
        }
        yaml::Value::Str(s) => {
            m.string(s.len())?;
            Value::str(s)
        }
        yaml::Value::Seq(items) => {
            m.list(items.len())?;
            let v = items
                .iter()
                .map(|n| yaml_value(&n.value, m))
                .collect::<Res<_>>()?;
            Value::list(v)
        }
        yaml::Value::Map(entries) => {
            m.list(entries.len())?;
            let mut pairs = Vec::with_capacity(entries.len());
            for (k, v) in entries {
                pairs.push((yaml_value(&k.value, m)?, yaml_value(&v.value, m)?));
            }
            Value::dict(pairs)
        }
    })
}

/// `a/b/../c` as `a/c` (lexically, for the paths messages print).
fn normalize(p: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// A Python identifier that is not a keyword.
fn is_identifier(s: &str) -> bool {
    const KEYWORDS: &[&str] = &[
        "False", "None", "True", "and", "as", "assert", "async", "await", "break", "class",
        "continue", "def", "del", "elif", "else", "except", "finally", "for", "from", "global",
        "if", "import", "in", "is", "lambda", "nonlocal", "not", "or", "pass", "raise", "return",
        "try", "while", "with", "yield",
    ];
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_')
        && !KEYWORDS.contains(&s)
}
