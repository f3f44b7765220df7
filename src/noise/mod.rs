//! Generators (SPEC §7, first part): which covariance the noise has ([`CovChoice`]), which
//! distribution shape it is drawn with ([`Shape`]), and the per-trial sampler that scales i.i.d.
//! unit-variance draws to that covariance exactly.

mod choice;
mod joint;
mod sampler;
mod shape;

pub use choice::CovChoice;
pub use joint::JointInput;
pub use sampler::{NoiseSampler, TrialDraw, trial_rng};
pub use shape::Shape;
