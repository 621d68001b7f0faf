//! Command-line front end. One file per subcommand; this file holds the clap
//! tree, the dispatch and the few helpers they share.
//!
//! Exit codes for every command: 0 ok, 1 the check found problems, 2 usage or
//! input error (clap's own usage errors also exit 2).

pub mod audit;
pub mod calibrate_threshold;
pub mod check;
pub mod degeneracy;
pub mod simulate;
pub mod survey;
pub mod tunnel;

use crate::diagnostic::{Error, Result, Warning};
use clap::{Parser, Subcommand};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
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
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// The survey table over a directory of rig files (one row per rig)
    Survey(survey::SurveyArgs),
    /// CI check of calibration files: validation, drift against a baseline
    Check(check::CheckArgs),
    // about/long_about come from the Args struct.
    Tunnel(tunnel::TunnelArgs),
    // about/long_about come from the Args struct.
    Simulate(simulate::SimulateArgs),
    // about/long_about come from the Args struct.
    Degeneracy(degeneracy::DegeneracyArgs),
    // about/long_about come from the Args struct.
    CalibrateThreshold(calibrate_threshold::CalibrateThresholdArgs),
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
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let code = match run(cli, &mut out) {
        Ok(code) => code,
        Err(e) => {
            let _ = out.flush();
            eprintln!("{}: {e}", Style::stderr().error("error"));
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
        Some(Command::Tunnel(args)) => tunnel::run(&args, out),
        Some(Command::Simulate(args)) => simulate::run(&args, out),
        Some(Command::Degeneracy(args)) => degeneracy::run(&args, out),
        Some(Command::CalibrateThreshold(args)) => calibrate_threshold::run(&args, out),
        Some(Command::Completions { shell }) => {
            let mut cmd = <Cli as clap::CommandFactory>::command();
            clap_complete::generate(shell, &mut cmd, "audit", out);
            Ok(0)
        }
        None => audit::run(&cli.audit, out),
    }
}

/// Terminal styling: colour only on a terminal and never when `NO_COLOR` is set.
#[derive(Debug, Clone, Copy)]
pub struct Style {
    pub color: bool,
}

impl Style {
    fn detect(is_tty: bool) -> Self {
        let no_color = std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty());
        Style {
            color: is_tty && !no_color,
        }
    }
    pub fn stdout() -> Self {
        Self::detect(std::io::stdout().is_terminal())
    }
    pub fn stderr() -> Self {
        Self::detect(std::io::stderr().is_terminal())
    }
    pub fn plain() -> Self {
        Style { color: false }
    }
    fn paint(&self, code: &str, s: &str) -> String {
        if self.color {
            format!("\x1b[{code}m{s}\x1b[0m")
        } else {
            s.to_string()
        }
    }
    pub fn bold(&self, s: &str) -> String {
        self.paint("1", s)
    }
    pub fn good(&self, s: &str) -> String {
        self.paint("1;32", s)
    }
    pub fn bad(&self, s: &str) -> String {
        self.paint("1;33", s)
    }
    pub fn error(&self, s: &str) -> String {
        self.paint("1;31", s)
    }
    pub fn dim(&self, s: &str) -> String {
        self.paint("2", s)
    }
}

/// Print warnings to stderr, one per line, with their names.
pub fn print_warnings(warnings: &[Warning]) {
    let st = Style::stderr();
    for w in warnings {
        let text = w.to_string();
        match text.split_once(": ") {
            Some((head, rest)) => eprintln!("{}: {rest}", st.bad(head)),
            None => eprintln!("{}", st.bad(&text)),
        }
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
    if !v.is_finite() {
        return Err(format!(
            "joint `{name}`: expected a finite number, found `{value}`"
        ));
    }
    Ok((name.trim().to_string(), v))
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

/// Expand directories (one level deep and below, sorted) into the files the tool
/// reads; plain files are taken as given.
pub fn expand_paths(paths: &[PathBuf], accept: fn(&Path) -> bool) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        let meta = std::fs::metadata(p).map_err(|e| Error::io(p, &e))?;
        if meta.is_dir() {
            let mut found = Vec::new();
            walk(p, accept, &mut found, 0)?;
            found.sort();
            out.extend(found);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

fn walk(dir: &Path, accept: fn(&Path) -> bool, out: &mut Vec<PathBuf>, depth: usize) -> Result<()> {
    // Depth cap: a calibration tree is shallow; a symlink loop must not hang us.
    if depth > 16 {
        return Ok(());
    }
    let rd = std::fs::read_dir(dir).map_err(|e| Error::io(dir, &e))?;
    for entry in rd {
        let entry = entry.map_err(|e| Error::io(dir, &e))?;
        let path = entry.path();
        let ft = entry.file_type().map_err(|e| Error::io(&path, &e))?;
        // A rosbag2 folder (metadata.yaml + its files) is one input.
        if ft.is_dir() && accept(&path) && crate::formats::bag::is_bag(&path) {
            out.push(path);
        } else if ft.is_dir() {
            walk(&path, accept, out, depth + 1)?;
        } else if accept(&path) {
            out.push(path);
        }
    }
    Ok(())
}

/// Write a file atomically: a temporary file `.NAME.tmp.PID` in the same
/// directory, written, flushed and synced, then renamed over the target, and the
/// directory synced so the rename itself is durable. An interrupted run leaves
/// the old file complete; a failed write removes the temporary and leaves the
/// old file. A process killed mid-write may leave its own temporary (nothing
/// runs after SIGKILL); a later run with the same pid overwrites it.
/// A symlink at `path` is replaced by the file, not followed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let tmp = dir.join(format!(".{name}.tmp.{}", std::process::id()));
    let res = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)?;
        Ok(())
    })();
    if let Err(e) = res {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::new(
            crate::diagnostic::ErrorKind::Io,
            format!("cannot write: {e}"),
        )
        .in_file(path));
    }
    // Best effort: some file systems cannot sync a directory.
    if let Ok(d) = std::fs::File::open(&dir) {
        let _ = d.sync_all();
    }
    Ok(())
}
