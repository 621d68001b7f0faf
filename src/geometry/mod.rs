//! Geometry of one rigid transform: SE(3) with its adjoint and screw
//! decomposition, and the certificate bands of the adjoint's singular values.
//! Depends on nothing else in the crate but the diagnostics.

pub mod certificate;
pub mod se3;
pub mod uncertainty;

pub use se3::{QuatOrder, Screw, ScrewKind, Transform};
pub use uncertainty::{EdgePrecision, PitchTol, PitchVerdict, Precision, UserSigma};
