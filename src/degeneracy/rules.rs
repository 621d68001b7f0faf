//! Metric rules: one family with its parameter (a characteristic length, an adapted matrix) and the metric it assigns to data.

#![allow(clippy::needless_range_loop)] // index loops mirror the maths and the lane layout

use super::accumulate::Assembly;
use crate::analysis::metric::{block_scaling_ell, Family};
use crate::diagnostic::{Error, Result};
use crate::tolerances::{DEFAULT_ELLS, JACOBI_FLOOR};
use nalgebra::{Matrix6, Vector6};

// ---------------------------------------------------------------------------
// Metric rules
// ---------------------------------------------------------------------------

/// One metric configuration: a family and its parameter.
#[derive(Debug, Clone, PartialEq)]
pub enum MetricRule {
    /// `I6`.
    Unnormalized,
    /// `diag(l^2 I3, I3)` with the given `l` (m).
    CharacteristicLength(f64),
    /// `diag(l^2 I3, I3)`, `l^2 = tr(H_rr) / tr(H_tt)` (`block_scaling_ell`).
    BlockScaling,
    /// `diag(H)` (floored, see `JACOBI_FLOOR`).
    Jacobi,
    /// A constant metric adapted to one rig (`metric::adapted_metric_matrix`).
    AdaptedConstant(Box<Matrix6<f64>>),
    /// `M = sum w J^T J`.
    PointDisplacement,
}

impl MetricRule {
    /// The detector family this rule belongs to (the parameter dropped).
    pub fn family(&self) -> Family {
        match self {
            MetricRule::Unnormalized => Family::Unnormalized,
            MetricRule::CharacteristicLength(_) => Family::CharacteristicLength,
            MetricRule::BlockScaling => Family::BlockScaling,
            MetricRule::Jacobi => Family::Jacobi,
            MetricRule::AdaptedConstant(_) => Family::AdaptedConstant,
            MetricRule::PointDisplacement => Family::PointDisplacement,
        }
    }

    /// The family's name (the family table's), with `l` for a
    /// characteristic length: `unnormalized`, `characteristic length l=2.85`.
    pub fn label(&self) -> String {
        match self {
            MetricRule::CharacteristicLength(l) => format!("{} l={l}", self.family().label()),
            _ => self.family().label().to_string(),
        }
    }

    /// Whether the rule is equivariant (the family table says).
    pub fn equivariant(&self) -> bool {
        self.family().is_equivariant_rule()
    }

    /// The fixed characteristic length (m) of a characteristic-length rule.
    pub fn fixed_ell(&self) -> Option<f64> {
        match self {
            MetricRule::CharacteristicLength(l) => Some(*l),
            _ => None,
        }
    }

    /// What the eigenvalues are divided by before the threshold compares them
    /// (see `degeneracy::threshold`, "Thresholds that transfer"): `sum w` (the
    /// point count with unit weights) for the families whose metric does not
    /// grow with the data (I6, characteristic length, block scaling, adapted
    /// constant: their eigenvalues add up over points), 1 for the families
    /// whose metric grows with `H` (Jacobi `diag(H)`, point displacement
    /// `sum w J^T J`: their eigenvalues are already count-free).
    pub fn count_scale(&self, asm: &Assembly) -> Result<f64> {
        if !self.family().spec().per_point {
            return Ok(1.0);
        }
        let w = asm.weight_sum;
        if !(w.is_finite() && w > 0.0) {
            return Err(Error::invalid(format!(
                "{} threshold: expected a positive sum of weights to normalise the eigenvalues per point, found {w}",
                self.what()
            )));
        }
        Ok(w)
    }

    /// `l` used (fixed, or from `H` for block scaling).
    pub fn ell(&self, asm: &Assembly) -> Option<f64> {
        match self {
            MetricRule::CharacteristicLength(l) => Some(*l),
            MetricRule::BlockScaling => Some(block_scaling_ell(&asm.h)),
            _ => None,
        }
    }

    /// The metric this rule assigns to the data.
    pub fn metric(&self, asm: &Assembly) -> Result<Matrix6<f64>> {
        let diag_ell = |l: f64| {
            let l2 = l * l;
            Matrix6::from_diagonal(&Vector6::new(l2, l2, l2, 1.0, 1.0, 1.0))
        };
        match self {
            MetricRule::Unnormalized => Ok(Matrix6::identity()),
            MetricRule::CharacteristicLength(l) => {
                if !(l.is_finite() && *l > 0.0) {
                    return Err(Error::usage(format!(
                        "characteristic length: expected a positive number of metres, found {l}"
                    )));
                }
                Ok(diag_ell(*l))
            }
            MetricRule::BlockScaling => {
                let l = block_scaling_ell(&asm.h);
                if !(l.is_finite() && l > 0.0) {
                    return Err(Error::invalid(format!(
                        "block scaling: l^2 = tr(H_rr)/tr(H_tt) is not a positive finite number (l = {l}); the data constrain no rotation or no translation at all"
                    )));
                }
                Ok(diag_ell(l))
            }
            MetricRule::Jacobi => {
                let mx = (0..6).map(|k| asm.h[(k, k)]).fold(0.0f64, f64::max);
                if mx.is_nan() || mx <= 0.0 {
                    return Err(Error::invalid(
                        "Jacobi metric: H has no positive diagonal entry",
                    ));
                }
                let floor = JACOBI_FLOOR * mx;
                Ok(Matrix6::from_diagonal(&Vector6::from_fn(|k, _| {
                    asm.h[(k, k)].max(floor)
                })))
            }
            MetricRule::AdaptedConstant(m0) => Ok(**m0),
            MetricRule::PointDisplacement => Ok(asm.m),
        }
    }

    /// The paper's eight configurations: I6, l = 0.25, 1, 2.85, 10, block
    /// scaling, Jacobi, point displacement (the default set at the default
    /// lengths).
    pub fn paper_configs() -> Vec<MetricRule> {
        Self::default_set(&DEFAULT_ELLS, None)
    }

    /// The families reported by default, in the family table's order: one
    /// rule per family, `ells` for the characteristic length, and the adapted
    /// constant metric only when `adapted` gives a rig's. Every command that
    /// runs several families takes them from here, so a new family is added
    /// to them all in this one place (with its `match` arms above).
    pub fn default_set(ells: &[f64], adapted: Option<Matrix6<f64>>) -> Vec<MetricRule> {
        let mut v = Vec::new();
        for family in Family::ALL {
            match family {
                Family::Unnormalized => v.push(MetricRule::Unnormalized),
                Family::CharacteristicLength => {
                    v.extend(ells.iter().map(|&l| MetricRule::CharacteristicLength(l)));
                }
                Family::BlockScaling => v.push(MetricRule::BlockScaling),
                Family::Jacobi => v.push(MetricRule::Jacobi),
                Family::AdaptedConstant => {
                    v.extend(adapted.map(|m0| MetricRule::AdaptedConstant(Box::new(m0))));
                }
                Family::PointDisplacement => v.push(MetricRule::PointDisplacement),
            }
        }
        v
    }

    pub(crate) fn what(&self) -> &'static str {
        self.family().label()
    }
}
