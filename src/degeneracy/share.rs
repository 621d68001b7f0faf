//! Each point's share of the information along one twist: for the scene
//! of a scan (`--format mcap`), which points hold the weakest direction.
//!
//! A point with normal `n` moved by the twist `v = [omega; t]` moves at
//! `u = omega x p + t`, so its row of the information is `a . v = n . u`
//! (`a = [p x n; n]`, conventions in [`crate::degeneracy`]), and
//! `v^T H v = sum_i w_i (n_i . u_i)^2`. Point `i`'s share is
//! `w_i (n_i . u_i)^2 / v^T H v`: the shares add up to 1, and they do not
//! depend on the frame (`a' . v' = a . v` under `H' = A^T H A`, `v = A v'`).
//! `u` is evaluated about the centroid (`omega x (p - c) + t + omega x c`),
//! so map or UTM coordinates lose no digit.

use crate::tolerances::SHARE_ZERO_EIGENVALUE;
use nalgebra::{Vector3, Vector6};

/// The shares of `v` (a twist in the points' frame) over the points (with
/// their normals and optional weights, a missing weight 1), about `center`;
/// `None` when `v` moves no point along its normal: its Rayleigh quotient
/// `v^T H v / v^T M v` is at most [`SHARE_ZERO_EIGENVALUE`] (or `v` is zero).
pub fn information_shares(
    points: &[[f64; 3]],
    normals: &[[f64; 3]],
    weights: Option<&[f64]>,
    v: &Vector6<f64>,
    center: [f64; 3],
) -> Option<Vec<f64>> {
    let om = Vector3::new(v[0], v[1], v[2]);
    let c = Vector3::from(center);
    let tc = Vector3::new(v[3], v[4], v[5]) + om.cross(&c);
    let (mut hv, mut mv) = (0.0, 0.0);
    let rows: Vec<f64> = points
        .iter()
        .zip(normals)
        .enumerate()
        .map(|(i, (p, n))| {
            let w = weights.and_then(|w| w.get(i)).copied().unwrap_or(1.0);
            let u = om.cross(&(Vector3::from(*p) - c)) + tc;
            let r = w * Vector3::from(*n).dot(&u).powi(2);
            hv += r;
            mv += w * u.norm_squared();
            r
        })
        .collect();
    if !(mv > 0.0 && hv > SHARE_ZERO_EIGENVALUE * mv) {
        return None;
    }
    Some(rows.into_iter().map(|r| r / hv).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_of_a_translation_follow_the_normals_and_add_up_to_one() {
        // Three points; a translation along x meets normals x, (x+y)/sqrt2, y.
        let s = 0.5f64.sqrt();
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let n = [[1.0, 0.0, 0.0], [s, s, 0.0], [0.0, 1.0, 0.0]];
        let v = Vector6::new(0.0, 0.0, 0.0, 1.0, 0.0, 0.0);
        let sh = information_shares(&p, &n, None, &v, [0.3, 0.3, 0.0]).unwrap();
        // (n . x)^2 = 1, 1/2, 0 over 3/2.
        let want = [2.0 / 3.0, 1.0 / 3.0, 0.0];
        for k in 0..3 {
            assert!((sh[k] - want[k]).abs() < 1e-15, "{sh:?}");
        }
        // Weights scale a point's row: weight 2 on the second gives 1, 1, 0 over 2.
        let sh = information_shares(&p, &n, Some(&[1.0, 2.0, 1.0]), &v, [0.0; 3]).unwrap();
        assert!((sh[0] - 0.5).abs() < 1e-15 && (sh[1] - 0.5).abs() < 1e-15);
    }

    #[test]
    fn a_rotation_is_measured_about_any_centre_alike_far_from_the_origin() {
        // Rotation about z through (1e6, 2e6, 0): u = omega x (p - q).
        let q = Vector3::new(1e6, 2e6, 0.0);
        let om = Vector3::new(0.0, 0.0, 1.0);
        let t = -om.cross(&q);
        let v = Vector6::new(om.x, om.y, om.z, t.x, t.y, t.z);
        let p = [[1e6 + 1.0, 2e6, 0.0], [1e6, 2e6 + 2.0, 0.0]];
        // Normals along the motion: u = (0, 1, 0) and (-2, 0, 0).
        let n = [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]];
        let a = information_shares(&p, &n, None, &v, [1e6, 2e6, 0.0]).unwrap();
        let b = information_shares(&p, &n, None, &v, [1e6 + 0.5, 2e6 + 1.0, 0.0]).unwrap();
        assert!(
            (a[0] - 0.2).abs() < 1e-12 && (a[1] - 0.8).abs() < 1e-12,
            "{a:?}"
        );
        assert!((a[0] - b[0]).abs() < 1e-12);
    }

    #[test]
    fn a_direction_no_point_constrains_has_no_shares() {
        // A plane z = 0 with normals z: a translation along x moves no point
        // along its normal.
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let n = [[0.0, 0.0, 1.0]; 3];
        let v = Vector6::new(0.0, 0.0, 0.0, 1.0, 0.0, 0.0);
        assert_eq!(information_shares(&p, &n, None, &v, [0.0; 3]), None);
        assert_eq!(
            information_shares(&p, &n, None, &Vector6::zeros(), [0.0; 3]),
            None
        );
    }
}
