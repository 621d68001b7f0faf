//! `load` and the `Robot` it gives: frames, transforms (4x4 numpy arrays),
//! rig reports and the frame tree.

use crate::diag::{json, pitch_tol, tuples, DiagTuple, IntoPy, LoadArgs};
use extrinsic_audit::{RigOptions, Robot, Transform, UserSigma};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use std::path::PathBuf;

/// A robot's frames loaded from its files into one tree.
#[pyclass(name = "Robot", module = "extrinsic_audit._native", frozen)]
pub struct PyRobot {
    robot: Robot,
}

/// Load `paths` into one frame tree (GIL released while the files are read).
#[pyfunction]
pub fn load(py: Python<'_>, paths: Vec<PathBuf>, load: LoadArgs) -> PyResult<PyRobot> {
    let opts = load.options().py()?;
    let robot = py.detach(|| Robot::load(&paths, &opts)).py()?;
    Ok(PyRobot { robot })
}

/// `t` as a row-major 4x4 numpy array.
pub fn matrix<'py>(py: Python<'py>, t: &Transform) -> Bound<'py, PyArray2<f64>> {
    let m = t.matrix4();
    Array2::from_shape_fn((4, 4), |(i, j)| m[(i, j)]).into_pyarray(py)
}

#[pymethods]
impl PyRobot {
    /// Every frame, sorted.
    fn frames(&self) -> Vec<String> {
        self.robot.frames()
    }

    /// The movable joints' names.
    fn joints(&self) -> Vec<String> {
        self.robot.joints()
    }

    /// The warnings the files gave.
    fn warnings(&self) -> Vec<DiagTuple> {
        tuples(self.robot.warnings())
    }

    /// Notes on how the files were read.
    fn notes(&self) -> Vec<String> {
        self.robot.notes().to_vec()
    }

    /// The frame pair to report (both given, a rig file's pair, the only edge).
    #[pyo3(signature = (frm=None, to=None))]
    fn frame_pair(&self, frm: Option<&str>, to: Option<&str>) -> PyResult<(String, String)> {
        self.robot.frame_pair(frm, to).py()
    }

    /// The pose of `to` in `frm` as a 4x4 array, with the chain's warnings.
    fn transform<'py>(
        &self,
        py: Python<'py>,
        frm: &str,
        to: &str,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Vec<DiagTuple>)> {
        let chain = self.robot.chain(frm, to).py()?;
        Ok((matrix(py, &chain.transform), tuples(&chain.warnings)))
    }

    /// The rig report's JSON (the CLI's, the robot's warnings and the
    /// chain's in it) and the chain's warnings; GIL released.
    #[pyo3(signature = (frm, to, ells, pitch_tol=None, kappa_lambda=None, sigma=None))]
    #[allow(clippy::too_many_arguments)]
    fn report(
        &self,
        py: Python<'_>,
        frm: &str,
        to: &str,
        ells: Option<Vec<f64>>,
        pitch_tol: Option<&str>,
        kappa_lambda: Option<(f64, f64)>,
        sigma: Option<(f64, f64)>,
    ) -> PyResult<(String, Vec<DiagTuple>)> {
        let mut opts = RigOptions::default();
        if let Some(ells) = ells {
            opts.ells = ells;
        }
        opts.pitch_tol = self::pitch_tol(pitch_tol).py()?;
        opts.kappa_lambda = kappa_lambda;
        opts.sigma = sigma.map(|(t, r)| UserSigma::new(t, r)).transpose().py()?;
        let robot = &self.robot;
        py.detach(|| {
            let (report, chain_warnings) = robot.report(frm, to, &opts)?;
            let all: Vec<_> = robot
                .warnings()
                .iter()
                .chain(&chain_warnings)
                .cloned()
                .collect();
            Ok((json(&report, &all)?, tuples(&chain_warnings)))
        })
        .py()
    }

    /// The frame tree's JSON (`audit FILES --frames --format json`), the
    /// `frm` -> `to` chain highlighted when both are given.
    #[pyo3(signature = (frm=None, to=None))]
    fn frame_tree(&self, frm: Option<&str>, to: Option<&str>) -> PyResult<String> {
        let chain = match (frm, to) {
            (Some(a), Some(b)) => Some(self.robot.chain(a, b).py()?),
            _ => None,
        };
        json(
            &self.robot.frame_tree(chain.as_ref()),
            self.robot.warnings(),
        )
        .py()
    }
}
