//! The detector on numpy arrays and on scan files. An `(N, 3)` float64 or
//! float32 array in C order is read in place (rust-numpy's read-only borrow:
//! no copy); the Python layer makes any other layout or dtype contiguous
//! first, so this side refuses rather than copies.

use crate::diag::{json, IntoPy};
use extrinsic_audit::{Coords, Detector, DetectorOptions, Error, Points, ScanFile, Transform};
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use std::path::PathBuf;

/// The detector's keyword arguments (every key passed by the Python layer).
#[derive(Debug, FromPyObject)]
#[pyo3(from_item_all)]
pub struct DetectorArgs {
    pub tau: Option<f64>,
    pub ells: Option<Vec<f64>>,
    /// The pose of the body frame in the points' frame, row-major 4x4.
    pub frame: Option<[[f64; 4]; 4]>,
    pub show_matrices: bool,
    pub voxel: Option<f64>,
    pub radius: Option<f64>,
    pub knn: Option<usize>,
    pub min_neighbours: Option<usize>,
    pub min_planarity: Option<f64>,
    pub viewpoint: Option<[f64; 3]>,
}

impl DetectorArgs {
    fn detector(&self) -> extrinsic_audit::Result<Detector> {
        let mut o = DetectorOptions::default();
        if let Some(tau) = self.tau {
            o.tau = tau;
        }
        if let Some(ells) = &self.ells {
            o.ells = ells.clone();
        }
        if let Some(m) = self.frame {
            let mut ws = Vec::new();
            o.frame = Transform::from_matrix4(m, &mut ws)?;
            if let Some(w) = ws.into_iter().next() {
                return Err(Error::usage(format!("frame: {}", w.message)));
            }
        }
        o.show_matrices = self.show_matrices;
        let n = &mut o.normals;
        n.voxel = self.voxel;
        n.radius = self.radius.unwrap_or(n.radius);
        n.knn = self.knn;
        n.min_neighbours = self.min_neighbours.unwrap_or(n.min_neighbours);
        n.min_planarity = self.min_planarity;
        n.viewpoint = self.viewpoint;
        Detector::new(o)
    }
}

/// A borrowed `(N, 3)` array of either precision.
enum Rows<'py> {
    F64(PyReadonlyArray2<'py, f64>),
    F32(PyReadonlyArray2<'py, f32>),
}

impl<'py> Rows<'py> {
    fn extract(a: &Bound<'py, PyAny>, what: &str) -> PyResult<Rows<'py>> {
        let rows = if let Ok(x) = a.extract::<PyReadonlyArray2<f64>>() {
            Rows::F64(x)
        } else if let Ok(x) = a.extract::<PyReadonlyArray2<f32>>() {
            Rows::F32(x)
        } else {
            return Err(crate::diag::to_py(Error::usage(format!(
                "{what}: expected a 2-D float64 or float32 numpy array"
            ))));
        };
        let (shape, contiguous) = match &rows {
            Rows::F64(x) => (x.shape().to_vec(), x.is_c_contiguous()),
            Rows::F32(x) => (x.shape().to_vec(), x.is_c_contiguous()),
        };
        if shape[1] != 3 || !contiguous {
            return Err(crate::diag::to_py(Error::usage(format!(
                "{what}: expected a C-contiguous (N, 3) array, found shape {shape:?}{}",
                if contiguous { "" } else { ", not C-contiguous" }
            ))));
        }
        Ok(rows)
    }

    /// The rows, in place.
    fn coords(&self) -> Coords<'_> {
        // Both checked C-contiguous with 3 columns: as_slice cannot fail.
        match self {
            Rows::F64(x) => Coords::F64(x.as_slice().unwrap_or(&[]).as_chunks::<3>().0),
            Rows::F32(x) => Coords::F32(x.as_slice().unwrap_or(&[]).as_chunks::<3>().0),
        }
    }
}

/// Every family on points held in numpy arrays: the report's JSON (that of
/// `audit degeneracy --format json`). GIL released while it runs.
#[pyfunction]
#[pyo3(signature = (points, normals, weights, args))]
pub fn degeneracy(
    py: Python<'_>,
    points: &Bound<'_, PyAny>,
    normals: Option<&Bound<'_, PyAny>>,
    weights: Option<PyReadonlyArray1<'_, f64>>,
    args: DetectorArgs,
) -> PyResult<String> {
    let detector = args.detector().py()?;
    let xyz = Rows::extract(points, "points")?;
    let nrm = normals.map(|n| Rows::extract(n, "normals")).transpose()?;
    let w = weights
        .as_ref()
        .map(|w| w.as_slice())
        .transpose()
        .map_err(|_| crate::diag::to_py(Error::usage("weights: expected a contiguous array")))?;
    let mut pts = Points::new(xyz.coords());
    if let Some(n) = &nrm {
        pts = pts.with_normals(n.coords());
    }
    if let Some(w) = w {
        pts = pts.with_weights(w);
    }
    py.detach(|| json(&detector.points(&pts)?, &[])).py()
}

/// Every family on a scan file (`audit degeneracy FILE`): the report's JSON.
#[pyfunction]
#[pyo3(signature = (path, estimate_normals, args))]
pub fn degeneracy_scan(
    py: Python<'_>,
    path: PathBuf,
    estimate_normals: bool,
    args: DetectorArgs,
) -> PyResult<String> {
    let detector = args.detector().py()?;
    let mut scan = ScanFile::new(path);
    scan.estimate_normals = estimate_normals;
    py.detach(|| json(&detector.scan(&scan)?, &[])).py()
}
