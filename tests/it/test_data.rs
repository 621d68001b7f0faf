//! Issue 25: no third-party file is committed. Every file of the repository
//! (`git ls-files`) differs from every file of the shared folder beside the
//! checkout (its test data, URDF corpus and rig sources), by sha256; the
//! manifest's files are all in the test-data folder with their sha256; the
//! table of docs/test-data.md is the manifest's.

use crate::common::testdata::{self, doc_table, manifest, root, sha256, DOC};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const CHECKOUT: &str = env!("CARGO_MANIFEST_DIR");

/// Every file under `dir`, recursively (symbolic links not followed).
fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let Ok(t) = e.file_type() else { continue };
        if t.is_dir() {
            walk(&e.path(), out);
        } else if t.is_file() {
            out.push(e.path());
        }
    }
}

/// The committed files (`git ls-files`), or `None` outside a git checkout.
fn committed() -> Option<Vec<String>> {
    let out = std::process::Command::new("git")
        .args(["ls-files", "-z"])
        .current_dir(CHECKOUT)
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    let text = String::from_utf8(out.stdout).expect("UTF-8 paths");
    Some(
        text.split('\0')
            .filter(|p| !p.is_empty())
            .map(String::from)
            .collect(),
    )
}

/// sha256 of each committed file that is on disk (a deletion not yet
/// committed is not there).
fn committed_hashes(files: &[String]) -> BTreeMap<String, String> {
    files
        .iter()
        .filter_map(|f| {
            let bytes = std::fs::read(Path::new(CHECKOUT).join(f)).ok()?;
            Some((sha256(&bytes), f.clone()))
        })
        .collect()
}

/// The folders whose files may not be committed: the shared folder beside the
/// checkout and the test-data folder (when set elsewhere).
fn shared_folders() -> Vec<PathBuf> {
    let mut dirs = vec![Path::new(CHECKOUT).join("../shared"), root()];
    dirs.retain(|d| d.is_dir());
    dirs
}

#[test]
fn no_committed_file_is_a_copy_of_a_shared_file() {
    let Some(files) = committed() else {
        testdata::skip_because("not a git checkout: the committed files are unknown");
        return;
    };
    let ours = committed_hashes(&files);
    // The manifest's hashes hold without the folder (docs/test-data.md).
    let mut copies: Vec<String> = manifest()
        .iter()
        .filter_map(|e| ours.get(&e.sha256).map(|f| format!("{f} = {}", e.path)))
        .collect();
    let dirs = shared_folders();
    if dirs.is_empty() {
        copies.sort();
        assert!(
            copies.is_empty(),
            "third-party copies:\n{}",
            copies.join("\n")
        );
        testdata::skip_because(&format!(
            "no shared folder at {}/../shared or {}: checked against the manifest's sha256 only",
            CHECKOUT,
            root().display()
        ));
        return;
    }
    testdata::used();
    let mut seen = 0;
    for d in &dirs {
        let mut shared = Vec::new();
        walk(d, &mut shared);
        seen += shared.len();
        for p in shared {
            let bytes = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            if let Some(f) = ours.get(&sha256(&bytes)) {
                copies.push(format!("{f} = {}", p.display()));
            }
        }
    }
    copies.sort();
    copies.dedup();
    assert!(
        copies.is_empty(),
        "{} committed file(s) are byte-identical to shared files:\n{}",
        copies.len(),
        copies.join("\n")
    );
    assert!(seen > 200, "only {seen} shared files found in {dirs:?}");
}

#[test]
fn every_manifest_file_is_in_the_test_data_folder() {
    if !root().join("MANIFEST.tsv").is_file() {
        testdata::skip_because(&format!("no {}/MANIFEST.tsv", root().display()));
        return;
    }
    let mut paths = BTreeSet::new();
    for e in manifest() {
        if paths.insert(e.path.clone()) {
            testdata::file(&e.path).expect("listed in the manifest, present");
        }
    }
    assert!(paths.len() > 200, "{} files", paths.len());
}

/// docs/test-data.md's table, written by tools/testdata.py, is the manifest's
/// (one row per file of the folder).
#[test]
fn the_docs_table_is_the_manifest() {
    let Ok(text) = std::fs::read_to_string(root().join("MANIFEST.tsv")) else {
        testdata::skip_because(&format!("no {}/MANIFEST.tsv", root().display()));
        return;
    };
    let row = |e: &testdata::Entry| {
        [
            e.path.clone(),
            e.repository.clone(),
            e.commit.clone(),
            e.path_in_repo.clone(),
            e.sha256.clone(),
            e.licence.clone(),
        ]
    };
    testdata::used();
    let want: BTreeSet<_> = testdata::parse_manifest(&text).iter().map(row).collect();
    let got: Vec<_> = doc_table().iter().map(row).collect();
    let got_set: BTreeSet<_> = got.iter().cloned().collect();
    assert_eq!(got.len(), got_set.len(), "{DOC}: a file listed twice");
    let missing: Vec<_> = want.difference(&got_set).collect();
    let extra: Vec<_> = got_set.difference(&want).collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "{DOC} differs from MANIFEST.tsv (rerun python3 tools/testdata.py table):\n\
         missing {missing:?}\nextra {extra:?}"
    );
}
