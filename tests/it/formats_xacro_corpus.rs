//! The real-package xacro corpus (docs/xacro.md, "Real packages"): 16 robots
//! from 13 public description repositories, expanded by the built-in
//! expander and compared edge by edge with Python xacro 2.1.1's joints
//! (tests/fixtures/xacro/corpus/edges/*.json, made by make_corpus.py).
//!
//! The packages are third-party files and are not committed: the test reads
//! them from the directory named by `EXTRINSIC_AUDIT_XACRO_CORPUS`, which
//! `make_corpus.py --populate-only --src DIR` fills from the repositories at
//! the commits of cases.tsv; without it the test is skipped with one message.

use crate::common::testdata;
use crate::formats_xacro::{compare, edge_table};
use extrinsic_audit::internals::formats::load_file;
use extrinsic_audit::LoadOptions;
use std::path::{Path, PathBuf};

const DIR: &str = "tests/fixtures/xacro/corpus";
const ENV: &str = "EXTRINSIC_AUDIT_XACRO_CORPUS";

/// The directory of `pkg` below `roots` (a package.xml naming it, at most
/// three levels down), for the `$(find pkg)` in a case's arguments.
fn package_dir(pkg: &str, roots: &[PathBuf]) -> PathBuf {
    fn walk(d: &Path, pkg: &str, depth: usize) -> Option<PathBuf> {
        let text = std::fs::read_to_string(d.join("package.xml")).unwrap_or_default();
        if text.contains(&format!("<name>{pkg}</name>")) {
            return Some(d.to_path_buf());
        }
        let mut subs: Vec<PathBuf> = std::fs::read_dir(d)
            .ok()?
            .flatten()
            .map(|e| e.path())
            .collect();
        subs.sort();
        (depth > 0).then(|| {
            subs.iter()
                .filter(|s| s.is_dir())
                .find_map(|s| walk(s, pkg, depth - 1))
        })?
    }
    roots
        .iter()
        .find_map(|r| walk(r, pkg, 3))
        .unwrap_or_else(|| panic!("package {pkg} not in the corpus"))
}

/// `NAME:=VALUE ...` with `$(find pkg)` replaced by the package's directory.
fn args(text: &str, roots: &[PathBuf]) -> std::collections::BTreeMap<String, String> {
    let mut text = text.to_string();
    while let Some(s) = text.find("$(find ") {
        let e = s + text[s..].find(')').expect(")");
        let dir = package_dir(&text[s + 7..e], roots);
        text.replace_range(s..=e, &dir.to_string_lossy());
    }
    text.split_whitespace()
        .map(|kv| {
            let (k, v) = kv.split_once(":=").expect("NAME:=VALUE");
            (k.to_string(), v.to_string())
        })
        .collect()
}

#[test]
fn real_description_packages_expand_as_python_xacro_expands_them() {
    let Some(src) = std::env::var_os(ENV).map(PathBuf::from) else {
        testdata::skip_because(&format!(
            "{ENV} is not set: the xacro corpus is third-party files, checked out by \
             {DIR}/make_corpus.py --populate-only --src DIR (docs/xacro.md)"
        ));
        return;
    };
    testdata::used();
    let cases = std::fs::read_to_string(Path::new(DIR).join("cases.tsv")).expect("cases.tsv");
    let (mut passed, mut failed) = (Vec::new(), Vec::new());
    for line in cases
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let c: Vec<&str> = line.split('\t').collect();
        let (name, repo, top) = (c[0], c[1], c[3]);
        let dir = |r: &str| src.join(r.split('@').next().expect("repo").replace('/', "+"));
        let roots: Vec<PathBuf> = std::iter::once(dir(repo))
            .chain(c.get(5).unwrap_or(&"").split_whitespace().map(dir))
            .collect();
        let input = match top.strip_prefix("wrapper:") {
            Some(w) => Path::new(DIR).join(w),
            None => roots[0].join(top),
        };
        let mut opts = LoadOptions::default();
        opts.xacro_args = args(c.get(4).unwrap_or(&""), &roots);
        opts.package_paths = roots.clone();
        let want = edge_table(
            &Path::new(DIR).join("edges").join(format!("{name}.json")),
            name,
        );
        match load_file(&input, &opts) {
            Ok(got) => {
                let d = compare(name, &got, &want);
                assert!(d <= 1e-9, "{name}: transforms differ by {d:e}");
                passed.push(format!("{name} ({} edges)", got.edges.len()));
            }
            Err(e) => failed.push(format!("{name}: {e}")),
        }
    }
    eprintln!(
        "xacro corpus: {} of {} agree: {}",
        passed.len(),
        passed.len() + failed.len(),
        passed.join(", ")
    );
    assert!(
        failed.is_empty(),
        "{} failed:\n{}",
        failed.len(),
        failed.join("\n")
    );
    assert_eq!(passed.len(), 16);
}
