//! Where a command may write a file (`--output`, `survey --plot`): a file,
//! in a directory that exists, that is none of the command's inputs (the
//! same file by device and inode, or by its real path, symlinks and `./`
//! resolved) and that no directory walk of the command would read. Checked
//! before the work and again just before the write; the write itself is
//! [`super::write_atomic`]'s.

use super::files::{same_file, unsafe_target, write_atomic};
use super::survey::{is_any_input, split_pair};
use crate::diagnostic::{Error, Result};
use crate::report::SurveyReport;
use std::path::{Path, PathBuf};

/// Whether `flag TARGET` may be written by a command (`whose`: `survey`,
/// `command`) that reads `inputs` (paths as given, `PATH:FROM:TO` included,
/// and the files they included); then `unsafe_target`'s refusals (a
/// symlink, a file of several names, a symlinked directory here).
pub fn check_output_target(
    flag: &str,
    whose: &str,
    target: &Path,
    inputs: &[PathBuf],
) -> Result<()> {
    let shown = target.display();
    if target.is_dir() {
        return Err(Error::usage(format!(
            "{flag} {shown}: expected a file, found a directory"
        )));
    }
    let real = real_path(target).ok_or_else(|| {
        Error::usage(format!(
            "{flag} {shown}: expected a file in an existing directory"
        ))
    })?;
    for p in inputs {
        let (p, _) = split_pair(p);
        let walked = p.is_dir()
            && p.canonicalize().is_ok_and(|d| real.starts_with(d))
            && is_any_input(&real);
        if same_file(&p, target) || p.canonicalize().is_ok_and(|c| c == real) || walked {
            return Err(Error::usage(format!(
                "{flag} {shown}: refusing to write over an input of the {whose} ({})",
                p.display()
            )));
        }
    }
    match unsafe_target(target) {
        Some(why) => Err(Error::usage(format!(
            "{flag} {shown}: refusing to write: {why}"
        ))),
        None => Ok(()),
    }
}

/// Whether the survey plot may be written to `target`: an `.svg` file name in
/// an existing directory that is none of the survey's inputs (checked before
/// the survey runs, so that nothing is read or written in vain).
pub fn check_plot_target(target: &Path, inputs: &[PathBuf]) -> Result<()> {
    plot_target("survey", target, inputs)
}

/// [`check_plot_target`] for `command`'s plot.
pub(super) fn plot_target(command: &str, target: &Path, inputs: &[PathBuf]) -> Result<()> {
    if !target
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"))
    {
        return Err(Error::usage(format!(
            "--plot {}: expected a file name ending in .svg",
            target.display()
        )));
    }
    check_output_target("--plot", command, target, inputs)
}

/// Draw the survey plot to `target` after [`check_plot_target`] (again: the
/// inputs must still not include it).
pub fn write_survey_plot(target: &Path, inputs: &[PathBuf], report: &SurveyReport) -> Result<()> {
    write_plot("survey", target, inputs, &report.plot())
}

/// Draw `plot` (a document of one plot block) as SVG to `target`, checked
/// again as [`plot_target`] checks it.
pub(super) fn write_plot(
    command: &str,
    target: &Path,
    inputs: &[PathBuf],
    plot: &crate::document::Document,
) -> Result<()> {
    plot_target(command, target, inputs)?;
    let svg = crate::render::draw(
        plot,
        crate::render::OutputFormat::Svg,
        crate::render::Style::plain(),
        &crate::render::Layout::default(),
    )?;
    write_atomic(target, svg.as_bytes())
}

/// `p` with its directory's real path (the file itself resolved too when it
/// exists); `None` when the directory does not exist.
fn real_path(p: &Path) -> Option<PathBuf> {
    let dir = p
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let joined = dir.canonicalize().ok()?.join(p.file_name()?);
    Some(joined.canonicalize().unwrap_or(joined))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_input_its_link_or_a_file_a_walk_reads_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("robot.urdf");
        std::fs::write(&input, "<robot/>").unwrap();
        let link = dir.path().join("hard.urdf");
        std::fs::hard_link(&input, &link).unwrap();
        let inputs = vec![input.clone()];
        let refused = |t: &Path, inputs: &[PathBuf]| {
            let e = check_output_target("--output", "command", t, inputs).unwrap_err();
            assert!(
                e.to_string().contains("refusing to write over an input"),
                "{e}"
            );
        };
        refused(&input, &inputs);
        refused(&dir.path().join(".").join("robot.urdf"), &inputs);
        refused(&link, &inputs);
        // A directory input: a file its walk would read, not another.
        let walked = vec![dir.path().to_path_buf()];
        refused(&dir.path().join("new.yaml"), &walked);
        check_output_target("--output", "command", &dir.path().join("plot.svg"), &walked).unwrap();
        // An MCAP file is a bag a walk reads.
        refused(&dir.path().join("rig.mcap"), &walked);
        // `PATH:FROM:TO` names its file.
        let pair = vec![PathBuf::from(format!("{}:base:lidar", input.display()))];
        refused(&input, &pair);
        check_output_target("--output", "command", &dir.path().join("out.mcap"), &inputs).unwrap();
    }

    #[test]
    fn a_directory_or_a_missing_directory_is_no_target() {
        let dir = tempfile::tempdir().unwrap();
        let e = check_output_target("--output", "command", dir.path(), &[]).unwrap_err();
        assert!(e.to_string().contains("found a directory"), "{e}");
        let e = check_output_target(
            "--output",
            "command",
            &dir.path().join("no/such/x.mcap"),
            &[],
        )
        .unwrap_err();
        assert!(e.to_string().contains("existing directory"), "{e}");
    }
}
