//! README.md stays true to the tool: every input format's row carries the
//! loader's own description; the set-up block holds the two commands .ci/run runs.

use extrinsic_audit::internals::formats::all_formats;

/// Lines that print rounding noise (e.g. `1.1e-16`) may differ between CPUs
/// (FMA or not); the README shows one run, the test skips them.
fn rounding_noise(line: &str) -> bool {
    (12..=20).any(|e| line.contains(&format!("e-{e}")))
}

fn readme() -> String {
    std::fs::read_to_string("README.md").expect("README.md")
}

/// The README's row for one format: its id, linked to its section of
/// docs/formats.md, and its loader's own description.
fn format_row(id: &str, desc: &str) -> String {
    // `<` escaped so that `<origin>` renders as text; `|` so that it stays in its cell.
    let desc = desc.replace('<', "&lt;").replace(" | ", " \\| ");
    format!("| [`{id}`](docs/formats.md#{id}) | {desc} |")
}

const TABLE_HEAD: &str = "| `--input-format` | what the numbers mean |\n|---|---|\n";

#[test]
fn formats_table_matches_loaders() {
    let r = readme();
    let rows: Vec<String> = all_formats()
        .map(|(f, d)| format_row(f.name(), d))
        .collect();
    let start = r
        .find(TABLE_HEAD)
        .expect("README.md: the formats table header")
        + TABLE_HEAD.len();
    let end = start + r[start..].find("\n\n").unwrap_or(r.len() - start);
    let table = rows.join("\n");
    if std::env::var_os("BLESS").is_some() {
        std::fs::write("README.md", format!("{}{table}{}", &r[..start], &r[end..]))
            .expect("write README.md");
        return;
    }
    assert_eq!(
        &r[start..end],
        table,
        "README.md formats table: one row per format, in registry order (regenerate with BLESS=1 cargo test --test it readme::formats_table)"
    );
}

/// Every format has its section in docs/formats.md (the README links there),
/// and every section names a format.
#[test]
fn docs_formats_has_a_section_per_format() {
    let doc = std::fs::read_to_string("docs/formats.md").expect("docs/formats.md");
    let sections: Vec<&str> = doc
        .lines()
        .filter_map(|l| l.strip_prefix("## `")?.strip_suffix('`'))
        .collect();
    let ids: Vec<&str> = all_formats().map(|(f, _)| f.name()).collect();
    for id in &ids {
        assert!(
            sections.contains(id),
            "docs/formats.md: no section ## `{id}`"
        );
    }
    for s in &sections {
        assert!(
            ids.contains(s),
            "docs/formats.md: section ## `{s}` names no format"
        );
    }
}

#[test]
fn setup_block_has_the_two_commands() {
    let r = readme();
    let start = r.find("<!-- setup:begin -->").expect("setup marker");
    let end = r.find("<!-- setup:end -->").expect("setup end marker");
    let cmds: Vec<&str> = r[start..end]
        .lines()
        .filter(|l| l.starts_with("cargo "))
        .collect();
    assert_eq!(
        cmds,
        ["cargo run --release -- survey calibrations/", "cargo test"]
    );
}

/// The example rig report in the README is the tool's current output.
#[test]
fn example_report_is_current() {
    let out = assert_cmd::Command::cargo_bin("audit")
        .unwrap()
        .env("NO_COLOR", "1")
        .args([
            "tests/fixtures/urdf/anymal_c_lidar.urdf",
            "--from",
            "base",
            "--to",
            "lidar",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let report = String::from_utf8(out.stdout).unwrap();
    let r = readme();
    for line in report
        .lines()
        .filter(|l| !l.trim().is_empty() && !rounding_noise(l))
    {
        assert!(
            r.contains(line),
            "README.md example report is stale; missing line:\n{line}"
        );
    }
}

/// The example tunnel output in the README is the tool's current output.
#[test]
fn example_tunnel_is_current() {
    let out = assert_cmd::Command::cargo_bin("audit")
        .unwrap()
        .env("NO_COLOR", "1")
        .arg("tunnel")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let r = readme();
    for line in String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .filter(|l| !l.trim().is_empty() && !rounding_noise(l))
    {
        assert!(
            r.contains(line),
            "README.md tunnel example is stale; missing line:\n{line}"
        );
    }
}

/// docs/ARCHITECTURE.md lists every diagnostic code by its name.
#[test]
fn every_diagnostic_code_is_documented() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/ARCHITECTURE.md"))
        .expect("docs/ARCHITECTURE.md");
    for c in extrinsic_audit::Code::ALL {
        assert!(
            doc.contains(&format!("`{}`", c.name())),
            "{} is not in docs/ARCHITECTURE.md",
            c.name()
        );
    }
}
