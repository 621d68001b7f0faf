//! What the detector is asked for, whatever its input (points in memory, a
//! scan file, later a recorded run): the threshold, the characteristic
//! lengths, the frame `H` and `M` are expressed in, how normals are estimated
//! for points that have none, and whether the report carries the matrices.

use crate::degeneracy::normals::NormalParams;
use crate::diagnostic::{Error, Result};
use crate::geometry::Transform;
use crate::tolerances::{
    DEFAULT_ELLS, DEFAULT_TAU, MAX_ELLS, RAW_MIN_NEIGHBOURS, RAW_NORMAL_RADIUS_M,
};

/// How the detector decides (the options of `audit degeneracy` that do not
/// name its input). `Default` gives the command's defaults.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct DetectorOptions {
    /// Point-displacement threshold (dimensionless, default
    /// [`DEFAULT_TAU`]): an eigenvalue below it is degenerate; the other
    /// families use their calibrated thresholds.
    pub tau: f64,
    /// Characteristic lengths (m) of the characteristic length family
    /// (default [`DEFAULT_ELLS`]).
    pub ells: Vec<f64>,
    /// The frame `H` and `M` are expressed in: its pose `T = (R, d)` in the
    /// input frame, so `p_new = R^T (p - d)` (default the identity).
    pub frame: Transform,
    /// How the normals of points without any are estimated.
    pub normals: NormalOptions,
    /// Add `H` and `M` to the report (`--show-matrices`).
    pub show_matrices: bool,
}

impl Default for DetectorOptions {
    fn default() -> Self {
        DetectorOptions {
            tau: DEFAULT_TAU,
            ells: DEFAULT_ELLS.to_vec(),
            frame: Transform::identity(),
            normals: NormalOptions::default(),
            show_matrices: false,
        }
    }
}

/// How a raw scan (points without normals) gets its normals: an optional
/// voxel grid, then PCA within a radius, oriented toward a viewpoint, all in
/// the input frame. `Default` gives `audit degeneracy --estimate-normals`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct NormalOptions {
    /// Voxel grid edge (m) applied first, one centroid per voxel (`None`:
    /// every point).
    pub voxel: Option<f64>,
    /// Neighbourhood radius (m), default [`RAW_NORMAL_RADIUS_M`].
    pub radius: f64,
    /// At most this many nearest neighbours within the radius.
    pub knn: Option<usize>,
    /// Fewest neighbours (the point counted) for a normal, default
    /// [`RAW_MIN_NEIGHBOURS`].
    pub min_neighbours: usize,
    /// Planarity gate `(l2 - l3) / l1` of a neighbourhood (eigenvalues
    /// descending), 0 to 1.
    pub min_planarity: Option<f64>,
    /// Normals point toward this point (input frame; `None`: the sensor
    /// origin).
    pub viewpoint: Option<[f64; 3]>,
}

impl Default for NormalOptions {
    fn default() -> Self {
        NormalOptions {
            voxel: None,
            radius: RAW_NORMAL_RADIUS_M,
            knn: None,
            min_neighbours: RAW_MIN_NEIGHBOURS,
            min_planarity: None,
            viewpoint: None,
        }
    }
}

impl NormalOptions {
    /// The estimation's parameters (the viewpoint defaults to the sensor
    /// origin); the voxel grid is applied before, by the caller.
    pub(crate) fn params(&self) -> NormalParams {
        NormalParams {
            radius: self.radius,
            knn: self.knn,
            min_neighbours: self.min_neighbours,
            min_planarity: self.min_planarity,
            viewpoint: self.viewpoint.unwrap_or([0.0; 3]),
        }
    }

    /// Whether any option of the estimation is set (they apply only to points
    /// without normals).
    pub(crate) fn estimation_asked(&self) -> bool {
        self.voxel.is_some() || self.viewpoint.is_some() || self.knn.is_some()
    }
}

/// The detector's numbers, checked once for every entry point (the
/// detector, the run reader): a positive finite `tau`, 1 to [`MAX_ELLS`]
/// finite positive lengths.
pub(crate) fn check_tau_ells(tau: f64, ells: &[f64]) -> Result<()> {
    if !(tau.is_finite() && tau > 0.0) {
        return Err(Error::usage(format!(
            "tau: expected a positive number, found {tau}"
        )));
    }
    if ells.is_empty() || ells.len() > MAX_ELLS || ells.iter().any(|l| !(l.is_finite() && *l > 0.0))
    {
        return Err(Error::usage(format!(
            "ells: expected 1 to {MAX_ELLS} positive lengths (m), found {ells:?}"
        )));
    }
    Ok(())
}
