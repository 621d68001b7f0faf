//! CSV `x,y,z,nx,ny,nz[,w]`, line by line.

use super::check::{Checker, Stats};
use super::record::{column_role, missing_roles, PointFormat, Sink};
use super::source::Source;
use crate::diagnostic::{Error, Result};
use std::io::Read;

fn split_fields(line: &str) -> Vec<&str> {
    line.split([',', ';', '\t', ' '])
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect()
}

/// Columns of each role (`None` for an absent weight) from the first row:
/// positional when it is numeric (`Ok((cols, true))`: the row is data),
/// named otherwise.
fn columns(fields: &[&str], lineno: usize, xyz_only: bool) -> Result<([Option<usize>; 7], bool)> {
    let mut cols = [None; 7];
    let numeric = fields.iter().all(|f| f.parse::<f64>().is_ok());
    if numeric && xyz_only && fields.len() >= 3 {
        // A raw scan: x, y, z first; the rest (intensity, ring, ...) unused.
        for (k, c) in cols.iter_mut().enumerate().take(3) {
            *c = Some(k);
        }
        return Ok((cols, true));
    }
    if numeric {
        if fields.len() != 6 && fields.len() != 7 {
            return Err(Error::parse(format!(
                "CSV: expected 6 or 7 columns x,y,z,nx,ny,nz[,w], found {}",
                fields.len()
            ))
            .at_line(lineno, None));
        }
        for (k, c) in cols.iter_mut().enumerate().take(fields.len()) {
            *c = Some(k);
        }
        return Ok((cols, true));
    }
    for (k, f) in fields.iter().enumerate() {
        if let Some(role) = column_role(f) {
            if cols[role].is_some() {
                return Err(
                    Error::parse(format!("CSV header: column {f:?} appears twice"))
                        .at_line(lineno, None),
                );
            }
            cols[role] = Some(k);
        }
    }
    let missing = missing_roles(&cols, ["x", "y", "z", "nx", "ny", "nz"], xyz_only);
    if !missing.is_empty() {
        return Err(Error::parse(format!(
            "CSV header: expected columns x,y,z,nx,ny,nz[,w], missing {} (found {:?})",
            missing.join(","),
            fields
        ))
        .at_line(lineno, None));
    }
    Ok((cols, false))
}

/// One data row into `v` (`x y z nx ny nz w`).
fn row(
    fields: &[&str],
    cols: &[Option<usize>; 7],
    ncols: usize,
    lineno: usize,
) -> Result<[f64; 7]> {
    if fields.len() != ncols {
        return Err(Error::parse(format!(
            "CSV: expected {ncols} fields, found {}",
            fields.len()
        ))
        .at_line(lineno, None));
    }
    // Without normal columns (a raw scan) the normal is a placeholder +z.
    let mut v = [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0];
    for (role, c) in cols.iter().enumerate() {
        if let Some(k) = c {
            let f = fields[*k];
            v[role] = f.parse::<f64>().map_err(|_| {
                Error::parse(format!(
                    "CSV: expected a number in column {}, found {f:?}",
                    k + 1
                ))
                .at_line(lineno, Some(k + 1))
            })?;
        }
    }
    Ok(v)
}

pub(super) fn decode<R: Read, S: Sink>(
    src: &mut Source<R>,
    sink: &mut S,
    xyz_only: bool,
) -> Result<(PointFormat, Stats)> {
    let mut layout: Option<([Option<usize>; 7], usize)> = None;
    let mut ck: Option<Checker<S>> = None;
    let mut sink = Some(sink);
    let mut line = Vec::new();
    loop {
        let at = src.offset();
        if src.read_line(&mut line)?.is_none() {
            break;
        }
        let lineno = src.lines();
        let text = std::str::from_utf8(&line).map_err(|e| {
            Error::parse(format!(
                "CSV: expected UTF-8 text, found invalid bytes at offset {}",
                at + e.valid_up_to() as u64
            ))
        })?;
        let text = text.trim();
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        let fields = split_fields(text);
        if layout.is_none() {
            let (cols, data) = columns(&fields, lineno, xyz_only)?;
            layout = Some((cols, fields.len()));
            if let Some(s) = sink.take() {
                ck = Some(Checker::new(s, cols[6].is_some(), 0));
            }
            if !data {
                continue;
            }
        }
        let (Some((cols, ncols)), Some(c)) = (layout.as_ref(), ck.as_mut()) else {
            continue;
        };
        let v = row(&fields, cols, *ncols, lineno)?;
        c.record(&v)
            .map_err(|f| f.error(format!("point on line {lineno}"), Some(lineno)))?;
    }
    match ck {
        Some(c) => Ok((PointFormat::Csv, c.stats)),
        None => Err(Error::parse(
            "CSV: expected rows x,y,z,nx,ny,nz[,w], found no data",
        )),
    }
}
