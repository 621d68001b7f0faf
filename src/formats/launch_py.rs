//! ROS 2 Python launch files, read statically: the file is parsed (never
//! imported or run) and a small interpreter follows what it would build:
//! literals, names bound once, lists, tuples and dicts, f-strings and `+` of
//! strings and lists, the builtins and `str` methods of `pyexpr`, calls of
//! the functions the file defines (their `return` value), `for` loops over
//! lists the file writes (`nodes.append(Node(...))`, `+=`, `extend`), and
//! `if` on values it knows. Launch actions are kept as records:
//! `Node(...)`, `GroupAction(...)`, `DeclareLaunchArgument(...)`,
//! `LaunchConfiguration('x')` (resolved from the declarations and `--arg`),
//! `PythonExpression([...])` (evaluated as ROS 2's `$(eval)`),
//! `IfCondition` / `UnlessCondition` (decided as launch XML's `if`/`unless`).
//!
//! Every `Node` whose `executable` (or `node_executable`) is
//! `static_transform_publisher`, wherever it is created (the module, or
//! `generate_launch_description()` and what it calls), is one publisher; its
//! `condition` and those of the `GroupAction`s holding it decide whether it
//! runs. What cannot be known from the file is refused naming its line: a
//! publisher created under an `if` or a `for` the reader cannot decide, an
//! argument built from a function of another module (`launch_pal`'s
//! `get_arm(...)`), a name bound more than once, a statement outside the
//! subset that binds what an argument needs.

use super::launch::parse_stp_args;
use super::launch_subst::{ArgDecl, Condition, LaunchArgs};
use super::pyexpr::budget::Budget;
use super::pyexpr::eval::{bind, BUILTINS};
use super::pyexpr::ops::{fail, iterate};
use super::pyexpr::{module, Eval, Expr, ExprKind, Func, Host, Record, Stmt, Value};
use super::spec::{Confidence, FormatSpec, LoadOptions, Parsed};
use crate::diagnostic::{Code, Error, Location, Result, Warning};
use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

use crate::tolerances::{MAX_PY_CALL_DEPTH as MAX_CALL_DEPTH, MAX_PY_STEPS as MAX_STEPS};

/// The launch API names the reader knows, recognised even where a snippet
/// does not import them.
const LAUNCH_NAMES: &[&str] = &[
    "Node",
    "GroupAction",
    "DeclareLaunchArgument",
    "LaunchDescription",
    "LaunchConfiguration",
    "PythonExpression",
    "IfCondition",
    "UnlessCondition",
    "TextSubstitution",
];

/// A function the file defines.
struct Def {
    params: Vec<(String, Option<Expr>)>,
    body: Vec<Stmt>,
}

/// One scope's names: a value, or why it has none.
#[derive(Default)]
struct Scope {
    vars: HashMap<String, (Value, usize)>,
}

/// A publisher Node created while interpreting, with why its creation is
/// uncertain (under an undecided `if` / `for`), and the conditions of the
/// groups holding it.
struct Created {
    node: Rc<Record>,
    uncertain: Option<String>,
    groups: Vec<Value>,
}

struct Interp {
    defs: HashMap<String, Rc<Def>>,
    scopes: Vec<Scope>,
    uncertain: Vec<String>,
    created: Vec<Created>,
    decls: Vec<ArgDecl>,
    depth: usize,
    steps: usize,
    /// What the file's expressions have created, all charged here.
    budget: Rc<Budget>,
}

fn is_publisher(r: &Record) -> bool {
    r.name == "Node"
        && ["executable", "node_executable"]
            .iter()
            .any(|k| matches!(r.kw(k), Some(Value::Str(s)) if s == "static_transform_publisher"))
}

impl Interp {
    fn lookup(&self, n: &str) -> Option<Value> {
        // The innermost function scope, then the module's.
        let local = self.scopes.last().and_then(|s| s.vars.get(n));
        let global = self.scopes.first().and_then(|s| s.vars.get(n));
        local.or(global).map(|(v, _)| v.clone())
    }

    fn assign(&mut self, name: &str, v: Value, line: usize) {
        let uncertain = self.uncertain.last().cloned();
        let scope = self.scopes.last_mut().expect("a scope");
        let v = match (scope.vars.get(name), uncertain) {
            (Some((_, first)), _) => Value::unknown(format!(
                "`{name}` is bound more than once (lines {first} and {line}): the reader follows names bound once"
            )),
            (None, Some(why)) => Value::unknown(format!("`{name}` is bound {why}")),
            (None, None) => v,
        };
        scope.vars.insert(name.to_string(), (v, line));
    }

    fn eval(&mut self, e: &Expr) -> Result<Value> {
        let budget = Rc::clone(&self.budget);
        Eval::with_budget(self, budget).eval(e)
    }

    /// Evaluate, turning an error into a value known to be unknown.
    fn value(&mut self, e: &Expr) -> Value {
        self.eval(e).unwrap_or_else(|err| {
            Value::unknown(format!(
                "{} (line {})",
                err.message,
                err.location.line.unwrap_or(e.line)
            ))
        })
    }

    fn step(&mut self, at: &Expr) -> Result<()> {
        if let Some(e) = self.budget.refused() {
            return Err(e);
        }
        self.steps += 1;
        if self.steps > MAX_STEPS {
            return fail(
                at,
                format!("more than {MAX_STEPS} loop iterations and calls: not followed"),
            );
        }
        Ok(())
    }

    /// Run statements; `Some(value)` when a `return` ends them.
    fn run(&mut self, body: &[Stmt]) -> Result<Option<Value>> {
        for s in body {
            if let Some(v) = self.stmt(s)? {
                return Ok(Some(v));
            }
        }
        Ok(None)
    }

    fn uncertainly<T>(&mut self, why: String, f: impl FnOnce(&mut Self) -> Result<T>) -> Result<T> {
        self.uncertain.push(why);
        let r = f(self);
        self.uncertain.pop();
        r
    }

    fn stmt(&mut self, s: &Stmt) -> Result<Option<Value>> {
        match s {
            Stmt::Expr(e) => {
                self.value(e);
            }
            Stmt::Assign {
                targets,
                value,
                line,
            } => {
                let v = self.value(value);
                for t in targets {
                    self.assign_target(t, v.clone(), *line);
                }
            }
            Stmt::AugAssign {
                target,
                op,
                value,
                line,
            } => self.aug_assign(target, op, value, *line),
            Stmt::Def {
                name,
                params,
                body,
                line,
            } => {
                self.defs.insert(
                    name.clone(),
                    Rc::new(Def {
                        params: params.clone(),
                        body: body.clone(),
                    }),
                );
                self.assign(name, Value::Func(Func::User(name.clone())), *line);
            }
            Stmt::Return(v, _) => {
                let v = v.as_ref().map(|e| self.value(e)).unwrap_or(Value::None);
                if self.uncertain.is_empty() {
                    return Ok(Some(v));
                }
            }
            Stmt::For {
                target,
                iter,
                body,
                orelse,
                line,
            } => return self.for_loop(target, iter, body, orelse, *line),
            Stmt::If {
                cond,
                body,
                orelse,
                line,
            } => {
                match self.value(cond).truth() {
                    Some(true) => return self.run(body),
                    Some(false) => return self.run(orelse),
                    None => {
                        let why = format!("under the `if` at line {line}, whose condition the reader cannot decide");
                        self.uncertainly(why, |me| {
                            me.run(body)?;
                            me.run(orelse)
                        })?;
                    }
                }
            }
            Stmt::Block { what, body, line } => {
                let why = format!("inside {what} (line {line}), which the reader does not follow");
                self.uncertainly(why, |me| me.run(body))?;
            }
            Stmt::Import(names, line) => {
                for n in names.iter().filter(|n| *n != "*") {
                    let v = if n == "math" {
                        Value::Module("math")
                    } else {
                        Value::Func(Func::Host(n.clone()))
                    };
                    self.assign(n, v, *line);
                }
            }
            Stmt::Other(..) => {}
        }
        Ok(None)
    }

    fn assign_target(&mut self, t: &Expr, v: Value, line: usize) {
        let mut scope = Vec::new();
        match bind(t, v, &mut scope) {
            Ok(()) => scope
                .into_iter()
                .for_each(|(n, v)| self.assign(&n, v, line)),
            Err(e) => {
                // Bind every name of the target to why it has no value.
                let mut names = Vec::new();
                collect_names(t, &mut names);
                for n in names {
                    self.assign(
                        &n,
                        Value::unknown(format!("{} (line {line})", e.message)),
                        line,
                    );
                }
            }
        }
    }

    /// `x += [...]` on a list extends it in place, as Python does; any other
    /// augmented assignment rebinds the name.
    fn aug_assign(&mut self, target: &Expr, op: &str, value: &Expr, line: usize) {
        let ExprKind::Name(n) = &target.kind else {
            return;
        };
        let rhs = self.value(value);
        if let (Some(Value::List(l)), "+") = (self.lookup(n), op) {
            match iterate(&rhs, value) {
                Ok(items) if !matches!(rhs, Value::Unknown(_)) => l.borrow_mut().extend(items),
                _ => l.borrow_mut().push(Value::unknown(format!(
                    "`{n} +=` at line {line}: a value the reader cannot know"
                ))),
            }
            return;
        }
        self.assign(n, Value::unknown("augmented assignment"), line);
    }

    fn for_loop(
        &mut self,
        target: &Expr,
        iter: &Expr,
        body: &[Stmt],
        orelse: &[Stmt],
        line: usize,
    ) -> Result<Option<Value>> {
        let it = self.value(iter);
        let items = match (&it, iterate(&it, iter)) {
            (Value::Unknown(_), _) | (_, Err(_)) => None,
            (_, Ok(items)) => Some(items),
        };
        let Some(items) = items else {
            let why = format!(
                "inside the `for` at line {line}, whose items the reader cannot know ({})",
                describe(&it)
            );
            return self.uncertainly(why, |me| {
                me.assign_loop(
                    target,
                    Value::unknown("a loop variable of an unknown loop"),
                    line,
                    None,
                );
                me.run(body).map(|_| None)
            });
        };
        // Names first bound in the body are bound afresh on each iteration.
        let before: Vec<String> = self
            .scopes
            .last()
            .map(|s| s.vars.keys().cloned().collect())
            .unwrap_or_default();
        for x in items {
            self.step(iter)?;
            self.assign_loop(target, x, line, Some(&before));
            if let Some(v) = self.run(body)? {
                return Ok(Some(v));
            }
        }
        self.run(orelse)
    }

    /// Loop variables, and the names the body bound in the previous
    /// iteration (those not in `before`), are rebound on every iteration.
    fn assign_loop(&mut self, target: &Expr, v: Value, line: usize, before: Option<&[String]>) {
        let mut names = Vec::new();
        collect_names(target, &mut names);
        if let Some(scope) = self.scopes.last_mut() {
            if let Some(before) = before {
                scope.vars.retain(|k, _| before.contains(k));
            }
            for n in &names {
                scope.vars.remove(n);
            }
        }
        self.assign_target(target, v, line);
    }

    fn call_def(
        &mut self,
        name: &str,
        args: Vec<Value>,
        kwargs: Vec<(String, Value)>,
        at: &Expr,
    ) -> Result<Value> {
        let Some(def) = self.defs.get(name).cloned() else {
            return fail(at, format!("`{name}` is not a function of this file"));
        };
        if self.depth >= MAX_CALL_DEPTH {
            return fail(
                at,
                format!("calls of the file's functions nest more than {MAX_CALL_DEPTH} deep"),
            );
        }
        self.step(at)?;
        let mut scope = Scope::default();
        let mut args = args.into_iter();
        for (p, default) in &def.params {
            if p.starts_with('*') {
                continue;
            }
            let v = match (args.next(), kwargs.iter().find(|(k, _)| k == p)) {
                (Some(v), _) => v,
                (None, Some((_, v))) => v.clone(),
                (None, None) => match default {
                    Some(d) => self.value(d),
                    None => return fail(at, format!("{name}() missing argument `{p}`")),
                },
            };
            scope.vars.insert(p.clone(), (v, at.line));
        }
        self.scopes.push(scope);
        self.depth += 1;
        let r = self.run(&def.body);
        self.depth -= 1;
        self.scopes.pop();
        Ok(r?.unwrap_or(Value::None))
    }

    fn host_call(
        &mut self,
        name: &str,
        args: Vec<Value>,
        kwargs: Vec<(String, Value)>,
        at: &Expr,
    ) -> Value {
        if name == "TextSubstitution" {
            if let Some(v @ Value::Str(_)) = kwargs
                .iter()
                .find(|(k, _)| k == "text")
                .map(|(_, v)| v.clone())
                .or_else(|| args.first().cloned())
            {
                return v;
            }
        }
        let kwpos = match &at.kind {
            ExprKind::Call { kwargs, .. } => {
                kwargs.iter().map(|(k, _, p)| (k.clone(), *p)).collect()
            }
            _ => Vec::new(),
        };
        let rec = Rc::new(Record {
            name: name.to_string(),
            args,
            kwargs,
            kwpos,
            line: at.line,
            col: at.col,
        });
        match name {
            "Node" if is_publisher(&rec) => self.created.push(Created {
                node: rec.clone(),
                uncertain: self.uncertain.last().cloned(),
                groups: Vec::new(),
            }),
            "GroupAction" => {
                if let Some(cond) = rec.kw("condition").cloned() {
                    let mut held = Vec::new();
                    publishers_in(rec.kw("actions").or(rec.args.first()), &mut held);
                    for c in self
                        .created
                        .iter_mut()
                        .filter(|c| held.iter().any(|h| Rc::ptr_eq(h, &c.node)))
                    {
                        c.groups.push(cond.clone());
                    }
                }
            }
            "DeclareLaunchArgument" => {
                let name = rec.kw("name").or(rec.args.first());
                if let Some(Value::Str(n)) = name {
                    let default = match rec.kw("default_value") {
                        Some(Value::Str(d)) => Some(d.clone()),
                        _ => None,
                    };
                    self.decls.push(ArgDecl {
                        name: n.clone(),
                        value: None,
                        default,
                    });
                }
            }
            _ => {}
        }
        Value::Record(rec)
    }
}

/// The publisher Nodes among `v` (a list of actions, nested groups included).
fn publishers_in(v: Option<&Value>, out: &mut Vec<Rc<Record>>) {
    let Some(v) = v else { return };
    match v {
        Value::Record(r) if is_publisher(r) => out.push(r.clone()),
        Value::Record(r) if r.name == "GroupAction" => {
            publishers_in(r.kw("actions").or(r.args.first()), out)
        }
        v => {
            for x in v.items().unwrap_or_default() {
                publishers_in(Some(&x), out);
            }
        }
    }
}

fn collect_names(t: &Expr, out: &mut Vec<String>) {
    match &t.kind {
        ExprKind::Name(n) => out.push(n.clone()),
        ExprKind::Tuple(ts) | ExprKind::List(ts) => ts.iter().for_each(|x| collect_names(x, out)),
        _ => {}
    }
}

fn describe(v: &Value) -> String {
    match v {
        Value::Unknown(w) => w.to_string(),
        Value::Record(r) => format!("{}(...) at line {}", r.name, r.line),
        other => format!("a {} value", other.type_name()),
    }
}

impl Host for Interp {
    fn name(&mut self, n: &str) -> Option<Value> {
        if let Some(v) = self.lookup(n) {
            return Some(v);
        }
        if let Some(b) = BUILTINS.iter().find(|b| **b == n) {
            return Some(Value::Func(Func::Builtin(b)));
        }
        // The launch API by its usual names, imported or not (a snippet).
        LAUNCH_NAMES
            .contains(&n)
            .then(|| Value::Func(Func::Host(n.to_string())))
    }

    fn lenient(&self) -> bool {
        true
    }

    fn call(
        &mut self,
        f: &Func,
        args: Vec<Value>,
        kwargs: Vec<(String, Value)>,
        at: &Expr,
    ) -> Result<Value> {
        match f {
            Func::User(name) => self.call_def(name, args, kwargs, at),
            Func::Host(name) => Ok(self.host_call(name, args, kwargs, at)),
            _ => fail(at, "not callable"),
        }
    }
}

/// A substitution value as launch-XML text (`$(var x)`, `$(eval ...)`), or
/// why it is not one.
fn substitution(v: &Value) -> std::result::Result<String, String> {
    match v {
        Value::Str(s) => Ok(s.clone()),
        Value::Int(_) | Value::Float(_) | Value::Bool(_) => Ok(v.to_str()),
        Value::Record(r) if r.name == "LaunchConfiguration" => match r.kw("variable_name").or(r.args.first()) {
            Some(Value::Str(n)) => Ok(format!("$(var {n})")),
            _ => Err(format!("LaunchConfiguration(...) at line {} without a literal name", r.line)),
        },
        Value::Record(r) if r.name == "PythonExpression" => {
            let parts = r.kw("expression").or(r.args.first()).cloned().unwrap_or(Value::None);
            let items = parts.items().unwrap_or_else(|| vec![parts.clone()]);
            let text: std::result::Result<Vec<String>, String> = items.iter().map(substitution).collect();
            Ok(format!("$(eval {})", text?.concat()))
        }
        // A list of substitutions is their concatenation.
        Value::List(_) | Value::Tuple(_) => v.items().unwrap_or_default().iter().map(substitution).collect::<std::result::Result<Vec<_>, _>>().map(|p| p.concat()),
        Value::Unknown(w) => Err(w.to_string()),
        Value::Record(r) => Err(format!(
            "{}(...) (line {}) is a function or action of another module, which a static reader of this file cannot evaluate",
            r.name, r.line
        )),
        other => Err(format!("a {} value", other.type_name())),
    }
}

/// The `if` / `unless` of a condition value (`IfCondition(...)`).
fn condition(v: &Value, place: &str) -> std::result::Result<Condition, String> {
    if let Value::Record(r) = v {
        let attr = match r.name.as_str() {
            "IfCondition" => Some("if"),
            "UnlessCondition" => Some("unless"),
            _ => None,
        };
        if let Some(attr) = attr {
            let inner = r
                .kw("predicate_expression")
                .or(r.args.first())
                .cloned()
                .unwrap_or(Value::None);
            return substitution(&inner)
                .map(|raw| Condition {
                    attr,
                    raw,
                    place: place.to_string(),
                })
                .map_err(|why| {
                    format!(
                        "condition={}(...) cannot be decided from the file: {why}",
                        r.name
                    )
                });
        }
    }
    Err(format!(
        "condition={} cannot be decided from the file: expected IfCondition(...) or UnlessCondition(...) of a literal, LaunchConfiguration('NAME') or PythonExpression([...])",
        describe(v)
    ))
}

/// ROS 2 Python launch files (see the module docs).
pub fn parse_launch_py(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let stmts = module(text)?;
    let mut it = Interp {
        defs: HashMap::new(),
        scopes: vec![Scope::default()],
        uncertain: Vec::new(),
        created: Vec::new(),
        decls: Vec::new(),
        depth: 0,
        steps: 0,
        budget: Rc::default(),
    };
    it.run(&stmts)?;
    if it.defs.contains_key("generate_launch_description") {
        let call = Expr {
            kind: ExprKind::Name("generate_launch_description".into()),
            line: 1,
            col: 1,
        };
        it.call_def("generate_launch_description", Vec::new(), Vec::new(), &call)?;
    }
    // A limit the lenient evaluation turned into an unknown value still
    // refuses the file.
    if let Some(e) = it.budget.refused() {
        return Err(e.in_file(path));
    }
    let args = LaunchArgs::from_decls(std::mem::take(&mut it.decls), &opts.xacro_args);
    let mut out = Parsed::default();
    let mut skipped: Option<(usize, String)> = None;
    for c in &it.created {
        let r = &c.node;
        let loc = Location::at(path, r.line, Some(r.col));
        if let Some(why) = &c.uncertain {
            return Err(Error::parse(format!(
                "static_transform_publisher Node created {why}: whether and how often it runs is not known from the file"
            ))
            .at(&loc));
        }
        let mut conds = Vec::new();
        let own = r.kw("condition").map(|v| condition(v, ""));
        let groups = c
            .groups
            .iter()
            .map(|v| condition(v, " on its enclosing GroupAction"));
        let cond_at = r
            .kw_at("condition")
            .map_or(loc.clone(), |(l, c)| Location::at(path, l, Some(c)));
        for cond in own.into_iter().chain(groups) {
            conds.push(cond.map_err(|m| Error::parse(m).at(&cond_at))?);
        }
        if let Some(why) = args.first_off(&conds, &loc)? {
            skipped.get_or_insert((r.line, why.clone()));
            out.warnings.push(
                Warning::new(Code::Ignored, format!("static_transform_publisher Node not started ({why}): its transform is not read")).at(&loc),
            );
            continue;
        }
        let toks = arguments(r, &args, &loc)?;
        out.edges.push(parse_stp_args(
            &toks,
            &loc,
            LAUNCH_PY.id,
            "Node(arguments=[...]) ",
            &mut out.warnings,
        )?);
    }
    if let (true, Some((line, why))) = (out.edges.is_empty(), skipped) {
        return Err(Error::parse(format!(
            "every static_transform_publisher Node is switched off (the first by {why}): expected at least one that runs; set the launch argument it depends on with --arg NAME=VALUE"
        ))
        .at_line(line, None));
    }
    if it.created.is_empty() {
        return Err(Error::parse(
            "no static_transform_publisher Node is created: expected Node(package='tf2_ros', executable='static_transform_publisher', arguments=[...])",
        ));
    }
    Ok(out)
}

/// The words of a publisher's `arguments`, substitutions resolved.
fn arguments(r: &Record, args: &LaunchArgs, loc: &Location) -> Result<Vec<String>> {
    let list = r.kw("arguments").ok_or_else(|| {
        Error::parse("static_transform_publisher Node without `arguments=[...]`: expected the transform in its arguments").at(loc)
    })?;
    let items = match list {
        Value::List(_) | Value::Tuple(_) => list.items().unwrap_or_default(),
        other => {
            return Err(Error::parse(format!(
                "static_transform_publisher arguments: expected a list, found {}",
                describe(other)
            ))
            .at(loc))
        }
    };
    let mut toks = Vec::new();
    for (i, v) in items.iter().enumerate() {
        let text = substitution(v).map_err(|why| {
            Error::parse(format!(
                "static_transform_publisher argument {}: {why}",
                i + 1
            ))
            .at(loc)
        })?;
        let text = args.resolve(&text, loc)?;
        toks.extend(text.split_whitespace().map(String::from));
    }
    Ok(toks)
}

/// ROS 2 Python launch.
pub const LAUNCH_PY: FormatSpec = FormatSpec {
    id: "launch-py",
    description: "ROS 2 Python launch, read statically (never run): static_transform_publisher Nodes wherever the file builds them (its helper functions, `for` loops over lists it writes), `arguments` from literals, f-strings, `+`, `LaunchConfiguration` / `PythonExpression` of a `DeclareLaunchArgument` or `--arg`; `IfCondition`/`UnlessCondition` decided; anything else is refused naming its line",
    extensions: &["py", "launch.py"],
    walk: &[".launch.py"],
    magic: &[],
    sniff: |i| i.text_head().contains("LaunchDescription").then_some(Confidence::Names),
    parse: |i, o| parse_launch_py(i.text()?, i.path(), o),
    checked: true,
};
