//! Which reader a stream needs, from its first bytes, and the decode of a
//! whole stream on one thread (the parallel reader splits the binary ones).

use super::check::Stats;
use super::record::{PointFormat, Sink};
use super::source::Source;
use super::{csv, pcd, ply};
use crate::bytes::{looks_like_pcd, LAS_MAGIC, PLY_MAGICS};
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
    Ok(if PLY_MAGICS.iter().any(|m| head.starts_with(m)) {
        Kind::Ply
    } else if head.starts_with(LAS_MAGIC) {
        Kind::Las
    } else if looks_like_pcd(head) {
        Kind::Pcd
    } else if let Some(what) = not_points(head) {
        return Err(Error::parse(format!(
            "expected a point cloud (PLY, PCD, CSV x,y,z[,nx,ny,nz], LAS/LAZ), found {what}"
        )));
    } else {
        Kind::Csv
    })
}

/// What a head that is no point file holds, for the refusal: XML (a URDF's
/// `<robot>` named as a robot description), or a YAML/TOML key line (a
/// calibration or configuration file). A CSV of points starts with a header
/// of names or with numbers, never `<`, `key:` or `[table]`.
fn not_points(head: &[u8]) -> Option<&'static str> {
    let s = String::from_utf8_lossy(head);
    let first = s
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))?;
    if first.starts_with('<') {
        let robot = s.contains("<robot");
        return Some(if robot {
            "a robot description (URDF, `<robot>`): its frames and extrinsics are read by `audit FILE --frames` and `audit FILE --from A --to B`"
        } else {
            "XML (a launch file or robot description?): its extrinsics are read by `audit FILE --frames`"
        });
    }
    let key = first.split_once([':', '=']).is_some_and(|(k, _)| {
        !k.is_empty()
            && !k.contains(',')
            && k.trim()
                .chars()
                .all(|c| c.is_alphanumeric() || "_-. /\"".contains(c))
    });
    (key || (first.starts_with('[') && !first.contains(',')))
        .then_some("a calibration or configuration file (YAML/TOML keys): its extrinsics are read by `audit FILE`")
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

/// LAS records have no normals: the same refusal as a PCD without them.
pub(super) fn las_without_normals() -> Error {
    Error::parse(
        "LAS: expected points with normals, LAS records have none (missing normal_x normal_y normal_z)",
    )
}
