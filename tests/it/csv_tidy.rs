//! `--format csv` is one tidy table for every command that offers it (issue
//! 33, item 5): one header, one observation per row, one number per cell,
//! units in the column names, and every cell equal to the JSON report's
//! value of the same run (`--format json`), found by the naming rule that
//! `src/render/csv.rs` states: a column is the JSON key, a vector's
//! component put before the unit (`translation_m[0]` is `translation_x_m`),
//! the parent key prefixed where one is needed (`screw.kind` is
//! `screw_kind`), values per characteristic length suffixed `_l{l}`.
//! python-tests/test_csv_tidy.py reads the same tables with pandas.

use crate::common::run_cli;
use crate::hostile_output::csv_rows;
use serde_json::Value;
use std::collections::BTreeMap;

const URDF: &str = "tests/fixtures/urdf/anymal_c_lidar.urdf";
const PLY: &str = "tests/fixtures/detector/tunnel_small_le.ply";

/// A command, where its JSON rows are, and the columns the JSON has no key
/// for (each said why in the module that writes it) or leaves out in this
/// run (an optional key no row has).
struct Case {
    name: &'static str,
    args: &'static [&'static str],
    rows: fn(&Value) -> Vec<Value>,
    not_in_json: &'static [&'static str],
}

/// `v[key]` as an array of rows.
fn each(v: &Value, key: &str) -> Vec<Value> {
    v[key].as_array().unwrap_or_else(|| panic!("{key}")).clone()
}

/// `short`'s spelling of a characteristic length in a column name.
fn ell(v: &Value) -> String {
    format!("{}", v.as_f64().unwrap())
}

fn put(row: &mut Value, key: String, v: Value) {
    row.as_object_mut().unwrap().insert(key, v);
}

fn rig_rows(v: &Value) -> Vec<Value> {
    let mut r = v.clone();
    put(
        &mut r,
        "sigma_max".into(),
        v["adjoint"]["singular_values"][0].clone(),
    );
    let certs = each(v, "certificate");
    for (k, c) in certs.iter().enumerate() {
        let l = ell(&c["ell_m"]);
        put(&mut r, format!("delta_eff_l{l}"), c["delta_eff"].clone());
        put(&mut r, format!("band_l{l}"), c["band"].clone());
        put(
            &mut r,
            format!("band_uncertainty_l{l}"),
            c["band_uncertainty"].clone(),
        );
        if let Some(kc) = v.get("kappa_check") {
            put(
                &mut r,
                format!("certified_l{l}"),
                kc["certified"][k].clone(),
            );
        }
    }
    for d in each(v, "detectors") {
        let f = d["family"].as_str().unwrap();
        put(
            &mut r,
            format!("invariant_on_rig_{f}"),
            d["invariant_on_rig"].clone(),
        );
    }
    vec![r]
}

fn spread_rows(v: &Value) -> Vec<Value> {
    let ells: Vec<String> = each(v, "bands").iter().map(|b| ell(&b["ell_m"])).collect();
    each(v, "calibrations")
        .into_iter()
        .map(|mut c| {
            for (k, l) in ells.iter().enumerate() {
                let b = c["bands"][k].clone();
                put(&mut c, format!("band_l{l}"), b);
            }
            c
        })
        .collect()
}

fn sweep_rows(v: &Value) -> Vec<Value> {
    let arms = each(v, "arms");
    each(v, "families")
        .into_iter()
        .map(|mut f| {
            for (k, a) in arms.iter().enumerate() {
                let n = f["decision_changes_by_arm"][k].clone();
                let arm = a.as_str().unwrap().replace(' ', "_");
                put(&mut f, format!("decision_changes_by_arm_{arm}"), n);
            }
            f
        })
        .collect()
}

fn simulate_rows(v: &Value) -> Vec<Value> {
    each(v, "families")
        .into_iter()
        .map(|mut f| {
            let e = f["ell_m"].clone();
            put(&mut f, "ell_from_m".into(), e[0].clone());
            put(&mut f, "ell_to_m".into(), e[1].clone());
            f
        })
        .collect()
}

fn tunnel_rows(v: &Value) -> Vec<Value> {
    ["on_axis", "shifted"]
        .iter()
        .map(|k| {
            let mut r = v[k].clone();
            put(&mut r, "frame".into(), Value::from(*k));
            r
        })
        .collect()
}

fn threshold_rows(v: &Value) -> Vec<Value> {
    let mut rows = Vec::new();
    for f in each(v, "families") {
        for mut c in each(&f, "configurations") {
            for k in ["family", "intersection", "gap_decades"] {
                put(&mut c, k.into(), f[k].clone());
            }
            rows.push(c);
        }
    }
    rows
}

const CASES: &[Case] = &[
    Case {
        name: "rig report",
        args: &[URDF, "--from", "base", "--to", "lidar", "--ell", "0.5,1"],
        rows: rig_rows,
        not_in_json: &[],
    },
    Case {
        name: "rig report with --kappa",
        args: &[
            URDF, "--from", "base", "--to", "lidar", "--kappa", "0.01", "--lambda", "0.004",
        ],
        rows: rig_rows,
        not_in_json: &[],
    },
    Case {
        name: "survey",
        args: &["survey", "calibrations/", "--all"],
        rows: |v| each(v, "rigs"),
        // The marks the text table writes beside the id.
        not_in_json: &["placeholder", "duplicate_of"],
    },
    Case {
        name: "check",
        args: &[
            "check",
            "calibrations/",
            "--max-lever-arm",
            "0.1",
            "--require-zero-pitch",
        ],
        rows: |v| each(v, "findings"),
        // No finding of these has help text: the JSON leaves `help` out.
        not_in_json: &["help"],
    },
    Case {
        name: "diff of whole files",
        args: &[
            "diff",
            "tests/fixtures/diff/whole_old.urdf",
            "tests/fixtures/diff/whole_new.urdf",
        ],
        rows: |v| each(v, "edges"),
        not_in_json: &[],
    },
    Case {
        name: "diff of a chain",
        args: &[
            "diff",
            "tests/fixtures/diff/whole_old.urdf",
            "tests/fixtures/diff/whole_new.urdf",
            "--from",
            "base",
            "--to",
            "lidar",
        ],
        rows: |v| each(v, "edges"),
        not_in_json: &[],
    },
    Case {
        name: "spread",
        args: &["spread", "tests/fixtures/spread/kitti-repeat"],
        rows: spread_rows,
        not_in_json: &[],
    },
    Case {
        name: "degeneracy of a scan",
        args: &["degeneracy", PLY, "--shift", "1,0,0"],
        rows: |v| each(v, "families"),
        // Every family has an answer: the JSON leaves `error` out.
        not_in_json: &["error"],
    },
    Case {
        name: "degeneracy of a pair",
        args: &["degeneracy", PLY, "--target", PLY, "--gate", "0.5"],
        rows: |v| each(v, "families"),
        // Every family has an answer: the JSON leaves `error` out.
        not_in_json: &["error"],
    },
    Case {
        name: "simulate",
        args: &[
            "simulate",
            "--shift",
            "0.3,0,0.2",
            "--rotate-rpy",
            "0,0,1.57",
            "--scene",
            "tunnel",
        ],
        rows: simulate_rows,
        not_in_json: &[],
    },
    Case {
        name: "sweep",
        args: &[
            "sweep", PLY, "--rig", URDF, "--from", "base", "--to", "lidar",
        ],
        rows: sweep_rows,
        not_in_json: &[],
    },
    Case {
        name: "tunnel",
        args: &["tunnel", "--shift", "0,2,0"],
        rows: tunnel_rows,
        not_in_json: &[],
    },
    Case {
        name: "calibrate-threshold",
        args: &[
            "calibrate-threshold",
            "--seeds",
            "1",
            "--noise",
            "0",
            "--voxel",
            "0.1",
        ],
        rows: threshold_rows,
        not_in_json: &[],
    },
];

/// The component names of an array of `n` values under `key`.
fn parts(key: &str, v: &[Value]) -> Vec<String> {
    let names: &[&str] = match v.len() {
        2 => &["low", "high"],
        3 if key.starts_with("rpy") => &["roll", "pitch", "yaw"],
        3 => &["x", "y", "z"],
        4 => &["x", "y", "z", "w"],
        6 if v.iter().all(Value::is_boolean) => &["rx", "ry", "rz", "tx", "ty", "tz"],
        6 => &["1", "2", "3", "4", "5", "6"],
        _ => &[],
    };
    names.iter().map(|s| s.to_string()).collect()
}

/// `key` with `part` put before its unit suffix, as the columns are named.
fn split(key: &str, part: &str) -> String {
    for u in ["m_per_rad", "mm", "m", "deg", "rad", "s", "ns"] {
        if let Some(stem) = key.strip_suffix(&format!("_{u}")) {
            return format!("{stem}_{part}_{u}");
        }
    }
    format!("{}_{part}", key.strip_suffix("_xyzw").unwrap_or(key))
}

/// Every leaf of a JSON row under each name a column may give it: its key,
/// its parent's key and its key, its grandparent's too; array components
/// named by [`parts`]. A null vector gives its names for every component
/// set (it has no length to tell which).
fn leaves(prefix: &[String], v: &Value, out: &mut BTreeMap<String, Value>) {
    let names = |out: &mut BTreeMap<String, Value>, keys: &[String], x: &Value| {
        for n in 1..=keys.len().min(3) {
            out.entry(keys[keys.len() - n..].join("_"))
                .or_insert_with(|| x.clone());
        }
    };
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                let mut p = prefix.to_vec();
                p.push(k.clone());
                leaves(&p, x, out);
            }
        }
        Value::Array(a) if a.iter().all(|x| !x.is_object() && !x.is_array()) => {
            let key = prefix.last().cloned().unwrap_or_default();
            for (x, part) in a.iter().zip(parts(&key, a)) {
                let mut p = prefix.to_vec();
                p.pop();
                p.push(split(&key, &part));
                names(out, &p, x);
            }
        }
        Value::Array(_) => {} // arrays of rows are other tables
        Value::Null => {
            names(out, prefix, v);
            let key = prefix.last().cloned().unwrap_or_default();
            for part in ["x", "y", "z", "w", "roll", "pitch", "yaw", "low", "high"] {
                let mut p = prefix.to_vec();
                p.pop();
                p.push(split(&key, part));
                names(out, &p, v);
            }
        }
        _ => names(out, prefix, v),
    }
}

/// The CSV cell a JSON value is written as.
fn cell_of(v: &Value) -> Option<String> {
    match v {
        Value::Null => Some(String::new()),
        Value::Bool(b) => Some(b.to_string()),
        Value::String(s) => Some(s.clone()),
        Value::Number(_) => None, // compared as f64
        _ => None,
    }
}

/// Every rule of a tidy table; returns the header and the rows.
fn assert_tidy(what: &str, text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    assert!(!text.is_empty(), "{what}: no CSV");
    assert!(text.ends_with('\n'), "{what}");
    assert!(
        !text.contains("\n\n"),
        "{what}: a blank line (a second table)\n{text}"
    );
    let mut rows = csv_rows(text);
    let header = rows.remove(0);
    let unique: std::collections::BTreeSet<&String> = header.iter().collect();
    assert_eq!(
        unique.len(),
        header.len(),
        "{what}: repeated column {header:?}"
    );
    for h in &header {
        // `audit run`'s per-frame columns are `FAMILY@FRAME.lambda1`, the
        // family's key holding its `l` (`l=0.25`): docs/runs.md.
        assert!(
            !h.is_empty()
                && h.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "_.@=".contains(c)),
            "{what}: column {h:?}"
        );
    }
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), header.len(), "{what}: row {i} {r:?}");
        assert_ne!(r, &header, "{what}: a second header at row {i}");
        for (c, h) in r.iter().zip(&header) {
            assert!(!c.contains('['), "{what}: {h} = {c:?}");
            // A cell that starts as a number is one number, no unit after it.
            if c.starts_with(|ch: char| ch.is_ascii_digit()) || c.starts_with("-0") {
                assert!(c.parse::<f64>().is_ok(), "{what}: {h} = {c:?}");
            }
        }
    }
    (header, rows)
}

#[test]
fn every_report_writes_one_tidy_table_equal_to_its_json() {
    for case in CASES {
        let csv_args = [case.args, &["--format", "csv"]].concat();
        let (code, csv, err) = run_cli(&csv_args);
        assert!(code == 0 || code == 1, "{}: {code} {err}", case.name);
        let (header, rows) = assert_tidy(case.name, &csv);
        let json_args = [case.args, &["--format", "json"]].concat();
        let (_, json, err) = run_cli(&json_args);
        let v: Value = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{e}: {err}"));
        let want = (case.rows)(&v);
        assert_eq!(rows.len(), want.len(), "{}: rows\n{csv}", case.name);
        assert!(!rows.is_empty(), "{}: a test without rows", case.name);
        let mut found = std::collections::BTreeSet::new();
        for (i, (row, w)) in rows.iter().zip(&want).enumerate() {
            let mut named = BTreeMap::new();
            leaves(&[], w, &mut named);
            for (h, c) in header.iter().zip(row) {
                let at = format!("{}: row {i}, {h} = {c:?}", case.name);
                let Some(x) = named.get(h) else {
                    // A key the JSON leaves out where it has no value
                    // (`help`, `error`): an empty cell.
                    assert!(
                        c.is_empty() || case.not_in_json.contains(&h.as_str()),
                        "{at}: no JSON key"
                    );
                    continue;
                };
                found.insert(h.clone());
                match (cell_of(x), x.as_f64()) {
                    (Some(text), _) => assert_eq!(c, &text, "{at}: JSON {x}"),
                    (None, Some(f)) => {
                        let got: f64 = c.parse().unwrap_or_else(|_| panic!("{at}: not a number"));
                        assert_eq!(got, f, "{at}: JSON {x}");
                    }
                    (None, None) => panic!("{at}: JSON {x}"),
                }
            }
        }
        for h in &header {
            assert!(
                found.contains(h) || case.not_in_json.contains(&h.as_str()),
                "{}: column {h} is no JSON key of any row",
                case.name
            );
        }
    }
}

/// A report without a data table is refused by name, never written as
/// the text tables (the frame tree is a picture).
#[test]
fn a_report_without_a_data_table_is_refused() {
    let (code, out, err) = run_cli(&[URDF, "--frames", "--format", "csv"]);
    assert_eq!(code, 2, "{out}");
    assert!(out.is_empty(), "{out}");
    assert!(err.contains("--format csv"), "{err}");
}

/// `audit run`'s CSV (one row per scan, streamed) keeps the same rules,
/// and its rows are the JSON lines' scans.
#[test]
fn the_run_writes_one_tidy_row_per_scan() {
    let (out, recs) =
        crate::run_fixtures::run_with_records(&["run.mcap", "--all-frames", "--format", "csv"]);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let (header, rows) = assert_tidy("run", &text);
    assert_eq!(rows.len(), recs.len());
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    for (r, rec) in rows.iter().zip(&recs) {
        assert_eq!(r[col("index")], rec["index"].to_string());
        assert_eq!(r[col("status")], rec["status"].as_str().unwrap());
    }
}

/// Every command of the width tests' list writes a tidy CSV (a new
/// report's command joins that list, and with it this test), but the frame
/// tree, a picture, and the error, which is no report.
#[test]
fn every_command_of_the_width_list_writes_a_tidy_csv() {
    for (name, args) in crate::widths::COMMANDS {
        if matches!(name, "frames" | "error") {
            continue;
        }
        let (code, csv, err) = run_cli(&[args, &["--format", "csv"][..]].concat());
        assert!(code == 0 || code == 1, "{name}: {code} {err}");
        let (_, rows) = assert_tidy(name, &csv);
        assert!(!rows.is_empty(), "{name}");
    }
}
