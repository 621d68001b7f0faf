//! `matrix4-text`: a plain text file holding one 4x4 matrix, 16 numbers
//! row-major, separated by blanks or commas (the layout `audit degeneracy
//! --initial-guess-file` reads).
//!
//! No direction can be traced: the file names no frames and no one program
//! consumes "a 4x4 text file" in one convention (registration results map the
//! source into the target; exports of other tools differ). It is therefore
//! read only with `--assume child-in-parent:PARENT,CHILD` (the matrix is the
//! pose of CHILD in PARENT) or `--assume parent-in-child:PARENT,CHILD` (the
//! inverse); the edge is `PARENT -> CHILD`. Without it the file is refused,
//! naming the flag. Refused too: another count than 16, a bottom row other
//! than `0 0 0 1`.

use super::calib_shapes::assumed;
use super::spec::{
    check_metres, locate_warnings, parse_number, Confidence, FormatSpec, Input, LoadOptions, Parsed,
};
use crate::diagnostic::{Error, Location, Result};
use crate::frames::Edge;
use crate::geometry::se3::Transform;
use crate::geometry::uncertainty::matrix4_precision;
use std::path::Path;

/// Plain 4x4 matrix text.
pub const MATRIX4_TEXT: FormatSpec = FormatSpec {
    id: "matrix4-text",
    description: "plain text 4x4 matrix (16 numbers, row-major, blanks or commas): no direction can be traced, so it is read only with --assume child-in-parent:PARENT,CHILD (or parent-in-child:...), edge PARENT -> CHILD",
    extensions: &[],
    // Never walked: many `.txt` files of a dataset are columns of numbers.
    walk: &[],
    magic: &[],
    sniff,
    parse: |i, o| parse(i.text()?, i.path(), o),
    checked: true,
};

/// The tokens of the text: numbers separated by blanks and commas.
fn tokens(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|t| !t.is_empty())
}

/// Only numbers, about one matrix of them (a 3x4 to a 4x4 with a stray one).
fn sniff(i: &Input) -> Option<Confidence> {
    let text = i.text().ok()?;
    let mut n = 0;
    for t in tokens(text) {
        parse_number(t)?;
        n += 1;
        if n > 20 {
            return None;
        }
    }
    (n >= 12).then_some(Confidence::Lines)
}

fn parse(text: &str, path: &Path, opts: &LoadOptions) -> Result<Parsed> {
    let loc = Location::at(path, 1, Some(1));
    let mut v = Vec::new();
    for t in tokens(text) {
        v.push(parse_number(t).ok_or_else(|| {
            Error::parse(format!(
                "4x4 matrix text: expected numbers only, found {:?}",
                crate::sanitize::clip(t)
            ))
            .at(&loc)
        })?);
    }
    if v.len() != 16 {
        return Err(Error::parse(format!(
            "4x4 matrix text: expected 16 numbers (row-major), found {}",
            v.len()
        ))
        .at(&loc));
    }
    let Some(a) = opts.assume.as_ref() else {
        return Err(Error::parse("a plain 4x4 matrix names no frames and no direction: pass --assume child-in-parent:PARENT,CHILD (the matrix is the pose of CHILD in PARENT) or --assume parent-in-child:PARENT,CHILD").at(&loc));
    };
    let Some((parent, child)) = &a.frames else {
        return Err(Error::usage(format!(
            "{}: a plain 4x4 matrix names no frames: expected {}:PARENT,CHILD",
            a.flag(),
            a.flag()
        )));
    };
    let m = [
        [v[0], v[1], v[2], v[3]],
        [v[4], v[5], v[6], v[7]],
        [v[8], v[9], v[10], v[11]],
        [v[12], v[13], v[14], v[15]],
    ];
    let mut out = Parsed::default();
    let mut ws = Vec::new();
    let t = Transform::from_matrix4(m, &mut ws).map_err(|e| e.at(&loc))?;
    check_metres(
        &[v[3], v[7], v[11]],
        "the matrix's translation",
        &loc,
        &mut ws,
    );
    locate_warnings(ws, &loc, &mut out.warnings);
    let e = Edge::new(
        parent.clone(),
        child.clone(),
        t,
        loc,
        MATRIX4_TEXT.id,
        "4x4 matrix",
    )
    .with_precision(matrix4_precision(m, 1.0));
    out.edges.push(assumed(a, e));
    Ok(out)
}
