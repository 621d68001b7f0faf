//! `xacro:macro` definitions and calls: parameters with defaults (`p:=1`,
//! `p:=^`, `p:=^|1`), block parameters (`*b` takes one element, `**b` an
//! element whose content is inserted), dotted names for macros included with
//! `ns`.

use super::expand::Expander;
use super::scope::{Macro, MacroEntry, MacroScope, MacroTable};
use super::tree::{Elem, Node};
use super::value::{eval_literal, Bindings, Scope, Slot, Value};
use crate::diagnostic::Result;
use std::collections::HashMap;
use std::rc::Rc;

/// One parameter spec from the front of `s`: (name, (forward, default) when
/// `:=`/`=` is given, rest). Python xacro's `parse_macro_arg`.
pub fn parse_param(s: &str) -> (String, Option<(bool, Option<String>)>, &str) {
    let t = s.trim_start();
    let name_len = t
        .find(|c: char| c.is_whitespace() || c == ':' || c == '=')
        .unwrap_or(t.len());
    let (name, after) = t.split_at(name_len);
    let a = after.trim_start();
    let def = a.strip_prefix(":=").or_else(|| a.strip_prefix('='));
    let (Some(def), false) = (def, name.is_empty()) else {
        let mut it = t.splitn(2, char::is_whitespace);
        let first = it.next().unwrap_or("").to_string();
        return (first, None, it.next().unwrap_or(""));
    };
    let def = def.trim_start();
    let (forward, def) = match def.strip_prefix("^|") {
        Some(d) => (true, d),
        None => match def.strip_prefix('^') {
            Some(d) => (true, d),
            None => (false, def),
        },
    };
    let n = default_len(def);
    let value = &def[..n];
    let rest = def[n..].trim_start();
    let value = (!value.is_empty()).then(|| value.to_string());
    (name.to_string(), Some((forward, value)), rest)
}

/// Length of a default value: `${...}` or `$(...)` up to the first closing
/// bracket that ends the word, else a run of quoted strings and non-space text.
fn default_len(s: &str) -> usize {
    let ends_word = |i: usize| s[i..].chars().next().is_none_or(char::is_whitespace);
    for (open, close) in [("${", '}'), ("$(", ')')] {
        if s.starts_with(open) {
            for (i, c) in s.char_indices().skip(2) {
                if c == close && ends_word(i + 1) {
                    return i + 1;
                }
            }
        }
    }
    let mut i = 0;
    while let Some(c) = s[i..].chars().next() {
        if c == '\'' || c == '"' {
            match s[i + 1..].find(c) {
                Some(j) => i += j + 2,
                None => break,
            }
        } else if c.is_whitespace() {
            break;
        } else {
            i += c.len_utf8();
        }
    }
    i
}

impl Expander<'_> {
    pub fn define_macro(&mut self, e: &Elem, macros: &MacroScope) -> Result<()> {
        let name = self.req(e, "name")?;
        if name == "call" {
            return Err(self.err(&e.src, "invalid use of macro name 'call'"));
        }
        if name.contains('.') {
            return Err(self.err(
                &e.src,
                format!("macro names must not contain '.' (reserved for namespaces): {name}"),
            ));
        }
        let name = name.strip_prefix("xacro:").unwrap_or(name);
        let mut params = Vec::new();
        let mut defaults = HashMap::new();
        let mut rest = e.attr("params").unwrap_or("");
        while !rest.trim().is_empty() {
            let (p, d, r) = parse_param(rest);
            if let Some(d) = d {
                defaults.insert(p.clone(), d);
            }
            params.push(p);
            rest = r;
        }
        macros.set(
            name,
            MacroEntry::Macro(Rc::new(Macro {
                name: name.to_string(),
                params,
                defaults,
                body: Rc::new(e.clone()),
            })),
        );
        Ok(())
    }

    /// The macro `name` names (walking `ns.` prefixes), with the tables its
    /// body is evaluated under.
    fn resolve(
        &mut self,
        name: &str,
        syms: &Scope,
        macros: &MacroScope,
        e: &Elem,
    ) -> Result<(Rc<Macro>, Scope, MacroScope)> {
        if let Some(MacroEntry::Macro(m)) = macros.get(name) {
            return Ok((m, syms.clone(), macros.clone()));
        }
        let parts: Vec<&str> = name.split('.').collect();
        let (mut ms, mut ss) = (macros.clone(), syms.clone());
        if parts.len() > 1 {
            for ns in &parts[..parts.len() - 1] {
                let Some(MacroEntry::Ns(next)) = ms.get(ns) else {
                    return Err(self.unknown_macro(name, macros, e));
                };
                ms = next;
                ss = match self.lookup(&ss, ns, &e.src)? {
                    Some(Value::Ns(s)) => s,
                    _ => return Err(self.unknown_macro(name, macros, e)),
                };
            }
            if let Some(MacroEntry::Macro(m)) = ms.get(parts[parts.len() - 1]) {
                return Ok((m, ss, ms));
            }
        }
        Err(self.unknown_macro(name, macros, e))
    }

    fn unknown_macro(&self, name: &str, macros: &MacroScope, e: &Elem) -> crate::diagnostic::Error {
        let known = macros.names();
        let hint = match known
            .iter()
            .map(|k| (strsim::levenshtein(k, name), k))
            .min()
        {
            Some((d, k)) if d <= 3 => format!("; did you mean xacro:{k}?"),
            _ if known.is_empty() => {
                "; no macro is defined at this point (is its file included before the call?)".into()
            }
            _ => format!("; macros defined here: {}", known.join(", ")),
        };
        self.err(&e.src, format!("unknown macro name: xacro:{name}{hint}"))
    }

    /// A call `<xacro:name attrs...>blocks</xacro:name>`.
    pub fn call_macro(
        &mut self,
        e: &Elem,
        name: &str,
        syms: &Scope,
        macros: &MacroScope,
        out: &mut Vec<Node>,
    ) -> Result<()> {
        let (m, scope_syms, scope_macros) = self.resolve(name, syms, macros, e)?;
        self.budget
            .enter_macro(&m.name, &e.src, &self.macro_stack)?;
        self.macro_stack.push(format!(
            "{} called at {}:{}",
            m.name,
            e.src.file.display(),
            e.src.line
        ));
        let r = self.bind_and_expand(e, &m, syms, macros, &scope_syms, &scope_macros, out);
        self.macro_stack.pop();
        self.budget.leave_macro();
        r
    }

    #[allow(clippy::too_many_arguments)]
    fn bind_and_expand(
        &mut self,
        e: &Elem,
        m: &Macro,
        syms: &Scope,
        macros: &MacroScope,
        scope_syms: &Scope,
        scope_macros: &MacroScope,
        out: &mut Vec<Node>,
    ) -> Result<()> {
        let local = Bindings::child(scope_syms, false);
        let local_macros = MacroTable::child(scope_macros);
        let mut params = m.params.clone();
        for (k, v) in &e.attrs {
            let Some(i) = params.iter().position(|p| p == k) else {
                return Err(self.err(
                    &e.src,
                    format!(
                        "macro {}: invalid parameter \"{k}\": expected one of {}",
                        m.name,
                        m.params.join(" ")
                    ),
                ));
            };
            params.remove(i);
            let val = eval_literal(self.eval_text(v, syms, &e.src)?);
            local.set(k, Slot::Val(val));
        }
        // Blocks are evaluated in the caller's scope, then bound in order.
        let mut given = Vec::new();
        let mut scratch = Vec::new();
        self.children(&e.children, syms, macros, &mut given, &mut scratch)?;
        let mut blocks = given.into_iter().filter_map(|n| match n {
            Node::Elem(b) => Some(b),
            _ => None,
        });
        for p in params.clone().iter().filter(|p| p.starts_with('*')) {
            let Some(b) = blocks.next() else {
                return Err(self.err(
                    &e.src,
                    format!("macro {}: not enough blocks (missing {p})", m.name),
                ));
            };
            params.retain(|x| x != p);
            local.set(p, Slot::Val(Value::Block(Rc::new(b))));
        }
        if let Some(b) = blocks.next() {
            return Err(self.err(
                &b.src,
                format!("macro {}: unused block <{}>", m.name, b.name),
            ));
        }
        for p in params.clone().iter().filter(|p| !p.starts_with('*')) {
            let Some((forward, default)) = m.defaults.get(p) else {
                continue;
            };
            let val = if *forward {
                match (self.lookup(syms, p, &e.src)?, default) {
                    (Some(v), _) => v,
                    (None, Some(d)) => self.eval_text(d, syms, &e.src)?,
                    (None, None) => {
                        return Err(self.err(
                            &e.src,
                            format!("macro {}: undefined property to forward: {p}", m.name),
                        ))
                    }
                }
            } else {
                match default {
                    Some(d) => self.eval_text(d, syms, &e.src)?,
                    None => continue,
                }
            };
            local.set(p, Slot::Val(eval_literal(val)));
            params.retain(|x| x != p);
        }
        if !params.is_empty() {
            return Err(self.err(
                &e.src,
                format!(
                    "macro {}: undefined parameters [{}]",
                    m.name,
                    params.join(",")
                ),
            ));
        }
        let mut scratch = Vec::new();
        self.children(&m.body.children, &local, &local_macros, out, &mut scratch)
    }
}

#[cfg(test)]
mod tests {
    use super::parse_param;

    #[test]
    fn parameter_specs_split_as_python_xacro_splits_them() {
        let p = |s| {
            let (n, d, r) = parse_param(s);
            (n, d, r.to_string())
        };
        assert_eq!(p("a b"), ("a".into(), None, "b".into()));
        assert_eq!(
            p("a:=1 b"),
            ("a".into(), Some((false, Some("1".into()))), "b".into())
        );
        assert_eq!(
            p("a:=^|x c"),
            ("a".into(), Some((true, Some("x".into()))), "c".into())
        );
        assert_eq!(p("a:=^"), ("a".into(), Some((true, None)), "".into()));
        assert_eq!(
            p("a:='x y' b"),
            ("a".into(), Some((false, Some("'x y'".into()))), "b".into())
        );
        assert_eq!(
            p("a:=${1 + 2} b"),
            (
                "a".into(),
                Some((false, Some("${1 + 2}".into()))),
                "b".into()
            )
        );
        assert_eq!(
            p("a:=${x}_y b"),
            ("a".into(), Some((false, Some("${x}_y".into()))), "b".into())
        );
        assert_eq!(
            p("  *origin **content"),
            ("*origin".into(), None, "**content".into())
        );
        assert_eq!(
            p("a=2"),
            ("a".into(), Some((false, Some("2".into()))), "".into())
        );
        assert_eq!(
            p("a:=''"),
            ("a".into(), Some((false, Some("''".into()))), "".into())
        );
    }
}
