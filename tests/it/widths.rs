//! Every command under a pseudo-terminal of 80 and 120 columns (`script`
//! from util-linux, the width set with `stty cols`): no line of what reaches
//! the terminal (standard output and standard error) is wider than it. Also
//! the display options: `--wide`, `--columns`, `--color`, and piped output
//! keeping the full table.

use crate::common::run_cli;
use std::process::Command;

/// The commands a person runs, with arguments that finish in seconds.
pub const COMMANDS: [(&str, &[&str]); 14] = [
    (
        "rig-report",
        &[
            "tests/fixtures/urdf/anymal_c_lidar.urdf",
            "--from",
            "base",
            "--to",
            "lidar",
        ],
    ),
    ("survey", &["survey", "calibrations/"]),
    ("check", &["check", "calibrations/"]),
    ("tunnel", &["tunnel", "--shift", "0,2,0"]),
    (
        "simulate",
        &[
            "simulate",
            "--shift",
            "0.3,0,0.2",
            "--rotate-rpy",
            "0,0,1.57",
            "--scene",
            "tunnel",
        ],
    ),
    (
        "degeneracy",
        &[
            "degeneracy",
            "tests/fixtures/detector/tunnel_small_le.ply",
            "--shift",
            "1,0,0",
        ],
    ),
    (
        "calibrate-threshold",
        &[
            "calibrate-threshold",
            "--seeds",
            "1",
            "--noise",
            "0",
            "--voxel",
            "0.1",
        ],
    ),
    (
        "sweep",
        &["sweep", "tests/fixtures/detector/tunnel_small_le.ply"],
    ),
    (
        "frames",
        &[
            "tests/fixtures/urdf/anymal_c_lidar.urdf",
            "--frames",
            "--from",
            "base",
            "--to",
            "lidar",
        ],
    ),
    (
        "error",
        &[
            "tests/fixtures/urdf/anymal_c_lidar.urdf",
            "--from",
            "base",
            "--to",
            "no_such_frame",
        ],
    ),
    (
        "kappa",
        &[
            "tests/fixtures/urdf/anymal_c_lidar.urdf",
            "--from",
            "base",
            "--to",
            "lidar",
            "--kappa",
            "0.01",
            "--lambda",
            "0.004",
        ],
    ),
    ("spread", &["spread", "tests/fixtures/spread/kitti-repeat"]),
    (
        "diff",
        &[
            "diff",
            "tests/fixtures/diff/whole_old.urdf",
            "tests/fixtures/diff/whole_new.urdf",
        ],
    ),
    ("run", &["run", "tests/fixtures/run/pcd_seq"]),
];

/// `script` is there (util-linux; every Debian-based machine has it).
pub fn have_pty() -> bool {
    Command::new("script").arg("--version").output().is_ok()
}

/// Run `audit ARGS` on a pseudo-terminal `cols` wide; its output (stdout and
/// stderr as the terminal shows them) without carriage returns.
pub fn pty_run(cols: usize, args: &[&str]) -> String {
    pty_run_with(cols, args, "")
}

/// [`pty_run`] with standard error left out (a progress bar is drawn in time).
pub fn pty_run_stdout(cols: usize, args: &[&str]) -> String {
    pty_run_with(cols, args, " 2>/dev/null")
}

fn pty_run_with(cols: usize, args: &[&str], redirect: &str) -> String {
    let quote = |s: &str| format!("'{}'", s.replace('\'', r"'\''"));
    let bin = env!("CARGO_BIN_EXE_audit");
    let cmd = format!(
        "stty cols {cols} rows 50; {} {}{redirect}",
        quote(bin),
        args.iter().map(|a| quote(a)).collect::<Vec<_>>().join(" ")
    );
    let out = Command::new("script")
        .args(["-qec", &cmd, "/dev/null"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env_remove("COLUMNS")
        .env_remove("NO_COLOR")
        .output()
        .expect("script runs");
    // A lone carriage return (a progress bar redrawn) starts a line again.
    String::from_utf8_lossy(&out.stdout)
        .replace("\r\n", "\n")
        .replace('\r', "\n")
}

/// Display width of a line, terminal control sequences (`ESC [ ... letter`) left out.
fn width(line: &str) -> usize {
    let mut n = 0;
    let mut esc = false;
    for c in line.chars() {
        match (esc, c) {
            (false, '\x1b') => esc = true,
            (true, c) if c.is_ascii_alphabetic() => esc = false,
            (true, _) => {}
            (false, _) => n += 1,
        }
    }
    n
}

fn assert_fits(cols: usize, name: &str, args: &[&str]) {
    let out = pty_run(cols, args);
    assert!(out.lines().count() > 1 || name == "error", "{name}: {out}");
    for l in out.lines() {
        assert!(
            width(l) <= cols,
            "{name} at {cols} columns: {} wide:\n{l}\n{out}",
            width(l)
        );
    }
}

#[test]
fn every_command_fits_80_and_120_columns() {
    if !have_pty() {
        eprintln!("skipped: no `script` for a pseudo-terminal");
        return;
    }
    for cols in [80, 120] {
        for (name, args) in COMMANDS {
            assert_fits(cols, name, args);
        }
    }
}

#[test]
fn the_survey_is_compact_on_a_terminal_and_full_in_a_pipe() {
    if !have_pty() {
        return;
    }
    let at120 = pty_run(120, &["survey", "calibrations/", "--color", "never"]);
    // One line per rig at 120 columns: id, lever arm, angle, h, pitch, band, metric.
    let row = at120
        .lines()
        .find(|l| l.contains("fusionportable-os1-128-stim300"))
        .unwrap();
    for cell in [
        "0.0430",
        "0.691*",
        "-0.0403",
        "no",
        "[0.9579, 1.044]",
        "none",
    ] {
        assert!(row.contains(cell), "{row}");
    }
    assert!(
        !at120.contains("Ouster OS1-128"),
        "sensor column shown:\n{at120}"
    );
    assert!(at120.contains("more columns with --wide"));
    let wide = pty_run(
        120,
        &["survey", "calibrations/", "--wide", "--color", "never"],
    );
    // Every column: wider than 120 here, as `(/stim300/imu/data_raw)` stays
    // whole, so one `key: value` line per cell.
    assert!(wide.contains("Ouster OS1-128") && wide.contains("s_max:"));
    // Piped: every column, nothing wrapped, no hint.
    let (_, piped, _) = run_cli(&["survey", "calibrations/"]);
    let row = piped
        .lines()
        .find(|l| l.contains("fusionportable"))
        .unwrap();
    assert!(
        row.contains("Ouster OS1-128") && row.contains("[0.9579, 1.044]"),
        "{row}"
    );
    assert!(!piped.contains("--wide"));
}

#[test]
fn columns_picks_table_columns_by_header() {
    if !have_pty() {
        return;
    }
    let out = pty_run(
        80,
        &[
            "survey",
            "calibrations/",
            "--columns",
            "id,lever arm,sensor",
            "--color",
            "never",
        ],
    );
    let header = out.lines().find(|l| l.contains(" id ")).unwrap();
    assert!(
        header.contains("lever") && header.contains("sensor"),
        "{out}"
    );
    assert!(!header.contains("angle"), "{out}");
    let (code, _, err) = run_cli(&["survey", "calibrations/", "--columns", "colour"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--columns: expected one of the columns of this report (id, sensor,"),
        "{err}"
    );
}

/// calibrate-threshold draws its progress bar on a terminal's stderr only.
#[test]
fn the_progress_bar_is_drawn_on_a_terminal_only() {
    let args = [
        "calibrate-threshold",
        "--seeds",
        "1",
        "--noise",
        "0",
        "--voxel",
        "0.1",
    ];
    let (code, _, err) = run_cli(&args);
    assert_eq!(code, 0);
    assert!(err.is_empty(), "{err}");
    if !have_pty() {
        return;
    }
    let out = pty_run(80, &args);
    assert!(out.contains("simulated scenes ["), "{out}");
    assert!(!pty_run_stdout(80, &args).contains("simulated scenes ["));
}

/// `check` over a directory counts the files it reads on a terminal's
/// standard error, and nothing reaches a pipe.
#[test]
fn check_shows_its_progress_on_a_terminal_only() {
    let args = ["check", "calibrations/"];
    let (_, _, err) = run_cli(&args);
    assert!(!err.contains("files checked ["), "{err}");
    if !have_pty() {
        return;
    }
    let out = pty_run(80, &args);
    assert!(out.contains("files checked ["), "{out}");
}

#[test]
fn color_is_chosen_by_the_flag_then_the_terminal() {
    let args = [
        "tests/fixtures/urdf/anymal_c_lidar.urdf",
        "--from",
        "base",
        "--to",
        "lidar",
    ];
    let (_, piped, _) = run_cli(&args);
    assert!(!piped.contains('\x1b'));
    let always = [&args[..], &["--color", "always"]].concat();
    let (_, forced, _) = run_cli(&always);
    assert!(forced.contains("\x1b[1;33m"), "{forced}");
    if !have_pty() {
        return;
    }
    assert!(pty_run(120, &args).contains('\x1b'));
    let never = [&args[..], &["--color", "never"]].concat();
    assert!(!pty_run(120, &never).contains('\x1b'));
}

/// The rows of the borderless survey: the lines after the rule under the
/// header, up to the hint about the hidden columns.
fn survey_rows(out: &str) -> Vec<&str> {
    out.lines()
        .skip_while(|l| !l.starts_with('─'))
        .skip(1)
        .take_while(|l| !l.is_empty() && !l.contains("more columns with --wide"))
        .collect()
}

/// The issue's compact default: at 80 columns the survey of the shipped
/// calibrations prints one line per rig (id, lever arm, angle, h, pitch,
/// band at l = 1, metric), ids shortened in their middle where needed.
#[test]
fn the_survey_is_one_line_per_rig_at_80_columns() {
    if !have_pty() {
        return;
    }
    let (_, json, _) = run_cli(&["survey", "calibrations/", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let rigs = v["rigs"].as_array().unwrap();
    assert_eq!(rigs.len(), 38);
    let out = pty_run_stdout(80, &["survey", "calibrations/", "--color", "never"]);
    assert!(out.lines().all(|l| width(l) <= 80), "{out}");
    let rows = survey_rows(&out);
    assert_eq!(rows.len(), rigs.len(), "{out}");
    for (row, rig) in rows.iter().zip(rigs) {
        let id = rig["id"].as_str().unwrap();
        let shown = row.split("  ").next().unwrap();
        match shown.split_once('…') {
            None => assert_eq!(shown, id),
            Some((head, tail)) => {
                assert!(id.starts_with(head) && id.ends_with(tail), "{shown} {id}")
            }
        }
        // lever arm (0.1 mm), band at l = 1, metric: the JSON's values, rounded.
        let lever = format!("{:.4}", rig["lever_arm_m"].as_f64().unwrap());
        let lower = rig["band_l1"][0].as_f64().unwrap();
        assert!(row.contains(&lever), "{row} {lever}");
        assert!(row.contains(&format!("[{lower:.4}, ")), "{row} {lower}");
        let metric = if rig["adapted_metric_exists"].as_bool().unwrap() {
            "exists"
        } else {
            "none"
        };
        assert!(row.ends_with(metric), "{row}");
    }
    // An id that fits is whole; a long one is cut in its middle.
    assert!(rows.iter().any(|r| r.starts_with("anymal-d-lidar-imu ")));
    assert!(
        rows.iter().any(|r| r.starts_with("fusionpor…-stim300 ")),
        "{out}"
    );
    // h without its uncertainty (it stays in --wide and JSON).
    assert!(!out.contains("+-") && !out.contains("2.9e-4"), "{out}");
    assert!(out.contains("4 more columns with --wide"), "{out}");
    // Narrower still: columns go from the right, still a line per rig.
    for cols in [50, 60] {
        let out = pty_run_stdout(cols, &["survey", "calibrations/", "--color", "never"]);
        assert!(out.lines().all(|l| width(l) <= cols), "{out}");
        assert_eq!(survey_rows(&out).len(), rigs.len(), "{out}");
    }
}

/// `--wide` on a narrow terminal: a whole word wider than its column turns
/// the table into `key: value` records rather than a line over the width.
#[test]
fn wide_on_a_narrow_terminal_falls_back_to_records() {
    if !have_pty() {
        return;
    }
    let out = pty_run_stdout(
        80,
        &["survey", "calibrations/", "--wide", "--color", "never"],
    );
    assert!(out.lines().all(|l| width(l) <= 80), "{out}");
    let ids: Vec<&str> = out
        .lines()
        .filter_map(|l| l.strip_prefix("id:"))
        .map(str::trim)
        .collect();
    assert_eq!(ids.len(), 38, "{out}");
    assert!(ids.contains(&"fusionportable-os1-128-stim300"));
    // Every column, the uncertainty of h included, values aligned.
    let rec: Vec<&str> = out
        .lines()
        .skip_while(|l| !l.contains("fusionportable-os1-128-stim300"))
        .take_while(|l| !l.is_empty())
        .collect();
    let keys: Vec<&str> = rec
        .iter()
        .filter_map(|l| l.split_once(':'))
        .map(|k| k.0)
        .collect();
    for k in [
        "id",
        "sensor",
        "platform",
        "lever arm (m)",
        "u(h) (m)",
        "s_max",
        "adapted metric",
    ] {
        assert!(keys.contains(&k), "{k}: {rec:?}");
    }
    assert!(rec.contains(&"u(h) (m):            7.8e-7"), "{rec:?}");
    // Per table: the rig report's chain of edges (a whole `file:line` beside
    // the `from` column) as records, its quantity tables still bordered.
    let report = pty_run_stdout(
        80,
        &[
            "tests/fixtures/urdf/anymal_c_lidar.urdf",
            "--from",
            "base",
            "--to",
            "lidar",
            "--wide",
        ],
    );
    assert!(report.lines().all(|l| width(l) <= 80), "{report}");
    assert!(
        report.contains("file:line: tests/fixtures/urdf/anymal_c_lidar.urdf:15:3"),
        "{report}"
    );
    assert!(report.contains("│ quantity "), "{report}");
}

/// `--frames` at 80 columns: a frame's place goes under its name.
#[test]
fn the_frame_tree_fits_80_columns() {
    if !have_pty() {
        return;
    }
    // The whole real robot (deep tree, long frame names), under a short path.
    let real = crate::real!(crate::common::testdata::ANYMAL_C);
    let dir = tempfile::tempdir().unwrap();
    let urdf = dir.path().join("anymal_c.urdf");
    std::fs::copy(real, &urdf).unwrap();
    let place = format!("[{}:250:5", urdf.display());
    let args = [urdf.to_str().unwrap(), "--frames", "--color", "never"];
    let out = pty_run_stdout(80, &args);
    assert!(out.lines().all(|l| width(l) <= 80), "{out}");
    let at = out
        .lines()
        .position(|l| l.ends_with("── depth_camera_front_color_optical_frame"))
        .unwrap();
    assert!(
        out.lines()
            .nth(at + 1)
            .unwrap()
            .trim_start_matches(['│', ' '])
            .starts_with(&place),
        "{out}"
    );
    let (_, piped, _) = run_cli(&args[..2]);
    assert!(piped.contains(&format!("depth_camera_front_color_optical_frame  {place}")));
}
