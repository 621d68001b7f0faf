//! One family's answer on one data set: eigenvalues, degenerate count, the remapping projector, the footprint and the subspace as screws.

#![allow(clippy::needless_range_loop)] // index loops mirror the maths and the lane layout

use super::accumulate::Assembly;
use super::eigen::{generalized_eigen, GenEigen};
use super::rules::MetricRule;
use super::subspace::{canonical_basis, footprint, TwistScrew};
use crate::diagnostic::Result;
use nalgebra::{Matrix6, Vector6};

// ---------------------------------------------------------------------------
// Analysis / report
// ---------------------------------------------------------------------------

/// One family's answer on one data set.
#[derive(Debug, Clone, PartialEq)]
pub struct Analysis {
    /// The family (and its parameter) that assigned the metric.
    pub rule: MetricRule,
    /// The metric `M` the rule assigned to this data (6x6, twist order
    /// `[omega; t]`, symmetric positive definite).
    pub metric: Matrix6<f64>,
    /// `H v = lambda M v`: eigenvalues ascending, `M`-orthonormal eigenvectors.
    pub eig: GenEigen,
    /// Degeneracy threshold on the normalised eigenvalues `lambda / scale`
    /// (per point for the count-scaling families, see
    /// [`MetricRule::count_scale`]).
    pub tau: f64,
    /// The normaliser: `sum w` or 1 ([`MetricRule::count_scale`]).
    pub scale: f64,
    /// Number of eigenvalues with `lambda / scale < tau` (the first ones).
    pub degenerate_count: usize,
}

/// Solve one family on one assembly.
pub fn analyse(asm: &Assembly, rule: &MetricRule, tau: f64) -> Result<Analysis> {
    let metric = rule.metric(asm)?;
    let eig = if *rule == MetricRule::PointDisplacement {
        // Equivariant: solved about the centroid, where no offset rounds
        // away the small eigenvalues, and the eigenvectors moved back
        // (`v = A v_c`, still `M`-orthonormal since `M = A^-T M_c A^-1`).
        let mut e = generalized_eigen(&asm.hc, &asm.mc, rule.what())?;
        e.vectors = asm.center_adjoint() * e.vectors;
        e
    } else {
        generalized_eigen(&asm.h, &metric, rule.what())?
    };
    let scale = rule.count_scale(asm)?;
    let degenerate_count = eig.values.iter().filter(|&&l| l / scale < tau).count();
    Ok(Analysis {
        rule: rule.clone(),
        metric,
        eig,
        tau,
        scale,
        degenerate_count,
    })
}

impl Analysis {
    /// The threshold on the raw eigenvalues `eig.values`: `tau * scale`.
    pub fn raw_threshold(&self) -> f64 {
        self.tau * self.scale
    }

    /// Whether anything is declared degenerate.
    pub fn degenerate(&self) -> bool {
        self.degenerate_count > 0
    }

    /// The `M`-orthonormal eigenvectors of the degenerate eigenvalues.
    pub fn degenerate_vectors(&self) -> Vec<Vector6<f64>> {
        (0..self.degenerate_count)
            .map(|k| self.eig.vectors.column(k).into_owned())
            .collect()
    }

    /// Remapping projector `P = sum over non-degenerate k of v_k v_k^T M`.
    pub fn projector(&self) -> Matrix6<f64> {
        let mut p = Matrix6::zeros();
        for k in self.degenerate_count..6 {
            let v = self.eig.vectors.column(k);
            p += v * v.transpose();
        }
        p * self.metric
    }

    /// Per-axis footprint (frame-dependent): axis `k` flagged when the `k`-th
    /// diagonal entry of the Euclidean projector onto the degenerate subspace
    /// is at least `tolerances::FOOTPRINT_SCORE_TOL`
    /// (an absolute 1e-6 flagged every axis on noisy data).
    pub fn footprint(&self) -> [bool; 6] {
        footprint(&self.degenerate_vectors())
    }

    /// The degenerate subspace as screws (canonical basis, see
    /// [`canonical_basis`]) with each basis twist's Rayleigh quotient
    /// `v^T H v / v^T M v` under this analysis' metric.
    pub fn subspace_screws(&self, h: &Matrix6<f64>) -> Vec<(f64, TwistScrew)> {
        canonical_basis(&self.degenerate_vectors())
            .into_iter()
            .map(|v| {
                let q = (v.transpose() * h * v)[(0, 0)] / (v.transpose() * self.metric * v)[(0, 0)];
                (q, TwistScrew::from_twist(&v))
            })
            .collect()
    }
}
