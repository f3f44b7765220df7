//! Generators (docs/math.md §7, first part): which covariance the noise has
//! ([`CovChoice`](crate::model::choice::CovChoice)), which distribution shape it is drawn with
//! ([`Shape`](crate::model::shape::Shape)), and the per-trial sampler that scales i.i.d.
//! unit-variance draws to that covariance exactly.

mod joint;
mod sampler;

pub use joint::JointInput;
pub(crate) use sampler::LaneDraw;
pub use sampler::NoiseSampler;
