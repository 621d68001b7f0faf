//! The degeneracy detector: information matrix `H` and point-displacement metric
//! `M` in one streaming pass, the generalized eigenproblem `H v = lambda M v` for
//! every metric family, the degenerate subspace reported as screws, the per-axis
//! footprint, transport of a report between body frames and the remapping
//! projector (paper, sections III-V).
//!
//! # Conventions (those of [`crate::geometry::se3`])
//!
//! - Twist `xi = [omega; t]`, rotation first; right (body) perturbation.
//! - `J_i = [-[p_i]x, I3]`, `a_i = J_i^T n_i = [p_i x n_i; n_i]`.
//! - `H = sum_i w_i a_i a_i^T`, `M = sum_i w_i J_i^T J_i`.
//! - `A = Ad(T) = [[R, 0], [[d]x R, R]]`, `xi = A xi'`; re-expression into the
//!   frame `T = (R, d)`: `p~ = R^T (p - d)`, `n~ = R^T n`; then `H' = A^T H A`,
//!   `M' = A^T M A`.
//!
//! # `M` from moments
//!
//! `J = [-[p]x, I3]`, so `J^T` stacks `-[p]x^T = [p]x` over `I3` and
//! `J^T J = [[-[p]x [p]x, [p]x], [-[p]x, I3]]`, with `-[p]x [p]x = |p|^2 I - p p^T`.
//! Summing with weights, with `W = sum w`, `s = sum w p`, `S = sum w p p^T`:
//! `M = [[tr(S) I - S, [s]x], [-[s]x, W I]]` (tested against the per-point sum).

#![allow(clippy::needless_range_loop)] // index loops mirror the maths and the lane layout

mod accumulate;
mod analysis;
mod cells;
mod classify;
mod eigen;
mod grid;
pub mod normals;
pub mod pairs;
pub mod points;
mod rules;
pub mod scene;
mod share;
mod subspace;
mod sweep;
mod sym3;
pub mod threshold;
mod transport;

pub use accumulate::*;
pub use analysis::*;
pub use classify::*;
pub use eigen::*;
pub use rules::*;
pub use share::*;
pub use subspace::*;
pub use sweep::*;
pub use transport::*;
