//! LAS and LAZ point clouds given where transforms are expected: recognised
//! by their magic bytes (`LASF`, ASPRS LAS 1.0 to 1.4) and refused with the
//! command that reads them, rather than "expected UTF-8 text". The points
//! themselves are read by `degeneracy::points` (`audit degeneracy FILE
//! --estimate-normals`).

use super::spec::{FormatSpec, Input, LoadOptions, Parsed};
use crate::bytes::LAS_MAGIC;
use crate::diagnostic::{Error, Result};

fn parse(input: &Input, _: &LoadOptions) -> Result<Parsed> {
    Err(Error::parse(
        "expected a file with transforms (URDF, launch, YAML, JSON, TOML, ...), found a LAS/LAZ point cloud (magic `LASF`); its degeneracy is read by `audit degeneracy FILE --estimate-normals`",
    )
    .in_file(input.path()))
}

/// LAS/LAZ point clouds: refused, naming the command that reads them.
pub const SPEC: FormatSpec = FormatSpec {
    id: "las",
    description: "LAS/LAZ point cloud (magic `LASF`): holds no transforms; refused with the command that reads it, `audit degeneracy FILE --estimate-normals`",
    extensions: &[],
    walk: &[],
    magic: &[LAS_MAGIC],
    sniff: |_| None,
    parse,
    checked: true,
};
