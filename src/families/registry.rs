//! Family name → design procedure.

use super::{Design, anisotropic, galerkin, h2, hinf_lambda, intermittent, kalman, markov_jump, minimax};
use crate::error::Result;
use crate::spec::{Experiment, FilterSpec};

/// Every family an experiment file may name.
pub const FAMILIES: &[&str] =
    &["kalman", "minimax", "hinf", "h2", "anisotropic", "intermittent", "markov_jump", "galerkin"];

pub fn is_family(name: &str) -> bool {
    FAMILIES.contains(&name)
}

/// Designs one filter of the experiment (its realization is checked against the plant and pattern).
pub fn design(exp: &Experiment, filter: &FilterSpec) -> Result<Design> {
    let d = match filter.family.as_str() {
        "kalman" => kalman::design(exp, filter)?,
        "minimax" => minimax::design(exp, filter)?,
        "hinf" => hinf_lambda::design(exp, filter)?,
        "h2" => h2::design(exp, filter)?,
        "anisotropic" => anisotropic::design(exp, filter)?,
        "intermittent" => intermittent::design(exp, filter)?,
        "markov_jump" => markov_jump::design(exp, filter)?,
        "galerkin" => galerkin::design(exp, filter)?,
        other => unreachable!("family `{other}` passed validation but has no design procedure"),
    };
    d.realization.check(&filter.name, &exp.plant, exp.pattern)?;
    Ok(d)
}
