//! The contract every point reader shares, a leaf: which reader was used
//! ([`PointFormat`]), where the readers put valid points ([`Sink`]), and the
//! column names they recognise.

/// Which reader was used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointFormat {
    /// CSV `x,y,z,nx,ny,nz[,w]`, with or without a header.
    Csv,
    /// PLY, ascii.
    PlyAscii,
    /// PLY, binary little-endian.
    PlyBinaryLittleEndian,
    /// PLY, binary big-endian.
    PlyBinaryBigEndian,
    /// PCD, ascii.
    PcdAscii,
    /// PCD, binary.
    PcdBinary,
    /// PCD, binary_compressed (LZF).
    PcdBinaryCompressed,
    /// LAS (uncompressed).
    Las,
    /// LAZ (LASzip-compressed LAS).
    Laz,
    /// Points held in memory by the caller (the library's `Points`).
    Memory,
}

impl PointFormat {
    /// The name reports print (`ply-binary-little-endian`).
    pub fn name(self) -> &'static str {
        match self {
            PointFormat::Csv => "csv",
            PointFormat::PlyAscii => "ply-ascii",
            PointFormat::PlyBinaryLittleEndian => "ply-binary-little-endian",
            PointFormat::PlyBinaryBigEndian => "ply-binary-big-endian",
            PointFormat::PcdAscii => "pcd-ascii",
            PointFormat::PcdBinary => "pcd-binary",
            PointFormat::PcdBinaryCompressed => "pcd-binary-compressed",
            PointFormat::Las => "las",
            PointFormat::Laz => "laz",
            PointFormat::Memory => "memory",
        }
    }
}

/// Where the readers put valid points.
pub(crate) trait Sink {
    /// Called once, after the header: whether there are weights, and a
    /// (capped, untrusted) size hint.
    fn begin(&mut self, weighted: bool, hint: usize);
    fn point(&mut self, p: &[f64; 3], n: &[f64; 3], w: f64);
    /// Valid points in bulk (weights 1 when the file has none).
    fn points(&mut self, p: &[[f64; 3]], n: &[[f64; 3]], w: &[f64]) {
        for ((p, n), w) in p.iter().zip(n).zip(w) {
            self.point(p, n, *w);
        }
    }
    /// Every `BLOCK` records.
    fn end_block(&mut self);
}

/// The names of the six required roles (x y z and the normal; x y z only
/// when `xyz_only`) that `roles` has not found, in order.
pub(super) fn missing_roles<'a, T>(
    roles: &[Option<T>],
    names: [&'a str; 6],
    xyz_only: bool,
) -> Vec<&'a str> {
    let need = if xyz_only { 3 } else { 6 };
    names
        .into_iter()
        .take(need)
        .zip(roles)
        .filter(|(_, r)| r.is_none())
        .map(|(n, _)| n)
        .collect()
}

/// The role (0..7: x y z nx ny nz w) a column or field name plays.
pub(super) fn column_role(name: &str) -> Option<usize> {
    match name.trim().trim_matches('"').to_ascii_lowercase().as_str() {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        "nx" | "normal_x" => Some(3),
        "ny" | "normal_y" => Some(4),
        "nz" | "normal_z" => Some(5),
        "w" | "weight" => Some(6),
        _ => None,
    }
}
