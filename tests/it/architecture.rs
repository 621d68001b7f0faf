//! The layering of `src/`, read from the source text: no module cycle, no
//! function over 120 lines.
//!
//! # The import graph
//!
//! The nodes are the files of each crate (the library from `src/lib.rs`, the
//! binary from `src/main.rs`), each named by its module path; an inline `mod
//! x { ... }` (a SIMD kernel) belongs to the file that holds it, and a
//! `#[cfg(test)]` one is left out: a unit test may reach the layers above the
//! code it tests (a reader's test through the format's loader), and nothing
//! imports a test.
//! A file *imports* module `m` when a `use` item or a path in its code
//! (`crate::...`, `super::...`, `self::...`, or a path starting at one of its
//! own child modules) names something through `m`, where `m` is the deepest
//! module the path goes through: `crate::frames::edge::Edge` imports
//! `frames::edge`, `super::Edge` (from `frames::graph`) imports `frames`, and
//! `use super::*` imports the parent. Declaring a child (`mod x;`) is not an
//! import; re-exporting its items (`pub use x::Y;`) is.
//!
//! The rule: **the import graph is acyclic**. A parent that re-exports its
//! children's items is above them, so a module may import from its ancestors
//! only their child modules, the leaves (`super::edge::Edge`), never the items
//! an ancestor defines or re-exports itself (`super::Edge`) unless that
//! ancestor imports nothing from it. A failure names each cycle, one import
//! per step with its file and line.
//!
//! Comments and string literals are blanked before the paths are read, so a
//! path in a doc comment or a message is not an import. `$crate::` in a
//! macro counts as an import of the module that defines the macro.
//!
//! # Function length
//!
//! Every `fn` item with a body, in every file of `src/`, spans at most 120
//! lines from the line of `fn` to its closing brace (braces matched on the
//! same blanked text, so a brace in a string or a comment does not count).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const MAX_FN_LINES: usize = 120;

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// `text` with every comment and the contents of every string and character
/// literal replaced by spaces (line breaks kept, so lines still count).
fn blank(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = b.to_vec();
    let mut i = 0;
    let wipe = |out: &mut Vec<u8>, from: usize, to: usize| {
        for c in &mut out[from..to] {
            if *c != b'\n' {
                *c = b' ';
            }
        }
    };
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                let end = b[i..]
                    .iter()
                    .position(|&c| c == b'\n')
                    .map_or(b.len(), |p| i + p);
                wipe(&mut out, i, end);
                i = end;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                let (mut depth, mut j) = (1, i + 2);
                while j < b.len() && depth > 0 {
                    if b[j..].starts_with(b"/*") {
                        depth += 1;
                        j += 2;
                    } else if b[j..].starts_with(b"*/") {
                        depth -= 1;
                        j += 2;
                    } else {
                        j += 1;
                    }
                }
                wipe(&mut out, i, j);
                i = j;
            }
            b'r' | b'b' if raw_string_start(b, i).is_some() => {
                let (hashes, open) = raw_string_start(b, i).unwrap_or((0, i));
                let close: Vec<u8> = std::iter::once(b'"')
                    .chain(std::iter::repeat_n(b'#', hashes))
                    .collect();
                let end = b[open + 1..]
                    .windows(close.len())
                    .position(|w| w == close.as_slice())
                    .map_or(b.len(), |p| open + 1 + p + close.len());
                wipe(&mut out, open + 1, end.saturating_sub(close.len()));
                i = end;
            }
            b'"' => {
                let mut j = i + 1;
                while j < b.len() && b[j] != b'"' {
                    j += if b[j] == b'\\' { 2 } else { 1 };
                }
                wipe(&mut out, i + 1, j.min(b.len()));
                i = j + 1;
            }
            b'\'' => {
                // A character literal ('x', '\n', '\u{..}'), not a lifetime.
                let j = if b.get(i + 1) == Some(&b'\\') {
                    b[i + 2..]
                        .iter()
                        .position(|&c| c == b'\'')
                        .map(|p| i + 2 + p)
                } else {
                    let ch = text[i + 1..].chars().next().map_or(1, char::len_utf8);
                    (b.get(i + 1 + ch) == Some(&b'\'')).then_some(i + 1 + ch)
                };
                match j {
                    Some(j) => {
                        wipe(&mut out, i + 1, j);
                        i = j + 1;
                    }
                    None => i += 1,
                }
            }
            _ => i += 1,
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// `r"`, `r#"`, `br"`, `br#"` at `i` (not inside an identifier): the number
/// of `#` and the index of the opening quote.
fn raw_string_start(b: &[u8], i: usize) -> Option<(usize, usize)> {
    if i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_') {
        return None;
    }
    let mut j = i;
    if b[j] == b'b' {
        j += 1;
    }
    if b.get(j) != Some(&b'r') {
        return None;
    }
    j += 1;
    let hashes = b[j..].iter().take_while(|&&c| c == b'#').count();
    (b.get(j + hashes) == Some(&b'"')).then_some((hashes, j + hashes))
}

/// A token of blanked source: an identifier (keywords included), `::`, or
/// one punctuation character; with its line.
#[derive(Debug, Clone, PartialEq)]
struct Tok {
    text: String,
    line: usize,
}

fn tokens(blanked: &str) -> Vec<Tok> {
    let mut out = Vec::new();
    let mut line = 1;
    let mut chars = blanked.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        if c == '\n' {
            line += 1;
        } else if c.is_alphanumeric() || c == '_' || c == '$' {
            let mut end = i + c.len_utf8();
            while let Some(&(j, d)) = chars.peek() {
                if !(d.is_alphanumeric() || d == '_') {
                    break;
                }
                end = j + d.len_utf8();
                chars.next();
            }
            out.push(Tok {
                text: blanked[i..end].to_string(),
                line,
            });
        } else if c == ':' && chars.peek().map(|&(_, d)| d) == Some(':') {
            chars.next();
            out.push(Tok {
                text: "::".into(),
                line,
            });
        } else if !c.is_whitespace() {
            out.push(Tok {
                text: c.to_string(),
                line,
            });
        }
    }
    out
}

/// One file of a crate: its module path and its tokens.
struct SourceFile {
    path: PathBuf,
    module: Vec<String>,
    toks: Vec<Tok>,
}

/// The files of the crate rooted at `root`, following `mod x;` declarations
/// (inline modules included); with the set of every module path.
fn crate_files(root: &Path) -> (Vec<SourceFile>, BTreeSet<Vec<String>>) {
    let mut files = Vec::new();
    let mut modules = BTreeSet::new();
    let mut todo = vec![(root.to_path_buf(), Vec::<String>::new())];
    while let Some((path, module)) = todo.pop() {
        let text = std::fs::read_to_string(&path).expect("read a source file");
        let toks = tokens(&blank(&text));
        // Child files live in the file's own directory when it is lib.rs,
        // main.rs or mod.rs, else in a directory named after it.
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let dir = if matches!(name, "lib.rs" | "main.rs" | "mod.rs") {
            path.parent().expect("dir").to_path_buf()
        } else {
            path.with_extension("")
        };
        modules.insert(module.clone());
        for (inline, child, in_file) in module_decls(&toks) {
            let mut m = module.clone();
            m.extend(inline.iter().cloned());
            m.push(child.clone());
            modules.insert(m.clone());
            if in_file {
                let mut d = dir.clone();
                d.extend(&inline);
                let file = [d.join(format!("{child}.rs")), d.join(&child).join("mod.rs")]
                    .into_iter()
                    .find(|p| p.exists())
                    .unwrap_or_else(|| panic!("{}: mod {child}; has no file", path.display()));
                todo.push((file, m));
            }
        }
        files.push(SourceFile { path, module, toks });
    }
    (files, modules)
}

/// The modules a file declares: the inline modules around the declaration,
/// the name, and whether it is a file of its own (`mod x;`).
fn module_decls(toks: &[Tok]) -> Vec<(Vec<String>, String, bool)> {
    let mut out = Vec::new();
    let mut scopes = Scopes::default();
    for (k, t) in toks.iter().enumerate() {
        if scopes.brace(&t.text) || t.text != "mod" {
            continue;
        }
        let (Some(name), Some(next)) = (toks.get(k + 1), toks.get(k + 2)) else {
            continue;
        };
        if next.text == ";" {
            out.push((scopes.names(), name.text.clone(), true));
        } else if next.text == "{" {
            out.push((scopes.names(), name.text.clone(), false));
            scopes.enter(&name.text, false);
        }
    }
    out
}

/// The inline modules (`mod name { ... }`) open at a token, followed as the
/// braces open and close (the one brace-tracking loop of this file): each
/// the module's name, the depth its `{` opens at, and whether it is under
/// `#[cfg(test)]`.
#[derive(Default)]
struct Scopes {
    open: Vec<(String, usize, bool)>,
    depth: usize,
}

impl Scopes {
    /// Follow `t` if it is a brace (a `}` closes the module it ends);
    /// whether it was one.
    fn brace(&mut self, t: &str) -> bool {
        match t {
            "{" => self.depth += 1,
            "}" => {
                self.depth = self.depth.saturating_sub(1);
                if self.open.last().is_some_and(|s| s.1 == self.depth) {
                    self.open.pop();
                }
            }
            _ => return false,
        }
        true
    }

    /// A module `name` opens at the next `{`.
    fn enter(&mut self, name: &str, test: bool) {
        self.open.push((name.to_string(), self.depth, test));
    }

    /// The open modules, outermost first.
    fn names(&self) -> Vec<String> {
        self.open.iter().map(|s| s.0.clone()).collect()
    }

    /// Whether a module open here is under `#[cfg(test)]`.
    fn in_test(&self) -> bool {
        self.open.iter().any(|s| s.2)
    }
}

/// One import: from a module to a module, where it is written.
#[derive(Debug, Clone)]
struct Import {
    from: Vec<String>,
    to: Vec<String>,
    file: PathBuf,
    line: usize,
}

/// The paths `toks` names, each with the inline module it is written in and
/// its line: `use` trees flattened, and the paths of the code (`crate::`,
/// `super::`, `self::`, or any other first segment, which [`resolve`] keeps
/// when it names a child module).
fn paths(toks: &[Tok]) -> Vec<(Vec<String>, Vec<String>, usize)> {
    let mut out = Vec::new();
    let mut scopes = Scopes::default();
    let mut k = 0;
    while k < toks.len() {
        let t = &toks[k];
        let inline = scopes.names();
        let in_test = scopes.in_test();
        if scopes.brace(&t.text) {
            k += 1;
            continue;
        }
        match t.text.as_str() {
            "mod" if toks.get(k + 2).is_some_and(|n| n.text == "{") => {
                let test = in_test || cfg_test_before(toks, k);
                scopes.enter(&toks[k + 1].text, test);
                scopes.brace("{");
                k += 3;
                continue;
            }
            _ if in_test => {}
            "use" => {
                let end = toks[k..]
                    .iter()
                    .position(|t| t.text == ";")
                    .map_or(toks.len(), |p| k + p);
                for p in flatten_use(&toks[k + 1..end]) {
                    out.push((inline.clone(), p, t.line));
                }
                k = end + 1;
                continue;
            }
            s if (is_ident(s) || s == "$crate")
                && toks.get(k + 1).is_some_and(|n| n.text == "::")
                && (k == 0 || toks[k - 1].text != "::") =>
            {
                let mut p = vec![t.text.trim_start_matches('$').to_string()];
                let mut j = k + 1;
                while toks.get(j).is_some_and(|n| n.text == "::")
                    && toks.get(j + 1).is_some_and(|n| is_ident(&n.text))
                {
                    p.push(toks[j + 1].text.clone());
                    j += 2;
                }
                out.push((inline, p, t.line));
                k = j;
                continue;
            }
            _ => {}
        }
        k += 1;
    }
    out
}

/// Whether the item at `k` (after its visibility) is marked `#[cfg(test)]`.
fn cfg_test_before(toks: &[Tok], k: usize) -> bool {
    let text: Vec<&str> = toks[..k]
        .iter()
        .rev()
        .take(9)
        .map(|t| t.text.as_str())
        .collect();
    let at = text.iter().position(|t| *t == "]").unwrap_or(usize::MAX);
    at <= 3 && text.get(at + 1..at + 6) == Some(&[")", "test", "(", "cfg", "["][..])
}

fn is_ident(s: &str) -> bool {
    s.chars()
        .next()
        .is_some_and(|c| c.is_alphabetic() || c == '_')
}

/// A use tree (`a::b::{c, d::{self, e}}`) as its paths.
fn flatten_use(toks: &[Tok]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut stack: Vec<Vec<String>> = vec![Vec::new()];
    let mut cur: Vec<String> = Vec::new();
    let mut alias = false;
    for t in toks {
        if std::mem::take(&mut alias) {
            continue; // `x as y`: the alias is not part of the path
        }
        match t.text.as_str() {
            "::" => {}
            "{" => {
                let mut base = stack.last().cloned().unwrap_or_default();
                base.append(&mut cur);
                stack.push(base);
            }
            "," | "}" => {
                if !cur.is_empty() {
                    let mut p = stack.last().cloned().unwrap_or_default();
                    p.append(&mut cur);
                    out.push(p);
                }
                if t.text == "}" {
                    stack.pop();
                }
            }
            "as" => alias = true,
            "*" => cur.push("*".into()),
            s if is_ident(s) => cur.push(s.to_string()),
            _ => {}
        }
    }
    if !cur.is_empty() {
        let mut p = stack.last().cloned().unwrap_or_default();
        p.append(&mut cur);
        out.push(p);
    }
    out
}

/// The module a path imports, written in module `at`: the deepest module it
/// goes through (`None`: a path outside the crate).
fn resolve(at: &[String], path: &[String], modules: &BTreeSet<Vec<String>>) -> Option<Vec<String>> {
    let mut m: Vec<String> = at.to_vec();
    let mut rest = path;
    match path.first().map(String::as_str) {
        Some("crate") => {
            m.clear();
            rest = &path[1..];
        }
        Some("self") => rest = &path[1..],
        Some("super") => {
            while rest.first().map(String::as_str) == Some("super") {
                m.pop()?;
                rest = &rest[1..];
            }
        }
        Some(first) => {
            let mut child = at.to_vec();
            child.push(first.to_string());
            if !modules.contains(&child) {
                return None;
            }
        }
        None => return None,
    }
    for seg in rest {
        let mut next = m.clone();
        next.push(seg.clone());
        if seg == "self" || !modules.contains(&next) {
            break;
        }
        m = next;
    }
    Some(m)
}

/// Every import of the crate rooted at `root`, between files: a path written
/// in an inline module resolves from there (`super::` in `mod tests` is the
/// file's module) and counts as an import of the file that holds it; a
/// file's imports of itself and of its own inline modules are left out.
fn imports(root: &Path) -> Vec<Import> {
    let (files, modules) = crate_files(root);
    let mut out = Vec::new();
    for f in &files {
        let own: BTreeSet<Vec<String>> = module_decls(&f.toks)
            .into_iter()
            .filter(|(.., in_file)| !in_file)
            .map(|(inline, name, _)| [f.module.clone(), inline, vec![name]].concat())
            .chain([f.module.clone()])
            .collect();
        for (inline, path, line) in paths(&f.toks) {
            let at = [f.module.clone(), inline].concat();
            let Some(to) = resolve(&at, &path, &modules) else {
                continue;
            };
            if own.contains(&to) {
                continue;
            }
            out.push(Import {
                from: f.module.clone(),
                to,
                file: f.path.clone(),
                line,
            });
        }
    }
    out
}

fn name(m: &[String]) -> String {
    if m.is_empty() {
        "crate".into()
    } else {
        m.join("::")
    }
}

/// The cycles of the import graph: for each strongly connected component of
/// more than one module, one cycle through it, each step with the import
/// that makes it (`file:line`, relative to `base`).
fn cycles(imports: &[Import], base: &Path) -> Vec<String> {
    let mut graph: BTreeMap<String, BTreeMap<String, &Import>> = BTreeMap::new();
    for i in imports {
        graph
            .entry(name(&i.from))
            .or_default()
            .entry(name(&i.to))
            .or_insert(i);
        graph.entry(name(&i.to)).or_default();
    }
    let mut found = Vec::new();
    let mut reported: BTreeSet<String> = BTreeSet::new();
    for start in graph.keys() {
        if reported.contains(start) {
            continue;
        }
        // The shortest path back to `start` (breadth first).
        let mut prev: BTreeMap<&String, &String> = BTreeMap::new();
        let mut queue = std::collections::VecDeque::from([start]);
        let mut back = None;
        while let Some(m) = queue.pop_front() {
            for next in graph[m].keys() {
                if next == start {
                    back = Some(m);
                    break;
                }
                if !prev.contains_key(next) {
                    prev.insert(next, m);
                    queue.push_back(next);
                }
            }
            if back.is_some() {
                break;
            }
        }
        let Some(mut m) = back else { continue };
        let mut cycle = vec![start.clone()];
        while m != start {
            cycle.push(m.clone());
            m = prev[m];
        }
        cycle.reverse();
        cycle.rotate_right(1);
        cycle.push(start.clone());
        let steps: Vec<String> = cycle
            .windows(2)
            .map(|w| {
                let i = graph[&w[0]][&w[1]];
                let file = i.file.strip_prefix(base).unwrap_or(&i.file);
                format!("{} -> {} ({}:{})", w[0], w[1], file.display(), i.line)
            })
            .collect();
        reported.extend(cycle.iter().cloned());
        found.push(steps.join(", "));
    }
    found
}

#[test]
fn no_module_imports_itself_back() {
    for root in ["lib.rs", "main.rs"] {
        let found = cycles(&imports(&src().join(root)), &src());
        let modules = |c: &String| -> String {
            c.split(", ")
                .map(|step| step.split(" -> ").next().unwrap_or(step))
                .collect::<Vec<_>>()
                .join(" -> ")
        };
        let new: Vec<&String> = found
            .iter()
            .filter(|c| !KNOWN_CYCLES.contains(&modules(c).as_str()))
            .collect();
        assert!(
            new.is_empty(),
            "src/{root}: {} module cycle(s), files under src/ (the rule: tests/it/architecture.rs):\n{}",
            new.len(),
            new.iter().map(|c| c.as_str()).collect::<Vec<_>>().join("\n")
        );
        if root == "lib.rs" {
            let gone: Vec<&&str> = KNOWN_CYCLES
                .iter()
                .filter(|k| !found.iter().any(|c| modules(c) == **k))
                .collect();
            assert!(
                gone.is_empty(),
                "broken cycles still listed in KNOWN_CYCLES (remove them): {gone:?}"
            );
        }
    }
}

/// Cycles allowed as debt, by the modules of each step: none (issue 24 broke
/// the last twelve). A new cycle fails the test; one listed here that is
/// broken fails it too, so the list can only shrink.
const KNOWN_CYCLES: &[&str] = &[];

/// The rule finds what it is meant to: a parent that re-exports a child
/// which imports the parent's items, and a cycle of siblings; not a path in a
/// comment or a string, nor a unit test's import.
#[test]
fn the_cycle_rule_finds_a_child_importing_its_parent() {
    let dir = tempfile_dir();
    let w = |p: &str, s: &str| {
        let f = dir.join(p);
        std::fs::create_dir_all(f.parent().expect("dir")).expect("mkdir");
        std::fs::write(f, s).expect("write");
    };
    w("lib.rs", "mod a;\nmod b;\nmod c;\n");
    w(
        "a/mod.rs",
        "mod leaf;\nmod x;\npub use x::X;\npub struct A;\n",
    );
    // A unit test may reach above its module: left out of the graph.
    w(
        "a/leaf.rs",
        "pub struct L;\n#[cfg(test)]\nmod tests {\n    use crate::a::A;\n}\n",
    );
    // x may use its sibling leaf; naming `super::A` imports `a`, which re-exports x.
    w(
        "a/x.rs",
        "use super::leaf::L;\nuse super::A;\npub struct X;\n",
    );
    w(
        "b.rs",
        "use crate::c::C; // crate::a::A in a comment\npub struct B;\n",
    );
    w(
        "c.rs",
        "pub struct C;\nfn f() -> &'static str { \"crate::b::B\" }\nuse crate::b;\n",
    );
    let found = cycles(&imports(&dir.join("lib.rs")), &dir);
    assert_eq!(
        found,
        [
            "a -> a::x (a/mod.rs:3), a::x -> a (a/x.rs:2)",
            "b -> c (b.rs:1), c -> b (c.rs:3)",
        ]
    );
    std::fs::remove_dir_all(&dir).ok();
}

fn tempfile_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("audit-architecture-{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    d
}

/// Every `fn` with a body in `toks`: (name, first line, last line).
fn functions(toks: &[Tok]) -> Vec<(String, usize, usize)> {
    let mut out = Vec::new();
    for (k, t) in toks.iter().enumerate() {
        if t.text != "fn" || !toks.get(k + 1).is_some_and(|n| is_ident(&n.text)) {
            continue;
        }
        // The body opens at the first `{` outside parentheses and angle
        // brackets; a `;` first means a declaration without a body.
        let mut j = k + 2;
        let mut paren = 0i32;
        while j < toks.len() {
            match toks[j].text.as_str() {
                "(" | "[" => paren += 1,
                ")" | "]" => paren -= 1,
                "{" if paren == 0 => break,
                ";" if paren == 0 => break,
                _ => {}
            }
            j += 1;
        }
        if toks.get(j).is_none_or(|t| t.text != "{") {
            continue;
        }
        let mut depth = 0;
        for end in &toks[j..] {
            match end.text.as_str() {
                "{" => depth += 1,
                "}" => {
                    depth -= 1;
                    if depth == 0 {
                        out.push((toks[k + 1].text.clone(), t.line, end.line));
                        break;
                    }
                }
                _ => {}
            }
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).expect("read src") {
        let p = e.expect("entry").path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn no_function_in_src_is_over_120_lines() {
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    files.sort();
    let mut long = Vec::new();
    let mut counted = 0;
    for f in &files {
        let text = std::fs::read_to_string(f).expect("read");
        for (name, first, last) in functions(&tokens(&blank(&text))) {
            counted += 1;
            let n = last - first + 1;
            if n > MAX_FN_LINES {
                let rel = f.strip_prefix(src()).unwrap_or(f);
                long.push(format!(
                    "src/{}:{first} fn {name}: {n} lines",
                    rel.display()
                ));
            }
        }
    }
    assert!(
        counted > 1000,
        "expected the functions of src/, found {counted}"
    );
    assert!(
        long.is_empty(),
        "functions over {MAX_FN_LINES} lines:\n{}",
        long.join("\n")
    );
}

/// The counter reads braces as the compiler does: not in strings, comments
/// or character literals, and a lifetime is not a character.
#[test]
fn function_lines_ignore_braces_in_strings_and_comments() {
    let text = "fn a<'x>(s: &'x str) -> usize {\n    let _ = \"}}}\"; // }\n    /* } */ let _c = '}';\n    let _r = r#\"}\"#;\n    1\n}\nfn b();\nfn c() {}\n";
    let got = functions(&tokens(&blank(text)));
    assert_eq!(got, [("a".to_string(), 1, 6), ("c".to_string(), 8, 8)]);
}
