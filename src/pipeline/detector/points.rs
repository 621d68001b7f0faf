//! Points the caller holds, for the detector: coordinates (and normals) as
//! `f64` or `f32` rows of three, read in place (`degeneracy_points` checks
//! them as a point file's records are). Points without normals are a raw
//! scan: their normals are estimated first.

use crate::diagnostic::{Error, Result};

/// Rows of three coordinates (points or normals) held by the caller, read in
/// place. A flat buffer of `3 n` values (a C-ordered `n x 3` array) is one:
/// `xs.as_chunks::<3>().0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Coords<'a> {
    /// Double precision.
    F64(&'a [[f64; 3]]),
    /// Single precision (read as `f64`).
    F32(&'a [[f32; 3]]),
}

impl Coords<'_> {
    /// The number of rows.
    pub fn len(&self) -> usize {
        match self {
            Coords::F64(v) => v.len(),
            Coords::F32(v) => v.len(),
        }
    }

    /// Whether there is no row.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub(super) fn row(&self, i: usize) -> [f64; 3] {
        match self {
            Coords::F64(v) => v[i],
            Coords::F32(v) => v[i].map(f64::from),
        }
    }
}

impl<'a> From<&'a [[f64; 3]]> for Coords<'a> {
    fn from(v: &'a [[f64; 3]]) -> Self {
        Coords::F64(v)
    }
}

impl<'a> From<&'a [[f32; 3]]> for Coords<'a> {
    fn from(v: &'a [[f32; 3]]) -> Self {
        Coords::F32(v)
    }
}

impl<'a> From<&'a Vec<[f64; 3]>> for Coords<'a> {
    fn from(v: &'a Vec<[f64; 3]>) -> Self {
        Coords::F64(v)
    }
}

impl<'a> From<&'a Vec<[f32; 3]>> for Coords<'a> {
    fn from(v: &'a Vec<[f32; 3]>) -> Self {
        Coords::F32(v)
    }
}

/// Points for the detector, in their own frame: coordinates (m), unit
/// normals (`None`: a raw scan, normals estimated), optional weights.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Points<'a> {
    /// The coordinates (m).
    pub xyz: Coords<'a>,
    /// One normal per point (renormalised when off unit length, with a
    /// warning); `None`: estimated.
    pub normals: Option<Coords<'a>>,
    /// One non-negative weight per point (`None`: 1 each).
    pub weights: Option<&'a [f64]>,
}

impl<'a> Points<'a> {
    /// Points without normals (a raw scan) and without weights.
    pub fn new(xyz: impl Into<Coords<'a>>) -> Self {
        Points {
            xyz: xyz.into(),
            normals: None,
            weights: None,
        }
    }

    /// The same points with these normals, one per point.
    pub fn with_normals(mut self, normals: impl Into<Coords<'a>>) -> Self {
        self.normals = Some(normals.into());
        self
    }

    /// The same points with these weights, one per point.
    pub fn with_weights(mut self, weights: &'a [f64]) -> Self {
        self.weights = Some(weights);
        self
    }

    /// One normal and one weight per point, when given.
    pub(super) fn check_lengths(&self) -> Result<()> {
        let n = self.xyz.len();
        let rows = [
            ("normals", self.normals.map(|c| c.len())),
            ("weights", self.weights.map(<[f64]>::len)),
        ];
        for (what, len) in rows {
            if let Some(m) = len.filter(|&m| m != n) {
                return Err(Error::usage(format!(
                    "points: expected one of the {what} per point ({n}), found {m}"
                )));
            }
        }
        Ok(())
    }
}
