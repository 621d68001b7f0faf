//! Scan pairs: `H` and `M` from correspondences, as point-to-plane ICP
//! evaluates them (issue 16).
//!
//! Each source point `p` (source frame) is moved by the initial guess
//! `T = (R, d)`, the pose of the source frame in the target frame
//! (`q = R p + d`), and paired with its nearest target point `t` when
//! `|q - t| <= gate`. The residual is `r = n_t . (T exp(xi) p - t)` with the
//! target normal `n_t`; with the right (body) perturbation of the source pose,
//! `dr/dxi = n_t^T R [-[p]x, I] = a^T` with `a = [p x n; n]`, `n = R^T n_t`.
//! So the pair assembles exactly as one cloud of the source points carrying
//! the target normals rotated into the source frame, and `M` is the
//! point-displacement metric of the matched source points: the twist is the
//! source pose's, in the source frame. The source's per-point weights, when
//! it has them, weight its pairs (`H = sum w a a^T`, `M = sum w J^T J`), as
//! in the single-cloud path.

use super::scene::Cloud;
use super::Assembly;
use crate::diagnostic::{Error, Result};
use crate::geometry::Transform;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use nalgebra::Vector3;

/// What the correspondence search found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairStats {
    /// Source points searched.
    pub source: usize,
    /// Target points (with normals).
    pub target: usize,
    /// Source points with a target point within the gate.
    pub matched: usize,
    /// Mean distance of the matched pairs (m).
    pub mean_distance: f64,
}

/// The matched source points with the target normals in the source frame.
pub fn correspondences(
    source: &[[f64; 3]],
    target: &Cloud,
    guess: &Transform,
    gate: f64,
) -> Result<(Cloud, PairStats)> {
    matches(source, target, guess, gate).map(|(c, _, st)| (c, st))
}

/// [`correspondences`] with the index in `source` of each matched point.
fn matches(
    source: &[[f64; 3]],
    target: &Cloud,
    guess: &Transform,
    gate: f64,
) -> Result<(Cloud, Vec<usize>, PairStats)> {
    if !(gate.is_finite() && gate > 0.0) {
        return Err(Error::usage(format!(
            "--gate: expected a positive number of metres, found {gate}"
        )));
    }
    let mut out = Cloud::default();
    let mut stats = PairStats {
        source: source.len(),
        target: target.len(),
        matched: 0,
        mean_distance: 0.0,
    };
    let mut index = Vec::new();
    if target.is_empty() || source.is_empty() {
        return Ok((out, index, stats));
    }
    let tree = ImmutableKdTree::<f64, 3>::new_from_slice(&target.points)
        .map_err(|e| Error::invalid(format!("target: cannot index the points ({e})")))?;
    let r = guess.rotation();
    let d = guess.translation();
    let mut dsum = 0.0;
    for (i, p) in source.iter().enumerate() {
        let q = r * Vector3::from(*p) + d;
        let nb = tree
            .query(&[q.x, q.y, q.z])
            .nearest_one::<SquaredEuclidean<f64>>()
            .execute();
        // A NaN distance (never for finite points) counts as unmatched.
        if nb.distance.is_nan() || nb.distance > gate * gate {
            continue;
        }
        let Some(nt) = target.normals.get(nb.item as usize) else {
            continue;
        };
        let n = r.transpose() * Vector3::from(*nt);
        out.points.push(*p);
        out.normals.push([n.x, n.y, n.z]);
        index.push(i);
        dsum += nb.distance.sqrt();
    }
    stats.matched = out.len();
    if stats.matched > 0 {
        stats.mean_distance = dsum / stats.matched as f64;
    }
    Ok((out, index, stats))
}

/// The matched source points with the target normals in the source frame
/// (what [`pair_assembly_weighted`] assembles) and their source weights.
pub fn matched_weighted(
    source: &[[f64; 3]],
    weights: Option<&[f64]>,
    target: &Cloud,
    guess: &Transform,
    gate: f64,
) -> Result<(Cloud, Option<Vec<f64>>)> {
    matched_stats(source, weights, target, guess, gate).map(|(c, w, _)| (c, w))
}

/// [`matched_weighted`] with the search's statistics.
fn matched_stats(
    source: &[[f64; 3]],
    weights: Option<&[f64]>,
    target: &Cloud,
    guess: &Transform,
    gate: f64,
) -> Result<(Cloud, Option<Vec<f64>>, PairStats)> {
    let (c, index, st) = matches(source, target, guess, gate)?;
    let w: Option<Vec<f64>> = weights.map(|w| {
        index
            .iter()
            .map(|&i| w.get(i).copied().unwrap_or(1.0))
            .collect()
    });
    Ok((c, w, st))
}

/// `H` and `M` of a pair (see the module notes); an error without any
/// correspondence.
pub fn pair_assembly(
    source: &[[f64; 3]],
    target: &Cloud,
    guess: &Transform,
    gate: f64,
) -> Result<(Assembly, PairStats)> {
    pair_assembly_weighted(source, None, target, guess, gate)
}

/// [`pair_assembly`] with the source's per-point weights (one per source
/// point; a missing one counts 1): each pair carries its source point's.
pub fn pair_assembly_weighted(
    source: &[[f64; 3]],
    weights: Option<&[f64]>,
    target: &Cloud,
    guess: &Transform,
    gate: f64,
) -> Result<(Assembly, PairStats)> {
    let (c, w, st) = matched_stats(source, weights, target, guess, gate)?;
    if c.is_empty() {
        return Err(Error::invalid(format!(
            "no correspondence: none of the {} source points has a target point within {gate} m (check --initial-guess or raise --gate)",
            source.len()
        )));
    }
    Ok((
        Assembly::from_points(&c.points, &c.normals, w.as_deref())?,
        st,
    ))
}
