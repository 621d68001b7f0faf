//! The rig TOML parser on malformed and edge-case input: every error names the
//! file and line, says what was expected and what was found, and nothing panics.

use extrinsic_audit::internals::formats::rig_toml::parse;
use extrinsic_audit::internals::formats::Parsed;
use extrinsic_audit::Code;
use extrinsic_audit::LoadOptions;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

const HEADER: &str = r#"[rig]
id = "test-rig"
sensor = "LiDAR"
platform = "bench"
dataset = "unit test"
category = "cad-or-nominal"
licence = "MIT"
direction = "pose of lidar in imu"
from = "imu"
to = "lidar"

[rig.source]
repo = "example/repo"
path = "calib.yaml"
commit = "0123456789abcdef0123456789abcdef01234567"
"#;

fn with_transform(body: &str) -> String {
    format!("{HEADER}\n[[transform]]\n{body}")
}

fn path() -> &'static Path {
    Path::new("calibrations/bad-rig.toml")
}

fn run(text: &str) -> Result<Parsed, extrinsic_audit::Error> {
    parse(text, path(), &LoadOptions::default())
}

/// The error, its `file:line` prefix, and checks that the message says what
/// was expected.
fn err(text: &str, line: usize, needles: &[&str]) -> extrinsic_audit::Error {
    let e = run(text).expect_err("expected an error");
    let shown = e.to_string();
    let prefix = format!("calibrations/bad-rig.toml:{line}");
    assert!(
        shown.starts_with(&prefix),
        "{shown:?} does not start with {prefix:?}"
    );
    for n in needles {
        assert!(shown.contains(n), "{shown:?} lacks {n:?}");
    }
    e
}

/// 1-based line of the first line equal to `needle` (trimmed).
fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.trim() == needle).expect("line") + 1
}

const GOOD: &str = r#"parent = "imu"
child = "lidar"
unit = "m"
translation = [0.1, 0.0, 0.0]
rotation_matrix = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
source_key = "extrinsic_T + extrinsic_R"
"#;

#[test]
fn a_minimal_rig_parses() {
    let text = with_transform(GOOD);
    let l = run(&text).unwrap();
    assert_eq!(l.edges.len(), 1);
    let e = &l.edges[0];
    assert_eq!((e.parent.as_str(), e.child.as_str()), ("imu", "lidar"));
    assert_eq!(e.transform.translation()[0], 0.1);
    assert_eq!(e.provenance.key, "extrinsic_T + extrinsic_R");
    assert_eq!(
        e.provenance.location.line,
        Some(line_of(&text, "[[transform]]"))
    );
    let m = l.rig.unwrap();
    assert_eq!(m.id, "test-rig");
    assert!(m.in_statistics());
    assert!(l.warnings.is_empty());
}

#[test]
fn missing_rotation() {
    let text = with_transform(
        "parent = \"imu\"\nchild = \"lidar\"\nunit = \"m\"\ntranslation = [0.1, 0, 0]\nsource_key = \"k\"\n",
    );
    let e = err(
        &text,
        line_of(&text, "[[transform]]"),
        &["expected exactly one rotation form", "found none"],
    );
    assert_eq!(e.code, Code::Parse);
}

#[test]
fn two_rotation_forms() {
    let text = with_transform(&format!("{GOOD}rpy = [0, 0, 0]\n"));
    err(
        &text,
        line_of(&text, "[[transform]]"),
        &["exactly one rotation form", "found rotation_matrix and rpy"],
    );
}

#[test]
fn unknown_unit() {
    let text = with_transform(&GOOD.replace("unit = \"m\"", "unit = \"cm\""));
    err(
        &text,
        line_of(&text, "unit = \"cm\""),
        &["unknown variant `cm`", "expected `m` or `mm`"],
    );
}

#[test]
fn nan_and_infinity() {
    let text = with_transform(&GOOD.replace("[0.1, 0.0, 0.0]", "[0.1, nan, 0.0]"));
    let e = err(
        &text,
        line_of(&text, "[[transform]]"),
        &["translation", "expected finite numbers, found NaN"],
    );
    assert_eq!(e.code, Code::Invalid);
    let text = with_transform(&GOOD.replace("[0, 1, 0], [0, 0, 1]]", "[0, 1, 0], [0, 0, inf]]"));
    err(
        &text,
        line_of(&text, "[[transform]]"),
        &["rotation_matrix", "expected finite numbers, found inf"],
    );
}

#[test]
fn unknown_field_is_refused() {
    let text = with_transform(&format!("{GOOD}extrinsic_T = [1, 2, 3]\n"));
    err(
        &text,
        line_of(&text, "extrinsic_T = [1, 2, 3]"),
        &["unknown field `extrinsic_T`", "expected one of"],
    );
    let text = HEADER.replace("licence = \"MIT\"", "licence = \"MIT\"\nlicense = \"MIT\"");
    err(
        &text,
        line_of(&text, "license = \"MIT\""),
        &["unknown field `license`"],
    );
}

#[test]
fn wrong_array_length() {
    let text = with_transform(&GOOD.replace("[0.1, 0.0, 0.0]", "[0.1, 0.0]"));
    err(
        &text,
        line_of(&text, "translation = [0.1, 0.0]"),
        &["invalid length 2", "expected an array of length 3"],
    );
}

#[test]
fn missing_translation_and_doubled_translation() {
    let text = with_transform(&GOOD.replace("translation = [0.1, 0.0, 0.0]\n", ""));
    err(
        &text,
        line_of(&text, "[[transform]]"),
        &["expected `translation = [x, y, z]`", "found none"],
    );
    let body = "parent = \"imu\"\nchild = \"lidar\"\nunit = \"m\"\ntranslation = [0, 0, 0]\nmatrix4 = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\nsource_key = \"k\"\n";
    let text = with_transform(body);
    err(
        &text,
        line_of(&text, "[[transform]]"),
        &[
            "carries the translation",
            "expected no separate `translation`",
        ],
    );
}

#[test]
fn bad_matrices() {
    // Bottom row of a 4x4 that is not [0 0 0 1].
    let body = "parent = \"imu\"\nchild = \"lidar\"\nunit = \"m\"\nmatrix4 = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 0]]\nsource_key = \"k\"\n";
    let text = with_transform(body);
    err(
        &text,
        line_of(&text, "[[transform]]"),
        &["expected bottom row [0, 0, 0, 1]"],
    );
    // A reflection.
    let text = with_transform(&GOOD.replace("[0, 0, 1]]", "[0, 0, -1]]"));
    err(&text, line_of(&text, "[[transform]]"), &["expected det +1"]);
    // Not a rotation at all.
    let text = with_transform(&GOOD.replace("[[1, 0, 0]", "[[2, 0, 0]"));
    err(
        &text,
        line_of(&text, "[[transform]]"),
        &["expected orthonormal"],
    );
    // A zero quaternion.
    let body = "parent = \"imu\"\nchild = \"lidar\"\nunit = \"m\"\ntranslation = [0, 0, 0]\nquaternion_xyzw = [0, 0, 0, 0]\nsource_key = \"k\"\n";
    let text = with_transform(body);
    err(
        &text,
        line_of(&text, "[[transform]]"),
        &["expected a unit quaternion"],
    );
}

#[test]
fn syntax_errors_carry_a_line() {
    let text = format!("{HEADER}\n[[transform]]\nparent = \"imu\nchild = 1\n");
    let e = run(&text).expect_err("error");
    assert_eq!(e.code, Code::Parse);
    assert!(e.location.line.is_some(), "{e}");
    assert!(e.to_string().starts_with("calibrations/bad-rig.toml:"));
    let e = run("this is not toml").expect_err("error");
    assert!(
        e.to_string().starts_with("calibrations/bad-rig.toml:1"),
        "{e}"
    );
}

#[test]
fn missing_rig_table_or_fields() {
    let e = run(&format!("[[transform]]\n{GOOD}")).expect_err("error");
    assert!(e.to_string().contains("missing field `rig`"), "{e}");
    assert!(e.location.file.is_some());
    let text = HEADER.replace("sensor = \"LiDAR\"\n", "");
    let e = run(&format!("{text}\n[[transform]]\n{GOOD}")).expect_err("error");
    assert!(e.to_string().contains("missing field `sensor`"), "{e}");
    assert!(
        e.to_string().starts_with("calibrations/bad-rig.toml:1"),
        "{e}"
    );
}

#[test]
fn rig_level_checks() {
    // No transform at all.
    err(HEADER, 1, &["expected at least one [[transform]]"]);
    // Unknown category.
    let text = with_transform(GOOD).replace("\"cad-or-nominal\"", "\"guess\"");
    err(&text, 1, &["category", "found \"guess\""]);
    // from frame that no edge names.
    let text = with_transform(GOOD).replace("from = \"imu\"", "from = \"base_link\"");
    err(&text, 1, &["from = \"base_link\"", "found only"]);
    // from == to.
    let text = with_transform(GOOD).replace("to = \"lidar\"", "to = \"imu\"");
    err(&text, 1, &["two different frames"]);
    // An empty required string.
    let text = with_transform(GOOD).replace("id = \"test-rig\"", "id = \"\"");
    err(&text, 1, &["[rig] id", "non-empty"]);
    // parent == child.
    let text = with_transform(&GOOD.replace("child = \"lidar\"", "child = \"imu\""));
    err(
        &text,
        line_of(&text, "[[transform]]"),
        &["parent and child to differ"],
    );
}

#[test]
fn include_paths_are_checked_before_loading() {
    for bad in ["../../etc/passwd", "/etc/passwd", "nested.toml", ""] {
        let text = format!("{HEADER}\n[[include]]\nfile = \"{bad}\"\n");
        err(&text, line_of(&text, "[[include]]"), &["[[include]] file"]);
    }
}

#[test]
fn every_rotation_form_gives_the_same_half_turn() {
    // A half-turn about z with the LiDAR 0.1 m above the IMU, written eight ways.
    let forms = [
        "translation = [0, 0, 0.1]\nrotation_matrix = [[-1, 0, 0], [0, -1, 0], [0, 0, 1]]",
        "translation = [0, 0, 0.1]\nquaternion_xyzw = [0, 0, 1, 0]",
        "translation = [0, 0, 0.1]\nquaternion_wxyz = [0, 0, 0, 1]",
        "translation = [0, 0, 0.1]\nrpy = [0, 0, 3.141592653589793]",
        "translation = [0, 0, 0.1]\nypr = [3.141592653589793, 0, 0]",
        "translation = [0, 0, 0.1]\naxis_angle = { axis = [0, 0, 2], angle = 3.141592653589793 }",
        "matrix4 = [[-1, 0, 0, 0], [0, -1, 0, 0], [0, 0, 1, 0.1], [0, 0, 0, 1]]",
        "matrix3x4 = [[-1, 0, 0, 0], [0, -1, 0, 0], [0, 0, 1, 0.1]]",
    ];
    for f in forms {
        let body =
            format!("parent = \"imu\"\nchild = \"lidar\"\nunit = \"m\"\n{f}\nsource_key = \"k\"\n");
        let l = run(&with_transform(&body)).unwrap_or_else(|e| panic!("{f}: {e}"));
        let t = l.edges[0].transform;
        assert!((t.translation()[2] - 0.1).abs() < 1e-15, "{f}");
        assert!((t.rotation()[(0, 0)] + 1.0).abs() < 1e-15, "{f}");
        assert!((t.rotation()[(1, 1)] + 1.0).abs() < 1e-15, "{f}");
        assert!((t.rotation()[(2, 2)] - 1.0).abs() < 1e-15, "{f}");
    }
}

#[test]
fn millimetres_and_invert() {
    // Published as the pose of imu in lidar, in mm: 1 m... rather 100 mm along x.
    let body = "parent = \"imu\"\nchild = \"lidar\"\nunit = \"mm\"\ntranslation = [100, 0, 0]\nrpy = [0, 0, 1.5707963267948966]\ninvert = true\nsource_key = \"k\"\n";
    let l = run(&with_transform(body)).unwrap();
    let t = l.edges[0].transform;
    // Inverse of (Rz(90), (0.1, 0, 0)) is (Rz(-90), -Rz(-90) (0.1, 0, 0)) = (.., (0, 0.1, 0)).
    assert!(t.translation()[0].abs() < 1e-15);
    assert!((t.translation()[1] - 0.1).abs() < 1e-15);
    assert!((t.rotation()[(0, 1)] - 1.0).abs() < 1e-15);
    assert!(l.edges[0].provenance.key.contains("inverted"));
}

#[test]
fn cli_invert_and_key_are_ignored_with_a_warning() {
    let mut opts = LoadOptions::default();
    opts.invert = true;
    let l = parse(&with_transform(GOOD), path(), &opts).unwrap();
    assert_eq!(l.edges[0].transform.translation()[0], 0.1, "not inverted");
    assert!(l.warnings.iter().any(|w| w.code == Code::Ignored));
}

#[test]
fn non_unit_quaternion_warns_at_its_transform() {
    let body = "parent = \"imu\"\nchild = \"lidar\"\nunit = \"m\"\ntranslation = [0, 0, 0]\nquaternion_xyzw = [0, 0, 0, 2]\nsource_key = \"k\"\n";
    let text = with_transform(body);
    let l = run(&text).unwrap();
    let w = &l.warnings[0];
    assert_eq!(w.code, Code::NonUnitQuaternion);
    assert_eq!(w.location.line, Some(line_of(&text, "[[transform]]")));
}

fn calibration_files() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("calibrations");
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

/// No file of the shipped set, cut at any line, makes the parser panic.
#[test]
fn truncated_real_rigs_never_panic() {
    for p in calibration_files() {
        let text = std::fs::read_to_string(&p).unwrap();
        if text.contains("[[include]]") {
            continue; // sidecar: its include is loaded by formats::load_file
        }
        let lines: Vec<&str> = text.lines().collect();
        for n in 0..lines.len() {
            let cut = lines[..n].join("\n");
            let _ = parse(&cut, &p, &LoadOptions::default());
        }
    }
}

/// The commented examples in the docs parse as they are written.
#[test]
fn documented_examples_parse() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    for doc in ["docs/rig-format.md", "calibrations/README.md"] {
        let text = std::fs::read_to_string(root.join(doc)).unwrap();
        let mut blocks = 0;
        let mut rest = text.as_str();
        while let Some(i) = rest.find("```toml\n") {
            let body = &rest[i + 8..];
            let end = body.find("```").expect("closed block");
            let block = &body[..end];
            if block.contains("[rig]") && !block.contains("[[include]]") {
                parse(block, Path::new(doc), &LoadOptions::default())
                    .unwrap_or_else(|e| panic!("{doc}: example does not parse: {e}"));
                blocks += 1;
            }
            rest = &body[end..];
        }
        assert!(blocks > 0, "{doc}: no complete ```toml example");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Arbitrary text never panics.
    #[test]
    fn arbitrary_text_never_panics(s in "\\PC{0,400}") {
        let _ = run(&s);
    }

    /// A valid rig with one numeric token replaced never panics.
    #[test]
    fn mutated_numbers_never_panic(
        x in prop_oneof![
            Just("nan".to_string()), Just("-inf".to_string()), Just("1e308".to_string()),
            Just("1e-320".to_string()), Just("\"1\"".to_string()), Just("[]".to_string()),
            any::<f64>().prop_map(|f| format!("{f:?}")),
        ],
        which in 0usize..12,
    ) {
        let body = GOOD.replace("0.1", "@");
        let body = body.replacen(['0', '1'], "@", which % 4 + 1).replace('@', &x);
        let _ = run(&with_transform(&body));
    }
}
