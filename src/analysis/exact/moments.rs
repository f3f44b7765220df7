//! The exact error's entry points: white or joint inputs, with or without a deterministic mean,
//! carried in plant coordinates and, where those lose too many digits, in error coordinates.

use super::augmented::{Augmented, modal};
use super::exact_error::{Coordinates, ExactError, MAX_DIGITS_LOST};
use super::form::error_form;
use super::propagate::{
    Input, MODAL_MIN_STATES, Start, propagate, propagate_modal, propagate_outputs, start, two_by_two_block_diagonal,
    white,
};
use crate::error::{Error, Result};
use crate::filter::realization::Realization;
use crate::model::plant::{Covariances, Plant};
use crate::numerics::linalg::{Mat, Vector};

/// The exact error of `real` on `plant` when x0 and w have the covariances `cov` (any distribution).
pub fn error(plant: &Plant, real: &Realization, cov: &Covariances) -> ExactError {
    error_with_mean(plant, real, cov, None)
}

/// [`error`] for pairs that differ only in their outputs, as [`errors_with_mean`].
pub fn errors(pairs: &[(&Plant, &Realization)], cov: &Covariances) -> Vec<ExactError> {
    errors_with_mean(pairs, cov, None)
}

/// Σ_k |E e\[k]|² over the steps that count: the deterministic part of J, from x0's mean, the known
/// input and a deterministic sequence `w_mean` (column k is the mean of w\[k]).
pub fn mean_error(plant: &Plant, real: &Realization, w_mean: &Mat) -> f64 {
    error_with_mean(plant, real, &zero_covariances(plant), Some(w_mean)).total
}

/// As [`error`], with w\[k] having mean `w_mean` column k (deterministic disturbances, seed 000 §5).
pub fn error_with_mean(plant: &Plant, real: &Realization, cov: &Covariances, w_mean: Option<&Mat>) -> ExactError {
    errors_with_mean(&[(plant, real)], cov, w_mean).pop().expect("one pair, one error")
}

/// [`error_with_mean`] for pairs of a plant and filter that differ only in their outputs (Cz, Dz,
/// Cf, Df: the projections of `nees::error_moments`), each the same bits as alone, from one state
/// recursion where the plant-coordinate recursion serves them.
pub fn errors_with_mean(pairs: &[(&Plant, &Realization)], cov: &Covariances, w_mean: Option<&Mat>) -> Vec<ExactError> {
    let Some(&(plant, real)) = pairs.first() else { return Vec::new() };
    let w = white(plant, cov);
    if !plant.random_matrices()
        && !plant.time_varying()
        && !cov.varies()
        && !has_mean(plant, real, w_mean)
        && plant.nx() >= MODAL_MIN_STATES
    {
        let bwb = plant.b_at(0) * &w[0] * plant.b_at(0).transpose();
        if [plant.a_at(0), cov.x0(), &bwb].into_iter().all(two_by_two_block_diagonal) {
            return pairs.iter().map(|(p, r)| propagate_modal(p, r, cov.x0(), &w[0], &bwb)).collect();
        }
    }
    let input = Input::White { w: &w, mean: w_mean };
    resolved(pairs, &start(plant, real, &Vector::zeros(plant.nx()), cov.x0(), &input), &input)
}

/// The plant-coordinate recursion, kept as the reference wherever it resolves the error; where it
/// loses more than [`MAX_DIGITS_LOST`] digits, the same moments in error coordinates (when the
/// realization's declared M passes [`error_form`]'s check). One pass serves every pair (see
/// [`errors_with_mean`]); a pair that needs error coordinates is redone alone.
fn resolved(pairs: &[(&Plant, &Realization)], start: &Start, input: &Input) -> Vec<ExactError> {
    let systems: Vec<Box<dyn Fn(usize) -> Vec<Augmented> + '_>> =
        pairs.iter().map(|&(p, r)| Box::new(move |k| modal(p, r, k)) as Box<dyn Fn(usize) -> Vec<Augmented>>).collect();
    let systems: Vec<&dyn Fn(usize) -> Vec<Augmented>> = systems.iter().map(|s| s.as_ref()).collect();
    let references = propagate_outputs(pairs[0].0, start, input, &systems);
    references
        .into_iter()
        .zip(pairs)
        .map(|(reference, &(plant, real))| {
            if reference.resolution.digits_lost <= MAX_DIGITS_LOST {
                return reference;
            }
            match error_form(plant, real) {
                Ok(form) => {
                    let mut out =
                        propagate(plant, &start.transformed(&form.to_error), input, &|k| form.steps[k].clone());
                    out.coordinates = Coordinates::Error;
                    out
                }
                Err(why) => ExactError { untracked: Some(why), ..reference },
            }
        })
        .collect()
}

/// The summed error with no noise at all: what x0's mean and the known input alone cost (with
/// dropouts the known input's trajectory is multiplied by λ − p, so this is not zero).
pub fn deterministic_error(plant: &Plant, real: &Realization) -> f64 {
    if !has_mean(plant, real, None) {
        return 0.0;
    }
    error(plant, real, &zero_covariances(plant)).total
}

/// Whether anything in the augmented state has a nonzero mean: x0's, the filter's start s0, the
/// known input or a deterministic sequence in w.
fn has_mean(plant: &Plant, real: &Realization, w_mean: Option<&Mat>) -> bool {
    w_mean.is_some() || !plant.known_input.is_empty() || plant.x0_mean.amax() != 0.0 || real.s0.amax() != 0.0
}

fn zero_covariances(plant: &Plant) -> Covariances {
    Covariances::new(
        std::iter::once(plant.nx()).chain(plant.noise_blocks.iter().map(|b| b.1)).map(|d| Mat::zeros(d, d)).collect(),
    )
}

/// The exact error when J = col(x0 − E x0, w\[0..N−1] or w\[0..N]) has mean `mean` and covariance
/// `cov` jointly over the horizon (not white).
pub fn error_joint(plant: &Plant, real: &Realization, mean: &Vector, cov: &Mat) -> Result<ExactError> {
    Ok(errors_joint(&[(plant, real)], mean, cov)?.pop().expect("one pair, one error"))
}

/// [`error_joint`] for pairs that differ only in their outputs, as [`errors_with_mean`].
pub fn errors_joint(pairs: &[(&Plant, &Realization)], mean: &Vector, cov: &Mat) -> Result<Vec<ExactError>> {
    let Some(&(plant, real)) = pairs.first() else { return Ok(Vec::new()) };
    let (n, nw) = (plant.nx(), plant.nw());
    let dj = mean.len();
    if cov.shape() != (dj, dj) || (dj != n + plant.horizon * nw && dj != n + plant.steps() * nw) {
        return Err(Error::invalid("input", format!("a joint input of dimension {dj} does not fit the plant")));
    }
    let raw = cov + mean * mean.transpose();
    let x0_cov = cov.view((0, 0), (n, n)).into_owned();
    let x0_shift = mean.rows(0, n).into_owned();
    let input = Input::Joint { mean, raw: &raw };
    Ok(resolved(pairs, &start(plant, real, &x0_shift, &x0_cov, &input), &input))
}
