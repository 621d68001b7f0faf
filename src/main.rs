//! `audit`: the command-line front end of extrinsic-audit, a client of the
//! library's face like any other (and of `extrinsic_audit::internals` only
//! where the crate docs say). This file holds the command tree and the
//! dispatch; `cli` holds each command's arguments (parsed, handed to the
//! library, the report rendered) and the output. Everything else is the
//! library's.
//!
//! Exit codes for every command: 0 ok, 1 the check found problems, 2 usage or
//! input error (clap's own usage errors also exit 2).

mod cli;

use clap::{Parser, Subcommand};
use cli::{audit, check, detector, diff, display, run, spread, survey};
use extrinsic_audit::Result;
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
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    audit: audit::AuditArgs,
    #[command(flatten)]
    display: display::DisplayArgs,
}

#[derive(Debug, Subcommand)]
enum Command {
    // about/long_about come from the Args struct (a doc comment here would
    // hide the long_about from `audit survey --help`).
    Survey(survey::SurveyArgs),
    // about/long_about come from the Args struct.
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
    // about/long_about come from the Args struct.
    Spread(spread::SpreadArgs),
    Sweep(detector::SweepArgs),
    // about/long_about come from the Args struct.
    Run(run::RunArgs),
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

fn main() -> ExitCode {
    ExitCode::from(main_with(std::env::args_os()))
}

/// The command line `args` (the program's name first) run to its exit code.
/// The Python package's `audit` console script calls this too: it compiles
/// this file into its extension (python/src/cli.rs) with `sys.argv`.
pub(crate) fn main_with<I, T>(args: I) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            // clap: 0 for --help / --version, 2 for usage errors.
            return e.exit_code().clamp(0, 255) as u8;
        }
    };
    display::set(cli.display.clone());
    if let Some(e) = mistyped_command(&cli) {
        let _ = e.print();
        return 2;
    }
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let code = match run(cli, &mut out) {
        Ok(code) => code,
        Err(e) => {
            let _ = out.flush();
            cli::print_error(&e);
            e.exit_code()
        }
    };
    let _ = out.flush();
    code.clamp(0, 255) as u8
}

/// A first file that does not exist, is a bare word (no `/`, no `.`) and is
/// close to a command's name (`surveyy`, `degenracy`, `calibrate`): a usage
/// error naming the command, as clap words its own suggestions, rather than
/// "cannot read". The rig report takes files as its positionals, so clap
/// cannot tell a mistyped command from a file name itself.
fn mistyped_command(cli: &Cli) -> Option<clap::Error> {
    if cli.command.is_some() {
        return None;
    }
    let word = cli.audit.files.first()?.to_str()?;
    if word.is_empty() || word.contains(['/', '\\', '.']) || std::path::Path::new(word).exists() {
        return None;
    }
    let colour = match display::stderr_style().color {
        true => clap::ColorChoice::Always,
        false => clap::ColorChoice::Never,
    };
    let mut cmd = <Cli as clap::CommandFactory>::command().color(colour);
    let lower = word.to_lowercase();
    let best = cmd
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .filter(|n| n != "help")
        .map(|n| (strsim::jaro_winkler(&lower, &n), n))
        .filter(|(score, n)| *score > 0.8 || n.starts_with(&lower))
        .max_by(|a, b| a.0.total_cmp(&b.0))?;
    Some(cmd.error(
        clap::error::ErrorKind::InvalidSubcommand,
        format!(
            "unrecognized subcommand '{word}' (and no file of that name)\n\n  tip: a similar subcommand exists: '{}'",
            best.1
        ),
    ))
}

/// Run a parsed command line, writing the report to `out`; returns the exit code.
fn run(cli: Cli, out: &mut dyn Write) -> Result<i32> {
    match cli.command {
        Some(Command::Survey(args)) => survey::run(&args, out),
        Some(Command::Check(args)) => check::run(&args, out),
        Some(Command::Tunnel(args)) => detector::tunnel(&args, out),
        Some(Command::Simulate(args)) => detector::simulate(&args, out),
        Some(Command::Degeneracy(args)) => detector::degeneracy(&args, out),
        Some(Command::CalibrateThreshold(args)) => detector::calibrate_threshold(&args, out),
        Some(Command::Diff(args)) => diff::run(&args, out),
        Some(Command::Spread(args)) => spread::run(&args, out),
        Some(Command::Sweep(args)) => detector::sweep(&args, out),
        Some(Command::Run(args)) => run::run(&args, out),
        Some(Command::Completions { shell }) => {
            let mut cmd = <Cli as clap::CommandFactory>::command();
            clap_complete::generate(shell, &mut cmd, "audit", out);
            Ok(0)
        }
        None => audit::run(&cli.audit, out),
    }
}
