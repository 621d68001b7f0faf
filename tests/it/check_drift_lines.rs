//! Issue 33 (item 3): a drift finding of `check --baseline` points at the line
//! and column where the changed number is written, so that the CI
//! annotation lands on the right line of a pull request: a rig TOML's
//! `translation = [...]` or rotation line inside its `[[transform]]` table
//! (not the table's header), a URDF `<origin>`'s `xyz` or `rpy` attribute
//! value, a FAST-LIO YAML's `extrinsic_T` or `extrinsic_R` key. The expected
//! lines are found in the text written here, by searching it.

use crate::check_gate::run_in;
use serde_json::Value;

/// 1-based (line, column) of the first `needle` in `text`, plus `skip`
/// characters (the column of the number after a key).
fn line_col(text: &str, needle: &str, skip: usize) -> (usize, usize) {
    let (i, l) = text
        .lines()
        .enumerate()
        .find(|(_, l)| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle}"));
    (i + 1, l.find(needle).unwrap() + 1 + skip)
}

/// Write `old` as `cal/NAME`, accept it as the baseline, write `new` over
/// it: the drift findings in GitHub's format, and SARIF's first region.
fn drift_after(name: &str, old: &str, new: &str) -> (String, Value) {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal");
    std::fs::create_dir(&cal).unwrap();
    std::fs::write(cal.join(name), old).unwrap();
    let w = run_in(
        dir.path(),
        &["check", "cal", "--write-baseline", "base.json"],
    );
    assert!(w.0 == 0 || w.0 == 1, "{w:?}");
    std::fs::write(cal.join(name), new).unwrap();
    let run = |format: &str| {
        let args = [
            "check",
            "cal",
            "--baseline",
            "base.json",
            "--format",
            format,
        ];
        run_in(dir.path(), &args)
    };
    let (code, github, err) = run("github");
    assert_eq!(code, 1, "{github}{err}");
    let (_, sarif, _) = run("sarif");
    let log: Value = serde_json::from_str(&sarif).unwrap();
    let drift = log["runs"][0]["results"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["ruleId"] == "drift")
        .cloned()
        .unwrap_or_else(|| panic!("{sarif}"));
    let drift_lines: String = github
        .lines()
        .filter(|l| l.contains("title=drift"))
        .collect::<Vec<_>>()
        .join("\n");
    (drift_lines, drift)
}

fn assert_at(name: &str, (github, sarif): &(String, Value), (line, col): (usize, usize)) {
    let want = format!("::error file=cal/{name},line={line},col={col},title=drift::");
    assert!(github.contains(&want), "{want}\n{github}");
    let region = &sarif["locations"][0]["physicalLocation"]["region"];
    assert_eq!(
        (region["startLine"].as_u64(), region["startColumn"].as_u64()),
        (Some(line as u64), Some(col as u64)),
        "{sarif}"
    );
}

const RIG: &str = "[rig]\nid = \"r\"\nsensor = \"s\"\nplatform = \"p\"\ndataset = \"d\"\n\
category = \"cad-or-nominal\"\nlicence = \"authored\"\ndirection = \"x\"\nfrom = \"base\"\nto = \"lidar\"\n\n\
[rig.source]\nrepo = \"a/b\"\npath = \"p\"\ncommit = \"0000000000000000000000000000000000000000\"\n\n\
[[transform]]\nparent = \"base\"\nchild = \"lidar\"\nunit = \"m\"\nsource_key = \"k\"\n";

fn rig(t: &str, rpy: &str) -> String {
    format!("{RIG}translation = [{t}]\nrpy = [{rpy}]\n")
}

#[test]
fn a_rig_toml_drift_points_at_the_changed_line() {
    let old = rig("0.1, 0.0, 0.2", "0.0, 0.0, 0.5");
    // The translation moved: its line, at its first number.
    let new = rig("0.11, 0.0, 0.2", "0.0, 0.0, 0.5");
    let at = line_col(&new, "translation = [", "translation = [".len());
    assert_ne!(at.0, line_col(&new, "[[transform]]", 0).0);
    assert_at("r.toml", &drift_after("r.toml", &old, &new), at);
    // Only the rotation moved: the rpy line.
    let new = rig("0.1, 0.0, 0.2", "0.0, 0.0, 0.6");
    let at = line_col(&new, "rpy = [", "rpy = [".len());
    assert_at("r.toml", &drift_after("r.toml", &old, &new), at);
}

fn urdf(xyz: &str, rpy: &str) -> String {
    format!(
        "<?xml version=\"1.0\"?>\n<robot name=\"r\">\n  <link name=\"base\"/>\n  <link name=\"lidar\"/>\n\
  <joint name=\"j\" type=\"fixed\">\n    <parent link=\"base\"/>\n    <child link=\"lidar\"/>\n\
    <origin\n      xyz=\"{xyz}\"\n      rpy=\"{rpy}\"/>\n  </joint>\n</robot>\n"
    )
}

#[test]
fn a_urdf_drift_points_at_the_origin_attribute() {
    let old = urdf("0.1 0 0.2", "0 0 0.5");
    let new = urdf("0.1 0 0.25", "0 0 0.5");
    let at = line_col(&new, "xyz=\"", "xyz=\"".len());
    assert_ne!(at.0, line_col(&new, "<joint", 0).0);
    assert_at("r.urdf", &drift_after("r.urdf", &old, &new), at);
    let new = urdf("0.1 0 0.2", "0 0 0.6");
    let at = line_col(&new, "rpy=\"", "rpy=\"".len());
    assert_at("r.urdf", &drift_after("r.urdf", &old, &new), at);
}

fn fast_lio(t: &str, r: &str) -> String {
    format!("# authored\nmapping:\n    extrinsic_est_en: false\n    extrinsic_T: [ {t} ]\n    extrinsic_R: [ {r} ]\n")
}

#[test]
fn a_yaml_drift_points_at_the_key_of_the_changed_numbers() {
    let identity = "1, 0, 0, 0, 1, 0, 0, 0, 1";
    let old = fast_lio("0.04, 0.02, -0.03", identity);
    let new = fast_lio("0.05, 0.02, -0.03", identity);
    let at = line_col(&new, "extrinsic_T", 0);
    assert_at("a.yaml", &drift_after("a.yaml", &old, &new), at);
    // A rotation of 0.2 deg about z: the extrinsic_R key.
    let (c, s) = (0.2f64.to_radians().cos(), 0.2f64.to_radians().sin());
    let turned = format!("{c}, {}, 0, {s}, {c}, 0, 0, 0, 1", -s);
    let new = fast_lio("0.04, 0.02, -0.03", &turned);
    let at = line_col(&new, "extrinsic_R", 0);
    assert_at("a.yaml", &drift_after("a.yaml", &old, &new), at);
}
