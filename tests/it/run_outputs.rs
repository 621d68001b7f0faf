//! `audit run`'s outputs as a user meets them (issue 26): the summary and
//! the JSON lines validate against their committed schemas
//! (docs/schemas/run.schema.json, run-scan.schema.json) on every kind of
//! run the fixtures hold; per-scan warnings come in scan order; the
//! timeline's legend never covers data; `--strict` gives exit 1 exactly
//! when data was lost (skipped scans, damage).

use crate::common::audit;
use crate::json_schemas::schema;
use crate::run_fixtures::{run_with_records, SHORT_POSES};
use serde_json::Value;
use std::path::Path;

const DIR: &str = "tests/fixtures/run";

/// `audit run ARGS --format json --jsonl F` in the fixtures' folder: exit
/// code, summary, records, stderr.
fn run_json(args: &[&str]) -> (i32, Value, Vec<Value>, String) {
    let (out, recs) = run_with_records(&[args, &["--format", "json"]].concat());
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let summary = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{e}: {err}"));
    (out.status.code().unwrap_or(-1), summary, recs, err)
}

fn assert_valid(v: &jsonschema::Validator, x: &Value, what: &str) {
    let errors: Vec<String> = v
        .iter_errors(x)
        .map(|e| format!("{e} at {}", e.instance_path))
        .collect();
    assert!(errors.is_empty(), "{what}: {errors:#?}");
}

/// A copy of the first `len` bytes of the fixture `name` in `dir`.
fn truncated(dir: &Path, name: &str, len: usize) -> String {
    let b = std::fs::read(Path::new(DIR).join(name)).unwrap();
    let p = dir.join(format!("cut_{name}"));
    std::fs::write(&p, &b[..len]).unwrap();
    std::fs::canonicalize(p)
        .unwrap()
        .to_string_lossy()
        .into_owned()
}

#[test]
fn summaries_and_records_match_the_run_schemas() {
    let (summary, record) = (schema("run"), schema("run-scan"));
    let dir = tempfile::tempdir().unwrap();
    let cut = truncated(dir.path(), "run.mcap", 30_000);
    let runs: [&[&str]; 7] = [
        &["run.mcap", "--all-frames"],
        &["run.bag", "--pairs", "--all-frames"],
        &["hostile.mcap"],
        &[
            "kitti_seq",
            "--rig-frames",
            "../../../calibrations/kitti-velo64-oxts.toml",
        ],
        &SHORT_POSES,
        &["pcd_seq", "--every", "2", "--start", "1"],
        &[&cut],
    ];
    let mut seen = std::collections::BTreeSet::new();
    for args in runs {
        let (code, s, recs, err) = run_json(args);
        assert_eq!(code, 0, "{args:?}: {err}");
        assert_valid(&summary, &s, &format!("{args:?} summary"));
        assert!(!recs.is_empty(), "{args:?}");
        for r in &recs {
            assert_valid(&record, r, &format!("{args:?} record {}", r["index"]));
            seen.insert(r["status"].as_str().unwrap().to_string());
            if let Some(why) = r["reason"].as_str() {
                seen.insert(why.to_string());
            }
        }
        if args[0] == cut {
            assert!(s["damage"].is_string(), "{s}");
        }
    }
    // The runs cover skipped records of several reasons, pairs and damage.
    for want in ["ok", "skipped", "empty", "invalid-cloud", "no-pose"] {
        assert!(seen.contains(want), "{want} not covered: {seen:?}");
    }
    // The schemas are strict: an unknown key or a wrong type is an error.
    let (_, mut s, mut recs, _) = run_json(&["run.mcap"]);
    s["extra"] = Value::from(1);
    assert!(!summary.is_valid(&s));
    recs[0]["frames"][0]["families"][0]["eigenvalues"] = Value::from("1");
    assert!(!record.is_valid(&recs[0]));
}

/// The scan index a per-scan warning line starts with (`warning[x]: scan 6, 7: ...`).
fn first_scan(line: &str) -> Option<usize> {
    let rest = line.split_once("]: ")?.1;
    let rest = rest.strip_prefix("scan ")?;
    let n: String = rest.chars().take_while(char::is_ascii_digit).collect();
    n.parse().ok()
}

#[test]
fn per_scan_warnings_come_in_scan_order() {
    // run.mcap: 16 bytes past the data on scan 2, 13 on scan 6 (messages
    // that sort the other way); hostile.mcap: skips and an `ignored`.
    for (args, ignored) in [
        (&["run.mcap"][..], vec![2, 6]),
        (&["run.mcap", "--pairs"][..], vec![2, 6]),
        (&["hostile.mcap"][..], vec![10]),
    ] {
        let (code, s, _, err) = run_json(args);
        assert_eq!(code, 0, "{err}");
        let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("warning[")).collect();
        let at: Vec<usize> = lines.iter().filter_map(|l| first_scan(l)).collect();
        assert!(at.windows(2).all(|w| w[0] <= w[1]), "{args:?}: {lines:#?}");
        let ign: Vec<usize> = lines
            .iter()
            .filter(|l| l.starts_with("warning[ignored]"))
            .filter_map(|l| first_scan(l))
            .collect();
        assert_eq!(ign, ignored, "{args:?}: {lines:#?}");
        // The summary's warnings are stderr's, in the same order.
        let ws: Vec<&str> = s["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .map(|w| w.as_str().unwrap())
            .collect();
        assert_eq!(ws, lines, "{args:?}");
    }
}

/// An element's bounding box `[x0, y0, x1, y1]` (px), for the shapes
/// plotters writes.
fn bbox(n: roxmltree::Node) -> Option<[f64; 4]> {
    let a = |k: &str| n.attribute(k).and_then(|v| v.parse::<f64>().ok());
    match n.tag_name().name() {
        "rect" => {
            let (x, y) = (a("x")?, a("y")?);
            Some([x, y, x + a("width")?, y + a("height")?])
        }
        "circle" => {
            let (x, y, r) = (a("cx")?, a("cy")?, a("r")?);
            Some([x - r, y - r, x + r, y + r])
        }
        "polyline" | "polygon" => {
            let pts: Vec<(f64, f64)> = n
                .attribute("points")?
                .split_whitespace()
                .filter_map(|p| p.split_once(','))
                .map(|(x, y)| (x.parse().unwrap(), y.parse().unwrap()))
                .collect();
            let fold = |f: fn(f64, f64) -> f64, init: f64, k: fn(&(f64, f64)) -> f64| {
                pts.iter().map(k).fold(init, f)
            };
            Some([
                fold(f64::min, f64::INFINITY, |p| p.0),
                fold(f64::min, f64::INFINITY, |p| p.1),
                fold(f64::max, f64::NEG_INFINITY, |p| p.0),
                fold(f64::max, f64::NEG_INFINITY, |p| p.1),
            ])
        }
        "text" => {
            let (x, y) = (a("x")?, a("y")?);
            Some([x, y, x, y])
        }
        _ => None,
    }
}

fn overlaps(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

fn inside(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[0] >= b[0] && a[2] <= b[2] && a[1] >= b[1] && a[3] <= b[3]
}

#[test]
fn the_timeline_legend_sits_outside_the_data() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("t.svg");
    let out = audit()
        .current_dir(DIR)
        .args(["run", "run.mcap", "--all-frames", "--timeline"])
        .arg(&svg)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let text = std::fs::read_to_string(&svg).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let nodes: Vec<_> = doc.descendants().filter(|n| n.is_element()).collect();
    let root = doc.root_element();
    let full = [root.attribute("width"), root.attribute("height")];
    // Legend boxes: the opaque white rectangles other than the background.
    let boxes: Vec<[f64; 4]> = nodes
        .iter()
        .filter(|n| n.tag_name().name() == "rect" && n.attribute("fill") == Some("#FFFFFF"))
        .filter(|n| [n.attribute("width"), n.attribute("height")] != full)
        .filter_map(|n| bbox(*n))
        .collect();
    assert_eq!(boxes.len(), 8, "one legend per family");
    let marks = ["rect", "circle", "polyline", "polygon"];
    for b in &boxes {
        let mut icons = 0;
        for n in &nodes {
            let Some(m) = bbox(*n) else { continue };
            let background = n.attribute("width") == full[0];
            if m == *b || background || !marks.contains(&n.tag_name().name()) {
                continue;
            }
            if inside(&m, b) {
                icons += 1; // the legend's own icon
            } else {
                assert!(
                    !overlaps(&m, b),
                    "{} at {m:?} under the legend {b:?}",
                    n.tag_name().name()
                );
            }
        }
        let texts = nodes
            .iter()
            .filter(|n| n.tag_name().name() == "text")
            .filter_map(|n| bbox(*n))
            .filter(|t| inside(t, b))
            .count();
        // Nothing of the data hides inside a box: one icon per entry (the
        // border, the box's own rectangle, is skipped above).
        assert!(texts >= 6, "{texts} entries");
        assert_eq!(icons, texts, "legend {b:?}");
    }
}

#[test]
fn strict_exits_1_when_data_was_lost_and_writes_everything() {
    // Ignored bytes are not lost data: exit 0.
    let (code, _, _, err) = run_json(&["run.mcap", "--strict"]);
    assert_eq!(code, 0, "{err}");
    // Skipped scans: exit 1, every record still written.
    let (code, s, recs, err) = run_json(&["hostile.mcap", "--strict"]);
    assert_eq!(code, 1, "{err}");
    assert_eq!(recs.len(), s["read"].as_u64().unwrap() as usize);
    assert!(
        err.contains("audit run --strict: 8 scans skipped: exit 1"),
        "{err}"
    );
    // Damage: exit 1, the scans before it reported.
    let dir = tempfile::tempdir().unwrap();
    let cut = truncated(dir.path(), "run.mcap", 30_000);
    let (code, s, recs, err) = run_json(&[&cut, "--strict"]);
    assert_eq!(code, 1, "{err}");
    assert!(!recs.is_empty() && s["damage"].is_string());
    assert!(err.contains("the read stopped at damage"), "{err}");
    // Without --strict the same runs exit 0.
    assert_eq!(run_json(&[&cut]).0, 0);
    assert_eq!(run_json(&["hostile.mcap"]).0, 0);
}
