//! The rig report of a composed chain, with what it is asked for besides the
//! chain (`RigOptions`).

use crate::diagnostic::Result;
use crate::frames::Chain;
use crate::geometry::{PitchTol, UserSigma};
use crate::report::rig::{kappa_check, rig_report, Judgement};
use crate::report::RigReport;
use crate::tolerances::DEFAULT_ELLS;

/// What the rig report is asked for besides the chain. `Default`: the
/// command's defaults (`--ell` [`DEFAULT_ELLS`], `--pitch-tol auto`, no
/// user uncertainty, no band check).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct RigOptions {
    /// Characteristic lengths (m) of the certificate bands.
    pub ells: Vec<f64>,
    /// `--pitch-tol`: `auto` or a tolerance on `|h|` (m).
    pub pitch_tol: PitchTol,
    /// `--sigma-t`/`--sigma-r`: the user's uncertainty per edge.
    pub sigma: Option<UserSigma>,
    /// `--kappa K --lambda L`: the band check.
    pub kappa_lambda: Option<(f64, f64)>,
}

impl Default for RigOptions {
    fn default() -> Self {
        RigOptions {
            ells: DEFAULT_ELLS.to_vec(),
            pitch_tol: PitchTol::Auto,
            sigma: None,
            kappa_lambda: None,
        }
    }
}

/// The rig report of a composed chain.
pub fn report(chain: &Chain, opts: &RigOptions) -> Result<RigReport> {
    let how = Judgement {
        pitch_tol: opts.pitch_tol,
        user: opts.sigma,
    };
    let mut rep = rig_report(chain, &opts.ells, &how)?;
    if let Some((kappa, lambda)) = opts.kappa_lambda {
        rep.kappa_check = Some(kappa_check(&rep, kappa, lambda)?);
    }
    Ok(rep)
}
