//! Loading: a file (or bytes, or text) through detection and its format's
//! parser, then the checks every format's result goes through.

use super::registry;
use super::spec::{Format, Includes, Input, LoadOptions, Parsed};
use crate::diagnostic::{Code, Error, Result, Warning};
use crate::frames::{Edge, JointType};
use crate::tolerances::MAX_TRANSLATION_M;
use std::path::Path;

/// Read one file: detect its format (or use `opts.format`), parse, validate.
/// A FIFO or a device is refused before anything blocks on it; a bag (a file
/// or a rosbag2 folder) is read through its index, never whole; anything else
/// at most `opts.max_file_size` bytes.
pub fn load_file(path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    if let Err(why) = opts.check_confined(path).or_else(|e| {
        if crate::input::is_stdin(path) {
            Ok(())
        } else {
            Err(e)
        }
    }) {
        return Err(Error::limit(why).in_file(path));
    }
    load(Input::open(path, opts.max_file_size)?, opts)
}

/// [`load_file`] on a file already opened and read whole (by a caller that
/// looked at its bytes first): the same result without a second read, or
/// [`load_file`] itself when the file is not one it would read at once.
pub(crate) fn load_opened(
    path: &Path,
    (file, len, bytes): crate::input::ReadWhole,
    opts: &LoadOptions,
) -> Result<Parsed> {
    if opts.check_confined(path).is_err() || crate::input::is_stdin(path) {
        return load_file(path, opts);
    }
    match Input::from_opened(path, file, len, bytes, opts.max_file_size) {
        Some(input) => load(input, opts),
        None => load_file(path, opts),
    }
}

/// Read bytes as if read from `path`: binary formats (bags, Arrow IPC
/// `.feather`, a LAS/LAZ refused with the command that reads it) by their
/// magic bytes or extension, anything else as UTF-8 text ([`load_str`]).
pub fn load_bytes(bytes: Vec<u8>, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    load(Input::from_bytes(path, bytes), opts)
}

/// Parse `text` as if read from `path` (the path names the file in provenance
/// and selects the format by extension).
pub fn load_str(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    load(Input::from_text(path, text), opts)
}

/// Detect the format of `text` read from `path` (by extension and content).
pub fn detect_format(path: &Path, text: &str) -> Result<Format> {
    let input = Input::from_text(path, text);
    match registry::binary(&input, None) {
        Some(f) => Ok(f),
        None => registry::detect_text(&input),
    }
}

/// The format [`load_file`] reads `path` as (without `--input-format`).
pub fn detect_file(path: &Path, opts: &LoadOptions) -> Result<Format> {
    let mut input = Input::open(path, opts.max_file_size)?;
    if let Some(f) = registry::binary(&input, None) {
        return Ok(f);
    }
    input.decode()?;
    not_empty(&input)?;
    registry::detect_text(&input)
}

/// What the formats' includes load through: [`load_file`] with the
/// including file's options, its `--key` and `--invert` replaced.
struct Includer<'o> {
    opts: &'o LoadOptions,
}

impl Includes for Includer<'_> {
    fn include(&self, path: &Path, key: Option<String>, invert: bool) -> Result<Parsed> {
        let opts = LoadOptions {
            key,
            invert,
            format: None,
            ..self.opts.clone()
        };
        load_file(path, &opts)
    }
}

fn load(input: Input, opts: &LoadOptions) -> Result<Parsed> {
    let includer = Includer { opts };
    let mut input = input.with_includes(&includer);
    if let Some(f) = registry::binary(&input, opts.format) {
        return run(f, &input, opts);
    }
    input.decode()?;
    load_text(&input, opts)
}

/// A text input: not empty, then its format (`opts.format`, or detected).
fn load_text(input: &Input, opts: &LoadOptions) -> Result<Parsed> {
    not_empty(input)?;
    let format = match opts.format {
        Some(f) => f,
        None => registry::detect_text(input)?,
    };
    run(format, input, opts)
}

fn not_empty(input: &Input) -> Result<()> {
    if input.text()?.trim().is_empty() {
        return Err(Error::parse(
            "file is empty: expected a URDF, launch file, calibration YAML/JSON or text",
        )
        .in_file(input.path()));
    }
    Ok(())
}

/// Parse with `format`, then the common checks unless the format has none.
fn run(format: Format, input: &Input, opts: &LoadOptions) -> Result<Parsed> {
    let path = input.path();
    let loaded = (format.0.parse)(input, opts).map_err(|e| e.in_file(path))?;
    if !format.0.checked {
        return Ok(loaded);
    }
    checked(loaded, format, path, opts)
}

/// A `--joint` value above 2 pi on a revolute or continuous joint of these
/// edges looks like degrees: a `degrees-in-radian-field` warning.
fn warn_degrees(edges: &[Edge], opts: &LoadOptions, warnings: &mut Vec<Warning>) {
    use crate::tolerances::DEGREES_LIKE_RAD;
    for e in edges {
        let Some(j) = &e.joint else { continue };
        let Some(&v) = opts.joints.get(&j.name) else {
            continue;
        };
        if matches!(j.joint_type, JointType::Revolute | JointType::Continuous)
            && v.abs() > DEGREES_LIKE_RAD
        {
            warnings.push(
                Warning::new(
                    Code::DegreesInRadianField,
                    format!(
                        "--joint {}={v}: {} joint positions are radians, and |{v}| > 2 pi looks like degrees ({v} deg = {:.6} rad)",
                        crate::sanitize::quote(&j.name),
                        j.joint_type,
                        v.to_radians()
                    ),
                )
                .at(&e.provenance.location),
            );
        }
    }
}

/// A NUL or a line break in a frame or joint name is an error at the edge's
/// place: no ROS name holds one, and a line break would let a name start a
/// line of a report or a CI log.
fn check_names(e: &Edge) -> Result<()> {
    let joint = e.joint.as_ref().map(|j| ("joint", j.name.as_str()));
    let names = [("frame", e.parent.as_str()), ("frame", e.child.as_str())];
    for (what, name) in names.into_iter().chain(joint) {
        let bad = name
            .chars()
            .find(|&c| matches!(c, '\0' | '\n' | '\r' | '\u{85}' | '\u{2028}' | '\u{2029}'));
        if let Some(c) = bad {
            let found = if c == '\0' { "a NUL" } else { "a line break" };
            return Err(Error::parse(format!(
                "{what} name \"{}\" contains {found}: expected a name without control characters",
                crate::sanitize::quote(name)
            ))
            .at(&e.provenance.location));
        }
    }
    Ok(())
}

/// What every loader's result goes through: at least one edge, names and
/// translations checked, `--joint` degrees warned, `--invert` applied.
fn checked(mut loaded: Parsed, format: Format, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    if loaded.edges.is_empty() {
        return Err(Error::parse(format!(
            "read as {}: expected at least one transform, found none",
            format.name()
        ))
        .in_file(path));
    }
    for e in loaded.edges.iter().chain(&loaded.redundant) {
        check_names(e).map_err(|err| err.in_file(path))?;
        let d = e.transform.translation();
        if let Some(x) = d.iter().find(|x| x.is_nan() || x.abs() > MAX_TRANSLATION_M) {
            return Err(Error::invalid(format!(
                "edge {} -> {} ({}): translation component {x:e} m: expected at most {MAX_TRANSLATION_M:e} m in magnitude (a sensor extrinsic; check the units)",
                e.parent, e.child, e.provenance.key
            ))
            .at(&e.provenance.location)
            .in_file(path));
        }
    }
    warn_degrees(&loaded.edges, opts, &mut loaded.warnings);
    if opts.invert {
        loaded.edges = loaded.edges.into_iter().map(numbers_inverted).collect();
        loaded.redundant = loaded.redundant.into_iter().map(numbers_inverted).collect();
    }
    Ok(loaded)
}

/// `--invert`: the file's numbers are the pose of the parent in the child, so
/// the edge keeps its frames and takes the inverse transform ([`Edge::inverted`]
/// alone, which also swaps the frames, states the same pose and changes nothing).
fn numbers_inverted(e: Edge) -> Edge {
    let mut e = e.inverted();
    std::mem::swap(&mut e.parent, &mut e.child);
    e
}
