//! Adjoint singular values in closed form, the effective lever arm and the
//! certificate band (paper, Sections III and IV-D; the README's rig report).
//! Conventions are those of [`crate::geometry::se3`].
//!
//! - `Ad(T) = [[R, 0], [[d]x R, R]]` factors as `D Q` with `Q = diag(R, R)`
//!   orthogonal, so its singular values depend on the lever arm `delta = ||d||`
//!   only: `s_max = delta/2 + sqrt(1 + delta^2/4)`, `s_min = 1/s_max`, and the six
//!   are `s_max, s_max, 1, 1, s_min, s_min` (each of the two directions normal to
//!   `d` contributes one shear pair).
//! - `Ad(T)` is orthogonal iff `d = 0`, and
//!   `||A^T A - I||_F / ||I||_F = delta sqrt((delta^2 + 2) / 3)`.
//! - For the characteristic-length metric `diag(l^2 I3, I3)` the same holds with
//!   the dimensionless effective lever arm `delta_eff = ||d|| / l`; the
//!   unnormalized spectrum is `l = 1` (in metres).
//! - Certificate (Ostrowski): under the frame change each generalized eigenvalue
//!   is multiplied by some `theta` in the closed band `[s_min^2, s_max^2]` at
//!   `delta_eff`. If `lambda / kappa` lies outside that band, no frame change with
//!   that lever arm can move `lambda` across the threshold `kappa`.
//!
//! Everything here is allocation-free; only error paths build a message.

use crate::diagnostic::{Error, Result};
use crate::geometry::se3::Transform;
use crate::tolerances::{BAND_EDGE_MARGIN, LENGTH_ZERO_TOL, MAX_ELLS};

/// Largest singular value of `Ad(T)` at lever arm `delta` (>= 0):
/// `delta/2 + sqrt(1 + delta^2/4)`, written with `hypot` so that it neither
/// overflows nor loses accuracy for large `delta`.
pub fn sigma_max(delta: f64) -> f64 {
    let h = 0.5 * delta;
    h + 1.0f64.hypot(h)
}

/// Smallest singular value, `1 / sigma_max` (`det Ad(T) = 1`).
pub fn sigma_min(delta: f64) -> f64 {
    1.0 / sigma_max(delta)
}

/// The six singular values of `Ad(T)`, descending:
/// `[s_max, s_max, 1, 1, s_min, s_min]`.
pub fn adjoint_singular_values(delta: f64) -> [f64; 6] {
    let smax = sigma_max(delta);
    let smin = 1.0 / smax;
    [smax, smax, 1.0, 1.0, smin, smin]
}

/// `||A^T A - I||_F / ||I||_F = delta sqrt((delta^2 + 2) / 3)` (zero iff `d = 0`).
///
/// Derivation: `A^T A - I` has the diagonal block `R^T (delta^2 I - d d^T) R`
/// (eigenvalues `delta^2, delta^2, 0`: squared norm `2 delta^4`) and the two
/// off-diagonal blocks `-+R^T [d]x R` (squared norm `2 delta^2` each), so
/// `||A^T A - I||_F^2 = 2 delta^4 + 4 delta^2`, divided by `||I6||_F^2 = 6`.
pub fn ata_minus_i_rel(delta: f64) -> f64 {
    delta * ((delta * delta + 2.0) / 3.0).sqrt()
}

/// `Ad(T)` is orthogonal iff `d = 0`; here `||d|| <= LENGTH_ZERO_TOL` (1 pm).
pub fn adjoint_is_orthogonal(t: &Transform) -> bool {
    t.lever_arm() <= LENGTH_ZERO_TOL
}

/// The adjoint part of the report (JSON `adjoint`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdjointSummary {
    /// Descending: `s_max, s_max, 1, 1, s_min, s_min`.
    pub singular_values: [f64; 6],
    /// `d = 0` (within `LENGTH_ZERO_TOL`).
    pub orthogonal: bool,
    /// `||A^T A - I||_F / ||I||_F`.
    pub ata_minus_i_rel: f64,
}

/// Closed-form adjoint summary of `t`.
pub fn adjoint_summary(t: &Transform) -> AdjointSummary {
    let delta = t.lever_arm();
    AdjointSummary {
        singular_values: adjoint_singular_values(delta),
        orthogonal: adjoint_is_orthogonal(t),
        ata_minus_i_rel: ata_minus_i_rel(delta),
    }
}

fn check_ell(ell: f64) -> Result<()> {
    if !(ell.is_finite() && ell > 0.0) {
        return Err(Error::usage(format!(
            "characteristic length: expected a finite length > 0 m, found {ell}"
        )));
    }
    Ok(())
}

/// `delta_eff = ||d|| / l`. An error unless `l` is finite and positive and the
/// lever arm finite and non-negative.
pub fn delta_eff(lever_arm: f64, ell: f64) -> Result<f64> {
    check_ell(ell)?;
    if !(lever_arm.is_finite() && lever_arm >= 0.0) {
        return Err(Error::invalid(format!(
            "lever arm: expected a finite length >= 0 m, found {lever_arm}"
        )));
    }
    Ok(lever_arm / ell)
}

/// The certificate band `[s_min^2, s_max^2]` at `delta_eff` (closed interval).
/// `delta_eff = 0` gives the point `[1, 1]`.
pub fn band(delta_eff: f64) -> [f64; 2] {
    let smax = sigma_max(delta_eff);
    let smin = 1.0 / smax;
    [smin * smin, smax * smax]
}

/// Whether the band at `delta_eff` certifies that no frame change with that
/// effective lever arm can move the eigenvalue `lambda` across the threshold
/// `kappa` (paper, Corollary "Certificate").
///
/// Returns `Ok(true)` iff `lambda / kappa` lies outside the closed band
/// `[s_min^2, s_max^2]`, with the band widened by the relative
/// `BAND_EDGE_MARGIN` so that rounding can only make the answer conservative.
/// On the edge itself the answer is `false`: some frame change can move `lambda`
/// exactly onto `kappa`, and whether that counts as a crossing depends on the
/// detector's `<` or `<=`.
///
/// - `kappa` must be finite and `> 0` (a degeneracy threshold); otherwise an error.
/// - `lambda` must be finite. `lambda = 0` (or negative, from rounding) is
///   certified: a congruence keeps zero eigenvalues zero and signs unchanged.
/// - `delta_eff` must be finite and `>= 0`.
pub fn certifies_no_crossing(lambda: f64, kappa: f64, delta_eff: f64) -> Result<bool> {
    if !(kappa.is_finite() && kappa > 0.0) {
        return Err(Error::usage(format!(
            "threshold kappa: expected a finite number > 0, found {kappa}"
        )));
    }
    if !lambda.is_finite() {
        return Err(Error::invalid(format!(
            "eigenvalue lambda: expected a finite number, found {lambda}"
        )));
    }
    if !(delta_eff.is_finite() && delta_eff >= 0.0) {
        return Err(Error::invalid(format!(
            "effective lever arm: expected a finite number >= 0, found {delta_eff}"
        )));
    }
    let [lo, hi] = band(delta_eff);
    let ratio = lambda / kappa;
    Ok(ratio < lo * (1.0 - BAND_EDGE_MARGIN) || ratio > hi * (1.0 + BAND_EDGE_MARGIN))
}

/// One certificate line (JSON `certificate[i]`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CertificateEntry {
    /// Characteristic length `l` (m).
    pub ell_m: f64,
    /// `||d|| / l`.
    pub delta_eff: f64,
    /// `[s_min^2, s_max^2]` at `delta_eff`.
    pub band: [f64; 2],
}

impl CertificateEntry {
    /// The entry for lever arm `||d||` (m) at characteristic length `ell` (m);
    /// an error when `ell` is not finite and `> 0` or the lever arm is not
    /// finite and `>= 0`.
    pub fn new(lever_arm: f64, ell: f64) -> Result<Self> {
        let de = delta_eff(lever_arm, ell)?;
        Ok(CertificateEntry {
            ell_m: ell,
            delta_eff: de,
            band: band(de),
        })
    }
    /// [`certifies_no_crossing`] at this entry's `delta_eff`.
    pub fn certifies_no_crossing(&self, lambda: f64, kappa: f64) -> Result<bool> {
        certifies_no_crossing(lambda, kappa, self.delta_eff)
    }
}

/// Up to [`MAX_ELLS`] certificate entries, in the order the lengths were given.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Certificates {
    entries: [CertificateEntry; MAX_ELLS],
    len: usize,
}

impl Certificates {
    /// The entries, one per characteristic length, in the order given.
    pub fn as_slice(&self) -> &[CertificateEntry] {
        &self.entries[..self.len]
    }
    /// How many characteristic lengths were given.
    pub fn len(&self) -> usize {
        self.len
    }
    /// No characteristic length was given.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// Iterates over [`Self::as_slice`].
    pub fn iter(&self) -> std::slice::Iter<'_, CertificateEntry> {
        self.as_slice().iter()
    }
}

/// Certificate entries for each characteristic length in `ells` (at most
/// [`MAX_ELLS`], each finite and `> 0`; otherwise an error).
pub fn certificates(lever_arm: f64, ells: &[f64]) -> Result<Certificates> {
    if ells.len() > MAX_ELLS {
        return Err(Error::usage(format!(
            "characteristic lengths: expected at most {MAX_ELLS}, found {}",
            ells.len()
        )));
    }
    let mut out = Certificates::default();
    for (slot, &ell) in out.entries.iter_mut().zip(ells) {
        *slot = CertificateEntry::new(lever_arm, ell)?;
    }
    out.len = ells.len();
    Ok(out)
}
