//! Rigid transforms, the adjoint and the screw (Chasles) decomposition.
//!
//! # Conventions (the project's; every other module follows these)
//!
//! - Units: metres and radians inside; a file in millimetres is converted on load.
//! - `T = (R, d)` is the pose of frame `to` expressed in frame `from`:
//!   `p_from = R p_to + d`. `audit FILE --from base_link --to lidar` prints the
//!   transform that `tf2_echo base_link lidar` prints.
//! - Twist `xi = [omega; t]`, rotation first; right (body) perturbation `T exp(xi^)`.
//! - Adjoint `Ad(T) = [[R, 0], [[d]x R, R]]`, so `xi = Ad(T) xi'`.
//! - Under a body-frame change the information matrix transforms by congruence,
//!   `H' = A^T H A` with `A = Ad(T)`; points `p~ = R^T (p - d)`, normals `n~ = R^T n`.
//! - Quaternions are printed `[x, y, z, w]`; constructors take an explicit order.
//! - URDF `rpy` is fixed-axis roll-pitch-yaw: `R = Rz(yaw) Ry(pitch) Rx(roll)`.
//!   ROS1 `static_transform_publisher` takes the same angles in the argument order
//!   yaw, pitch, roll.
//! - Rotation angle `phi` in `[0, pi]`, unit axis `e` (none when `phi` is zero).
//!   At an exact half-turn the axis sign is free; it is chosen so that the screw
//!   translation `h = e . d` is non-negative (then `h(T) = h(T^-1)` holds there too),
//!   and when `h = 0` so that the first non-zero component of `e` is positive.
//!   "Exact" means `sin(phi) <= HALF_TURN_SIN_TOL`; closer to `pi` than that the
//!   skew part of `R` carries no reliable sign. Short of it (e.g. `phi = pi - 1e-9`)
//!   the sign comes from the skew part, `T^-1` gets `-e`, and `h` agrees anyway.
//! - [`Transform::screw`] classifies zero pitch with an absolute tolerance on
//!   `|h|` in metres. The reports choose it from `h` and its uncertainty
//!   (`--pitch-tol auto`, the three-way verdict of
//!   [`crate::geometry::uncertainty`]) or take the user's `--pitch-tol M`, and
//!   print `h` with its standard uncertainty beside the verdict.
//! - Below `ANGLE_ZERO_TOL` (1e-9 rad) a rotation counts as none: the transform is
//!   the identity or a pure translation, with no axis (the angle is still reported).

use crate::diagnostic::{Code, Error, Result, Warning};
use crate::tolerances::{
    ANGLE_ZERO_TOL, AXIS_MIN_NORM, BOTTOM_ROW_TOL, HALF_TURN_SIN_TOL, LENGTH_ZERO_TOL,
    ORTHONORMAL_ERROR_TOL, ORTHONORMAL_EXACT_TOL, ORTHONORMAL_ROUNDING_TOL, ORTHONORMAL_WARN_TOL,
    QUATERNION_MIN_NORM, QUATERNION_ROUNDING_TOL, QUATERNION_WARN_TOL,
};
use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3};

/// Quaternion component order as written in a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QuatOrder {
    /// `[x, y, z, w]`: scalar last (ROS, Eigen's `coeffs()`, scipy).
    Xyzw,
    /// `[w, x, y, z]`: scalar first (Eigen's constructor, FusionPortable).
    Wxyz,
}

/// `[v]x`, the matrix with `[v]x u = v x u`.
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// The vector `v` with `[v]x = (M - M^T)/2`.
fn vee_antisym(m: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        0.5 * (m[(2, 1)] - m[(1, 2)]),
        0.5 * (m[(0, 2)] - m[(2, 0)]),
        0.5 * (m[(1, 0)] - m[(0, 1)]),
    )
}

fn check_finite(what: &str, xs: &[f64]) -> Result<()> {
    if let Some(x) = xs.iter().find(|x| !x.is_finite()) {
        return Err(Error::invalid(format!(
            "{what}: expected finite numbers, found {x}"
        )));
    }
    Ok(())
}

/// `R = Rz(yaw) Ry(pitch) Rx(roll)` (fixed-axis roll, pitch, yaw).
pub fn rpy_to_matrix(roll: f64, pitch: f64, yaw: f64) -> Matrix3<f64> {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let (sy, cy) = yaw.sin_cos();
    Matrix3::new(
        cy * cp,
        cy * sp * sr - sy * cr,
        cy * sp * cr + sy * sr,
        sy * cp,
        sy * sp * sr + cy * cr,
        sy * sp * cr - cy * sr,
        -sp,
        cp * sr,
        cp * cr,
    )
}

/// Roll, pitch, yaw with `R = Rz(yaw) Ry(pitch) Rx(roll)`, pitch in `[-pi/2, pi/2]`.
/// At gimbal lock (`|pitch| = pi/2`) roll is set to 0 and yaw carries the rest.
pub fn matrix_to_rpy(r: &Matrix3<f64>) -> [f64; 3] {
    let sp = (-r[(2, 0)]).clamp(-1.0, 1.0);
    let cp = r[(0, 0)].hypot(r[(1, 0)]);
    let pitch = sp.atan2(cp);
    if cp > 1e-12 {
        let roll = r[(2, 1)].atan2(r[(2, 2)]);
        let yaw = r[(1, 0)].atan2(r[(0, 0)]);
        [roll, pitch, yaw]
    } else {
        // Gimbal lock: only yaw -/+ roll is determined.
        let yaw = (-r[(0, 1)]).atan2(r[(1, 1)]);
        [0.0, pitch, yaw]
    }
}

/// `||v||` without overflow or underflow of the squares.
pub fn robust_norm(v: &Vector3<f64>) -> f64 {
    let m = v.amax();
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    m * (v / m).norm()
}

/// `v / ||v||` for a finite non-zero `v`, without overflow.
pub fn scaled_unit(v: &Vector3<f64>) -> Vector3<f64> {
    let w = v / v.amax();
    w / w.norm()
}

/// Rodrigues' formula for a unit axis.
fn axis_angle_matrix(e: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    let k = skew(e);
    let (s, c) = angle.sin_cos();
    Matrix3::identity() + k * s + k * k * (1.0 - c)
}

/// A rigid transform `T = (R, d)`: the pose of frame `to` in frame `from`,
/// `p_from = R p_to + d`. `R` is orthonormal with det +1 to rounding.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    r: Matrix3<f64>,
    d: Vector3<f64>,
}

impl Default for Transform {
    fn default() -> Self {
        Self::identity()
    }
}

impl Transform {
    /// The identity: `R = I`, `d = 0` (`from` and `to` coincide).
    pub fn identity() -> Self {
        Transform {
            r: Matrix3::identity(),
            d: Vector3::zeros(),
        }
    }

    /// A pure translation (metres).
    pub fn from_translation(d: [f64; 3]) -> Result<Self> {
        check_finite("translation", &d)?;
        Ok(Transform {
            r: Matrix3::identity(),
            d: Vector3::from(d),
        })
    }

    /// Internal: trusted parts (already a rotation to rounding).
    pub(crate) fn from_parts_unchecked(r: Matrix3<f64>, d: Vector3<f64>) -> Self {
        Transform { r, d }
    }

    /// From a rotation matrix (row-major `r[row][col]`) and a translation.
    ///
    /// Checked: finite; `||R^T R - I||_F <= ORTHONORMAL_ERROR_TOL` (else an error
    /// that says how far off it is); `det R > 0` (a reflection is an error). Between
    /// `ORTHONORMAL_WARN_TOL` and the error tolerance the matrix is projected to the
    /// nearest rotation (SVD) with a `non-orthonormal-rotation` warning.
    pub fn from_matrix3(
        r: [[f64; 3]; 3],
        d: [f64; 3],
        warnings: &mut Vec<Warning>,
    ) -> Result<Self> {
        Self::from_matrix3_to(r, d, Some(warnings))
    }

    /// [`Transform::from_matrix3`] and [`Transform::from_matrix4`] for the
    /// steps of a numerical derivative (`uncertainty::rounding_covariance`):
    /// the same transform or refusal, its warning dropped before it is
    /// formatted (nobody reads it: formatting it was a tenth of checking a
    /// rig file, issue 29).
    pub(crate) fn from_matrix3_quiet(r: [[f64; 3]; 3], d: [f64; 3]) -> Result<Self> {
        Self::from_matrix3_to(r, d, None)
    }

    /// See [`Transform::from_matrix3_quiet`]; a refused bottom row is an
    /// error without its message.
    pub(crate) fn from_matrix4_quiet(m: [[f64; 4]; 4]) -> Result<Self> {
        Self::from_matrix4_to(m, None)
    }

    fn from_matrix3_to(
        r: [[f64; 3]; 3],
        d: [f64; 3],
        warnings: Option<&mut Vec<Warning>>,
    ) -> Result<Self> {
        check_finite("rotation matrix", r.as_flattened())?;
        check_finite("translation", &d)?;
        let m = Matrix3::from_fn(|i, j| r[i][j]);
        let r = checked_rotation(&m, warnings)?;
        Ok(Transform {
            r,
            d: Vector3::from(d),
        })
    }

    /// From a quaternion in the named order. Normalised with a
    /// `non-unit-quaternion` warning when `| ||q|| - 1 | > QUATERNION_WARN_TOL`;
    /// an error when its norm is below `QUATERNION_MIN_NORM` or not finite.
    pub fn from_quaternion(
        q: [f64; 4],
        order: QuatOrder,
        d: [f64; 3],
        warnings: &mut Vec<Warning>,
    ) -> Result<Self> {
        check_finite("quaternion", &q)?;
        check_finite("translation", &d)?;
        let (x, y, z, w) = match order {
            QuatOrder::Xyzw => (q[0], q[1], q[2], q[3]),
            QuatOrder::Wxyz => (q[1], q[2], q[3], q[0]),
        };
        // Scale first so that norms like 1e300 do not overflow when squared;
        // the unit quaternion is taken from the scaled one. A norm beyond the
        // f64 range (components near f64::MAX) is an error, as is one below
        // QUATERNION_MIN_NORM.
        let scale = x.abs().max(y.abs()).max(z.abs()).max(w.abs());
        let (xs, ys, zs, ws) = if scale > 0.0 {
            (x / scale, y / scale, z / scale, w / scale)
        } else {
            (0.0, 0.0, 0.0, 0.0)
        };
        let ns = (xs * xs + ys * ys + zs * zs + ws * ws).sqrt();
        let norm = scale * ns;
        if scale.is_nan() || scale <= 0.0 || !norm.is_finite() || norm < QUATERNION_MIN_NORM {
            return Err(Error::invalid(format!(
                "quaternion {}: expected a unit quaternion, found norm {norm:e} (no rotation can be recovered)",
                fmt_quat(q, order)
            )));
        }
        if (norm - 1.0).abs() > QUATERNION_WARN_TOL {
            warnings.push(
                Warning::new(
                    Code::NonUnitQuaternion,
                    format!(
                        "quaternion {} has norm {norm:.9}, expected 1; normalised",
                        fmt_quat(q, order)
                    ),
                )
                .with_severity(rounding_severity(
                    (norm - 1.0).abs(),
                    QUATERNION_ROUNDING_TOL,
                )),
            );
        }
        let (x, y, z, w) = (xs / ns, ys / ns, zs / ns, ws / ns);
        let r = Matrix3::new(
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - z * w),
            2.0 * (x * z + y * w),
            2.0 * (x * y + z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - x * w),
            2.0 * (x * z - y * w),
            2.0 * (y * z + x * w),
            1.0 - 2.0 * (x * x + y * y),
        );
        Ok(Transform {
            r,
            d: Vector3::from(d),
        })
    }

    /// URDF `rpy` (fixed axes): `R = Rz(yaw) Ry(pitch) Rx(roll)`.
    pub fn from_rpy(rpy: [f64; 3], d: [f64; 3]) -> Result<Self> {
        check_finite("roll-pitch-yaw", &rpy)?;
        check_finite("translation", &d)?;
        Ok(Transform {
            r: rpy_to_matrix(rpy[0], rpy[1], rpy[2]),
            d: Vector3::from(d),
        })
    }

    /// ROS1 `static_transform_publisher x y z yaw pitch roll`: the same rotation as
    /// [`Transform::from_rpy`], arguments in yaw, pitch, roll order.
    pub fn from_ypr(ypr: [f64; 3], d: [f64; 3]) -> Result<Self> {
        Self::from_rpy([ypr[2], ypr[1], ypr[0]], d)
    }

    /// Axis-angle. The axis need not be unit (it is normalised; a non-unit axis is
    /// not suspicious in most formats); a zero axis is an error unless the angle is 0.
    pub fn from_axis_angle(axis: [f64; 3], angle: f64, d: [f64; 3]) -> Result<Self> {
        check_finite("rotation axis", &axis)?;
        check_finite("rotation angle", &[angle])?;
        check_finite("translation", &d)?;
        if angle == 0.0 {
            return Self::from_translation(d);
        }
        // Scaled norm: an axis like [1e300, 1e300, 0] must not overflow to inf
        // (that would silently give the identity).
        let a = Vector3::from(axis);
        let n = robust_norm(&a);
        if n < AXIS_MIN_NORM {
            return Err(Error::invalid(format!(
                "rotation axis {axis:?}: expected a non-zero axis for angle {angle}, found a zero vector"
            )));
        }
        let e = scaled_unit(&a);
        Ok(Transform {
            r: axis_angle_matrix(&e, angle),
            d: Vector3::from(d),
        })
    }

    /// Rotation vector `theta * e` (as in Kalibr / OpenCV `rvec`).
    pub fn from_rotation_vector(v: [f64; 3], d: [f64; 3]) -> Result<Self> {
        check_finite("rotation vector", &v)?;
        let a = Vector3::from(v);
        let n = robust_norm(&a);
        if !n.is_finite() {
            return Err(Error::invalid(format!(
                "rotation vector {v:?}: expected a finite angle, found norm {n:e}"
            )));
        }
        if n == 0.0 {
            return Self::from_translation(d);
        }
        Self::from_axis_angle(v, n, d)
    }

    /// A 4x4 homogeneous matrix (row-major). The bottom row must be `[0 0 0 1]`
    /// within `BOTTOM_ROW_TOL`; the rotation block is checked as in
    /// [`Transform::from_matrix3`].
    pub fn from_matrix4(m: [[f64; 4]; 4], warnings: &mut Vec<Warning>) -> Result<Self> {
        Self::from_matrix4_to(m, Some(warnings))
    }

    fn from_matrix4_to(m: [[f64; 4]; 4], warnings: Option<&mut Vec<Warning>>) -> Result<Self> {
        check_finite("4x4 matrix", m.as_flattened())?;
        let bottom = m[3];
        let expect = [0.0, 0.0, 0.0, 1.0];
        if bottom
            .iter()
            .zip(expect.iter())
            .any(|(a, b)| (a - b).abs() > BOTTOM_ROW_TOL)
        {
            if warnings.is_none() {
                return Err(Error::invalid(String::new()));
            }
            return Err(Error::invalid(format!(
                "4x4 matrix: expected bottom row [0, 0, 0, 1], found {bottom:?}"
            )));
        }
        let r = [
            [m[0][0], m[0][1], m[0][2]],
            [m[1][0], m[1][1], m[1][2]],
            [m[2][0], m[2][1], m[2][2]],
        ];
        Self::from_matrix3_to(r, [m[0][3], m[1][3], m[2][3]], warnings)
    }

    /// Rotation matrix.
    pub fn rotation(&self) -> &Matrix3<f64> {
        &self.r
    }
    /// Translation `d` (m).
    pub fn translation(&self) -> &Vector3<f64> {
        &self.d
    }

    /// `self * other`: first `other`, then `self` (`T_a_c = T_a_b * T_b_c`).
    pub fn compose(&self, other: &Transform) -> Transform {
        Transform {
            r: self.r * other.r,
            d: self.r * other.d + self.d,
        }
    }

    /// `T^-1 = (R^T, -R^T d)`.
    pub fn inverse(&self) -> Transform {
        let rt = self.r.transpose();
        Transform {
            r: rt,
            d: -(rt * self.d),
        }
    }

    /// Apply to a point: `R p + d`.
    pub fn apply(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.r * p + self.d
    }

    /// Scale the translation (e.g. millimetres to metres).
    pub fn scaled_translation(&self, s: f64) -> Transform {
        Transform {
            r: self.r,
            d: self.d * s,
        }
    }

    /// The homogeneous 4x4 matrix `[[R, d], [0, 1]]` (translation in metres).
    pub fn matrix4(&self) -> Matrix4<f64> {
        let mut m = Matrix4::identity();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.r);
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.d);
        m
    }

    /// Quaternion `[x, y, z, w]` with `w >= 0`.
    pub fn quaternion_xyzw(&self) -> [f64; 4] {
        // R is a rotation to rounding (checked on construction): use the direct
        // (Shepperd) conversion rather than nalgebra's iterative `from_matrix`.
        let rot = nalgebra::Rotation3::from_matrix_unchecked(self.r);
        let q = nalgebra::UnitQuaternion::from_rotation_matrix(&rot);
        let (mut x, mut y, mut z, mut w) = (q.i, q.j, q.k, q.w);
        if w < 0.0 {
            (x, y, z, w) = (-x, -y, -z, -w);
        }
        [x, y, z, w]
    }

    /// Roll, pitch, yaw (URDF convention).
    pub fn rpy(&self) -> [f64; 3] {
        matrix_to_rpy(&self.r)
    }

    /// `Ad(T) = [[R, 0], [[d]x R, R]]`.
    pub fn adjoint(&self) -> Matrix6<f64> {
        let mut a = Matrix6::zeros();
        a.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.r);
        a.fixed_view_mut::<3, 3>(3, 3).copy_from(&self.r);
        a.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&(skew(&self.d) * self.r));
        a
    }

    /// `Ad(T)^-1 = Ad(T^-1)`, formed directly.
    pub fn adjoint_inverse(&self) -> Matrix6<f64> {
        self.inverse().adjoint()
    }

    /// Lever arm `||d||` (the same for `T` and `T^-1`).
    pub fn lever_arm(&self) -> f64 {
        self.d.norm()
    }

    /// Rotation angle in `[0, pi]` and unit axis (`None` below `ANGLE_ZERO_TOL`).
    ///
    /// The angle is `atan2(sin, cos)` from the skew and trace parts, accurate at
    /// both ends. For `cos(phi) > 0` the axis is the skew part `sin(phi) e`
    /// normalised. Otherwise it comes from the symmetric part
    /// `(R + R^T)/2 - cos(phi) I = (1 - cos phi) e e^T` (its largest-diagonal
    /// column), which stays well conditioned up to and at `phi = pi`, with its sign
    /// taken from the skew part. At an exact half-turn (`sin(phi) <=
    /// HALF_TURN_SIN_TOL`) the skew part carries no sign, so the sign is canonical
    /// here (first non-zero component positive) and [`Transform::screw`] re-signs it
    /// so that `h >= 0`.
    pub fn rotation_angle_axis(&self) -> (f64, Option<Vector3<f64>>) {
        let (phi, e, _) = self.angle_axis_sin();
        (phi, e)
    }

    /// `(phi, e, sin(phi))`, `sin(phi)` as the norm of the skew part.
    fn angle_axis_sin(&self) -> (f64, Option<Vector3<f64>>, f64) {
        let r = &self.r;
        let w = vee_antisym(r); // = sin(phi) e
        let s = w.norm();
        let c = 0.5 * (r.trace() - 1.0);
        let phi = s.atan2(c);
        // NaN (a transform made non-finite through `scaled_translation` cannot
        // reach here, but a NaN rotation would): no axis, never a panic.
        if phi.is_nan() || phi < ANGLE_ZERO_TOL {
            return (phi, None, s);
        }
        if c > 0.0 {
            return (phi, Some(w / s), s);
        }
        // Symmetric part: (1 - c) e e^T; use its largest-diagonal column.
        let b = 0.5 * (r + r.transpose()) - Matrix3::identity() * c;
        let mut k = 0;
        for i in 1..3 {
            if b[(i, i)] > b[(k, k)] {
                k = i;
            }
        }
        let mut e: Vector3<f64> = b.column(k).into_owned();
        e /= e.norm();
        if s > HALF_TURN_SIN_TOL {
            if e.dot(&w) < 0.0 {
                e = -e;
            }
        } else {
            e = canonical_sign(e);
        }
        (phi, Some(e), s)
    }

    /// Chasles decomposition with the zero-pitch tolerance `pitch_tol` (m) on `|h|`.
    ///
    /// `T` is a rotation by `phi` about the line `{c + t e}` followed by a
    /// translation `h` along it: `d = (I - R) c + h e`, `c . e = 0`, so
    /// `c = (d_perp + cot(phi/2) e x d) / 2` with `d_perp = d - h e` (at `phi = pi`
    /// the cotangent is 0 and `c = d_perp / 2`).
    ///
    /// `h(T) = h(T^-1)`: `T^-1 = (R^T, -R^T d)` rotates about `-e`, and
    /// `(-e) . (-R^T d) = (R e) . d = e . d`. At an exact half-turn `R = R^T` and
    /// the axis extraction returns the same `e` for both, which would give
    /// `h(T^-1) = -h(T)`; choosing the sign with `h >= 0` (a half-turn about `e`
    /// and about `-e` are the same rotation) restores the equality.
    ///
    /// `pitch_tol` is an absolute length (m) on `|h|`; a negative or NaN tolerance
    /// classifies every rotation as `General`.
    pub fn screw(&self, pitch_tol: f64) -> Screw {
        let (phi, axis, s) = self.angle_axis_sin();
        let lever = self.lever_arm();
        let Some(mut e) = axis else {
            let kind = if lever <= LENGTH_ZERO_TOL {
                ScrewKind::Identity
            } else {
                ScrewKind::PureTranslation
            };
            return Screw {
                kind,
                angle: phi,
                axis: None,
                translation_along_axis: None,
                pitch: None,
                axis_point: None,
                half_turn: false,
            };
        };
        let half_turn = s <= HALF_TURN_SIN_TOL;
        let mut h = e.dot(&self.d);
        if half_turn && h < 0.0 {
            e = -e;
            h = -h;
        }
        let d_perp = self.d - e * h;
        let half = 0.5 * phi;
        let cot = half.cos() / half.sin();
        let c = 0.5 * (d_perp + e.cross(&self.d) * cot);
        let kind = if h.abs() <= pitch_tol {
            ScrewKind::ZeroPitch
        } else {
            ScrewKind::General
        };
        Screw {
            kind,
            angle: phi,
            axis: Some(e),
            translation_along_axis: Some(h),
            pitch: Some(h / phi),
            axis_point: Some(c),
            half_turn,
        }
    }
}

fn canonical_sign(e: Vector3<f64>) -> Vector3<f64> {
    for k in 0..3 {
        if e[k].abs() > 1e-12 {
            return if e[k] < 0.0 { -e } else { e };
        }
    }
    e
}

fn fmt_quat(q: [f64; 4], order: QuatOrder) -> String {
    let names = match order {
        QuatOrder::Xyzw => "xyzw",
        QuatOrder::Wxyz => "wxyz",
    };
    format!(
        "[{}, {}, {}, {}] ({names})",
        short_num(q[0]),
        short_num(q[1]),
        short_num(q[2]),
        short_num(q[3])
    )
}

/// A number as written in files: plain for ordinary magnitudes, exponent form
/// for very small or large ones (`{}` prints 1e-300 with 300 digits).
fn short_num(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-6..1e9).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// Rounding of published digits (at most `tol`) is a warning; beyond, an error
/// (the severity policy in docs/check.md).
fn rounding_severity(off: f64, tol: f64) -> crate::diagnostic::Severity {
    if off > tol {
        crate::diagnostic::Severity::Error
    } else {
        crate::diagnostic::Severity::Warning
    }
}

/// Check and, if needed, project a 3x3 matrix to SO(3).
/// `warnings`: `None` drops the projection's warning unformatted.
fn checked_rotation(m: &Matrix3<f64>, warnings: Option<&mut Vec<Warning>>) -> Result<Matrix3<f64>> {
    let err = (m.transpose() * m - Matrix3::identity()).norm();
    let det = m.determinant();
    if err.is_nan() || err > ORTHONORMAL_ERROR_TOL {
        return Err(Error::invalid(format!(
            "rotation matrix: expected orthonormal (||R^T R - I||_F <= {ORTHONORMAL_ERROR_TOL:e}), found ||R^T R - I||_F = {err:.3e}, det = {det:.6}"
        )));
    }
    if det < 0.0 {
        return Err(Error::invalid(format!(
            "rotation matrix: expected det +1, found det = {det:.6} (a reflection, not a rotation: check the handedness of the frames)"
        )));
    }
    if err <= ORTHONORMAL_EXACT_TOL {
        return Ok(*m);
    }
    if let Some(warnings) = warnings.filter(|_| err > ORTHONORMAL_WARN_TOL) {
        warnings.push(
            Warning::new(
                Code::NonOrthonormalRotation,
                format!(
                    "rotation matrix is orthonormal only to ||R^T R - I||_F = {err:.3e} (det {det:.9}); projected to the nearest rotation"
                ),
            )
            .with_severity(rounding_severity(err, ORTHONORMAL_ROUNDING_TOL)),
        );
    }
    nearest_rotation(m).ok_or_else(|| Error::invalid("rotation matrix: SVD did not converge"))
}

/// The nearest rotation `U V^T` of `m` (its SVD), `None` when the SVD does
/// not converge; remembered per thread by the exact bits of `m`. A rig
/// file's rounding derivative projects eighteen perturbed matrices, and the
/// files of a fleet share their rotations: the SVD was a seventh of checking
/// a rig file (issue 29). The same bits in, the same bits out.
fn nearest_rotation(m: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    use std::cell::RefCell;
    use std::collections::HashMap;
    /// Entries kept per thread (about 150 bytes each) before the table is
    /// emptied and refilled: bounded memory whatever the input.
    const KEPT: usize = 4096;
    type Table = HashMap<[u64; 9], Option<[f64; 9]>, foldhash::fast::RandomState>;
    thread_local! {
        static SEEN: RefCell<Table> = RefCell::new(Table::default());
    }
    let key: [u64; 9] = std::array::from_fn(|k| m.as_slice()[k].to_bits());
    let hit = SEEN.with_borrow(|t| t.get(&key).copied());
    let r = match hit {
        Some(r) => r,
        None => {
            let svd = m.svd(true, true);
            let r = match (svd.u, svd.v_t) {
                (Some(u), Some(vt)) => {
                    let p = u * vt;
                    Some(std::array::from_fn(|k| p.as_slice()[k]))
                }
                _ => None,
            };
            SEEN.with_borrow_mut(|t| {
                if t.len() >= KEPT {
                    t.clear();
                }
                t.insert(key, r);
            });
            r
        }
    };
    r.map(|a: [f64; 9]| Matrix3::from_column_slice(&a))
}

/// Kind of rigid motion (Chasles).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ScrewKind {
    /// No rotation (angle below `ANGLE_ZERO_TOL`) and no translation
    /// (`||d||` at most `LENGTH_ZERO_TOL`).
    Identity,
    /// No rotation, nonzero translation: no axis, no pitch.
    PureTranslation,
    /// A rotation whose screw translation `|h| = |e . d|` is within the pitch
    /// tolerance: a pure rotation about an axis that may miss the origin.
    ZeroPitch,
    /// A rotation with nonzero screw translation `h` (a helical motion).
    General,
}

impl ScrewKind {
    /// The name in the JSON reports (`screw.kind`, README "JSON").
    pub fn name(self) -> &'static str {
        match self {
            ScrewKind::Identity => "identity",
            ScrewKind::PureTranslation => "pure_translation",
            ScrewKind::ZeroPitch => "zero_pitch",
            ScrewKind::General => "general",
        }
    }

    /// The name in text and markdown (`pure translation`): [`Self::name`]
    /// with spaces, one name across the rig report and the diff.
    pub fn label(self) -> &'static str {
        match self {
            ScrewKind::Identity => "identity",
            ScrewKind::PureTranslation => "pure translation",
            ScrewKind::ZeroPitch => "zero pitch",
            ScrewKind::General => "general",
        }
    }
}

/// Screw decomposition of a transform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Screw {
    /// Which kind of motion; decides which of the optional fields are set.
    pub kind: ScrewKind,
    /// Rotation angle `phi` in `[0, pi]`.
    pub angle: f64,
    /// Unit axis `e`; `None` for identity and pure translation.
    pub axis: Option<Vector3<f64>>,
    /// `h = e . d` (m); the same for `T` and `T^-1`.
    pub translation_along_axis: Option<f64>,
    /// `h / phi` (m/rad).
    pub pitch: Option<f64>,
    /// The point of the screw axis closest to the origin of `from` (m).
    pub axis_point: Option<Vector3<f64>>,
    /// `sin(phi) <= HALF_TURN_SIN_TOL`: the axis sign was chosen by `h >= 0`.
    pub half_turn: bool,
}
