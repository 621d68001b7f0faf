//! Command-line front end: the clap tree, the dispatch, and output. Each
//! command parses its arguments, calls `extrinsic_audit::pipeline`, and renders
//! the typed report it gets back with `extrinsic_audit::render`.
//!
//! Exit codes for every command: 0 ok, 1 the check found problems, 2 usage or
//! input error (clap's own usage errors also exit 2).

mod audit;
mod check;
mod detector;
mod diff;
mod display;
mod frames;
mod survey;

use clap::{Parser, Subcommand};
use extrinsic_audit::diagnostic::{Code, Error, Result, Warning};
use extrinsic_audit::document::Report;
use extrinsic_audit::render::{self, OutputFormat, Style};
use extrinsic_audit::sanitize;
use extrinsic_audit::tolerances::{
    ELL_RANGE_M, KAPPA_RANGE, MAX_JOINT_VALUE, MAX_SIM_NOISE_M, SIM_VOXEL_RANGE_M,
};
use std::io::Write;
use std::process::ExitCode;

const ABOUT: &str = "What your LiDAR extrinsic does to degeneracy detection";

const LONG_ABOUT: &str = "\
Loads a robot's extrinsics (URDF, static TF launch files and dumps, FAST-LIO / \
LIO-SAM / Kalibr YAML, Ouster metadata JSON, TOML rig files), composes the \
transform between two frames and reports lever arm, screw pitch, adjoint singular \
values, certificate bands, the adapted metric when the pitch is zero, and which \
degeneracy-detector families can be frame-invariant on that robot.

Convention: T = (R, d) is the pose of --to in --from, p_from = R p_to + d \
(what `tf2_echo FROM TO` prints). Twists are [omega; t], rotation first.";

const AFTER_HELP: &str = "\
Examples:
  audit robot.urdf --from base_link --to lidar
  audit robot.urdf --frames
  audit robot.urdf --frames --from base_link --to lidar --format svg > frames.svg
  audit diff old.urdf new.urdf --from base_link --to lidar --format markdown
  audit robot.urdf lidar_calib.yaml --from base_link --to lidar --format json
  audit fast_lio.yaml                      # one edge: imu -> lidar
  audit robot.urdf --from base --to lidar --joint torso_joint=0.2
  audit robot.urdf --from base --to lidar --kappa 0.01 --lambda 0.004
  audit survey calibrations/
  audit check calibrations/ --baseline calibrations/baseline.json
  audit completions bash > /etc/bash_completion.d/audit";

#[derive(Debug, Parser)]
#[command(
    name = "audit",
    version,
    about = ABOUT,
    long_about = LONG_ABOUT,
    after_long_help = AFTER_HELP,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub audit: audit::AuditArgs,
    #[command(flatten)]
    pub display: display::DisplayArgs,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// The survey table over a directory of rig files (one row per rig)
    Survey(survey::SurveyArgs),
    /// CI check of calibration files: validation, drift against a baseline
    Check(check::CheckArgs),
    // about/long_about come from the Args struct.
    Tunnel(detector::TunnelArgs),
    // about/long_about come from the Args struct.
    Simulate(detector::SimulateArgs),
    // about/long_about come from the Args struct.
    Degeneracy(detector::DegeneracyArgs),
    // about/long_about come from the Args struct.
    CalibrateThreshold(detector::CalibrateThresholdArgs),
    // about/long_about come from the Args struct.
    Diff(diff::DiffArgs),
    Sweep(detector::SweepArgs),
    /// Print shell completions (bash, zsh, fish, elvish, powershell)
    #[command(
        long_about = "Print a completion script for your shell to standard output.",
        after_long_help = "Examples:\n  audit completions bash > ~/.local/share/bash-completion/completions/audit\n  audit completions zsh > ~/.zfunc/_audit\n  audit completions fish > ~/.config/fish/completions/audit.fish"
    )]
    Completions {
        /// The shell
        shell: clap_complete::Shell,
    },
}

/// Entry point of the binary.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            // clap: 0 for --help / --version, 2 for usage errors.
            return ExitCode::from(e.exit_code().clamp(0, 255) as u8);
        }
    };
    display::set(cli.display.clone());
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let code = match run(cli, &mut out) {
        Ok(code) => code,
        Err(e) => {
            let _ = out.flush();
            let msg = sanitize::line(&e.to_string());
            let line = display::stderr_fit(&format!("error: {msg}"));
            let rest = line.strip_prefix("error:").unwrap_or(&line);
            to_stderr(&format!(
                "{}:{rest}",
                display::stderr_style().error("error")
            ));
            e.exit_code()
        }
    };
    let _ = out.flush();
    ExitCode::from(code.clamp(0, 255) as u8)
}

/// Run a parsed command line, writing the report to `out`; returns the exit code.
pub fn run(cli: Cli, out: &mut dyn Write) -> Result<i32> {
    match cli.command {
        Some(Command::Survey(args)) => survey::run(&args, out),
        Some(Command::Check(args)) => check::run(&args, out),
        Some(Command::Tunnel(args)) => detector::tunnel(&args, out),
        Some(Command::Simulate(args)) => detector::simulate(&args, out),
        Some(Command::Degeneracy(args)) => detector::degeneracy(&args, out),
        Some(Command::CalibrateThreshold(args)) => detector::calibrate_threshold(&args, out),
        Some(Command::Diff(args)) => diff::run(&args, out),
        Some(Command::Sweep(args)) => detector::sweep(&args, out),
        Some(Command::Completions { shell }) => {
            let mut cmd = <Cli as clap::CommandFactory>::command();
            clap_complete::generate(shell, &mut cmd, "audit", out);
            Ok(0)
        }
        None => audit::run(&cli.audit, out),
    }
}

/// Render `report` in `format` to `out` (colour for tables on a terminal).
pub fn emit<R: Report>(report: &R, format: OutputFormat, out: &mut dyn Write) -> Result<()> {
    emit_warned(report, &[], format, out)
}

/// [`emit`], the JSON carrying `warnings` (already printed on stderr). Every
/// report, the frame tree included, reaches standard output here.
pub fn emit_warned<R: Report>(
    report: &R,
    warnings: &[Warning],
    format: OutputFormat,
    out: &mut dyn Write,
) -> Result<()> {
    let style = if format == OutputFormat::Table {
        display::stdout_style()
    } else {
        Style::plain()
    };
    let layout = display::stdout_layout();
    write_output(
        out,
        &render::render(report, warnings, format, style, &layout)?,
    )
}

/// Write `text` to standard output. A closed pipe (`audit ... | head -1`) ends
/// the process quietly with status 0, as `head` asked for no more.
fn write_output(out: &mut dyn Write, text: &str) -> Result<()> {
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => Err(Error::new(Code::Io, format!("cannot write output: {e}"))),
    }
}

/// One line to standard error; a closed standard error is ignored (the
/// process must not panic, as `eprintln!` does).
fn to_stderr(line: &str) {
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}

/// Print warnings to stderr, one per line, with their names (escaped: a
/// warning quotes names from files).
pub fn print_warnings(warnings: &[Warning]) {
    let st = display::stderr_style();
    for w in warnings {
        let text = display::stderr_fit(&sanitize::line(&w.to_string()));
        match text.split_once(": ") {
            Some((head, rest)) => to_stderr(&format!("{}: {rest}", st.bad(head))),
            None => to_stderr(&st.bad(&text)),
        }
    }
}

/// Notes (a redundant edge that agrees, the path a chain used) to stderr.
pub fn print_notes(notes: &[String]) {
    for n in notes {
        to_stderr(&format!("note: {}", sanitize::line(n)));
    }
}

/// `NAME=VALUE` for `--joint`.
pub fn parse_joint(s: &str) -> std::result::Result<(String, f64), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=VALUE, found `{s}`"))?;
    let v: f64 = value
        .trim()
        .parse()
        .map_err(|_| format!("joint `{name}`: expected a number, found `{value}`"))?;
    if !(v.is_finite() && v.abs() <= MAX_JOINT_VALUE) {
        return Err(format!(
            "joint `{name}`: expected a finite number of at most {MAX_JOINT_VALUE:e} in magnitude (rad or m), found `{value}`"
        ));
    }
    Ok((name.trim().to_string(), v))
}

/// A finite number in `[lo, hi]` (the option's name is added by clap).
fn parse_in(s: &str, lo: f64, hi: f64, unit: &str) -> std::result::Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("expected a number, found `{s}`"))?;
    if !(v.is_finite() && (lo..=hi).contains(&v)) {
        let (lo, hi) = (short(lo), short(hi));
        return Err(format!(
            "expected a finite number from {lo} to {hi}{unit}, found `{s}`"
        ));
    }
    Ok(v)
}

/// A bound as people write it: `0.02`, `1e-100`.
fn short(x: f64) -> String {
    if x == 0.0 || (1e-3..1e4).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `--ell`: a characteristic length in [`ELL_RANGE_M`].
pub fn parse_ell(s: &str) -> std::result::Result<f64, String> {
    parse_in(s, ELL_RANGE_M.0, ELL_RANGE_M.1, " m")
}

/// `--kappa`: a detector threshold in [`KAPPA_RANGE`].
pub fn parse_kappa(s: &str) -> std::result::Result<f64, String> {
    parse_in(s, KAPPA_RANGE.0, KAPPA_RANGE.1, "")
}

/// `--lambda`: an eigenvalue, 0 to the top of [`KAPPA_RANGE`].
pub fn parse_lambda(s: &str) -> std::result::Result<f64, String> {
    parse_in(s, 0.0, KAPPA_RANGE.1, "")
}

/// `--noise` of `simulate`: 0 to [`MAX_SIM_NOISE_M`].
pub fn parse_noise(s: &str) -> std::result::Result<f64, String> {
    parse_in(s, 0.0, MAX_SIM_NOISE_M, " m")
}

/// `--voxel` of `simulate`: in [`SIM_VOXEL_RANGE_M`].
pub fn parse_voxel(s: &str) -> std::result::Result<f64, String> {
    parse_in(s, SIM_VOXEL_RANGE_M.0, SIM_VOXEL_RANGE_M.1, " m")
}

/// A positive, finite length for `--ell`, `--max-lever-arm`, ...
pub fn parse_positive(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("expected a number, found `{s}`"))?;
    if !(v.is_finite() && v > 0.0) {
        return Err(format!("expected a positive finite number, found `{s}`"));
    }
    Ok(v)
}

/// A non-negative, finite number.
/// `--sigma-t M`: a calibration's standard uncertainty per edge (m).
pub fn parse_sigma_t(s: &str) -> std::result::Result<f64, String> {
    let v = parse_nonneg(s)?;
    let max = extrinsic_audit::tolerances::MAX_SIGMA_T_M;
    if v > max {
        return Err(format!("expected at most {max} m, found `{s}`"));
    }
    Ok(v)
}

/// `--sigma-r DEG`: a calibration's standard uncertainty per edge (degrees).
pub fn parse_sigma_r(s: &str) -> std::result::Result<f64, String> {
    let v = parse_nonneg(s)?;
    let max = extrinsic_audit::tolerances::MAX_SIGMA_R_DEG;
    if v > max {
        return Err(format!("expected at most {max} deg, found `{s}`"));
    }
    Ok(v)
}

/// `--sigma-t`/`--sigma-r` as one user uncertainty (`None`: neither given).
pub fn user_sigma(
    sigma_t: Option<f64>,
    sigma_r_deg: Option<f64>,
) -> Option<extrinsic_audit::geometry::UserSigma> {
    (sigma_t.is_some() || sigma_r_deg.is_some()).then(|| extrinsic_audit::geometry::UserSigma {
        sigma_t_m: sigma_t.unwrap_or(0.0),
        sigma_r_rad: sigma_r_deg.unwrap_or(0.0).to_radians(),
    })
}

pub fn parse_nonneg(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("expected a number, found `{s}`"))?;
    if !(v.is_finite() && v >= 0.0) {
        return Err(format!(
            "expected a non-negative finite number, found `{s}`"
        ));
    }
    Ok(v)
}
