//! Which reader a stream needs, from its first bytes, and the decode of a
//! whole stream on one thread (the parallel reader splits the binary ones).

use super::check::Stats;
use super::record::{PointFormat, Sink};
use super::source::Source;
use super::{csv, pcd, ply};
use crate::bytes::LAS_MAGIC;
use crate::diagnostic::{Error, Result};
use std::io::Read;

/// Which reader a file needs, from its first bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    Ply,
    Pcd,
    Las,
    Csv,
}

pub(super) fn detect<R: Read>(src: &mut Source<R>) -> Result<Kind> {
    src.fill(4096)?;
    // A UTF-8 byte-order mark is skipped, as in every text format (issue 12).
    if src.data().starts_with(b"\xef\xbb\xbf") {
        src.consume(3);
    }
    let head = src.data();
    let head = &head[..head.len().min(4096)];
    Ok(
        if head.starts_with(b"ply\n") || head.starts_with(b"ply\r\n") {
            Kind::Ply
        } else if head.starts_with(LAS_MAGIC) {
            Kind::Las
        } else if looks_like_pcd(head) {
            Kind::Pcd
        } else {
            Kind::Csv
        },
    )
}

/// Decode a whole stream into `sink` on this thread. `xyz_only`: normals are
/// not required (a raw scan; absent normals read as the placeholder `+z`).
pub(super) fn decode<R: Read, S: Sink>(
    src: &mut Source<R>,
    sink: &mut S,
    xyz_only: bool,
) -> Result<(PointFormat, Stats)> {
    match detect(src)? {
        Kind::Ply => {
            let h = ply::read_header(src, xyz_only)?;
            ply::body(src, &h, sink)
        }
        Kind::Pcd => {
            let h = pcd::read_header(src, xyz_only)?;
            pcd::body(src, &h, sink)
        }
        // Normals required (H and M streamed): refused; raw scans are read
        // whole by `read_mode`.
        Kind::Las => Err(las_without_normals()),
        Kind::Csv => csv::decode(src, sink, xyz_only),
    }
}

fn looks_like_pcd(head: &[u8]) -> bool {
    let s = String::from_utf8_lossy(head);
    for line in s.lines() {
        let t = line.trim();
        if t.is_empty() || (t.starts_with('#') && !t.contains(".PCD")) {
            continue;
        }
        if t.starts_with("# .PCD") {
            return true;
        }
        let first = t.split_whitespace().next().unwrap_or("");
        return matches!(first, "VERSION" | "FIELDS");
    }
    false
}

/// LAS records have no normals: the same refusal as a PCD without them.
pub(super) fn las_without_normals() -> Error {
    Error::parse(
        "LAS: expected points with normals, LAS records have none (missing normal_x normal_y normal_z)",
    )
}
