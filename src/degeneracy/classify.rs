//! The degenerate subspace of real scans read with tolerances relative to the
//! cloud (issue 16): rotations and translations are compared at the cloud's
//! RMS radius `L` about its centroid ([`Assembly::rms_radius`]), so that a
//! translation with a trace of rotation from noisy normals is reported as a
//! translation and a rotation about an axis through the cloud as zero pitch,
//! whatever the frame and the length unit.
//!
//! About the centroid, a basis twist `[omega; t]` is scaled to `[L omega; t]`
//! (a rotation by `|omega|` moves points at distance `L` by `L |omega|`), the
//! scaled span is split by the singular values of its rotational block as in
//! [`canonical_basis_scored`]: a unit direction whose rotational part has norm
//! (its rotation fraction, in `[0, 1]`) at or below
//! [`ROTATION_FRACTION_TOL`] (0.3) is a translation. The rotational twists are
//! zero-pitch when `|pitch| <= SCREW_PITCH_REL_TOL * L`. The twists are then
//! moved back to the frame (`v = Ad(I, c) v_c`), so axis points are in the
//! frame's coordinates; pitch and kind do not depend on the frame.

use super::accumulate::Assembly;
use super::analysis::Analysis;
use super::subspace::{canonical_basis_scored, TwistScrew};
use crate::tolerances::{FOOTPRINT_SCORE_TOL, ROTATION_FRACTION_TOL, SCREW_PITCH_REL_TOL};
use nalgebra::Vector6;

/// One basis twist of the degenerate subspace, classified.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScoredScrew {
    /// `v^T H v / v^T M v` under the point-displacement metric.
    pub rayleigh: f64,
    /// The twist (in the frame) read as a screw, with the relative kind.
    pub screw: TwistScrew,
    /// Rotation fraction `L |omega| / |[L omega; t]|` of the direction it came
    /// from, about the centroid (0: a translation, 1: a rotation about the
    /// centroid).
    pub rotation_fraction: f64,
}

/// The point-displacement analysis' degenerate subspace as classified screws
/// (rotations first, then translations).
pub fn classify_subspace(asm: &Assembly, an: &Analysis) -> Vec<ScoredScrew> {
    let l = asm.rms_radius();
    let a = asm.center_adjoint();
    // Ad(I, c)^-1 = Ad(I, -c).
    let mut ai = a;
    ai.fixed_view_mut::<3, 3>(3, 0).neg_mut();
    let len = if l > 0.0 { l } else { 1.0 };
    let scaled: Vec<Vector6<f64>> = an
        .degenerate_vectors()
        .iter()
        .map(|v| {
            let mut u = ai * v;
            u.fixed_rows_mut::<3>(0).scale_mut(len);
            u
        })
        .collect();
    canonical_basis_scored(&scaled, ROTATION_FRACTION_TOL)
        .into_iter()
        .map(|(u, frac)| {
            let mut vc = u;
            vc.fixed_rows_mut::<3>(0).scale_mut(1.0 / len);
            // Rotations with |omega| = 1 (rad), as the tunnel's canonical basis.
            let w = vc.fixed_rows::<3>(0).norm();
            if w > 0.0 {
                vc /= w;
            }
            let rayleigh =
                (vc.transpose() * asm.hc * vc)[(0, 0)] / (vc.transpose() * asm.mc * vc)[(0, 0)];
            let v = a * vc;
            let mut screw = TwistScrew::from_twist(&v);
            if let Some(p) = screw.pitch {
                screw.kind = if p.abs() <= SCREW_PITCH_REL_TOL * len {
                    "zero_pitch"
                } else {
                    "general"
                };
            }
            ScoredScrew {
                rayleigh,
                screw,
                // A singular value of an orthonormal basis block: <= 1 up to rounding.
                rotation_fraction: frac.clamp(0.0, 1.0),
            }
        })
        .collect()
}

/// Footprint flags from scores: an axis is flagged when its score is at least
/// `FOOTPRINT_SCORE_TOL`.
pub fn footprint_flags(scores: &[f64; 6]) -> [bool; 6] {
    scores.map(|s| s >= FOOTPRINT_SCORE_TOL)
}
