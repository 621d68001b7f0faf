//! The bad-input catalogue (tests/bad_inputs/README.md): every file is refused
//! with the committed message. `BLESS=1` rewrites the `.expected` files.

use extrinsic_audit::internals::formats::load_file;
use extrinsic_audit::internals::frames::FrameGraph;
use extrinsic_audit::{Format, LoadOptions};
use std::path::{Path, PathBuf};

const DIR: &str = "tests/bad_inputs";

fn stem(p: &Path) -> String {
    let name = p.file_name().and_then(|s| s.to_str()).unwrap_or("");
    name.split('.').next().unwrap_or("").to_string()
}

fn run(path: &Path) -> Result<(), String> {
    // The 6N cases are point files (LAS, LAZ): read as a raw scan.
    if matches!(
        path.extension().and_then(|e| e.to_str()),
        Some("las" | "laz")
    ) {
        let r = extrinsic_audit::internals::degeneracy::points::read_xyz(path);
        return r.map(|_| ()).map_err(|e| e.to_string());
    }
    // The xacro case must not depend on whether `xacro` is installed.
    let mut opts = LoadOptions::default();
    opts.xacro_search_path = Some("".into());
    let (mut from, mut to) = (None, None);
    let args_path = Path::new(DIR).join(format!("{}.args", stem(path)));
    if let Ok(a) = std::fs::read_to_string(&args_path) {
        let words: Vec<&str> = a.split_whitespace().collect();
        let mut i = 0;
        while i + 1 < words.len() {
            let v = words[i + 1];
            match words[i] {
                "--from" => from = Some(v.to_string()),
                "--to" => to = Some(v.to_string()),
                "--key" => opts.key = Some(v.to_string()),
                "--max-file-size" => opts.max_file_size = v.parse().expect("size"),
                "--input-format" => {
                    opts.format = Some(Format::from_name(v).map_err(|e| e.to_string())?)
                }
                "--joint" => {
                    let (n, x) = v.split_once('=').expect("NAME=VALUE");
                    opts.joints.insert(n.to_string(), x.parse().expect("value"));
                }
                other => panic!("{}: unknown option {other}", args_path.display()),
            }
            i += 2;
        }
    }
    let loaded = load_file(path, &opts).map_err(|e| e.to_string())?;
    let mut g = FrameGraph::new();
    g.add(loaded).map_err(|e| e.to_string())?;
    if let (Some(f), Some(t)) = (from, to) {
        g.transform(&f, &t).map_err(|e| e.to_string())?;
    }
    Ok(())
}

#[test]
fn catalogue() {
    let bless = std::env::var_os("BLESS").is_some();
    let mut inputs: Vec<PathBuf> = std::fs::read_dir(DIR)
        .expect("dir")
        .map(|e| e.expect("entry").path())
        .filter(|p| {
            let n = p.file_name().and_then(|s| s.to_str()).unwrap_or("");
            n.chars()
                .next()
                .map(|c| c.is_ascii_digit())
                .unwrap_or(false)
                && !n.ends_with(".expected")
                && !n.ends_with(".args")
        })
        .collect();
    inputs.sort();
    assert!(inputs.len() >= 25, "only {} bad inputs", inputs.len());
    let mut failures = Vec::new();
    for p in &inputs {
        let got = match run(p) {
            Ok(()) => {
                failures.push(format!("{}: accepted, expected an error", p.display()));
                continue;
            }
            Err(m) => m,
        };
        assert!(
            got.contains(&p.display().to_string()),
            "{}: message does not name the file: {got}",
            p.display()
        );
        let exp_path = Path::new(DIR).join(format!("{}.expected", stem(p)));
        if bless {
            std::fs::write(&exp_path, format!("{got}\n")).expect("write");
            continue;
        }
        let want = std::fs::read_to_string(&exp_path).unwrap_or_default();
        if want.trim_end() != got {
            failures.push(format!(
                "{}:\n  expected: {}\n  got:      {got}",
                p.display(),
                want.trim_end()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The two damaged point files of the catalogue (60-*, 61-*) are made at run
/// time from the real scans (the test-data folder) and refused with the
/// catalogue's message: the first 3000 bytes of autzen.las, and autzen.laz
/// with its legacy point count (byte 108, 1-based) set from 106 to 100.
#[test]
fn damaged_las_and_laz_made_from_the_real_files() {
    use crate::common::testdata::{read, AUTZEN_LAS, AUTZEN_LAZ};
    let (Some(las), Some(mut laz)) = (read(AUTZEN_LAS), read(AUTZEN_LAZ)) else {
        return;
    };
    assert_eq!(laz[107], 106, "autzen.laz: the legacy point count");
    laz[107] = 100;
    let tmp = tempfile::tempdir().expect("tempdir");
    for (name, bytes) in [
        ("60-las-truncated.las", &las[..3000]),
        ("61-laz-count-below-data.laz", &laz[..]),
    ] {
        let p = tmp.path().join(name);
        std::fs::write(&p, bytes).expect("write");
        let got = run(&p)
            .expect_err("refused")
            .replace(&format!("{}/", tmp.path().display()), &format!("{DIR}/"));
        let exp = Path::new(DIR).join(format!("{}.expected", stem(&p)));
        if std::env::var_os("BLESS").is_some() {
            std::fs::write(&exp, format!("{got}\n")).expect("write");
            continue;
        }
        let want = std::fs::read_to_string(&exp).expect("expected message");
        assert_eq!(want.trim_end(), got, "{name}");
    }
}
