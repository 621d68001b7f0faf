//! Many calibrations of one frame pair: their mean on SE(3), each one's
//! deviation from it, the per-axis spread and the outliers by a stated robust
//! rule (`audit spread`, the fleet check).
//!
//! # Conventions (stated once here)
//!
//! Calibration `i` is `T_i = (R_i, t_i)`, the pose of `to` in `from`
//! ([`crate::geometry::se3`]).
//!
//! - Rotation mean: the chordal L2 mean `argmin_M sum ||R_i - M||_F^2`, which
//!   is what scipy's `Rotation.mean` computes: the unit eigenvector of
//!   `K = sum q_i q_i^T` with the largest eigenvalue (`||R(p) - R(q)||_F^2 =
//!   8 (1 - (p.q)^2)`, so the loss is `8 N - 8 q^T K q`). `K` does not change
//!   when a `q_i` flips sign: no hemisphere to choose. When the top eigenvalue
//!   is not simple (relative gap below [`SPREAD_MEAN_MIN_GAP`]) the mean is
//!   not unique and it is an error. The geodesic (Karcher) mean differs from
//!   it by 1.6e-5 deg on a set with a 1.5 deg outlier: far below calibration
//!   noise, and it has no closed form.
//! - Translation mean: the arithmetic mean of `t_i` in from-frame
//!   coordinates (the mean position of the child's origin in the parent). It
//!   is exactly equivariant under a change of the from-frame; under a change
//!   of the to-frame by `H = (R_H, t_H)` only to first order, the error being
//!   `(mean R_i - R_mean) t_H`, second order in the rotation spread times
//!   `|t_H|`.
//! - Deviations of calibration `i`: rotation in to-frame (sensor) axes
//!   `Log(R_mean^T R_i)` (the right perturbation, `T exp(xi)`) and in
//!   from-frame axes `Log(R_i R_mean^T)`; translation in from-frame axes
//!   `t_i - t_mean` and in the mean's to-frame axes `R_mean^T (t_i - t_mean)`
//!   (not the deviation of `-R_i^T t_i`, which mixes rotation into translation
//!   through the lever arm). Rotation components are rotation-vector
//!   components in degrees, not Euler angles.
//! - Spread per axis: the sample standard deviation (`ddof = 1`; none for one
//!   calibration) and the largest absolute deviation with its calibration.
//! - Outliers, applied to the rotation and the translation deviations (from-
//!   frame axes) separately: centre `c` = the component-wise median; robust
//!   sigma per axis `MAD / 0.6745` ([`MAD_NORMAL_CONSTANT`], the MAD floored at
//!   [`MAD_FLOOR_M`] and [`MAD_FLOOR_DEG`]); standardised distance
//!   `d_i = |(delta_i - c) / sigma|`; flagged when `d_i > max(`[`OUTLIER_RATIO`]
//!   ` * median d, `[`OUTLIER_RADIUS`]`)`: Iglewicz and Hoaglin's `|M| > 3.5`
//!   carried to three dimensions. Not applied below [`OUTLIER_MIN_COUNT`]
//!   calibrations; below [`OUTLIER_FEW`](crate::tolerances::OUTLIER_FEW) the robust scale is uncertain.

use crate::diagnostic::{Error, Result};
use crate::geometry::Transform;
use crate::tolerances::{
    MAD_FLOOR_DEG, MAD_FLOOR_M, MAD_NORMAL_CONSTANT, OUTLIER_MIN_COUNT, OUTLIER_RADIUS,
    OUTLIER_RATIO, SPREAD_MEAN_MIN_GAP,
};
use nalgebra::{Matrix3, Matrix4, SymmetricEigen, UnitQuaternion, Vector3, Vector4};
use serde::Serialize;

/// One calibration's deviation from the mean (mm, deg): also the spread
/// report's `calibrations[].deviation`, serialized as it is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Deviation {
    /// `Log(R_i R_mean^T)` (deg), from-frame axes.
    pub rotation_from_deg: [f64; 3],
    /// `Log(R_mean^T R_i)` (deg), to-frame axes.
    pub rotation_to_deg: [f64; 3],
    /// `t_i - t_mean` (mm), from-frame axes.
    pub translation_from_mm: [f64; 3],
    /// `R_mean^T (t_i - t_mean)` (mm), the mean's to-frame axes.
    pub translation_to_mm: [f64; 3],
    /// The rotation angle of the deviation (deg).
    pub angle_deg: f64,
    /// `|t_i - t_mean|` (mm).
    pub distance_mm: f64,
}

/// The spread of one group of deviations (one quantity in one frame's axes).
#[derive(Debug, Clone, PartialEq)]
pub struct AxisSpread {
    /// Sample standard deviation per axis (`ddof = 1`); `None` for one
    /// calibration.
    pub std: Option<[f64; 3]>,
    /// Largest absolute deviation per axis.
    pub max_abs: [f64; 3],
    /// The calibration (index) each largest deviation belongs to.
    pub max_abs_index: [usize; 3],
    /// Largest norm of a deviation vector.
    pub norm_max: f64,
}

/// The spread in both frames' axes.
#[derive(Debug, Clone, PartialEq)]
pub struct Spreads {
    /// Rotation (deg), from-frame axes.
    pub rotation_from: AxisSpread,
    /// Rotation (deg), to-frame axes.
    pub rotation_to: AxisSpread,
    /// Translation (mm), from-frame axes.
    pub translation_from: AxisSpread,
    /// Translation (mm), to-frame axes.
    pub translation_to: AxisSpread,
}

/// The outlier test on one quantity (from-frame deviations).
#[derive(Debug, Clone, PartialEq)]
pub struct OutlierTest {
    /// The component-wise median (mm or deg).
    pub centre: [f64; 3],
    /// `MAD / 0.6745` per axis, the MAD floored (mm or deg).
    pub robust_sigma: [f64; 3],
    /// Each calibration's standardised distance from the centre.
    pub distance: Vec<f64>,
    /// The median of those distances.
    pub median_distance: f64,
    /// `max(OUTLIER_RATIO * median, OUTLIER_RADIUS)`: beyond it, an outlier.
    pub limit: f64,
}

/// The outlier rule's result; `None` tests below [`OUTLIER_MIN_COUNT`].
#[derive(Debug, Clone, PartialEq)]
pub struct Outliers {
    /// On the rotation deviations (deg).
    pub rotation: Option<OutlierTest>,
    /// On the translation deviations (mm).
    pub translation: Option<OutlierTest>,
    /// Indices flagged by either test, ascending.
    pub flagged: Vec<usize>,
}

/// The mean of a set of calibrations and what it says about them.
#[derive(Debug, Clone, PartialEq)]
pub struct Spread {
    /// The chordal rotation mean and the arithmetic translation mean.
    pub mean: Transform,
    /// `(w4 - w3) / w4` of `K = sum q q^T`: near 1 for a tight set.
    pub eigen_gap: f64,
    /// One per calibration, in input order.
    pub deviations: Vec<Deviation>,
    /// Standard deviation and largest deviation per axis.
    pub spreads: Spreads,
    /// The robust outlier rule.
    pub outliers: Outliers,
}

/// `Log(R)` (rad): the rotation vector, accurate at small angles (the
/// angle from `atan2`), below the zero-angle tolerance the skew part.
fn log(r: &Matrix3<f64>) -> Vector3<f64> {
    let t = Transform::from_parts_unchecked(*r, Vector3::zeros());
    match t.rotation_angle_axis() {
        (phi, Some(e)) => e * phi,
        _ => {
            0.5 * Vector3::new(
                r[(2, 1)] - r[(1, 2)],
                r[(0, 2)] - r[(2, 0)],
                r[(1, 0)] - r[(0, 1)],
            )
        }
    }
}

/// The chordal L2 mean of the rotations of the `n` transforms `at(0)`, ...,
/// `at(n - 1)` and the relative eigen-gap of `K`.
fn chordal_mean(n: usize, at: &impl Fn(usize) -> Transform) -> Result<(Matrix3<f64>, f64)> {
    if n == 0 {
        return Err(Error::usage(
            "expected at least one calibration, found none",
        ));
    }
    let mut k = Matrix4::<f64>::zeros();
    for i in 0..n {
        let q = Vector4::from(at(i).quaternion_xyzw());
        k += q * q.transpose();
    }
    let eig = SymmetricEigen::new(k);
    let mut order: Vec<usize> = (0..4).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let (top, second) = (eig.eigenvalues[order[3]], eig.eigenvalues[order[2]]);
    let gap = (top - second) / top;
    // A NaN gap (a NaN quaternion cannot reach here, but) is refused too.
    if gap.is_nan() || gap < SPREAD_MEAN_MIN_GAP {
        return Err(Error::invalid(format!(
            "the rotations have no unique mean: expected the top eigenvalue of sum q q^T to be \
             simple, found a relative gap of {gap:.1e} (rotations spread over a great circle)"
        )));
    }
    let v = eig.eigenvectors.column(order[3]);
    let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(v[3], v[0], v[1], v[2]));
    Ok((*q.to_rotation_matrix().matrix(), gap))
}

fn to_array(v: Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// The per-axis spread of `values` (already in mm or deg).
pub fn axis_spread(values: &[[f64; 3]]) -> AxisSpread {
    let n = values.len();
    let mut max_abs = [0.0; 3];
    let mut max_abs_index = [0; 3];
    let mut std = [0.0; 3];
    for k in 0..3 {
        let mean = values.iter().map(|v| v[k]).sum::<f64>() / n as f64;
        let ss: f64 = values.iter().map(|v| (v[k] - mean).powi(2)).sum();
        std[k] = (ss / (n as f64 - 1.0)).sqrt();
        for (i, v) in values.iter().enumerate() {
            if v[k].abs() > max_abs[k] {
                max_abs[k] = v[k].abs();
                max_abs_index[k] = i;
            }
        }
    }
    let norm_max = values
        .iter()
        .map(|v| Vector3::from(*v).norm())
        .fold(0.0, f64::max);
    AxisSpread {
        std: (n > 1).then_some(std),
        max_abs,
        max_abs_index,
        norm_max,
    }
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    if n % 2 == 1 {
        xs[n / 2]
    } else {
        0.5 * (xs[n / 2 - 1] + xs[n / 2])
    }
}

/// The robust rule on one quantity's deviations (`floor`: the MAD's floor
/// in the deviations' unit).
pub fn outlier_test(values: &[[f64; 3]], floor: f64) -> OutlierTest {
    let mut centre = [0.0; 3];
    let mut robust_sigma = [0.0; 3];
    for k in 0..3 {
        centre[k] = median(values.iter().map(|v| v[k]).collect());
        let mad = median(values.iter().map(|v| (v[k] - centre[k]).abs()).collect());
        robust_sigma[k] = mad.max(floor) / MAD_NORMAL_CONSTANT;
    }
    let distance: Vec<f64> = values
        .iter()
        .map(|v| {
            (0..3)
                .map(|k| ((v[k] - centre[k]) / robust_sigma[k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    let median_distance = median(distance.clone());
    OutlierTest {
        centre,
        robust_sigma,
        limit: (OUTLIER_RATIO * median_distance).max(OUTLIER_RADIUS),
        distance,
        median_distance,
    }
}

/// The deviation of `t` from `mean`.
pub fn deviation(mean: &Transform, t: &Transform) -> Deviation {
    let (rm, tm) = (mean.rotation(), mean.translation());
    let rot_to = log(&(rm.transpose() * t.rotation())).map(f64::to_degrees);
    let rot_from = log(&(t.rotation() * rm.transpose())).map(f64::to_degrees);
    let dt = (t.translation() - tm) * 1e3;
    Deviation {
        rotation_from_deg: to_array(rot_from),
        rotation_to_deg: to_array(rot_to),
        translation_from_mm: to_array(dt),
        translation_to_mm: to_array(rm.transpose() * dt),
        angle_deg: rot_to.norm(),
        distance_mm: dt.norm(),
    }
}

/// The chordal rotation mean and the arithmetic translation mean of
/// `transforms` (at least one), and the eigen-gap: what `audit spread` and
/// check's fleet findings share.
pub fn mean(transforms: &[Transform]) -> Result<(Transform, f64)> {
    mean_by(transforms.len(), |i| transforms[i])
}

/// [`mean`] of the `n` transforms `at(0)`, ..., `at(n - 1)` (the same sums in
/// the same order), for a caller that keeps them in a smaller form.
pub fn mean_by(n: usize, at: impl Fn(usize) -> Transform) -> Result<(Transform, f64)> {
    let (r, eigen_gap) = chordal_mean(n, &at)?;
    let t = (0..n).fold(Vector3::zeros(), |a, i| a + at(i).translation()) / n as f64;
    Ok((Transform::from_parts_unchecked(r, t), eigen_gap))
}

/// The robust outlier rule on the from-frame deviations (`rotation_from`
/// in deg, `translation_from` in mm, one per calibration): no test below
/// [`OUTLIER_MIN_COUNT`]. Shared by `audit spread` and check's fleet findings.
pub fn outliers(rotation_from: &[[f64; 3]], translation_from: &[[f64; 3]]) -> Outliers {
    if rotation_from.len() < OUTLIER_MIN_COUNT {
        return Outliers {
            rotation: None,
            translation: None,
            flagged: Vec::new(),
        };
    }
    let rotation = outlier_test(rotation_from, MAD_FLOOR_DEG);
    let translation = outlier_test(translation_from, MAD_FLOOR_M * 1e3);
    let flagged = (0..rotation_from.len())
        .filter(|&i| {
            rotation.distance[i] > rotation.limit || translation.distance[i] > translation.limit
        })
        .collect();
    Outliers {
        rotation: Some(rotation),
        translation: Some(translation),
        flagged,
    }
}

/// The mean, deviations, spreads and outliers of `transforms` (one frame
/// pair, at least one calibration).
pub fn spread(transforms: &[Transform]) -> Result<Spread> {
    let (mean, eigen_gap) = mean(transforms)?;
    let deviations: Vec<Deviation> = transforms.iter().map(|t| deviation(&mean, t)).collect();
    let pick = |f: fn(&Deviation) -> [f64; 3]| deviations.iter().map(f).collect::<Vec<_>>();
    let (rf, tf) = (
        pick(|d| d.rotation_from_deg),
        pick(|d| d.translation_from_mm),
    );
    let spreads = Spreads {
        rotation_from: axis_spread(&rf),
        rotation_to: axis_spread(&pick(|d| d.rotation_to_deg)),
        translation_from: axis_spread(&tf),
        translation_to: axis_spread(&pick(|d| d.translation_to_mm)),
    };
    let outliers = outliers(&rf, &tf);
    Ok(Spread {
        mean,
        eigen_gap,
        deviations,
        spreads,
        outliers,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rz(deg: f64, t: [f64; 3]) -> Transform {
        Transform::from_axis_angle([0.0, 0.0, 1.0], deg.to_radians(), t).unwrap()
    }

    #[test]
    fn two_rotations_about_one_axis_average_to_the_midpoint() {
        // Closed form: the chordal mean of Rz(a) and Rz(b) is Rz((a + b) / 2).
        let s = spread(&[rz(10.0, [0.0; 3]), rz(30.0, [0.0; 3])]).unwrap();
        let (phi, _) = s.mean.rotation_angle_axis();
        assert!((phi.to_degrees() - 20.0).abs() < 1e-12);
        assert!((s.deviations[0].rotation_to_deg[2] + 10.0).abs() < 1e-12);
        // ddof = 1: the two deviations -10, +10 have standard deviation 14.142.
        let std = s.spreads.rotation_to.std.unwrap();
        assert!((std[2] - 200f64.sqrt()).abs() < 1e-10);
        assert!(s.outliers.rotation.is_none(), "no test below three");
    }

    #[test]
    fn one_calibration_has_no_standard_deviation() {
        let s = spread(&[rz(5.0, [1.0, 0.0, 0.0])]).unwrap();
        assert!(s.spreads.translation_from.std.is_none());
        assert_eq!(s.spreads.translation_from.max_abs, [0.0; 3]);
    }

    #[test]
    fn opposite_quarter_turns_have_no_unique_mean() {
        // Rz(+90) and Rz(-90): K has a double top eigenvalue (any rotation about
        // z between them is as near), so the mean is refused.
        let e = spread(&[rz(90.0, [0.0; 3]), rz(-90.0, [0.0; 3])]).unwrap_err();
        assert!(e.to_string().contains("no unique mean"), "{e}");
    }

    #[test]
    fn identical_calibrations_flag_nothing() {
        // MAD = 0: the floor keeps the distances finite and the copies clean.
        let t = rz(1.0, [0.1, 0.2, 0.3]);
        let s = spread(&[t, t, t, t]).unwrap();
        assert!(s.outliers.flagged.is_empty());
        assert!(s
            .outliers
            .translation
            .unwrap()
            .distance
            .iter()
            .all(|d| *d == 0.0));
    }
}
