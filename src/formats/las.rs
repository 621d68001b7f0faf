//! Point clouds given where transforms are expected (`audit FILE`, `check`,
//! `survey`): LAS/LAZ by their magic bytes (`LASF`, ASPRS LAS 1.0 to 1.4),
//! PLY by its magic line (`ply`), PCD by its header (`# .PCD`, `VERSION`,
//! `FIELDS`: `crate::bytes`, which the point readers share) and the point
//! files' extensions (`.las`, `.laz`, `.ply`, `.pcd`, `.csv`: no calibration
//! format here reads a CSV), refused with the command that reads them rather
//! than a YAML reader's "no transform found". The points themselves are read
//! by `degeneracy::points` (`audit degeneracy FILE`).

use super::spec::{Confidence, FormatSpec, Input, LoadOptions, Parsed};
use crate::bytes::{looks_like_pcd, LAS_MAGIC, PLY_MAGICS};
use crate::diagnostic::{Error, Result};

/// Which point cloud `input` holds, as the message names it.
fn kind(input: &Input) -> &'static str {
    let head = input.head();
    if head.starts_with(LAS_MAGIC) {
        "a LAS/LAZ point cloud (magic `LASF`)"
    } else if PLY_MAGICS.iter().any(|m| head.starts_with(m)) {
        "a PLY point cloud (magic `ply`)"
    } else if looks_like_pcd(head) {
        "a PCD point cloud (header `VERSION`/`FIELDS`)"
    } else {
        match input.ext() {
            "las" | "laz" => "a LAS/LAZ point cloud (by its name)",
            "ply" => "a PLY point cloud (by its name)",
            "pcd" => "a PCD point cloud (by its name)",
            _ => "a CSV point cloud (by its name: x,y,z[,nx,ny,nz] rows)",
        }
    }
}

fn parse(input: &Input, _: &LoadOptions) -> Result<Parsed> {
    Err(Error::parse(format!(
        "expected a file with transforms (URDF, launch, YAML, JSON, TOML, ...), found {}; its degeneracy is read by `audit degeneracy FILE --estimate-normals` (without --estimate-normals when the points carry normals)",
        kind(input)
    ))
    .in_file(input.path()))
}

/// A PCD header by content (text, so no magic bytes of its own).
fn sniff(input: &Input) -> Option<Confidence> {
    looks_like_pcd(input.head()).then_some(Confidence::Certain)
}

/// Point clouds: refused, naming the command that reads them.
pub const SPEC: FormatSpec = FormatSpec {
    id: "point-cloud",
    description: "Point cloud (LAS/LAZ magic `LASF`, PLY magic `ply`, PCD header, or a .las/.laz/.ply/.pcd/.csv name): holds no transforms; refused with the command that reads it, `audit degeneracy FILE`",
    extensions: &["las", "laz", "ply", "pcd", "csv"],
    walk: &[],
    magic: &[LAS_MAGIC, PLY_MAGICS[0], PLY_MAGICS[1]],
    sniff,
    parse,
    checked: true,
};
