//! The paper's per-pair frame sweep: frame changes in five arms and the change rates of every reported quantity.

#![allow(clippy::needless_range_loop)] // index loops mirror the maths and the lane layout

use super::accumulate::Assembly;
use super::analysis::{analyse, Analysis};
use super::rules::MetricRule;
use crate::diagnostic::{Error, Result};
use crate::geometry::se3::Transform;
use nalgebra::{Matrix3, Matrix6, Vector3};

// ---------------------------------------------------------------------------
// The paper's per-pair frame sweep
// ---------------------------------------------------------------------------

/// Arm of the per-pair frame sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Arm {
    /// `A = I6`: the reference frame itself (one change).
    Identity,
    /// `Ad(T)` of a uniform random rotation with `d = 0`.
    PureRotation,
    /// `Ad(T)` of `R = I` and a random direction of `d` at each lever arm.
    PureTranslation,
    /// `Ad(T)` of a random rotation and a random direction of `d` at each
    /// lever arm.
    General,
    /// `A` a random orthogonal 6x6 matrix, not an adjoint.
    OrthogonalControl,
}

impl Arm {
    /// Label in tables and reports (`identity`, `pure rotation`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Arm::Identity => "identity",
            Arm::PureRotation => "pure rotation",
            Arm::PureTranslation => "pure translation",
            Arm::General => "general",
            Arm::OrthogonalControl => "orthogonal control",
        }
    }
}

/// One frame change of the sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameChange {
    /// Which arm of the sweep the change belongs to.
    pub arm: Arm,
    /// `||d||` (m); 0 for identity and pure rotation. For the orthogonal
    /// control (no `d`) it is only the magnitude slot the draw was filed under.
    pub magnitude: f64,
    /// `Ad(T)` or the orthogonal control matrix.
    pub a: Matrix6<f64>,
}

/// The fourteen lever arms (m) of the sweep, 0 to 20 m (the paper gives the
/// range and the count, not the values; these include the tabulated 0.1, 0.5,
/// 1 and 20 m).
pub const SWEEP_MAGNITUDES: [f64; 14] = [
    0.0, 0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0, 5.0, 10.0, 15.0, 20.0,
];

/// The paper's 861 frame changes: identity, 20 pure rotations, and 3 arms (pure
/// translation, general, orthogonal control) x 14 magnitudes x 20 draws;
/// seeded (PCG64, see `scene::SceneRng`).
pub fn paper_frame_changes(seed: u64) -> Vec<FrameChange> {
    let mut rng = crate::degeneracy::scene::SceneRng::new(seed);
    let mut out = Vec::with_capacity(861);
    out.push(FrameChange {
        arm: Arm::Identity,
        magnitude: 0.0,
        a: Matrix6::identity(),
    });
    for _ in 0..20 {
        let r = rng.rotation();
        let t = Transform::from_parts_unchecked(r, Vector3::zeros());
        out.push(FrameChange {
            arm: Arm::PureRotation,
            magnitude: 0.0,
            a: t.adjoint(),
        });
    }
    for arm in [Arm::PureTranslation, Arm::General, Arm::OrthogonalControl] {
        for &mag in &SWEEP_MAGNITUDES {
            for _ in 0..20 {
                let a = match arm {
                    Arm::PureTranslation => {
                        let d = rng.unit_vector() * mag;
                        Transform::from_parts_unchecked(Matrix3::identity(), d).adjoint()
                    }
                    Arm::General => {
                        let d = rng.unit_vector() * mag;
                        Transform::from_parts_unchecked(rng.rotation(), d).adjoint()
                    }
                    _ => rng.orthogonal6(),
                };
                out.push(FrameChange {
                    arm,
                    magnitude: mag,
                    a,
                });
            }
        }
    }
    out
}

/// Outcome of the sweep for one metric configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepRow {
    /// The metric configuration swept.
    pub rule: MetricRule,
    /// Its degeneracy threshold on the generalized eigenvalues.
    pub tau: f64,
    /// Frame changes whose binary decision (any `lambda < tau`) differs from the
    /// reference frame's.
    pub decision_changes: usize,
    /// Frame changes whose degenerate count differs.
    pub count_changes: usize,
    /// Decision changes per arm, in [`Arm::ALL`] order.
    pub decision_changes_by_arm: [usize; 5],
    /// Largest relative eigenvalue change per arm, in [`Arm::ALL`] order (each
    /// eigenvalue relative to itself, floored at 1e-12 of the largest).
    pub max_eigenvalue_change_by_arm: [f64; 5],
    /// Largest relative eigenvalue change over the whole sweep.
    pub max_eigenvalue_change: f64,
    /// Frame changes evaluated (the length of the sweep).
    pub evaluations: usize,
}

impl Arm {
    /// The five arms in the order of the per-arm arrays of `SweepRow`.
    pub const ALL: [Arm; 5] = [
        Arm::Identity,
        Arm::PureRotation,
        Arm::PureTranslation,
        Arm::General,
        Arm::OrthogonalControl,
    ];
    fn index(self) -> usize {
        match self {
            Arm::Identity => 0,
            Arm::PureRotation => 1,
            Arm::PureTranslation => 2,
            Arm::General => 3,
            Arm::OrthogonalControl => 4,
        }
    }
}

/// Apply every frame change to one assembly (`H' = A^T H A`, `M' = A^T M A`;
/// each rule then assigns its metric to the new data) and count decision
/// changes per rule, each rule with its own threshold (`taus[k]` for
/// `rules[k]`). Constant metrics stay the same matrix in every frame.
pub fn frame_sweep(
    asm: &Assembly,
    changes: &[FrameChange],
    rules: &[MetricRule],
    taus: &[f64],
) -> Result<Vec<SweepRow>> {
    if taus.len() != rules.len() {
        return Err(Error::usage(format!(
            "frame sweep: expected one threshold per rule, found {} rules and {} thresholds",
            rules.len(),
            taus.len()
        )));
    }
    let refs: Vec<Analysis> = rules
        .iter()
        .zip(taus)
        .map(|(r, &t)| analyse(asm, r, t))
        .collect::<Result<_>>()?;
    let mut rows: Vec<SweepRow> = rules
        .iter()
        .zip(taus)
        .map(|(r, &t)| SweepRow {
            rule: r.clone(),
            tau: t,
            decision_changes: 0,
            count_changes: 0,
            decision_changes_by_arm: [0; 5],
            max_eigenvalue_change_by_arm: [0.0; 5],
            max_eigenvalue_change: 0.0,
            evaluations: 0,
        })
        .collect();
    for ch in changes {
        let moved = asm.congruence(&ch.a);
        let arm = ch.arm.index();
        for (k, rule) in rules.iter().enumerate() {
            let an = analyse(&moved, rule, taus[k])?;
            let row = &mut rows[k];
            row.evaluations += 1;
            if an.degenerate() != refs[k].degenerate() {
                row.decision_changes += 1;
                row.decision_changes_by_arm[arm] += 1;
            }
            if an.degenerate_count != refs[k].degenerate_count {
                row.count_changes += 1;
            }
            // Relative to each eigenvalue, floored at 1e-12 of the largest so
            // that exact zeros compare absolutely.
            let floor = 1e-12 * refs[k].eig.values[5].abs();
            let d = an
                .eig
                .values
                .iter()
                .zip(refs[k].eig.values.iter())
                .map(|(x, y)| (x - y).abs() / y.abs().max(floor).max(f64::MIN_POSITIVE))
                .fold(0.0, f64::max);
            row.max_eigenvalue_change = row.max_eigenvalue_change.max(d);
            row.max_eigenvalue_change_by_arm[arm] = row.max_eigenvalue_change_by_arm[arm].max(d);
        }
    }
    Ok(rows)
}
