//! Every command under a pseudo-terminal of 80 and 120 columns (`script`
//! from util-linux, the width set with `stty cols`): no line of what reaches
//! the terminal (standard output and standard error) is wider than it. Also
//! the display options: `--wide`, `--columns`, `--color`, and piped output
//! keeping the full table.

use crate::common::run_cli;
use std::process::Command;

/// The commands a person runs, with arguments that finish in seconds.
pub const COMMANDS: [(&str, &[&str]); 9] = [
    (
        "rig-report",
        &[
            "tests/fixtures/urdf/anymal_c.urdf",
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
        "error",
        &[
            "tests/fixtures/urdf/anymal_c.urdf",
            "--from",
            "base",
            "--to",
            "no_such_frame",
        ],
    ),
    (
        "kappa",
        &[
            "tests/fixtures/urdf/anymal_c.urdf",
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
    // (Every column: wider than 120 here, as `(/stim300/imu/data_raw)` stays whole.)
    assert!(wide.contains("Ouster OS1-128") && wide.contains("s_max"));
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
        "tests/fixtures/urdf/anymal_c.urdf",
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
