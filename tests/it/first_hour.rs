//! Issue 33, what a new user meets in the first hour: mistakes that get a
//! named answer (a mistyped command, a point cloud or a robot description
//! where the other is expected, an unknown frame on a robot whose root is not
//! `base_link`), each seen on a pseudo-terminal of 80 and 120 columns
//! (snapshots in tests/it/snapshots/, `first_hour_*`).

use crate::common::run_cli;
use crate::widths::{have_pty, pty_run};

const PLY: &str = "tests/fixtures/detector/tunnel_small_ascii.ply";
const PCD: &str = "tests/fixtures/detector/tunnel_small_ascii.pcd";
const CSV: &str = "tests/fixtures/detector/tunnel_small.csv";
const URDF: &str = "tests/fixtures/urdf/husky_kinematics.urdf";

/// A humanoid's frames: root `pelvis`, no `base_link`.
const HUMANOID: &str = r#"<robot name="h1">
  <link name="pelvis"/><link name="left_hip_yaw_link"/><link name="right_hip_yaw_link"/>
  <link name="torso_link"/><link name="mid360_link"/><link name="imu_link"/>
  <joint name="left_hip" type="fixed"><parent link="pelvis"/><child link="left_hip_yaw_link"/><origin xyz="0 0.09 0"/></joint>
  <joint name="right_hip" type="fixed"><parent link="pelvis"/><child link="right_hip_yaw_link"/><origin xyz="0 -0.09 0"/></joint>
  <joint name="torso" type="fixed"><parent link="pelvis"/><child link="torso_link"/><origin xyz="0 0 0.1"/></joint>
  <joint name="imu" type="fixed"><parent link="pelvis"/><child link="imu_link"/><origin xyz="0 0 0.05"/></joint>
  <joint name="lidar" type="fixed"><parent link="torso_link"/><child link="mid360_link"/><origin xyz="0.0 0 0.4" rpy="0 0.8 0"/></joint>
</robot>
"#;

#[test]
fn a_mistyped_command_is_suggested() {
    for (typo, meant) in [
        ("surveyy", "survey"),
        ("degenracy", "degeneracy"),
        ("chek", "check"),
        ("calibrate", "calibrate-threshold"),
    ] {
        let (code, out, err) = run_cli(&[typo, "calibrations/"]);
        assert_eq!(code, 2, "{typo}: {err}");
        assert!(out.is_empty(), "{out}");
        assert!(
            err.contains(&format!("unrecognized subcommand '{typo}'"))
                && err.contains(&format!("a similar subcommand exists: '{meant}'")),
            "{typo}: {err}"
        );
        assert!(!err.contains("cannot read"), "{err}");
    }
    // A word far from every command stays a file that cannot be read; a file
    // of that name is read as a file.
    let (code, _, err) = run_cli(&["robotfile"]);
    assert_eq!(code, 2);
    assert!(err.contains("robotfile: cannot read"), "{err}");
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy("calibrations/fastlio-avia.toml", dir.path().join("survey")).unwrap();
    let o = crate::common::audit()
        .current_dir(dir.path())
        .args(["survey", "--frames"])
        .output()
        .unwrap();
    // `survey` is the command (clap's own parse), never the file: its usage.
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn point_clouds_given_as_extrinsics_are_named() {
    for (file, kind) in [
        (PLY, "a PLY point cloud (magic `ply`)"),
        (PCD, "a PCD point cloud"),
        (CSV, "a CSV point cloud"),
    ] {
        let (code, _, err) = run_cli(&[file, "--frames"]);
        assert_eq!(code, 2, "{file}: {err}");
        assert!(err.contains(file), "names the file: {err}");
        assert!(err.contains(kind), "{file}: {err}");
        assert!(err.contains("audit degeneracy FILE"), "{file}: {err}");
    }
    // By content alone: a PCD and a PLY without their extensions.
    let dir = tempfile::tempdir().unwrap();
    for (file, kind) in [(PLY, "PLY"), (PCD, "PCD")] {
        let to = dir.path().join("scan");
        std::fs::copy(file, &to).unwrap();
        let (code, _, err) = run_cli(&[to.to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(&format!("a {kind} point cloud")), "{err}");
    }
}

/// A document only the fallback YAML reader would claim is refused as not a
/// calibration file, naming what it looks like (before: "not valid YAML:
/// simple key expected ':'" on calibrations/README.md); a broken `.yaml` file
/// keeps its YAML error with the line.
#[test]
fn documents_are_not_calibration_files() {
    let dir = tempfile::tempdir().unwrap();
    let notes = dir.path().join("NOTES");
    std::fs::write(&notes, "# Notes\n\nsee: the rig: it moved\n  badly\n").unwrap();
    let prose = dir.path().join("notes");
    std::fs::write(&prose, "hello world\nthis is: a: b\n  x\n").unwrap();
    let broken = dir.path().join("broken.yaml");
    std::fs::write(&broken, "a: [1,\n").unwrap();
    let (n, p) = (notes.to_str().unwrap(), prose.to_str().unwrap());
    for (file, kind) in [
        ("calibrations/README.md", "Markdown (.md)"),
        (n, "Markdown, not YAML"),
        (p, "plain text, not YAML"),
    ] {
        let (code, out, err) = run_cli(&[file]);
        assert_eq!(code, 2, "{file}: {err}");
        assert!(out.is_empty(), "{out}");
        assert!(
            err.contains(&format!(
                "{file}: not a calibration file this tool reads: it looks like {kind}"
            )),
            "{file}: {err}"
        );
        assert!(!err.contains("not valid YAML"), "{file}: {err}");
    }
    let (code, _, err) = run_cli(&[broken.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("broken.yaml:1:4: not valid YAML"), "{err}");
}

#[test]
fn a_robot_description_given_to_degeneracy_is_named() {
    let (code, _, err) = run_cli(&["degeneracy", URDF]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("expected a point cloud") && err.contains("a robot description (URDF"),
        "{err}"
    );
    assert!(err.contains("audit FILE --from A --to B"), "{err}");
    assert!(!err.contains("CSV header"), "{err}");
    let (code, _, err) = run_cli(&["degeneracy", "calibrations/fastlio-avia.toml"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("a calibration or configuration file"), "{err}");
    // A CSV of points is still read.
    let (code, _, err) = run_cli(&["degeneracy", CSV]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn an_unknown_frame_names_the_root_and_the_frames_below_it() {
    let dir = tempfile::tempdir().unwrap();
    let urdf = dir.path().join("h1.urdf");
    std::fs::write(&urdf, HUMANOID).unwrap();
    let (code, _, err) = run_cli(&[
        urdf.to_str().unwrap(),
        "--from",
        "base_link",
        "--to",
        "mid360_link",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("unknown frame 'base_link'"), "{err}");
    assert!(
        err.contains(
            "the tree's root: 'pelvis' (one edge below it: 'imu_link', 'left_hip_yaw_link', 'right_hip_yaw_link')"
        ),
        "{err}"
    );
}

/// The mistakes as a person sees them, at 80 and 120 columns.
#[test]
fn mistakes_on_a_terminal() {
    if !have_pty() {
        eprintln!("skipped: no `script` for a pseudo-terminal");
        return;
    }
    let cases: &[(&str, &[&str])] = &[
        ("typo", &["surveyy", "calibrations/"]),
        ("ply", &[PLY]),
        ("urdf_to_degeneracy", &["degeneracy", URDF]),
        ("unknown_frame", &[URDF, "--from", "base", "--to", "lidar"]),
    ];
    for cols in [80, 120] {
        for (name, args) in cases {
            let args = [args, &["--color", "never"][..]].concat();
            insta::assert_snapshot!(format!("first_hour_{name}_{cols}"), pty_run(cols, &args));
        }
    }
}

/// The README's first command: the four rigs whose rotations are rounded as
/// published are one note, not four warnings; `--format json` keeps each.
#[test]
fn survey_says_rounded_rotations_in_one_note() {
    let (code, _, err) = run_cli(&["survey", "calibrations/"]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("warning[non-orthonormal-rotation]"), "{err}");
    let notes: Vec<&str> = err.lines().filter(|l| l.starts_with("note: ")).collect();
    assert_eq!(notes.len(), 1, "{err}");
    assert!(
        notes[0].starts_with("note: 4 rigs: rotation rounded as published")
            && notes[0].contains("1.1e-6 to 1.3e-4")
            && notes[0].ends_with(
                "geode-alpha-vlp16, geode-beta-os1-64, geode-gamma-avia, m3dgr-avia-d435i-imu"
            ),
        "{err}"
    );
    let (_, out, _) = run_cli(&["survey", "calibrations/", "--format", "json"]);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let w = j["warnings"].as_array().unwrap();
    assert_eq!(w.len(), 4, "{w:?}");
    // One rig alone keeps its warning.
    let (_, _, err) = run_cli(&["survey", "calibrations/geode-alpha-vlp16.toml"]);
    assert!(err.contains("warning[non-orthonormal-rotation]"), "{err}");
}

/// A pure translation has the verdict `nonzero` (infinite pitch, no adapted
/// metric: the paper), in the rig report and in every survey row, so the
/// survey's counts cover every rig.
#[test]
fn a_pure_translation_has_a_pitch_verdict() {
    let (_, out, _) = run_cli(&["calibrations/fastlio-avia.toml", "--format", "json"]);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["screw"]["kind"], "pure_translation");
    assert_eq!(j["screw"]["pitch_verdict"], "nonzero");
    assert_eq!(j["adapted_metric"]["exists"], false);
    // Rounded as written (six decimals), still definite.
    let (_, out, _) = run_cli(&["calibrations/m2dgr-vlp32c-xsens.toml", "--format", "json"]);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(j["rotation"]["angle_uncertainty_rad"].as_f64().unwrap() > 0.0);
    assert_eq!(j["screw"]["pitch_verdict"], "nonzero");
    let (_, text, _) = run_cli(&["calibrations/fastlio-avia.toml"]);
    assert!(
        text.contains("infinite (no rotation), pitch nonzero"),
        "{text}"
    );
    let (_, out, _) = run_cli(&["survey", "calibrations/", "--format", "json"]);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let rigs = j["rigs"].as_array().unwrap();
    let pure: Vec<_> = rigs.iter().filter(|r| r["angle_deg"] == 0.0).collect();
    assert_eq!(pure.len(), 8);
    assert!(
        pure.iter().all(|r| r["pitch_verdict"] == "nonzero"),
        "{pure:?}"
    );
    assert!(rigs.iter().all(|r| r["pitch_verdict"].is_string()));
}

fn fast_lio(x: f64) -> String {
    format!("mapping:\n  extrinsic_T: [ {x}, 0.02326, -0.0284 ]\n  extrinsic_R: [ 1, 0, 0,\n                 0, 1, 0,\n                 0, 0, 1 ]\n")
}

/// One tolerance convention in check and diff: units written (`5mm`,
/// `0.5deg`, `1mrad`), the bare number's unit each option's help states.
#[test]
fn check_and_diff_tolerances_take_units() {
    let dir = tempfile::tempdir().unwrap();
    let d = |p: &str| dir.path().join(p).to_str().unwrap().to_string();
    std::fs::create_dir(dir.path().join("cal")).unwrap();
    std::fs::write(d("cal/fast_lio.yaml"), fast_lio(0.04165)).unwrap();
    std::fs::write(d("old.yaml"), fast_lio(0.04165)).unwrap();
    let (code, _, err) = run_cli(&["check", &d("cal"), "--write-baseline", &d("base.json")]);
    assert_eq!(code, 0, "{err}");
    // A 2 mm recalibration.
    std::fs::write(d("cal/fast_lio.yaml"), fast_lio(0.04365)).unwrap();
    let check = |tol: &str| {
        let (code, _, err) = run_cli(&[
            "check",
            &d("cal"),
            "--baseline",
            &d("base.json"),
            "--max-translation-drift",
            tol,
        ]);
        (code, err)
    };
    for (tol, code) in [
        ("3mm", 0),
        ("0.3cm", 0),
        ("0.003", 0),
        ("0.003m", 0),
        ("1mm", 1),
        ("0.001", 1),
    ] {
        assert_eq!(check(tol).0, code, "--max-translation-drift {tol}");
    }
    let (code, err) = check("1deg");
    assert_eq!(code, 2);
    assert!(
        err.contains("expected a length (m, cm, mm), found an angle"),
        "{err}"
    );
    let diff = |tol: &str| {
        let (code, _, err) = run_cli(&[
            "diff",
            &d("old.yaml"),
            &d("cal/fast_lio.yaml"),
            "--from",
            "imu",
            "--to",
            "lidar",
            "--tolerance",
            tol,
        ]);
        (code, err)
    };
    for (tol, code) in [
        ("3mm,0.05deg", 0),
        ("3,0.05", 0),
        ("0.003m,1mrad", 0),
        ("0.3cm,0.05", 0),
        ("1mm,0.05deg", 1),
        ("1,0.05", 1),
    ] {
        assert_eq!(diff(tol).0, code, "--tolerance {tol}: {}", diff(tol).1);
    }
    let (code, err) = diff("0.05deg,3mm");
    assert_eq!(code, 2);
    assert!(
        err.contains("--tolerance translation: expected a length"),
        "{err}"
    );
    // The help states the units and the bare number's.
    let flat = |s: String| s.split_whitespace().collect::<Vec<_>>().join(" ");
    let help = flat(run_cli(&["check", "--help"]).1);
    assert!(
        help.contains("a bare number is metres") && help.contains("[default: 1mm]"),
        "{help}"
    );
    assert!(
        help.contains("a bare number is degrees") && help.contains("[default: 0.05deg]"),
        "{help}"
    );
    let help = flat(run_cli(&["diff", "--help"]).1);
    assert!(
        help.contains("a bare translation is millimetres, a bare rotation degrees")
            && help.contains("[default: 1mm 0.05deg]"),
        "{help}"
    );
}

/// docs/urdf-differences.md, "Versions and empty axes": what urdfdom's code
/// does with each (lines cited there), and what `audit` does.
#[test]
fn urdf_versions_and_empty_axes_as_urdfdom_reads_them() {
    let dir = tempfile::tempdir().unwrap();
    let robot = |version: &str, joint: &str| {
        let p = dir.path().join("r.urdf");
        std::fs::write(
            &p,
            format!(
                "<robot name=\"r\" version=\"{version}\"><link name=\"a\"/><link name=\"b\"/>{joint}</robot>\n"
            ),
        )
        .unwrap();
        let (code, _, err) = run_cli(&[p.to_str().unwrap(), "--frames"]);
        (code, err)
    };
    let fixed = "<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/><origin xyz=\"1 0 0\"/></joint>";
    for (v, needle) in [
        (" 1.2 ", "extra characters after the number in field \"2 \""),
        ("2.0", "URDF version 2.0"),
        ("1.10", "URDF version 1.10"),
    ] {
        let (code, err) = robot(v, fixed);
        assert_eq!(code, 2, "{v:?}: {err}");
        assert!(
            err.contains(needle) && err.contains("ROS (urdfdom) refuses this file"),
            "{v:?}: {err}"
        );
    }
    for v in [" 1.0", "01.01", "1.2"] {
        let (code, err) = robot(v, fixed);
        assert_eq!(code, 0, "{v:?}: {err}");
    }
    let axis = |t: &str| {
        format!("<joint name=\"j\" type=\"{t}\"><parent link=\"a\"/><child link=\"b\"/><axis/><limit effort=\"1\" velocity=\"1\" lower=\"-1\" upper=\"1\"/></joint>")
    };
    for t in ["revolute", "continuous", "prismatic"] {
        let (code, err) = robot("1.0", &axis(t));
        assert_eq!(code, 2, "{t}: {err}");
        assert!(
            err.contains("<axis> without xyz, which urdfdom reads as 0 0 0"),
            "{t}: {err}"
        );
    }
    let (code, err) = robot("1.0", &axis("fixed"));
    assert_eq!(code, 0, "{err}");
}

/// At 80 columns a header wraps at its words, never inside one (issue 33:
/// "equivarian / t rule"), and the frame tree's wrapped lines stay under
/// their branch.
#[test]
fn headers_and_the_tree_wrap_at_words_at_80_columns() {
    if !have_pty() {
        eprintln!("skipped: no `script` for a pseudo-terminal");
        return;
    }
    let out = pty_run(
        80,
        &["calibrations/geode-alpha-vlp16.toml", "--color", "never"],
    );
    assert!(out.contains("┆ equivariant ┆"), "{out}");
    assert!(!out.contains("equivarian ┆"), "{out}");
    let tree = pty_run(80, &[URDF, "--frames", "--color", "never"]);
    // A wrapped place line starts with the tree's rails or spaces, never at
    // column 0 with text.
    for l in tree.lines().skip(1).filter(|l| !l.is_empty()) {
        assert!(
            l.starts_with(['│', '├', '└', ' ']),
            "a tree line restarts at column 0: {l:?}\n{tree}"
        );
    }
}

/// One file, two pairs: two ids (path and pair); a file surveyed once keeps
/// its path; a URDF's sensor is its `to` frame and its platform the robot it
/// names (`<robot name="husky">`); a file that names no platform shows a dash.
#[test]
fn survey_ids_are_unique_per_pair() {
    let a = format!("{URDF}:base_link:velodyne");
    let b = format!("{URDF}:base_link:imu_link");
    let (code, out, err) = run_cli(&["survey", &a, &b, "--format", "json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    let mut ids: Vec<&str> = j["rigs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["id"].as_str().unwrap())
        .collect();
    ids.sort();
    assert_eq!(ids, [b.as_str(), a.as_str()]);
    let (_, out, _) = run_cli(&["survey", &a, "--format", "json"]);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["rigs"][0]["id"], URDF);
    assert_eq!(j["rigs"][0]["sensor"], "velodyne");
    assert_eq!(j["rigs"][0]["platform"], "husky");
    let (_, out, _) = run_cli(&["survey", &a, "--format", "markdown"]);
    let row = out
        .lines()
        .find(|l| l.starts_with(&format!("| {URDF}")))
        .unwrap();
    assert!(
        row.starts_with(&format!("| {URDF} | velodyne | husky | ")),
        "{row}"
    );
    // A YAML names no robot: its platform is a dash, its sensor its `to`.
    let yaml = "tests/fixtures/formats/fastlio_avia.yaml";
    let pair = format!("{yaml}:imu:lidar");
    let (code, out, err) = run_cli(&["survey", &pair, "--format", "markdown"]);
    assert_eq!(code, 0, "{err}");
    let row = out
        .lines()
        .find(|l| l.starts_with(&format!("| {yaml}")))
        .unwrap();
    assert!(
        row.starts_with(&format!("| {yaml} | lidar | - | ")),
        "{row}"
    );
}

/// `--help` of survey and check shows their long description (a doc comment
/// on the command variant hid it), and says what the table marks.
#[test]
fn survey_and_check_help_show_their_description() {
    let flat = |s: String| s.split_whitespace().collect::<Vec<_>>().join(" ");
    let survey = flat(run_cli(&["survey", "--help"]).1);
    assert!(
        survey.contains("Rotations below 5 degrees are marked `*`"),
        "{survey}"
    );
    assert!(
        survey.contains("listed in one note before the table"),
        "{survey}"
    );
    let check = flat(run_cli(&["check", "--help"]).1);
    assert!(
        check.contains("Exit codes: 0 clean (warnings allowed)"),
        "{check}"
    );
    let top = flat(run_cli(&["--help"]).1);
    assert!(
        top.contains("survey The survey table over a directory of rig files"),
        "{top}"
    );
}
