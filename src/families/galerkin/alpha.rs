//! A data-driven choice of seed 004's regularization parameter α (the seed's references [1–3, 5]:
//! Tikhonov's α chosen from the data, not from the unknown truth): the discrepancy principle on the
//! innovations.
//!
//! A user has one record y[0..N] and the projected, regularized model of
//! [`super::projected`]. Its Kalman filter predicts the innovations
//! ν\[k] = y\[k] − C x̂\[k|k−1] to have covariance S_α\[k] = C P̄\[k] Cᵀ + S_α/Δ, so the discrepancy
//! D(α) = (1/(N m)) Σ_k ν\[k]ᵀ S_α\[k]⁻¹ ν\[k] is ≈ 1 when the model explains the record. A large α
//! pretends the noise is larger than it is (D < 1); as α → 0 the model believes the noise-free
//! combinations of W_m exactly while it misses the truth's modes beyond n, and D grows. Morozov's
//! rule: take the α where D(α) = 1 (bracketed on the grid, then bisected on log α), the smallest α of the
//! grid when D ≤ 1 throughout (the record cannot tell the regularization apart from none), the
//! largest when D > 1 throughout.
//!
//! The record is one draw of the truth (Gaussian, the nominal covariances) from its own random
//! stream, independent of every Monte Carlo trial ([`super::super::RunView::pilot_record`]).

use rayon::prelude::*;

use super::projection::{Basis, ill_conditioned, projected, realization};
use crate::error::{Error, Result};
use crate::model::plant::{Covariances, Plant};
use crate::model::string::StringModel;
use crate::numerics::linalg::{Mat, Vector};
use crate::numerics::riccati;
use crate::numerics::solve::line::bisect;

/// The rule's outcome on a grid of α.
#[derive(Clone, Debug, serde::Serialize)]
pub struct AlphaChoice {
    /// The grid, as given.
    pub alphas: Vec<f64>,
    /// D(α) on the grid.
    pub discrepancy: Vec<f64>,
    /// The chosen α.
    pub alpha: f64,
    /// The exact error of the Galerkin filter at the chosen α against the truth at the nominal
    /// covariances (summed over the horizon): what the rule costs, to set against the best α.
    pub exact: f64,
}

/// The string experiment the rule works on: the string, its sampled plant, the nominal covariances
/// and one record y\[0..N] of the truth (column k = y\[k]).
pub struct Pilot<'a> {
    pub model: &'a StringModel,
    pub plant: &'a Plant,
    pub nominal: &'a Covariances,
    pub y: &'a Mat,
}

/// D(α) of the `basis`, `n` Galerkin filter on the record `y` (module docs). The innovation
/// covariance is solved by Cholesky, as in the filter itself; a step it cannot solve accurately is
/// refused under `key` ([`crate::families::galerkin::ill_conditioned`]).
pub fn discrepancy(r: &Pilot, basis: Basis, n: usize, alpha: f64, key: &str) -> Result<f64> {
    let y = r.y;
    let (fp, fcov) = projected(r.model, r.plant.horizon, basis, n, alpha);
    let (mut pbar, mut s) = (fcov.x0().clone(), Vector::zeros(fp.nx()));
    let mut sum = 0.0;
    for k in 0..y.ncols() {
        let w = fcov.w_at(k);
        let (a, b, c, d) = (fp.a_at(k), fp.b_at(k), fp.c.at(k), fp.d.at(k));
        let (bwb, dwd, bwd) = (b * &w * b.transpose(), d * &w * d.transpose(), b * &w * d.transpose());
        let nu = y.column(k) - c * &s;
        let nu_row = Mat::from_row_slice(1, nu.len(), nu.as_slice());
        let inn = riccati::innovation_pd(a, c, &pbar, &dwd, &bwd, &[&nu_row])
            .map_err(|why| Error::invalid(key, ill_conditioned(k, why, alpha)))?;
        sum += (inn.right_solve(&nu_row) * &nu)[(0, 0)];
        s = a * &s + &inn.k * &nu;
        pbar = crate::numerics::linalg::symmetrize(&riccati::propagate(a, &pbar, &bwb, &inn.k, &inn.s));
    }
    Ok(sum / (y.ncols() * y.nrows()) as f64)
}

/// Morozov's rule on the grid `alphas` (module docs) for the `basis`, `n` Galerkin filter.
pub fn choose_alpha(r: &Pilot, basis: Basis, n: usize, alphas: &[f64]) -> Result<AlphaChoice> {
    if alphas.iter().any(|a| !(*a > 0.0 && a.is_finite())) || alphas.windows(2).any(|w| w[1] >= w[0]) {
        return Err(Error::invalid("alphas", "a decreasing grid of α > 0"));
    }
    // The grid's points are independent filters: one per task (the first failure in grid order is reported).
    let d = alphas.par_iter().map(|a| discrepancy(r, basis, n, *a, "alphas")).collect::<Vec<_>>();
    let d = d.into_iter().collect::<Result<Vec<f64>>>()?;
    let alpha = match d.iter().position(|v| *v > 1.0) {
        None => *alphas.last().expect("a grid"),
        Some(0) => alphas[0],
        Some(i) => {
            // D crosses 1 between two grid points: bisect on log10 α to 0.01 decades. A refused
            // step inside the bracket stops the rule with its error, never a guessed side.
            let refused = std::cell::RefCell::new(None);
            let d_above_one = |t: f64| match discrepancy(r, basis, n, 10f64.powf(t), "alphas") {
                Ok(d) => d > 1.0,
                Err(e) => {
                    refused.borrow_mut().get_or_insert(e);
                    true
                }
            };
            let (lo, hi) = bisect(alphas[i].log10(), alphas[i - 1].log10(), d_above_one, |a, b| b - a < 0.01, 40);
            if let Some(e) = refused.into_inner() {
                return Err(e);
            }
            10f64.powf(0.5 * (lo + hi))
        }
    };
    let filter = realization(r.model, r.plant.horizon, basis, n, alpha)
        .map_err(|(k, why)| Error::invalid("alphas", ill_conditioned(k, why, alpha)))?;
    let exact = crate::analysis::exact::error(r.plant, &filter, r.nominal).total;
    Ok(AlphaChoice { alphas: alphas.to_vec(), discrepancy: d, alpha, exact })
}
