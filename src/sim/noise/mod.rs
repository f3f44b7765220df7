//! Generators (docs/math.md §7, first part): which covariance the noise has
//! ([`CovChoice`](crate::model::choice::CovChoice)), which distribution shape it is drawn with
//! ([`Shape`](crate::model::shape::Shape)), and the per-trial sampler that scales i.i.d.
//! unit-variance draws to that covariance exactly.

mod joint;
mod lane_rng;
mod sampler;
mod shaping;
mod ziggurat;

pub use joint::JointInput;
#[doc(hidden)]
pub use lane_rng::LaneRng;
pub(crate) use sampler::LaneDraw;
pub use sampler::NoiseSampler;
#[doc(hidden)]
pub use sampler::{Stream, trial_rng};
pub use shaping::{ShapeStep, Shaping};
#[doc(hidden)]
pub use ziggurat::{LAYERS, exp, ln, normal_lane, normal_rows, wedge, wedge_decisions};
