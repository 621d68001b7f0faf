//! The expander: Python xacro's in-order evaluation (`eval_all`) over the
//! owned tree, element by element in document order. Properties, args and
//! macros take effect where they are defined; a macro body is evaluated in a
//! child of the caller's scope; blocks are evaluated where they are given and
//! again where they are inserted. Output elements keep the `Src` of the element
//! they were made from (in the file that wrote them), which becomes the edge's
//! location.

use super::eval::{self, Env};
use super::limits::Budget;
use super::scope::{MacroEntry, MacroScope, MacroTable};
use super::subst::{self, Subst};
use super::tree::{self, err_at, Doc, Elem, Node, Src};
use super::value::{eval_literal, Bindings, Scope, Slot, Value};
use crate::diagnostic::{Code, Error, Result, Warning};
use crate::formats::spec::LoadOptions;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// `{` and `}` of `${...}`, named: brace literals in patterns confuse the
/// line-based brace counting of the repository's function-length check.
const LBRACE: u8 = 0x7b;
/// See [`LBRACE`].
const RBRACE: char = '\u{7d}';

pub struct Expander<'o> {
    pub opts: &'o LoadOptions,
    /// `$(arg)` values: `--arg` first, then `xacro:arg` defaults as met.
    pub args: BTreeMap<String, String>,
    /// Files being read, innermost last (relative includes resolve from it).
    pub files: Vec<Rc<PathBuf>>,
    /// Parsed files, by path (an include of the same file is parsed once).
    pub docs: HashMap<PathBuf, Rc<Doc>>,
    pub namespaces: BTreeMap<String, String>,
    pub packages: HashMap<String, PathBuf>,
    /// The packages on the search path (built at the first `$(find)`).
    package_index: Option<subst::PackageIndex>,
    pub budget: Budget,
    /// The top-level input, for the package search.
    pub input: PathBuf,
    /// Macro names being expanded, outermost first (for messages).
    pub macro_stack: Vec<String>,
    /// The element met last: where an error in the text after it is placed.
    here: Option<Src>,
    /// Things expanded as Python xacro does that are likely not meant.
    pub warnings: Vec<Warning>,
    /// The working directory (canonical), to print paths below it relative.
    pub cwd: Option<PathBuf>,
}

impl<'o> Expander<'o> {
    pub fn new(opts: &'o LoadOptions, input: &Path) -> Self {
        Expander {
            opts,
            args: opts.xacro_args.clone(),
            files: vec![tree::file_ref(input)],
            docs: HashMap::new(),
            namespaces: BTreeMap::new(),
            packages: HashMap::new(),
            package_index: None,
            budget: Budget::new(),
            input: input.to_path_buf(),
            macro_stack: Vec::new(),
            here: None,
            warnings: Vec::new(),
            cwd: std::env::current_dir().and_then(std::fs::canonicalize).ok(),
        }
    }

    pub fn err(&self, src: &Src, msg: impl Into<String>) -> Error {
        err_at(src, msg, &self.macro_stack)
    }

    /// The file being read now.
    pub fn current_file(&self) -> PathBuf {
        self.files
            .last()
            .map(|f| f.as_ref().clone())
            .unwrap_or_else(|| self.input.clone())
    }

    /// Evaluate text with `${...}` and `$(...)`: one piece keeps its type,
    /// several are joined as text (Python xacro's `eval_text`).
    pub fn eval_text(&mut self, text: &str, syms: &Scope, src: &Src) -> Result<Value> {
        if !text.contains('$') {
            return Ok(Value::str(text));
        }
        let mut parts: Vec<Value> = Vec::new();
        let mut rest = text;
        while !rest.is_empty() {
            let (piece, used) = self.next_piece(rest, syms, src)?;
            parts.push(piece);
            rest = &rest[used..];
        }
        if parts.len() == 1 {
            return Ok(parts.remove(0));
        }
        let mut joined = String::new();
        for p in &parts {
            let t = self.py_str(p, src)?;
            joined.push_str(&t);
            self.budget
                .meter
                .string(joined.len())
                .map_err(|m| self.limit(src, m))?;
        }
        Ok(Value::str(&joined))
    }

    /// Python's `str()` of a value, within the meter.
    pub fn py_str(&mut self, v: &Value, src: &Src) -> Result<String> {
        v.to_py_str(&mut self.budget.meter)
            .map_err(|m| self.limit(src, m))
    }

    /// An evaluation error: a limit when the meter tripped, else a parse
    /// error at `src`.
    pub fn limit(&self, src: &Src, msg: String) -> Error {
        let e = self.err(src, msg);
        if self.budget.meter.tripped().is_some() {
            return Error::limit(e.message).at(&e.location);
        }
        e
    }

    /// [`Self::eval_text`] as text (Python's `str()` of it).
    pub fn eval_str(&mut self, text: &str, syms: &Scope, src: &Src) -> Result<String> {
        if !text.contains('$') {
            return Ok(text.to_string());
        }
        let v = self.eval_text(text, syms, src)?;
        self.py_str(&v, src)
    }

    /// One lexer token of xacro's text grammar, evaluated; and its length.
    fn next_piece(&mut self, s: &str, syms: &Scope, src: &Src) -> Result<(Value, usize)> {
        let b = s.as_bytes();
        if b[0] != b'$' {
            let n = s.find('$').unwrap_or(s.len());
            return Ok((Value::str(&s[..n]), n));
        }
        // `$$...{` / `$$...(`: drop one `$` (the escape).
        let dollars = b.iter().take_while(|c| **c == b'$').count();
        if dollars >= 2 && matches!(b.get(dollars), Some(&LBRACE) | Some(b'(')) {
            return Ok((Value::str(&s[1..=dollars]), dollars + 1));
        }
        match b.get(1) {
            Some(&LBRACE) => {
                let Some(end) = s.find(RBRACE) else {
                    return Err(self.err(src, format!("'${{' without a closing '}}' in {s:?}")));
                };
                let inner = &s[2..end];
                let v = self.expression(inner, syms, src)?;
                Ok((v, end + 1))
            }
            Some(b'(') => {
                let Some(end) = s.find(')') else {
                    return Err(self.err(src, format!("'$(' without a closing ')' in {s:?}")));
                };
                let inner = self.eval_str(&s[2..end], syms, src)?;
                let v = self.substitute(&inner, src)?;
                Ok((Value::str(&v), end + 1))
            }
            _ if dollars == 1 => {
                // A `$` not starting a substitution is text up to the next `$`.
                let n = 1 + s[1..].find('$').unwrap_or(s.len() - 1);
                Ok((Value::str(&s[..n]), n))
            }
            _ => Err(self.err(src, format!("invalid expression: {s:?}"))),
        }
    }

    /// `${inner}`: substitutions inside first, then the Python subset.
    fn expression(&mut self, inner: &str, syms: &Scope, src: &Src) -> Result<Value> {
        let code = self.eval_str(inner, syms, src)?;
        if let Some(bad) = code
            .split(|c: char| !(c.is_alphanumeric() || c == '_'))
            .find(|w| w.starts_with("__"))
        {
            return Err(self.err(src, format!("use of invalid name {bad} in ${{{inner}}}")));
        }
        let src2 = src.clone();
        let mut env = EvalEnv {
            ex: self,
            syms: syms.clone(),
            src: src2,
            failure: None,
        };
        match eval::eval(&code, &mut env) {
            Ok(v) => Ok(v),
            Err(msg) => {
                if let Some(e) = env.failure.take() {
                    return Err(e);
                }
                let shown: String = inner.chars().take(200).collect();
                let more = if shown.len() < inner.len() { "..." } else { "" };
                Err(self.limit(src, format!("cannot evaluate ${{{shown}{more}}}: {msg}")))
            }
        }
    }

    /// `$(command args)` resolved to text.
    fn substitute(&mut self, inner: &str, src: &Src) -> Result<String> {
        let s = subst::parse(inner).map_err(|m| self.err(src, m))?;
        match s {
            Subst::Arg(name) => self.args.get(name).cloned().ok_or_else(|| {
                self.err(
                    src,
                    format!(
                        "$(arg {name}): undefined substitution argument: expected an <xacro:arg name=\"{name}\" default=\"...\"/> before this use, or --arg {name}=VALUE"
                    ),
                )
            }),
            Subst::Find(pkg) => self.find(pkg, src).map(|p| p.to_string_lossy().to_string()),
            Subst::Env(name) if self.opts.confined() => Err(self.err(
                src,
                format!("$(env {name}): the environment is not read under --confine (a CI job's environment holds its secrets); give the value with --arg, or drop --confine"),
            )),
            Subst::Env(name) => std::env::var(name).map_err(|_| {
                self.err(src, format!("$(env {name}): environment variable {name} is not set"))
            }),
            Subst::OptEnv(name, default) if self.opts.confined() => {
                if std::env::var_os(name).is_some() {
                    self.warnings.push(
                        Warning::new(
                            Code::Ignored,
                            format!("$(optenv {name}): {name} is set, but the environment is not read under --confine: its default {default:?} used"),
                        )
                        .at(&src.location()),
                    );
                }
                Ok(default)
            }
            Subst::OptEnv(name, default) => Ok(std::env::var(name).unwrap_or(default)),
            Subst::Dirname => {
                let f = self.current_file();
                let dir = f.parent().map(Path::to_path_buf).unwrap_or_default();
                let abs = std::fs::canonicalize(&dir).unwrap_or(dir);
                Ok(abs.to_string_lossy().to_string())
            }
            Subst::Cwd => std::env::current_dir()
                .map(|d| d.to_string_lossy().to_string())
                .map_err(|e| self.err(src, format!("$(cwd): {e}"))),
        }
    }

    /// `$(find pkg)`: the package's directory (the search path indexed at
    /// the first call); a second copy of the package on the search path is
    /// a `duplicate-package` warning naming both, once per package.
    pub fn find(&mut self, pkg: &str, src: &Src) -> Result<PathBuf> {
        if let Some(p) = self.packages.get(pkg) {
            return Ok(p.clone());
        }
        let index = self.package_index.get_or_insert_with(|| {
            subst::PackageIndex::build(&self.opts.package_paths, &self.input)
        });
        let found = index
            .find(pkg, &self.opts.package_paths)
            .map_err(|m| self.err(src, m))?;
        if let Err(why) = self.opts.check_confined(&found.dir) {
            let e = self.err(src, format!("$(find {pkg}): {why}"));
            return Err(Error::limit(e.message).at(&e.location));
        }
        if !found.others.is_empty() {
            let others: Vec<String> = found
                .others
                .iter()
                .map(|(d, from)| format!("{} ({from})", d.display()))
                .collect();
            self.warnings.push(
                Warning::new(
                    Code::DuplicatePackage,
                    format!(
                        "$(find {pkg}): {} packages named {pkg} on the search path: used {} ({}); also {}",
                        others.len() + 1,
                        found.dir.display(),
                        found.from,
                        others.join(", ")
                    ),
                )
                .at(&src.location()),
            );
        }
        self.packages.insert(pkg.to_string(), found.dir.clone());
        Ok(found.dir)
    }

    /// A property's value, evaluating a lazy one (in the table that defines
    /// it) at first use.
    pub fn lookup(&mut self, syms: &Scope, name: &str, src: &Src) -> Result<Option<Value>> {
        let Some((table, slot)) = syms.find(name) else {
            return Ok(None);
        };
        match slot {
            Slot::Val(v) => Ok(Some(v)),
            Slot::Busy => Err(self.err(
                src,
                format!("circular property definition: '{name}' depends on itself"),
            )),
            Slot::Lazy(text, at) => {
                self.budget.enter_property(name, &at, &self.macro_stack)?;
                table.set(name, Slot::Busy);
                let v = self.eval_text(&text, &table, &at);
                self.budget.leave_property();
                let v = match v {
                    Ok(v) => eval_literal(v),
                    Err(e) => {
                        table.set(name, Slot::Lazy(text, at));
                        return Err(e);
                    }
                };
                table.set(name, Slot::Val(v.clone()));
                Ok(Some(v))
            }
        }
    }

    /// Evaluate a document's root: its children in a fresh scope.
    pub fn run(&mut self, doc: &Doc) -> Result<Elem> {
        let syms = Bindings::root();
        let macros = MacroTable::root();
        self.namespaces.extend(doc.namespaces.clone());
        let mut root = Elem {
            name: doc.root.name.clone(),
            attrs: Vec::new(),
            children: Vec::new(),
            src: doc.root.src.clone(),
        };
        for (k, v) in &doc.root.attrs {
            if !k.starts_with("xacro:") {
                let val = self.eval_str(v, &syms, &doc.root.src)?;
                root.attrs.push((k.clone(), val));
            }
        }
        let mut attrs = std::mem::take(&mut root.attrs);
        self.children(
            &doc.root.children,
            &syms,
            &macros,
            &mut root.children,
            &mut attrs,
        )?;
        root.attrs = attrs;
        Ok(root)
    }

    /// Evaluate a list of nodes into `out`; `attrs` are the attributes of the
    /// element they belong to (for `xacro:attribute`).
    pub fn children(
        &mut self,
        nodes: &[Node],
        syms: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
        attrs: &mut Vec<(String, String)>,
    ) -> Result<()> {
        for n in nodes {
            match n {
                Node::Elem(e) => self.element(e, syms, macros, out, attrs)?,
                // Layout whitespace: the writer drops it anyway.
                Node::Text(t) if !t.contains('$') && t.trim().is_empty() => {}
                Node::Text(t) => {
                    let src = self.text_src();
                    let v = self.eval_str(t, syms, &src)?;
                    self.budget.bytes(v.len(), &src, &self.macro_stack)?;
                    out.push(Node::Text(v));
                }
            }
        }
        Ok(())
    }

    /// Text has no position of its own: errors point at the file being read.
    fn text_src(&self) -> Src {
        if let Some(h) = &self.here {
            return h.clone();
        }
        Src {
            file: self
                .files
                .last()
                .cloned()
                .unwrap_or_else(|| tree::file_ref(&self.input)),
            line: 1,
            col: 1,
            end_line: 1,
        }
    }

    /// One element, one level deeper (`XACRO_MAX_ELEMENT_DEPTH`).
    fn element(
        &mut self,
        e: &Elem,
        syms: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
        attrs: &mut Vec<(String, String)>,
    ) -> Result<()> {
        self.budget.tick(&e.src, &self.macro_stack)?;
        self.budget.enter_element(&e.src, &self.macro_stack)?;
        let r = self.element_here(e, syms, macros, out, attrs);
        self.budget.leave_element();
        r
    }

    fn element_here(
        &mut self,
        e: &Elem,
        syms: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
        attrs: &mut Vec<(String, String)>,
    ) -> Result<()> {
        self.here = Some(e.src.clone());
        let Some(tag) = e.name.strip_prefix("xacro:") else {
            return self.plain(e, syms, macros, out);
        };
        let mut scratch = Vec::new();
        match tag {
            "insert_block" => self.insert_block(e, syms, macros, out, attrs),
            "include" => self.include(e, syms, macros, out),
            "property" => self.property(e, syms),
            "macro" => self.define_macro(e, macros),
            "arg" => self.arg(e, syms),
            "if" | "unless" => {
                let cond = self.req(e, "value")?;
                let v = self.eval_text(cond, syms, &e.src)?;
                let keep = self.boolean(&v, cond, &e.src)? == (tag == "if");
                if keep {
                    self.children(&e.children, syms, macros, out, &mut scratch)?;
                }
                Ok(())
            }
            "element" => {
                let name = self.req(e, "xacro:name")?;
                let name = self.eval_str(name, syms, &e.src)?;
                if name.is_empty() {
                    return Err(self.err(&e.src, "xacro:element: empty name"));
                }
                let mut renamed = e.clone();
                renamed.name = name;
                renamed.attrs.retain(|(k, _)| k != "xacro:name");
                self.element(&renamed, syms, macros, out, attrs)
            }
            "attribute" => {
                let name = self.req(e, "name")?;
                let value = self.req(e, "value")?;
                let name = self.eval_str(name, syms, &e.src)?;
                let value = self.eval_str(value, syms, &e.src)?;
                if name.is_empty() {
                    return Err(self.err(&e.src, "xacro:attribute: empty name"));
                }
                match attrs.iter_mut().find(|(k, _)| *k == name) {
                    Some(slot) => slot.1 = value,
                    None => attrs.push((name, value)),
                }
                Ok(())
            }
            "call" => {
                let name = self.req(e, "macro")?;
                let name = self.eval_str(name, syms, &e.src)?;
                let mut call = e.clone();
                call.name = format!("xacro:{name}");
                call.attrs.retain(|(k, _)| k != "macro");
                self.call_macro(&call, &name, syms, macros, out)
            }
            "message" | "warning" | "error" | "eval-comments" => Err(self.err(
                &e.src,
                format!("<xacro:{tag}> is not supported by this expander"),
            )),
            name => self.call_macro(e, name, syms, macros, out),
        }
    }

    /// A required attribute, or an error naming it.
    pub fn req<'e>(&self, e: &'e Elem, name: &str) -> Result<&'e str> {
        e.attr(name).ok_or_else(|| {
            self.err(
                &e.src,
                format!(
                    "<{}>: expected a {name}=\"...\" attribute, found none",
                    e.name
                ),
            )
        })
    }

    /// Python xacro's `get_boolean_value`.
    pub fn boolean(&self, v: &Value, cond: &str, src: &Src) -> Result<bool> {
        match v {
            Value::Str(s) => match &**s {
                "true" | "True" => Ok(true),
                "false" | "False" => Ok(false),
                other => super::value::parse_py_int(other)
                    .map(|i| i != 0)
                    .ok_or_else(|| {
                        self.err(
                            src,
                            format!("xacro conditional \"{cond}\" evaluated to \"{other}\", which is not a boolean expression"),
                        )
                    }),
            },
            other => Ok(other.truthy()),
        }
    }

    /// An element that is not xacro's: attributes evaluated (`xacro:*` ones
    /// dropped), children evaluated inside it.
    fn plain(
        &mut self,
        e: &Elem,
        syms: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
    ) -> Result<()> {
        self.budget.element(&e.src, &self.macro_stack)?;
        const XACRO_TAGS: &[&str] = &[
            "property",
            "macro",
            "include",
            "arg",
            "insert_block",
            "if",
            "unless",
        ];
        if XACRO_TAGS.contains(&e.name.as_str()) {
            self.warnings.push(
                Warning::new(
                    Code::Ignored,
                    format!(
                        "<{0}> without the `xacro:` prefix: copied as is, not processed (as Python xacro 2 does; ROS 1 xacro before 1.12 processed it); write <xacro:{0}>",
                        e.name
                    ),
                )
                .at(&e.src.location()),
            );
        }
        if let Some(MacroEntry::Macro(_)) = macros.get(&e.name) {
            self.warnings.push(
                Warning::new(
                    Code::Ignored,
                    format!(
                        "<{0}> has the name of a macro but no `xacro:` prefix: copied as is, not expanded (as Python xacro 2 does); write <xacro:{0}> to call the macro",
                        e.name
                    ),
                )
                .at(&e.src.location()),
            );
        }
        let mut attrs = Vec::with_capacity(e.attrs.len());
        for (k, v) in &e.attrs {
            if k.starts_with("xacro:") {
                continue;
            }
            let val = self.eval_str(v, syms, &e.src)?;
            self.budget
                .bytes(k.len() + val.len() + 4, &e.src, &self.macro_stack)?;
            attrs.push((k.clone(), val));
        }
        let mut children = Vec::new();
        self.children(&e.children, syms, macros, &mut children, &mut attrs)?;
        out.push(Node::Elem(Elem {
            name: e.name.clone(),
            attrs,
            children,
            src: e.src.clone(),
        }));
        Ok(())
    }

    fn insert_block(
        &mut self,
        e: &Elem,
        syms: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
        attrs: &mut Vec<(String, String)>,
    ) -> Result<()> {
        let name = self.req(e, "name")?;
        let (block, content) = if syms.contains(&format!("**{name}")) {
            (self.lookup(syms, &format!("**{name}"), &e.src)?, true)
        } else if syms.contains(&format!("*{name}")) {
            (self.lookup(syms, &format!("*{name}"), &e.src)?, false)
        } else {
            return Err(self.err(&e.src, format!("undefined block \"{name}\"")));
        };
        let Some(Value::Block(b)) = block else {
            return Err(self.err(&e.src, format!("\"{name}\" is not a block")));
        };
        if content {
            let mut scratch = Vec::new();
            self.children(&b.children, syms, macros, out, &mut scratch)
        } else if b.name.starts_with("xacro:") {
            Err(self.err(
                &b.src,
                format!("a block that is itself <{}> is not supported", b.name),
            ))
        } else {
            let _ = attrs;
            self.plain(&b, syms, macros, out)
        }
    }

    fn arg(&mut self, e: &Elem, syms: &Scope) -> Result<()> {
        let name = self.req(e, "name")?;
        let default = self.req(e, "default")?;
        if !self.args.contains_key(name) {
            let v = self.eval_str(default, syms, &e.src)?;
            self.args.insert(name.to_string(), v);
        }
        Ok(())
    }
}

/// The expression evaluator's view of the expander at one element.
struct EvalEnv<'a, 'o> {
    ex: &'a mut Expander<'o>,
    syms: Scope,
    src: Src,
    /// A full error (with its own location) raised while evaluating, e.g. in
    /// a lazy property defined elsewhere: reported as is.
    failure: Option<Error>,
}

impl EvalEnv<'_, '_> {
    fn keep<T>(&mut self, r: Result<T>) -> std::result::Result<T, String> {
        r.map_err(|e| {
            let m = e.message.clone();
            self.failure = Some(e);
            m
        })
    }
}

impl Env for EvalEnv<'_, '_> {
    fn meter(&mut self) -> &mut super::limits::Meter {
        &mut self.ex.budget.meter
    }

    fn abs_filename(&mut self, path: &str) -> std::result::Result<String, String> {
        let p = Path::new(path);
        if p.is_absolute() {
            return Ok(path.to_string());
        }
        let cur = self.ex.current_file();
        let dir = cur.parent().unwrap_or(Path::new(""));
        Ok(dir.join(p).to_string_lossy().to_string())
    }

    fn message(&mut self, level: &'static str, text: String) {
        let cut: String = text.chars().take(500).collect();
        self.ex.warnings.push(
            Warning::new(
                Code::XacroMessage,
                format!("xacro.{level}() in the file: {cut}"),
            )
            .at(&self.src.location()),
        );
    }

    fn lookup(&mut self, name: &str) -> std::result::Result<Option<Value>, String> {
        let (syms, src) = (self.syms.clone(), self.src.clone());
        let r = self.ex.lookup(&syms, name, &src);
        self.keep(r)
    }

    fn lookup_in(&mut self, ns: &Scope, name: &str) -> std::result::Result<Option<Value>, String> {
        let src = self.src.clone();
        let r = self.ex.lookup(ns, name, &src);
        self.keep(r)
    }

    fn load_yaml(&mut self, path: &str) -> std::result::Result<Value, String> {
        let src = self.src.clone();
        let r = self.ex.load_yaml(path, &src);
        self.keep(r)
    }

    fn arg(&mut self, name: &str) -> std::result::Result<Value, String> {
        self.ex
            .args
            .get(name)
            .map(|v| Value::str(v))
            .ok_or_else(|| format!("undefined substitution argument {name}"))
    }
}
