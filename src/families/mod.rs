//! Filter families: each is a design procedure that turns an experiment and its own parameters into
//! a [`Realization`] plus what its theory guarantees. Adding a family is one file here and one line
//! in [`registry`].

pub mod kalman;
pub mod registry;

use crate::realization::Realization;

/// What a family's theory promises about its error.
#[derive(Clone, Debug)]
pub struct Guarantee {
    /// Short name of the promise, e.g. `exact_at_design` for Kalman (the summed error it attains
    /// when the noise has its design covariance).
    pub kind: String,
    pub total: f64,
    pub per_step: Vec<f64>,
}

/// A designed filter.
#[derive(Clone, Debug)]
pub struct Design {
    pub realization: Realization,
    pub guarantee: Option<Guarantee>,
}
