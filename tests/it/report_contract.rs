//! The report checklist's contract (docs/ARCHITECTURE.md, "Adding a report",
//! step 4), read from the binary itself: every command `audit --help` lists
//! (and the rig report, the command without a name) is run under 80 and 120
//! columns by `widths::every_command_fits_80_and_120_columns` (an entry of
//! `widths::COMMANDS`) or is exempt below with its reason, and every command
//! whose `--format` takes `json` has its JSON checked against a committed
//! schema by `json_schemas::every_command_s_json_matches_its_schema` (an
//! entry of `json_schemas::SCHEMAS`). The command list is clap's own
//! `Commands:` section, so a command added to `src/main.rs` without either
//! fails here.

use crate::common::run_cli;
use crate::json_schemas::SCHEMAS;
use crate::widths::COMMANDS;

/// Commands not run under a pseudo-terminal by the widths test, and why.
const NOT_IN_WIDTHS: [(&str, &str); 1] = [(
    "completions",
    "prints a shell script (clap_complete's), not a report: no table, no --format",
)];

/// Commands whose `--format` takes `json` but whose JSON has no schema, and
/// why. Empty: every JSON output has one.
const NO_SCHEMA: [(&str, &str); 0] = [];

/// The subcommands `audit --help` lists under `Commands:` (clap's own `help`
/// left out), in its order.
fn commands() -> Vec<String> {
    let (code, out, err) = run_cli(&["--help"]);
    assert_eq!(code, 0, "{err}");
    let section = out
        .split_once("\nCommands:\n")
        .unwrap_or_else(|| panic!("no `Commands:` section in `audit --help`:\n{out}"))
        .1;
    let names: Vec<String> = section
        .lines()
        .take_while(|l| !l.trim().is_empty())
        // A name is indented two spaces; a wrapped description, more.
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|n| *n != "help")
        .map(str::to_string)
        .collect();
    assert!(names.len() > 5, "too few commands read: {names:?}\n{out}");
    names
}

/// The values `audit ARGS --help` lists for `--format` (empty without it).
fn format_values(args: &[&str]) -> Vec<String> {
    let (code, out, err) = run_cli(&[args, &["--help"]].concat());
    assert_eq!(code, 0, "{args:?}: {err}");
    let Some((_, rest)) = out.split_once("--format <FORMAT>") else {
        return Vec::new();
    };
    // clap's long help: "Possible values:" then one "- NAME: what" line per
    // value (a long one wrapped onto more lines), up to a blank line.
    let block = rest
        .split_once("Possible values:")
        .unwrap_or_else(|| panic!("{args:?}: --format lists no values:\n{out}"))
        .1;
    block
        .lines()
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.trim_start().strip_prefix("- "))
        .filter_map(|v| v.split([':', ' ']).next())
        .map(str::to_string)
        .collect()
}

/// Whether an entry's arguments `args` run the command `name`; `None` is the
/// rig report, whose first argument is a file, not a command.
fn runs(args: &[&str], name: Option<&str>, commands: &[String]) -> bool {
    let first = args.first().copied().unwrap_or_default();
    match name {
        Some(n) => first == n,
        None => !commands.iter().any(|c| c == first),
    }
}

#[test]
fn every_command_is_in_the_widths_test_and_every_json_has_a_schema() {
    let commands = commands();
    // Every exemption names a command that exists, once.
    for (name, why) in NOT_IN_WIDTHS.iter().chain(NO_SCHEMA.iter()) {
        assert!(commands.iter().any(|c| c == name), "{name}: {why}");
    }
    let all: Vec<Option<&str>> = std::iter::once(None)
        .chain(commands.iter().map(|c| Some(c.as_str())))
        .collect();
    let mut missing = Vec::new();
    for name in all {
        let shown = name.unwrap_or("audit FILE... (the rig report)");
        let in_widths = COMMANDS.iter().any(|(_, a)| runs(a, name, &commands));
        let exempt = NOT_IN_WIDTHS.iter().any(|(n, _)| Some(*n) == name);
        assert!(
            !(in_widths && exempt),
            "{shown}: both in widths::COMMANDS and exempt"
        );
        if !in_widths && !exempt {
            missing.push(format!(
                "{shown}: not in tests/it/widths.rs's COMMANDS (nor in NOT_IN_WIDTHS with a reason)"
            ));
        }
        let values = format_values(name.as_slice());
        let has_schema = SCHEMAS.iter().any(|(_, a)| runs(a, name, &commands));
        let no_schema = NO_SCHEMA.iter().any(|(n, _)| Some(*n) == name);
        if values.iter().any(|v| v == "json") {
            if !has_schema && !no_schema {
                missing.push(format!(
                    "{shown}: takes --format json but has no entry in tests/it/json_schemas.rs's SCHEMAS (nor in NO_SCHEMA with a reason)"
                ));
            }
        } else {
            assert!(
                !has_schema,
                "{shown}: an entry in SCHEMAS, but its --format takes no json ({values:?})"
            );
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

/// The reading of the help above on what it must find: the root and `survey`
/// take `--format json` among the formats `OutputFormat` lists; `completions`
/// has no `--format`.
#[test]
fn the_help_is_read_as_it_is_written() {
    let commands = commands();
    for c in ["survey", "check", "run", "completions"] {
        assert!(commands.iter().any(|n| n == c), "{c}: {commands:?}");
    }
    for args in [&[][..], &["survey"]] {
        let values = format_values(args);
        for v in ["table", "markdown", "json", "csv"] {
            assert!(values.iter().any(|x| x == v), "{args:?}: {v} in {values:?}");
        }
    }
    assert!(format_values(&["completions"]).is_empty());
}
