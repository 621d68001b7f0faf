//! Uncertainty of an edge and of a composed chain: the precision of the numbers
//! as written, the user's calibration uncertainty, and their first-order
//! propagation to the quantities the rig report prints.
//!
//! # Conventions (stated once here; docs/CONVENTIONS.md repeats them)
//!
//! - Tangent of one edge: `xi = [omega; t]` (rad, m), applied on the right,
//!   `T' = T * (Exp(omega), t)`. Its first order is the body perturbation
//!   `T exp(xi^)` of [`crate::geometry::se3`]; the covariance of `xi` is the
//!   edge's covariance.
//! - Rounding: a number written with its last decimal at place `10^-k` stands
//!   for any value within half a unit of it, uniformly, so its standard
//!   uncertainty is `0.5 * 10^-k / sqrt(3)`. In a tuple (`xyz="0 0 0.1235"`)
//!   zeros and numbers written as integers adopt the finest place written in
//!   the same tuple; a tuple of zeros and integers only is exact. A literal
//!   with [`EXACT_SIGNIFICANT_DIGITS`] or more significant digits is the
//!   shortest print of a double (a xacro expression such as `${pi/2}` prints so)
//!   and counts as exact. The covariance of the edge is
//!   `J diag(u_i^2) J^T` with `J` the derivative of the tangent by the written
//!   parameters (central differences through the format's own constructor).
//! - User uncertainty (`--sigma-t M`, `--sigma-r DEG`): independent, isotropic,
//!   per edge: `diag(sigma_r^2 I3, sigma_t^2 I3)`, added to the rounding.
//! - Propagation: first order through the chain. The edges' covariances are
//!   carried to the composed transform's tangent with adjoints
//!   ([`chain_covariance`], linear in the chain's length), then to each output
//!   with `Sigma_y = J Sigma_T J^T`, `J` by central differences. The
//!   rotation angle and `h` are taken against the nominal screw axis (the angle
//!   unwrapped past `pi`), so both are smooth through a half-turn.
//! - Three-way pitch verdict with `auto` tolerance (constants in
//!   [`crate::tolerances`]): `zero` when `|h| <= PITCH_FLOAT_FLOOR_M` (zero to
//!   double precision) or `|h| <= PITCH_K * sigma_h <= PITCH_RESOLUTION_M`;
//!   `nonzero` when `|h| > max(PITCH_K * sigma_h, PITCH_FLOAT_FLOOR_M)`;
//!   otherwise `undecidable`: `h` is within `PITCH_K` standard uncertainties of
//!   zero, but those are too wide for zero to mean anything. A standard
//!   uncertainty below `max(|h|, PITCH_RESOLUTION_M) / PITCH_K` decides it.
//!   With an explicit tolerance the verdict is two-way: `|h| <= tol`.
//! - Not covered: errors of the model (a wrong frame, a wrong convention),
//!   correlations between edges, and rounding that happened before the
//!   numbers were written (a calibration printed to 6 digits from a solver
//!   accurate to 3): the user's `--sigma-t`/`--sigma-r` carry those.

use super::se3::{QuatOrder, ScrewKind, Transform};
use crate::diagnostic::Result;
use crate::tolerances::{
    EXACT_SIGNIFICANT_DIGITS, MAX_SIGMA_R_DEG, MAX_SIGMA_T_M, PITCH_FLOAT_FLOOR_M, PITCH_K,
    PITCH_RESOLUTION_M, UNCERTAINTY_STEP,
};
use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};
use serde::Serialize;

/// The half-unit of the last written decimal of one number literal, or `None`
/// when it is written as an integer (no `.`, no exponent) or is zero: those
/// adopt the tuple's finest place ([`tuple_half_units`]). `Some(0.0)` means
/// exact (a double printed in full).
pub fn literal_half_unit(text: &str) -> Option<f64> {
    plain_half_unit(text).unwrap_or_else(|| general_half_unit(text))
}

fn general_half_unit(text: &str) -> Option<f64> {
    let t = text.trim().trim_start_matches(['+', '-']);
    let (mant, exp) = match t.find(['e', 'E']) {
        Some(i) => (&t[..i], t[i + 1..].parse::<i32>().ok()?),
        None => (t, 0),
    };
    if !mant.bytes().all(|b| b.is_ascii_digit() || b == b'.') {
        return None;
    }
    // Significant digits: from the first non-zero digit on.
    let significant = mant
        .bytes()
        .filter(u8::is_ascii_digit)
        .skip_while(|&b| b == b'0')
        .count();
    if significant == 0 {
        return None; // zero, in any spelling
    }
    if significant >= EXACT_SIGNIFICANT_DIGITS {
        return Some(0.0);
    }
    let decimals = match mant.find('.') {
        Some(i) => (mant.len() - i - 1) as i32,
        None if exp == 0 => return None,
        None => 0,
    };
    Some(0.5 * 10f64.powi(exp - decimals))
}

/// [`literal_half_unit`] of the common literal in one pass over its bytes:
/// signs, then digits and dots only (`None` for anything else, white space or
/// an exponent: the general path reads those). A URDF reads six per joint.
fn plain_half_unit(text: &str) -> Option<Option<f64>> {
    let b = text.as_bytes();
    let mant = &b[b.iter().take_while(|&&c| c == b'+' || c == b'-').count()..];
    let (mut significant, mut dot) = (0usize, None);
    for (k, &c) in mant.iter().enumerate() {
        match c {
            b'0' if significant == 0 => {}
            b'0'..=b'9' => significant += 1,
            b'.' => dot = dot.or(Some(k)),
            _ => return None,
        }
    }
    Some(if significant == 0 {
        None // zero, in any spelling
    } else if significant >= EXACT_SIGNIFICANT_DIGITS {
        Some(0.0)
    } else {
        dot.map(|d| 0.5 * 10f64.powi(-((mant.len() - d - 1) as i32)))
    })
}

/// Half-units of the numbers of one tuple as written (see the module
/// conventions): integers and zeros take the finest place of the tuple, a
/// tuple without any decimal is exact.
pub fn tuple_half_units(texts: &[&str]) -> Vec<f64> {
    let mut out = vec![0.0; texts.len()];
    fill_half_units(texts, &mut out);
    out
}

/// [`tuple_half_units`] of a fixed-size tuple, without allocating (the URDF
/// reader's path, once per joint).
pub fn half_units<const N: usize>(texts: &[&str; N]) -> [f64; N] {
    let mut out = [0.0; N];
    fill_half_units(texts, &mut out);
    out
}

fn fill_half_units(texts: &[&str], out: &mut [f64]) {
    // NaN marks "adopts the finest place" (a half-unit is never NaN).
    let mut finest = f64::INFINITY;
    for (o, t) in out.iter_mut().zip(texts) {
        *o = literal_half_unit(t).unwrap_or(f64::NAN);
        finest = finest.min(*o);
    }
    let fill = if finest.is_finite() { finest } else { 0.0 };
    for o in out.iter_mut().filter(|o| o.is_nan()) {
        *o = fill;
    }
}

/// Half-units of a tuple of parsed numbers, from the digits of their shortest
/// print (for readers that keep no text). That print is the written literal
/// without its trailing zeros, so the half-unit is never smaller than the
/// written one: the uncertainty errs on the wide side.
pub fn value_half_units(xs: &[f64]) -> Vec<f64> {
    // `{:e}` prints the shortest digits (`1.2345e-1`); a whole number prints
    // as an integer, which adopts the tuple's finest place.
    let texts: Vec<String> = xs
        .iter()
        .map(|x| {
            if x.fract() == 0.0 && x.abs() < 1e15 {
                format!("{x:.0}")
            } else {
                format!("{x:e}")
            }
        })
        .collect();
    let refs: Vec<&str> = texts.iter().map(String::as_str).collect();
    tuple_half_units(&refs)
}

/// The tangent covariance of `(Rz(yaw) Ry(pitch) Rx(roll), d)` from
/// independent standard uncertainties of `d` (`u_d`, m) and of `rpy`
/// (`u_rpy`, rad), in closed form: the translation tangent is `R^T delta_d`,
/// the rotation tangent the body angular velocity
/// `[1, 0, -sp; 0, cr, sr cp; 0, -sr, cr cp] delta_rpy`. The same as
/// [`rounding_covariance`] through [`Transform::from_rpy`] (tested), without
/// its twelve constructions per edge (a URDF may hold 100,000 joints).
pub fn rpy_covariance(rpy: [f64; 3], u_d: [f64; 3], u_rpy: [f64; 3]) -> Result<Matrix6<f64>> {
    if !rpy.iter().all(|x| x.is_finite()) {
        return Err(crate::diagnostic::Error::invalid(format!(
            "rpy {rpy:?}: expected finite angles"
        )));
    }
    let rt = tr(&m3(&super::se3::rpy_to_matrix(rpy[0], rpy[1], rpy[2])));
    let (sr, cr) = rpy[0].sin_cos();
    let (sp, cp) = rpy[1].sin_cos();
    let jr: M3 = [[1.0, 0.0, -sp], [0.0, cr, sr * cp], [0.0, -sr, cr * cp]];
    let sq = |u: [f64; 3]| -> M3 {
        [
            [u[0] * u[0], 0.0, 0.0],
            [0.0, u[1] * u[1], 0.0],
            [0.0, 0.0, u[2] * u[2]],
        ]
    };
    let mut cov = Matrix6::zeros();
    put(&mut cov, 0, 0, &mul(&mul(&jr, &sq(u_rpy)), &tr(&jr)));
    put(&mut cov, 3, 3, &mul(&mul(&rt, &sq(u_d)), &tr(&rt)));
    Ok(cov)
}

/// A rotation as a reader parsed it (its numbers, in the file's order).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Written {
    /// URDF `rpy` (rad).
    Rpy([f64; 3]),
    /// `yaw pitch roll` (rad).
    Ypr([f64; 3]),
    /// A quaternion in the given order.
    Quat([f64; 4], QuatOrder),
    /// A 3x3 matrix, row-major.
    Matrix3([[f64; 3]; 3]),
}

/// The rounding of a rotation and translation `d` written as decimal numbers
/// (digits from [`value_half_units`]; rotation and translation each one
/// tuple), with the translation scaled by `scale` afterwards (1e-3 for a file
/// in millimetres). `default` (none recorded) when the constructor refuses.
pub fn written_precision(rot: Written, d: [f64; 3], scale: f64) -> EdgePrecision {
    if let Written::Rpy(rpy) = rot {
        let (hd, hr) = (value_half_units(&d), value_half_units(&rpy));
        let u = |h: &[f64]| [rounding_std(h[0]), rounding_std(h[1]), rounding_std(h[2])];
        let cov = rpy_covariance(rpy, u(&hd), u(&hr));
        return precision_or_none(cov).scaled_translation(scale);
    }
    let rp: Vec<f64> = match rot {
        Written::Rpy(a) | Written::Ypr(a) => a.to_vec(),
        Written::Quat(q, _) => q.to_vec(),
        Written::Matrix3(m) => m.as_flattened().to_vec(),
    };
    let mut params = d.to_vec();
    let mut halves = value_half_units(&d);
    halves.extend(value_half_units(&rp));
    params.extend(rp);
    let build = |p: &[f64]| {
        let d = [p[0], p[1], p[2]];
        let r = &p[3..];
        let t = match rot {
            Written::Rpy(_) => Transform::from_rpy([r[0], r[1], r[2]], d),
            Written::Ypr(_) => Transform::from_ypr([r[0], r[1], r[2]], d),
            Written::Quat(_, order) => {
                Transform::from_quaternion([r[0], r[1], r[2], r[3]], order, d, &mut Vec::new())
            }
            Written::Matrix3(_) => Transform::from_matrix3(
                [[r[0], r[1], r[2]], [r[3], r[4], r[5]], [r[6], r[7], r[8]]],
                d,
                &mut Vec::new(),
            ),
        }?;
        Ok(t.scaled_translation(scale))
    };
    precision_or_none(rounding_covariance(&params, &halves, build))
}

/// The rounding of a homogeneous matrix written as decimals (its top three
/// rows are one tuple), translation scaled by `scale` afterwards.
pub fn matrix4_precision(m: [[f64; 4]; 4], scale: f64) -> EdgePrecision {
    let params: Vec<f64> = m[..3].as_flattened().to_vec();
    let halves = value_half_units(&params);
    let build = |p: &[f64]| {
        let r = [[p[0], p[1], p[2]], [p[4], p[5], p[6]], [p[8], p[9], p[10]]];
        let t = Transform::from_matrix3(r, [p[3], p[7], p[11]], &mut Vec::new())?;
        Ok(t.scaled_translation(scale))
    };
    precision_or_none(rounding_covariance(&params, &halves, build))
}

fn precision_or_none(cov: Result<Matrix6<f64>>) -> EdgePrecision {
    match cov {
        Ok(c) => EdgePrecision {
            rounding: Some(c),
            user: None,
        },
        Err(_) => EdgePrecision::default(),
    }
}

/// The standard uncertainty of a uniform rounding of half-width `half`.
pub fn rounding_std(half: f64) -> f64 {
    half / 3f64.sqrt()
}

/// The tangent `[omega; t]` that takes `t0` to `t1` on the right,
/// `t1 = t0 * (Exp(omega), t)` (small rotations: the skew part of
/// `R0^T R1` is `sin|omega|` times its axis).
pub fn tangent_between(t0: &Transform, t1: &Transform) -> Vector6<f64> {
    let r0t = t0.rotation().transpose();
    let dr = r0t * t1.rotation();
    let w = Vector3::new(
        0.5 * (dr[(2, 1)] - dr[(1, 2)]),
        0.5 * (dr[(0, 2)] - dr[(2, 0)]),
        0.5 * (dr[(1, 0)] - dr[(0, 1)]),
    );
    let s = w.norm().min(1.0);
    let omega = if s > 0.0 { w * (s.asin() / s) } else { w };
    let dt = r0t * (t1.translation() - t0.translation());
    Vector6::new(omega.x, omega.y, omega.z, dt.x, dt.y, dt.z)
}

/// `t * (Exp(omega), t)` for a tangent `xi = [omega; t]`.
pub fn perturbed(t: &Transform, xi: &Vector6<f64>) -> Result<Transform> {
    let delta = Transform::from_rotation_vector([xi[0], xi[1], xi[2]], [xi[3], xi[4], xi[5]])?;
    Ok(t.compose(&delta))
}

/// The covariance of an edge's tangent from the rounding of its written
/// parameters: `params` as parsed, `halves` their half-units (0: exact),
/// `build` the format's constructor from the parameters. A parameter step the
/// constructor refuses (e.g. at the edge of its domain) contributes nothing.
pub fn rounding_covariance(
    params: &[f64],
    halves: &[f64],
    build: impl Fn(&[f64]) -> Result<Transform>,
) -> Result<Matrix6<f64>> {
    let t0 = build(params)?;
    let mut cov = Matrix6::zeros();
    // The steps' parameters on the stack (a rig's transform has at most 19).
    let (mut stack, mut heap) = ([0.0; 24], Vec::new());
    let p: &mut [f64] = if params.len() <= stack.len() {
        &mut stack[..params.len()]
    } else {
        heap.resize(params.len(), 0.0);
        &mut heap
    };
    p.copy_from_slice(params);
    for (i, (&x, &half)) in params.iter().zip(halves).enumerate() {
        if half <= 0.0 {
            continue;
        }
        let step = UNCERTAINTY_STEP * x.abs().max(1.0);
        p[i] = x + step;
        let plus = build(p);
        p[i] = x - step;
        let minus = build(p);
        p[i] = x;
        let (Ok(plus), Ok(minus)) = (plus, minus) else {
            continue;
        };
        let col = (tangent_between(&t0, &plus) - tangent_between(&t0, &minus)) / (2.0 * step);
        let u = rounding_std(half);
        cov += col * col.transpose() * (u * u);
    }
    Ok(cov)
}

/// The user's calibration uncertainty of one edge (`--sigma-t`, `--sigma-r`,
/// or `sigma_t_m`/`sigma_r_deg` of a rig TOML file).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct UserSigma {
    /// Standard uncertainty of each translation component (m).
    pub sigma_t_m: f64,
    /// Standard uncertainty of each rotation component (rad).
    pub sigma_r_rad: f64,
}

impl UserSigma {
    /// `sigma_t_m` (m, 0 to [`MAX_SIGMA_T_M`]) and `sigma_r_deg` (degrees,
    /// 0 to [`MAX_SIGMA_R_DEG`]), checked: the ranges of `--sigma-t` and
    /// `--sigma-r`.
    ///
    /// ```
    /// use extrinsic_audit::UserSigma;
    ///
    /// let s = UserSigma::new(0.002, 0.5).unwrap();
    /// assert_eq!(s.sigma_r_rad, 0.5_f64.to_radians());
    /// assert!(UserSigma::new(-0.001, 0.0).is_err());
    /// assert!(UserSigma::new(0.0, 11.0).is_err());
    /// ```
    pub fn new(sigma_t_m: f64, sigma_r_deg: f64) -> Result<UserSigma> {
        let check = |v: f64, max: f64, what: &str, unit: &str| {
            if (0.0..=max).contains(&v) {
                Ok(())
            } else {
                Err(crate::diagnostic::Error::usage(format!(
                    "{what}: expected 0 to {max} {unit}, found {v}"
                )))
            }
        };
        check(sigma_t_m, MAX_SIGMA_T_M, "sigma_t", "m")?;
        check(sigma_r_deg, MAX_SIGMA_R_DEG, "sigma_r", "deg")?;
        Ok(UserSigma {
            sigma_t_m,
            sigma_r_rad: sigma_r_deg.to_radians(),
        })
    }

    /// `diag(sigma_r^2 I3, sigma_t^2 I3)`.
    pub fn covariance(&self) -> Matrix6<f64> {
        let (r2, t2) = (self.sigma_r_rad.powi(2), self.sigma_t_m.powi(2));
        Matrix6::from_diagonal(&Vector6::new(r2, r2, r2, t2, t2, t2))
    }

    /// Both zero.
    pub fn is_zero(&self) -> bool {
        self.sigma_t_m == 0.0 && self.sigma_r_rad == 0.0
    }
}

/// The uncertainty an edge carries (a field of [`crate::frames::Edge`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EdgePrecision {
    /// Covariance of the tangent from the rounding of the numbers as written;
    /// `None` when the format records none (a binary file, or a reader that
    /// keeps no text).
    pub rounding: Option<Matrix6<f64>>,
    /// The user's calibration uncertainty, when given.
    pub user: Option<UserSigma>,
}

impl EdgePrecision {
    /// Exact numbers (integers only, or doubles printed in full).
    pub fn exact() -> Self {
        EdgePrecision {
            rounding: Some(Matrix6::zeros()),
            user: None,
        }
    }

    /// The tangent covariance, rounding and user uncertainty added.
    pub fn covariance(&self) -> Matrix6<f64> {
        self.rounding.unwrap_or_else(Matrix6::zeros)
            + self
                .user
                .map(|u| u.covariance())
                .unwrap_or_else(Matrix6::zeros)
    }

    /// The same for the transform with its translation scaled by `s` (a file
    /// in millimetres read in metres): the translation tangent scales by `s`.
    pub fn scaled_translation(mut self, s: f64) -> Self {
        if let Some(c) = &mut self.rounding {
            let m = Matrix6::from_diagonal(&Vector6::new(1.0, 1.0, 1.0, s, s, s));
            *c = m * *c * m;
        }
        self
    }

    fn has_rounding(&self) -> bool {
        self.rounding.is_some_and(|c| c.iter().any(|x| *x != 0.0))
    }

    fn has_user(&self) -> bool {
        self.user.is_some_and(|u| !u.is_zero())
    }
}

/// The uncertainty an edge carries, as the edge stores it: the same content
/// as [`EdgePrecision`] in a fifth of the room (issue 12: an eager 6x6
/// covariance was 288 of an edge's 608 bytes). A URDF `rpy` origin keeps its
/// angles and the standard uncertainties of its six numbers, and its
/// covariance is computed where it is used ([`rpy_covariance`], the same
/// arithmetic as when it was stored); any other covariance is boxed.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Precision {
    rounding: Rounding,
    /// The user's calibration uncertainty, when given.
    pub user: Option<UserSigma>,
}

#[derive(Debug, Clone, PartialEq, Default)]
enum Rounding {
    /// No rounding recorded.
    #[default]
    None,
    /// Exact numbers: a zero covariance.
    Exact,
    /// `rpy_covariance(rpy, u_d, u_rpy)`.
    Rpy {
        rpy: [f64; 3],
        u_d: [f64; 3],
        u_rpy: [f64; 3],
    },
    Matrix(Box<Matrix6<f64>>),
}

impl Precision {
    /// The rounding of a URDF-style `rpy` origin: angles `rpy` (rad) and the
    /// standard uncertainties of the translation (`u_d`, m) and of the angles
    /// (`u_rpy`, rad); none when the angles are not finite.
    pub fn rpy(rpy: [f64; 3], u_d: [f64; 3], u_rpy: [f64; 3]) -> Self {
        let rounding = if rpy.iter().all(|x| x.is_finite()) {
            Rounding::Rpy { rpy, u_d, u_rpy }
        } else {
            Rounding::None
        };
        Precision {
            rounding,
            user: None,
        }
    }

    /// The covariance of the rounding, `None` when none is recorded.
    pub fn rounding(&self) -> Option<Matrix6<f64>> {
        match &self.rounding {
            Rounding::None => None,
            Rounding::Exact => Some(Matrix6::zeros()),
            Rounding::Rpy { rpy, u_d, u_rpy } => rpy_covariance(*rpy, *u_d, *u_rpy).ok(),
            Rounding::Matrix(m) => Some(**m),
        }
    }

    /// Whether a rounding is recorded.
    pub fn has_recorded_rounding(&self) -> bool {
        !matches!(self.rounding, Rounding::None)
    }

    /// The rounding's covariance carried by `a`: `a C a^T` (an adjoint).
    pub fn transform_rounding(&mut self, a: &Matrix6<f64>) {
        if let Some(c) = self.rounding() {
            self.rounding = Rounding::Matrix(Box::new(a * c * a.transpose()));
        }
    }

    /// The full record, covariance computed.
    pub fn full(&self) -> EdgePrecision {
        EdgePrecision {
            rounding: self.rounding(),
            user: self.user,
        }
    }
}

impl From<EdgePrecision> for Precision {
    fn from(p: EdgePrecision) -> Self {
        let rounding = match p.rounding {
            None => Rounding::None,
            Some(c) if c.iter().all(|x| *x == 0.0 && x.is_sign_positive()) => Rounding::Exact,
            Some(c) => Rounding::Matrix(Box::new(c)),
        };
        Precision {
            rounding,
            user: p.user,
        }
    }
}

/// Where a chain's uncertainty comes from (JSON `uncertainty.source`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum UncertaintySource {
    /// Every number exact (or no format recorded its rounding) and no user value.
    None,
    /// The rounding of the numbers as written only.
    Rounding,
    /// The user's `--sigma-t`/`--sigma-r` only.
    User,
    /// Both.
    Both,
}

impl UncertaintySource {
    /// The JSON name.
    pub fn name(self) -> &'static str {
        match self {
            UncertaintySource::None => "none",
            UncertaintySource::Rounding => "rounding",
            UncertaintySource::User => "user",
            UncertaintySource::Both => "both",
        }
    }

    /// The source of a chain of edges.
    pub fn of<'a>(edges: impl IntoIterator<Item = &'a EdgePrecision>) -> Self {
        let (mut r, mut u) = (false, false);
        for e in edges {
            r |= e.has_rounding();
            u |= e.has_user();
        }
        match (r, u) {
            (false, false) => UncertaintySource::None,
            (true, false) => UncertaintySource::Rounding,
            (false, true) => UncertaintySource::User,
            (true, true) => UncertaintySource::Both,
        }
    }
}

/// One step of a chain as the propagation sees it.
#[derive(Debug, Clone, Copy)]
pub struct Step {
    /// The edge's transform as stored (pose of its child in its parent).
    pub transform: Transform,
    /// Walked child -> parent: enters inverted.
    pub inverted: bool,
    /// Covariance of the edge's tangent.
    pub covariance: Matrix6<f64>,
}

/// The product of the steps, each edge perturbed by its tangent in `xi`
/// (six entries per step; `None`: nominal).
pub fn compose_steps(steps: &[Step], xi: Option<&[f64]>) -> Result<Transform> {
    let mut t = Transform::identity();
    for (i, s) in steps.iter().enumerate() {
        let e = match xi {
            Some(x) => perturbed(
                &s.transform,
                &Vector6::from_column_slice(&x[6 * i..6 * i + 6]),
            )?,
            None => s.transform,
        };
        t = t.compose(&if s.inverted { e.inverse() } else { e });
    }
    Ok(t)
}

/// The quantities propagated, for a transform `t` measured against the
/// nominal axis `e0` (`None`: no rotation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outputs {
    /// `||d||` (m).
    pub lever_arm: f64,
    /// Rotation angle (rad), unwrapped past `pi` against `e0`.
    pub angle: f64,
    /// `h = e . d` (m) along the axis aligned with `e0`; 0 without `e0`.
    pub h: f64,
}

/// `Outputs` of `t` against the nominal axis `e0`.
pub fn outputs(t: &Transform, e0: Option<&Vector3<f64>>) -> Outputs {
    let (mut phi, axis) = t.rotation_angle_axis();
    let h = match (axis, e0) {
        (Some(mut e), Some(e0)) => {
            if e.dot(e0) < 0.0 {
                e = -e;
                phi = 2.0 * std::f64::consts::PI - phi;
            }
            e.dot(t.translation())
        }
        _ => 0.0,
    };
    Outputs {
        lever_arm: t.lever_arm(),
        angle: phi,
        h,
    }
}

/// First-order standard uncertainties of a chain's report quantities.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainUncertainty {
    /// Of the lever arm `||d||` (m).
    pub lever_arm_m: f64,
    /// Of the rotation angle (rad). Without a rotation axis: the square root
    /// of the largest eigenvalue of the composed rotation covariance.
    pub angle_rad: f64,
    /// Of `h` (m); `None` without a rotation axis.
    pub h_m: Option<f64>,
    /// Of the pitch `h / phi` (m/rad); `None` without a rotation axis.
    pub pitch_m_per_rad: Option<f64>,
    /// Covariance of the composed transform's tangent (right, `[omega; t]`).
    pub transform_covariance: Matrix6<f64>,
}

/// The covariance of the composed transform's tangent (right, `[omega; t]`),
/// in one pass: perturbing step `i` on the right moves the product
/// `T = A S_i B` by `T Exp(G_i xi)` with `G_i = Ad(B^-1)` for a step walked
/// down and `G_i = -Ad(B^-1 T_i)` for one walked up (`S_i = T_i^-1`), so
/// `Sigma_T = sum G_i Sigma_i G_i^T` (first order).
pub fn chain_covariance(steps: &[Step]) -> Matrix6<f64> {
    chain_covariance_and_product(steps).0
}

/// [`chain_covariance`] and the product of the steps (the suffix after the
/// last step walked back is the whole chain).
fn chain_covariance_and_product(steps: &[Step]) -> (Matrix6<f64>, M3, [f64; 3]) {
    let mut cov = Matrix6::zeros();
    // B = (rb, db): the product after step i.
    let (mut rb, mut db): (M3, [f64; 3]) = (
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        [0.0; 3],
    );
    for s in steps.iter().rev() {
        let ri = m3(s.transform.rotation());
        let di: [f64; 3] = (*s.transform.translation()).into();
        let rbt = tr(&rb);
        if s.covariance.iter().any(|x| *x != 0.0) {
            // X = B^-1 (down) or B^-1 T_i (up); the sign of G_i cancels.
            let (rx, dx) = if s.inverted {
                (mul(&rbt, &ri), apply(&rbt, &sub(&di, &db)))
            } else {
                (rbt, apply(&rbt, &sub(&[0.0; 3], &db)))
            };
            cov += adjoint_congruence(&rx, &dx, &s.covariance);
        }
        // B <- S_i B with S_i = T_i or T_i^-1.
        (rb, db) = if s.inverted {
            let rit = tr(&ri);
            (mul(&rit, &rb), apply(&rit, &sub(&db, &di)))
        } else {
            let t = apply(&ri, &db);
            (mul(&ri, &rb), [t[0] + di[0], t[1] + di[1], t[2] + di[2]])
        };
    }
    (cov, rb, db)
}

fn apply(a: &M3, v: &[f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2])
}

fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// A 3x3 block as plain arrays: a chain may hold 100,000 edges and the
/// generic small-matrix code is slow in unoptimised (test) builds.
type M3 = [[f64; 3]; 3];

fn m3(m: &Matrix3<f64>) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

fn mul(a: &M3, b: &M3) -> M3 {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j])
    })
}

fn tr(a: &M3) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[j][i]))
}

fn add(a: &M3, b: &M3) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][j] + b[i][j]))
}

fn block(s: &Matrix6<f64>, r: usize, c: usize) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| s[(r + i, c + j)]))
}

fn put(out: &mut Matrix6<f64>, r: usize, c: usize, m: &M3) {
    for (i, row) in m.iter().enumerate() {
        for (j, x) in row.iter().enumerate() {
            out[(r + i, c + j)] = *x;
        }
    }
}

/// `Ad(X) S Ad(X)^T` by 3x3 blocks for `X = (r, d)` (`Ad(X) = [[R, 0],
/// [P R, R]]`, `P = [d]x`): a rotation of both blocks, then the shear by `P`.
fn adjoint_congruence(r: &M3, d: &[f64; 3], s: &Matrix6<f64>) -> Matrix6<f64> {
    let p: M3 = [[0.0, -d[2], d[1]], [d[2], 0.0, -d[0]], [-d[1], d[0], 0.0]];
    let (rt, pt) = (tr(r), tr(&p));
    let rot = |m: M3| mul(&mul(r, &m), &rt);
    let a = rot(block(s, 0, 0));
    let b = rot(block(s, 0, 3));
    let c = rot(block(s, 3, 3));
    let pa = mul(&p, &a);
    let bt = tr(&b);
    let lower_left = add(&pa, &bt);
    let lower_right = add(&add(&mul(&pa, &pt), &mul(&p, &b)), &add(&mul(&bt, &pt), &c));
    let mut out = Matrix6::zeros();
    put(&mut out, 0, 0, &a);
    put(&mut out, 0, 3, &tr(&lower_left));
    put(&mut out, 3, 0, &lower_left);
    put(&mut out, 3, 3, &lower_right);
    out
}

/// First-order propagation of the steps' covariances to the chain's outputs
/// (see the module conventions); `e0` is the nominal screw axis. Linear in
/// the number of steps: [`chain_covariance`], then the outputs' derivatives
/// by the composed tangent (central differences).
pub fn propagate(steps: &[Step], e0: Option<&Vector3<f64>>) -> Result<ChainUncertainty> {
    let (tcov, r, d) = chain_covariance_and_product(steps);
    let nominal = Transform::from_matrix3(r, d, &mut Vec::new())?;
    let y0 = outputs(&nominal, e0);
    // Rows: lever arm, angle, h, pitch.
    let mut jac = nalgebra::Matrix4x6::<f64>::zeros();
    for c in 0..6 {
        let mut xi = Vector6::zeros();
        xi[c] = UNCERTAINTY_STEP;
        let p = outputs(&perturbed(&nominal, &xi)?, e0);
        let m = outputs(&perturbed(&nominal, &-xi)?, e0);
        let col = [
            p.lever_arm - m.lever_arm,
            p.angle - m.angle,
            p.h - m.h,
            p.h / p.angle - m.h / m.angle,
        ];
        for (r, v) in col.iter().enumerate() {
            jac[(r, c)] = v / (2.0 * UNCERTAINTY_STEP);
        }
    }
    let cov = jac * tcov * jac.transpose();
    let sd = |r: usize| cov[(r, r)].max(0.0).sqrt();
    let has_axis = e0.is_some() && y0.angle > 0.0;
    let angle_rad = if has_axis {
        sd(1)
    } else {
        let rot: Matrix3<f64> = tcov.fixed_view::<3, 3>(0, 0).into_owned();
        rot.symmetric_eigenvalues().max().max(0.0).sqrt()
    };
    Ok(ChainUncertainty {
        lever_arm_m: sd(0),
        angle_rad,
        h_m: has_axis.then(|| sd(2)),
        pitch_m_per_rad: has_axis.then(|| sd(3)),
        transform_covariance: tcov,
    })
}

/// The derivative of `f` at `x` by central differences (for the closed-form
/// quantities of the lever arm: singular values and band edges).
pub fn derivative(f: impl Fn(f64) -> f64, x: f64) -> f64 {
    let step = UNCERTAINTY_STEP * x.abs().max(1.0);
    (f(x + step) - f(x - step)) / (2.0 * step)
}

/// The screw-pitch verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PitchVerdict {
    /// `h` is zero within the tolerance: an adapted constant metric exists.
    Zero,
    /// `h` is beyond the tolerance.
    Nonzero,
    /// `h` is within `PITCH_K` standard uncertainties of zero, but they exceed
    /// `PITCH_RESOLUTION_M`: this precision cannot tell.
    Undecidable,
}

impl PitchVerdict {
    /// The JSON name.
    pub fn name(self) -> &'static str {
        match self {
            PitchVerdict::Zero => "zero",
            PitchVerdict::Nonzero => "nonzero",
            PitchVerdict::Undecidable => "undecidable",
        }
    }
}

/// `--pitch-tol`: `auto` (the three-way verdict, the default) or a length in
/// metres.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum PitchTol {
    /// Decided from `h` and its standard uncertainty.
    #[default]
    Auto,
    /// `|h| <= tol` (m): two-way.
    Fixed(f64),
}

impl std::str::FromStr for PitchTol {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        if s.trim().eq_ignore_ascii_case("auto") {
            return Ok(PitchTol::Auto);
        }
        match s.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && v >= 0.0 => Ok(PitchTol::Fixed(v)),
            _ => Err(format!(
                "expected `auto` or a finite length >= 0 (m), found `{s}`"
            )),
        }
    }
}

impl std::fmt::Display for PitchTol {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PitchTol::Auto => f.write_str("auto"),
            PitchTol::Fixed(v) => write!(f, "{v:e}"),
        }
    }
}

/// A pitch verdict with the tolerance it implies for the screw decomposition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PitchDecision {
    /// The verdict.
    pub verdict: PitchVerdict,
    /// The tolerance on `|h|` (m) the screw kind is taken with: `|h|` within
    /// it exactly when the verdict is `zero`.
    pub screw_tol: f64,
    /// For `undecidable`: the standard uncertainty of `h` (m) below which the
    /// verdict would be decided.
    pub deciding_sigma_m: Option<f64>,
}

/// The verdict on `h` (m) with standard uncertainty `sigma_h` (m) under `tol`.
pub fn pitch_decision(h: f64, sigma_h: f64, tol: PitchTol) -> PitchDecision {
    let a = h.abs();
    let decided = |verdict, screw_tol| PitchDecision {
        verdict,
        screw_tol,
        deciding_sigma_m: None,
    };
    match tol {
        PitchTol::Fixed(t) if a <= t => decided(PitchVerdict::Zero, t),
        PitchTol::Fixed(t) => decided(PitchVerdict::Nonzero, t),
        PitchTol::Auto => {
            let band = PITCH_K * sigma_h;
            if a <= PITCH_FLOAT_FLOOR_M {
                decided(PitchVerdict::Zero, PITCH_FLOAT_FLOOR_M)
            } else if a > band {
                decided(PitchVerdict::Nonzero, PITCH_FLOAT_FLOOR_M)
            } else if band <= PITCH_RESOLUTION_M {
                decided(PitchVerdict::Zero, band)
            } else {
                PitchDecision {
                    verdict: PitchVerdict::Undecidable,
                    screw_tol: PITCH_FLOAT_FLOOR_M,
                    deciding_sigma_m: Some(a.max(PITCH_RESOLUTION_M) / PITCH_K),
                }
            }
        }
    }
}

/// The verdict of a transform without a rotation axis (`kind` identity or
/// pure translation) under `tol`: the identity is `zero` (every metric is
/// invariant), a pure translation `nonzero`, whatever the rounding.
///
/// The screw of a pure translation has infinite pitch, and no constant metric
/// is invariant under it (the paper, on adapted metrics: "A pure translation
/// admits no such metric"): a definite answer. Not `undecidable` when the
/// rotation as written is rounded: a rotation hidden in the rounding of a
/// written identity (at most `PITCH_K` standard uncertainties, 6e-6 rad at six
/// decimals) about an axis across the lever arm `d` would have zero pitch,
/// but its axis, where M0 is centred, would lie `|d| / angle` away (40 km for
/// a 0.23 m lever arm at six decimals): a metric no detector can use, and an
/// answer that changes with every digit printed. The rotation is taken as
/// published (no rotation), as the paper's survey takes it; a rig whose
/// rotation is not written as the identity gets the three-way verdict on its
/// `h` ([`pitch_decision`]).
pub fn no_axis_decision(kind: ScrewKind, tol: PitchTol) -> PitchDecision {
    let screw_tol = match tol {
        PitchTol::Fixed(t) => t,
        PitchTol::Auto => PITCH_FLOAT_FLOOR_M,
    };
    let verdict = match kind {
        ScrewKind::Identity => PitchVerdict::Zero,
        _ => PitchVerdict::Nonzero,
    };
    PitchDecision {
        verdict,
        screw_tol,
        deciding_sigma_m: None,
    }
}

#[cfg(test)]
mod no_axis_tests {
    use super::*;

    /// Issue 33: a pure translation has a verdict; the identity is zero.
    #[test]
    fn pure_translation_verdicts() {
        let pt = ScrewKind::PureTranslation;
        let v = |k, t| no_axis_decision(k, t).verdict;
        assert_eq!(v(pt, PitchTol::Auto), PitchVerdict::Nonzero);
        assert_eq!(v(pt, PitchTol::Fixed(1e-3)), PitchVerdict::Nonzero);
        assert_eq!(v(ScrewKind::Identity, PitchTol::Auto), PitchVerdict::Zero);
        assert_eq!(no_axis_decision(pt, PitchTol::Fixed(0.01)).screw_tol, 0.01);
        assert_eq!(
            no_axis_decision(pt, PitchTol::Auto).screw_tol,
            PITCH_FLOAT_FLOOR_M
        );
    }
}

#[cfg(test)]
mod half_unit_tests {
    use super::{general_half_unit, plain_half_unit};

    /// The one-pass reading of plain literals agrees with the general one on
    /// every literal of a small alphabet it accepts.
    #[test]
    fn plain_path_agrees_with_the_general_one() {
        let alphabet = ["0", "1", "5", ".", "-", "+", "e", " "];
        let mut texts = vec![String::new()];
        for _ in 0..5 {
            let next: Vec<String> = texts
                .iter()
                .flat_map(|t| alphabet.iter().map(move |c| format!("{t}{c}")))
                .collect();
            texts.extend(next);
        }
        texts.push("1.2345678901234567890".into());
        texts.push("-0.000123456789012345678".into());
        let mut plain = 0;
        for t in &texts {
            if let Some(h) = plain_half_unit(t) {
                plain += 1;
                assert_eq!(h, general_half_unit(t), "{t:?}");
            }
        }
        assert!(plain > 1000, "{plain}");
    }
}
