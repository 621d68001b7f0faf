//! The detector families, one entry each in [`FAMILIES`]: the metric rule
//! `M(D)` each implies for `H v = lambda M v`, its names, whether the rule is
//! equivariant, and the threshold calibrated on the synthetic corridors
//! (`audit calibrate-threshold`; setup in `degeneracy::threshold`).
//!
//! Adding a family: a [`Family`] variant, its row in [`FAMILIES`] and its
//! place in [`Family::ALL`]; its verdict in `analysis::metric::family_verdicts`;
//! its `degeneracy::MetricRule`, with its metric and its place in
//! `MetricRule::default_set` (the compiler flags every `match`). The rest of
//! the code takes the families from these; docs/ARCHITECTURE.md lists what
//! follows outside the code (schemas, references, snapshots).

use serde::Serialize;

/// The detector families, by the metric rule each implies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Family {
    /// `I6`.
    Unnormalized,
    /// `diag(l^2 I3, I3)` for a fixed `l`.
    CharacteristicLength,
    /// Same family, `l` from `H` (see `analysis::metric::block_scaling_ell`).
    BlockScaling,
    /// `diag(H)`.
    Jacobi,
    /// `M0 = Ad(P)^-T Ad(P)^-1`, built for one zero-pitch rig.
    AdaptedConstant,
    /// `M = sum_i J_i^T J_i`.
    PointDisplacement,
}

/// A threshold calibrated on the synthetic corridors (see
/// `degeneracy::threshold::default_threshold`): per point (`lambda / sum w`)
/// for the families marked [`FamilySpec::per_point`], on the eigenvalues as
/// they are for the others.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Calibrated {
    /// One value.
    Fixed(f64),
    /// Per characteristic length `(l in m, threshold)`; other lengths use the
    /// user's `tau`.
    PerEll(&'static [(f64, f64)]),
    /// The user's `tau` (dimensionless families).
    Tau,
}

/// One row of the family table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FamilySpec {
    /// The family.
    pub family: Family,
    /// The JSON name (`point_displacement`).
    pub name: &'static str,
    /// The family's one name in text, markdown and help (`point
    /// displacement`): the JSON name's words.
    pub label: &'static str,
    /// Its metric, for documentation (`sum J^T J`, `diag(l^2 I, I)`).
    pub formula: &'static str,
    /// Whether the rule transforms by the same congruence as `H`.
    pub equivariant: bool,
    /// Its calibrated threshold.
    pub calibrated: Calibrated,
    /// Whether its eigenvalues add up over points, so that thresholds compare
    /// them per point (`lambda / sum w`; see `degeneracy::threshold`).
    pub per_point: bool,
}

/// The family table, in report order.
pub const FAMILIES: [FamilySpec; Family::ALL.len()] = [
    FamilySpec {
        family: Family::Unnormalized,
        name: "unnormalized",
        label: "unnormalized",
        formula: "I6",
        equivariant: false,
        per_point: true,
        calibrated: Calibrated::Fixed(0.04582),
    },
    FamilySpec {
        family: Family::CharacteristicLength,
        name: "characteristic_length",
        label: "characteristic length",
        formula: "diag(l^2 I, I)",
        equivariant: false,
        per_point: true,
        calibrated: Calibrated::PerEll(&[
            (0.25, 0.02157),
            (1.0, 0.04582),
            (2.85, 0.01462),
            (10.0, 0.001202),
        ]),
    },
    FamilySpec {
        family: Family::BlockScaling,
        name: "block_scaling",
        label: "block scaling",
        formula: "diag(l^2 I, I), l from H",
        equivariant: false,
        per_point: true,
        calibrated: Calibrated::Fixed(0.01221),
    },
    FamilySpec {
        family: Family::Jacobi,
        name: "jacobi",
        label: "Jacobi",
        formula: "diag(H)",
        equivariant: false,
        // diag(H) grows with H: count-free.
        per_point: false,
        calibrated: Calibrated::Fixed(0.8619),
    },
    FamilySpec {
        family: Family::AdaptedConstant,
        name: "adapted_constant",
        label: "adapted constant",
        formula: "M0",
        equivariant: false,
        per_point: true,
        // Same scale as I6 (a constant metric near the identity).
        calibrated: Calibrated::Fixed(0.04582),
    },
    FamilySpec {
        family: Family::PointDisplacement,
        name: "point_displacement",
        label: "point displacement",
        formula: "sum J^T J",
        equivariant: true,
        // sum J^T J grows with H: count-free.
        per_point: false,
        calibrated: Calibrated::Tau,
    },
];

impl Family {
    /// Every family, in report order.
    pub const ALL: [Family; 6] = [
        Family::Unnormalized,
        Family::CharacteristicLength,
        Family::BlockScaling,
        Family::Jacobi,
        Family::AdaptedConstant,
        Family::PointDisplacement,
    ];

    /// Its row of `FAMILIES`.
    pub fn spec(self) -> &'static FamilySpec {
        // FAMILIES lists the variants in declaration order.
        &FAMILIES[self as usize]
    }
    /// The JSON name.
    pub fn name(self) -> &'static str {
        self.spec().name
    }
    /// The name reports print.
    pub fn label(self) -> &'static str {
        self.spec().label
    }
    /// Only the point-displacement rule transforms by the same congruence as `H`.
    pub fn is_equivariant_rule(self) -> bool {
        self.spec().equivariant
    }
    /// The calibrated threshold for characteristic length `ell` (ignored by
    /// the other families), or `tau` where none is calibrated.
    pub fn calibrated_threshold(self, ell: Option<f64>, tau: f64) -> f64 {
        match (self.spec().calibrated, ell) {
            (Calibrated::Fixed(t), _) => t,
            (Calibrated::PerEll(table), Some(l)) => table
                .iter()
                .find(|(x, _)| (x - l).abs() < 1e-12)
                .map_or(tau, |&(_, t)| t),
            (Calibrated::PerEll(_), None) | (Calibrated::Tau, _) => tau,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_in_declaration_order() {
        for (i, f) in Family::ALL.iter().enumerate() {
            assert_eq!(FAMILIES[i].family, *f);
            assert_eq!(f.spec().family, *f);
        }
    }
}
