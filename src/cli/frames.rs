//! `audit FILE... --frames [--from A --to B] --format text|json|markdown|dot|mermaid|svg|mcap`:
//! the frame tree, the chain highlighted when asked, through the one output
//! path (its document is a graph; the formats that cannot draw one refuse).

use super::args::OutputArgs;
use super::emit_warned;
use extrinsic_audit::{Error, Result, Robot};
use std::io::Write;
use std::path::PathBuf;

/// Print the frame tree of `robot` as `output` asks, the `from` -> `to`
/// chain marked when both are given; its JSON carries the robot's warnings (already
/// printed on standard error).
pub fn run(
    robot: &Robot,
    from: Option<&str>,
    to: Option<&str>,
    output: &OutputArgs,
    inputs: &[PathBuf],
    out: &mut dyn Write,
) -> Result<i32> {
    let chain = match (from, to) {
        (Some(f), Some(t)) => Some(robot.chain(f, t)?),
        (None, None) => None,
        _ => {
            return Err(Error::usage(
                "--frames: give both --from and --to to highlight a chain, or neither",
            ))
        }
    };
    let rep = robot.frame_tree(chain.as_ref());
    emit_warned(&rep, robot.warnings(), output, inputs, out)?;
    Ok(0)
}
