//! The regularized Galerkin filter (seed 004, docs/math.md §6) for the string of [`crate::model::string`].
//!
//! **Projection.** u ≈ Σ_{i ≤ n} x_i φ_i with either the eigenfunctions (`basis = "eigen"`:
//! mass matrix I, F = diag(ω_i²), forcing covariance diag(q_i)) or the piecewise-linear hat
//! functions on n interior nodes (`basis = "hat"`: mass M_ij = (φ_i, φ_j), stiffness K_ij =
//! c²(φ_i', φ_j'), F = M⁻¹K full, forcing covariance M⁻¹ V_φ M⁻¹ with V_φ,ij = Σ_k q_k (e_k, φ_i)(e_k, φ_j)).
//! Then χ = (x, ẋ) obeys χ̇ = [[0, I], [−F, 0]] χ + ζ (the printed [[0, I], [F, 0]] drops the sign)
//! and the observation sees C_ji = (ρ_j, φ_i) (a window average (1/h)∫_window_j φ_i, or (e_j, φ_i)).
//!
//! **Regularization.** The measurement intensity W_m is replaced by S_α = W_m + α I (Tikhonov,
//! seed 004 eq (6)); α = 0 with a singular W_m leaves the Kalman–Bucy gain P Cᵀ S⁻¹ undefined and is
//! refused. For α > 0 the innovation covariance C P Cᵀ + S_α/Δ is positive definite and is solved
//! by Cholesky (`crate::numerics::riccati::innovation_pd`), never by a pseudo-inverse that
//! would drop its small eigenvalues; a step whose solve has a worst-case relative error (condition
//! number × a multiple of ε, [`crate::numerics::pd`]) above [`crate::numerics::pd::MAX_SOLVE_ERROR`]
//! is refused with its condition number, under the key `filters.NAME.alpha`.
//!
//! **Time-varying intensities** (seed 004's V_(n)(τ), W_(m)(τ)): over step k the forcing covariance
//! is s_k times the constant-intensity one and S_α becomes r_k W_m + α I, s_k and r_k the string's
//! step means ([`StringModel::forcing_scale`](crate::model::string::StringModel::forcing_scale),
//! [`StringModel::noise_scale`](crate::model::string::StringModel::noise_scale)); the filter is the
//! Kalman filter of that time-varying sampled model.
//!
//! **Discretization.** The projected system is discretized exactly over Δ (Van Loan: one matrix
//! exponential gives Φ and the integrated noise covariance), the measurement noise of intensity
//! S_α becomes S_α/Δ per sample, and the filter is the Kalman filter of that sampled model in
//! filtering form (x̂\[k] from y\[0..k]). As Δ → 0 it converges to the Kalman–Bucy filter
//! P' = F₂P + PF₂ᵀ + Q − P Cᵀ S_α⁻¹ C P, P(0) = diag(P0, P10): the covariances of the basis
//! coefficients of u(0) and u_t(0), T 𝒰₀ Tᵀ and T 𝒰₁ Tᵀ with T the modal amplitudes' map to the
//! coefficients (the first n rows for the eigenfunctions, M⁻¹(e_k, φ_i) for the hats); 0 at rest.
//! The output is û(ξ_p) = Σ_i x̂_i φ_i(ξ_p).

pub mod alpha;
mod projection;
pub mod sweep;

use std::sync::Arc;

use serde::Deserialize;

use super::family::{Finding, RunView};
use crate::error::{Error, Result};
use crate::filter::design::{Design, DesignInput, Figures};
use crate::numerics::linalg::min_eigenvalue;
pub use projection::{Basis, GalerkinPoint, ill_conditioned, projected, realization};

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct Params {
    basis: Basis,
    n: usize,
    alpha: f64,
}

/// The family's entry: `family = "galerkin"`.
pub struct Galerkin;

impl super::family::Family for Galerkin {
    const NAME: &'static str = "galerkin";
    type Params = Params;

    /// The string of seed 004, observed up to t: the filtering pattern.
    fn supports(_: &Params) -> super::family::Supports {
        super::family::Supports { patterns: super::family::FILTERING, needs_string: true, ..super::family::Supports::ALL }
    }

    fn check(p: &Params) -> std::result::Result<(), (&'static str, String)> {
        if p.n == 0 {
            return Err(("n", "the number of basis functions must be at least 1".into()));
        }
        if !(p.alpha >= 0.0 && p.alpha.is_finite()) {
            return Err(("alpha", format!("the regularization parameter must be ≥ 0, got {}", p.alpha)));
        }
        Ok(())
    }

    /// n positions and their velocities.
    fn footprint(p: &Params, _: super::family::PlantSize) -> super::family::Footprint {
        super::family::Footprint { state: 2 * p.n, gain_sets: 1, dense_horizon: false }
    }

    fn design(input: &DesignInput, p: &Params) -> Result<Design> {
        let key = |k: &str| format!("filters.{}.{k}", input.name);
        let model = input
            .string
            .as_ref()
            .ok_or_else(|| Error::design(input.name, "the Galerkin filter needs a [string] plant (seed 004)"))?;
        let vanishes = (0..input.plant.steps()).any(|k| model.noise_scale(k) == 0.0);
        if p.alpha == 0.0 && (vanishes || min_eigenvalue(&model.w_m) <= 1e-12 * model.w_m.amax().max(1e-300)) {
            return Err(Error::invalid(
                key("alpha"),
                "W_m is singular, so α = 0 leaves the Kalman–Bucy gain P Cᵀ W_m⁻¹ undefined (seed 004 (5) is ill-posed): use α > 0",
            ));
        }
        let realization = realization(model, input.plant.horizon, p.basis, p.n, p.alpha)
            .map_err(|(k, why)| Error::invalid(key("alpha"), ill_conditioned(k, why, p.alpha)))?;
        let mut diagnostics = serde_json::Map::new();
        diagnostics.insert("dt".into(), model.dt.into());
        let point = GalerkinPoint { basis: p.basis.name().into(), n: p.n, alpha: p.alpha };
        Ok(Design { figures: Figures::of(point), ..Design::new(realization, diagnostics) })
    }

    fn after_run(run: &RunView, mine: &[usize]) -> Result<Option<Finding>> {
        Ok(sweep::analyze(run, mine)?.map(|sweep| Finding { family: Self::NAME, record: Arc::new(sweep) }))
    }
}
