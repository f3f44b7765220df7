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
//! step means ([`StringModel::forcing_scale`], [`StringModel::noise_scale`]); the filter is the
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
pub mod sweep;

use serde::Deserialize;

use crate::error::{Error, Result};
use super::{Finding, RunView};
use crate::filter::design::{Design, DesignInput, Figures, Record};
use crate::filter::realization::Realization;
use crate::model::plant::Pattern;
use crate::model::plant::{Covariances, Plant};
use crate::model::string::{Observation, StringModel};
use crate::numerics::linalg::{Mat, Vector, min_eigenvalue, symmetrize};
use crate::numerics::pd::MAX_SOLVE_ERROR;
use crate::numerics::riccati::IllConditioned;

#[derive(Deserialize, Clone, Copy, PartialEq, Debug)]
#[serde(rename_all = "snake_case")]
pub enum Basis {
    Eigen,
    Hat,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct Params {
    basis: Basis,
    n: usize,
    alpha: f64,
}

/// The family's entry: `family = "galerkin"`.
pub struct Galerkin;

impl super::Family for Galerkin {
    const NAME: &'static str = "galerkin";
    type Params = Params;

    /// The string of seed 004, observed up to t: the filtering pattern.
    fn supports(_: &Params) -> super::Supports {
        super::Supports { patterns: super::FILTERING, needs_string: true, ..super::Supports::ALL }
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
    fn footprint(p: &Params, _: super::PlantSize) -> super::Footprint {
        super::Footprint { state: 2 * p.n, gain_sets: 1, dense_horizon: false }
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
        sweep::analyze(run, mine)
    }
}

/// A Galerkin filter's place in the sweep: its basis, number of modes n and regularization α.
#[derive(Clone, Debug, serde::Serialize)]
pub struct GalerkinPoint {
    pub basis: String,
    pub n: usize,
    pub alpha: f64,
}

impl Record for GalerkinPoint {}

impl Basis {
    /// The name experiment files use.
    pub fn name(self) -> &'static str {
        match self {
            Basis::Eigen => "eigen",
            Basis::Hat => "hat",
        }
    }
}

/// The refusal of a step whose positive definite solve would not be accurate (module docs).
pub fn ill_conditioned(step: usize, why: IllConditioned, alpha: f64) -> String {
    if why.error.is_finite() {
        format!(
            "at step {step} the innovation covariance C P Cᵀ + (W_m + αI)/Δ has condition number {:.3e}, so its \
             Cholesky solve may be off by {:.1e} relative (at most {MAX_SOLVE_ERROR:e} is accepted): α = {alpha:e} is \
             too small to be solved accurately in double precision, use a larger α",
            why.kappa, why.error
        )
    } else {
        format!(
            "at step {step} the innovation covariance C P Cᵀ + (W_m + αI)/Δ is not positive definite in double \
             precision (condition number {:.3e}): α = {alpha:e} is too small, use a larger α",
            why.kappa
        )
    }
}

/// The Galerkin filter as a realization: the Kalman filter of the [`projected`] model, each step's
/// innovation covariance solved by Cholesky (module docs); or the first step whose solve would not
/// be accurate, with why.
pub fn realization(
    model: &StringModel,
    horizon: usize,
    basis: Basis,
    n: usize,
    alpha: f64,
) -> std::result::Result<Realization, (usize, IllConditioned)> {
    let (fplant, fcov) = projected(model, horizon, basis, n, alpha);
    let mut realization = crate::families::kalman::kalman_pd(&fplant, &fcov, Pattern::Filtering)?;
    // The string has no known input, and the projected model's Gf (2n × 2n) would not fit the
    // truth's r (2M): none at all.
    for g in realization.gains.iter_mut().flatten() {
        g.gf = Mat::zeros(2 * n, 0);
    }
    // Its state tracks the projected model's, not the truth's modes: declare no M (the string is
    // stable, so the plant-coordinate recursion resolves its error).
    realization.tracks = None;
    Ok(realization)
}

/// The projected, regularized, sampled model as a plant (state (x, ẋ), noise blocks `process` and
/// `measurement`) with its covariances: per step (`Covariances::varying`) when an intensity follows
/// a time profile.
pub fn projected(model: &StringModel, horizon: usize, basis: Basis, n: usize, alpha: f64) -> (Plant, Covariances) {
    let (mass, stiff, forcing, sens, out, to_coefficients) = match basis {
        Basis::Eigen => eigen(model, n),
        Basis::Hat => hat(model, n),
    };
    let minv = mass.clone().try_inverse().expect("the mass matrix is positive definite");
    // P(0) = diag(T 𝒰₀ Tᵀ, T 𝒰₁ Tᵀ), the covariance of the coefficients of (u(0), u_t(0)).
    let modal = |velocity: bool| {
        Mat::from_diagonal(&Vector::from_iterator(
            model.truth_modes,
            (1..=model.truth_modes).map(|k| if velocity { model.initial(k).1 } else { model.initial(k).0 }),
        ))
    };
    let mut p0 = Mat::zeros(2 * n, 2 * n);
    p0.view_mut((0, 0), (n, n))
        .copy_from(&symmetrize(&(&to_coefficients * modal(false) * to_coefficients.transpose())));
    p0.view_mut((n, n), (n, n)).copy_from(&symmetrize(&(&to_coefficients * modal(true) * to_coefficients.transpose())));
    let f = &minv * stiff;
    let v = symmetrize(&(&minv * forcing * &minv));
    let dt = model.dt;
    // Van Loan: exp([[−Ac, Qc], [0, Acᵀ]] Δ) = [[·, Φ⁻¹Qd], [0, Φᵀ]].
    let mut ac = Mat::zeros(2 * n, 2 * n);
    ac.view_mut((0, n), (n, n)).fill_with_identity();
    ac.view_mut((n, 0), (n, n)).copy_from(&(-&f));
    let mut qc = Mat::zeros(2 * n, 2 * n);
    qc.view_mut((n, n), (n, n)).copy_from(&v);
    let mut vl = Mat::zeros(4 * n, 4 * n);
    vl.view_mut((0, 0), (2 * n, 2 * n)).copy_from(&(-&ac * dt));
    vl.view_mut((0, 2 * n), (2 * n, 2 * n)).copy_from(&(&qc * dt));
    vl.view_mut((2 * n, 2 * n), (2 * n, 2 * n)).copy_from(&(ac.transpose() * dt));
    let e = vl.exp();
    let phi = e.view((2 * n, 2 * n), (2 * n, 2 * n)).transpose();
    let qd = symmetrize(&(&phi * e.view((0, 2 * n), (2 * n, 2 * n))));
    let m = model.n_sensors();
    let mut c = Mat::zeros(m, 2 * n);
    c.view_mut((0, 0), (m, n)).copy_from(&sens);
    let mut cz = Mat::zeros(out.nrows(), 2 * n);
    cz.view_mut((0, 0), (out.nrows(), n)).copy_from(&out);
    let s_alpha = |scale: f64| {
        let w = if model.noise.varies() { scale * &model.w_m } else { model.w_m.clone() };
        (w + alpha * Mat::identity(m, m)) / dt
    };
    let (fplant, mut fcov) = crate::model::string::sampled(horizon, phi, c, cz, qd.clone(), s_alpha(1.0), p0);
    let steps = fplant.steps();
    if model.forcing.varies() {
        fcov.varying.push((1, (0..steps).map(|k| model.forcing_scale(k) * &qd).collect()));
    }
    if model.noise.varies() {
        fcov.varying.push((2, (0..steps).map(|k| s_alpha(model.noise_scale(k))).collect()));
    }
    (fplant, fcov)
}

/// Mass, stiffness, forcing covariance V_φ, sensor matrix (m × n), output matrix (p × n), and the
/// map T (n × M) from the truth's modal amplitudes to the basis coefficients of their L² projection.
type Projection = (Mat, Mat, Mat, Mat, Mat, Mat);

fn eigen(model: &StringModel, n: usize) -> Projection {
    let w2 = Mat::from_diagonal(&Vector::from_iterator(n, (1..=n).map(|i| model.omega(i).powi(2))));
    let q = Mat::from_diagonal(&Vector::from_iterator(n, (1..=n).map(|i| model.intensity(i))));
    let sens = Mat::from_fn(model.n_sensors(), n, |j, i| model.observe(i + 1, j));
    let out = Mat::from_fn(model.outputs.len(), n, |p, i| model.eigenfunction(i + 1, model.outputs[p]));
    let to_coefficients = Mat::from_fn(n, model.truth_modes, |i, k| (i == k) as u8 as f64);
    (Mat::identity(n, n), w2, q, sens, out, to_coefficients)
}

fn hat(model: &StringModel, n: usize) -> Projection {
    let l = model.length;
    let h = l / (n + 1) as f64;
    let node = |i: usize| (i + 1) as f64 * h;
    let phi = |i: usize, x: f64| (1.0 - (x - node(i)).abs() / h).max(0.0);
    let mass = Mat::from_fn(n, n, |i, j| match i.abs_diff(j) {
        0 => 2.0 * h / 3.0,
        1 => h / 6.0,
        _ => 0.0,
    });
    let c2 = model.speed * model.speed;
    let stiff = Mat::from_fn(n, n, |i, j| match i.abs_diff(j) {
        0 => 2.0 * c2 / h,
        1 => -c2 / h,
        _ => 0.0,
    });
    // (e_k, φ_i) = sqrt(2/L) sin(a ξ_i) · 2(1 − cos a h)/(a² h), a = kπ/L.
    let proj = Mat::from_fn(model.truth_modes, n, |k, i| {
        let a = (k + 1) as f64 * std::f64::consts::PI / l;
        (2.0 / l).sqrt() * (a * node(i)).sin() * 2.0 * (1.0 - (a * h).cos()) / (a * a * h)
    });
    let q = Mat::from_diagonal(&Vector::from_iterator(
        model.truth_modes,
        (1..=model.truth_modes).map(|k| model.intensity(k)),
    ));
    let forcing = symmetrize(&(proj.transpose() * q * &proj));
    // (ρ_j, φ_i): for eigenfunction projections (e_j, φ_i); for windows (1/h_s)∫_window φ_i, where φ_i
    // is linear between its kinks, so the trapezoid rule on them is exact.
    let sens = match &model.observation {
        Observation::Eigen(m) => proj.rows(0, *m).into_owned(),
        Observation::Windows { centres, width } => Mat::from_fn(model.n_sensors(), n, |j, i| {
            let (lo, hi) = (centres[j] - width / 2.0, centres[j] + width / 2.0);
            let mut knots = vec![lo, hi];
            knots.extend([node(i) - h, node(i), node(i) + h].into_iter().filter(|x| *x > lo && *x < hi));
            knots.sort_by(f64::total_cmp);
            knots.windows(2).map(|w| (w[1] - w[0]) * (phi(i, w[0]) + phi(i, w[1])) / 2.0).sum::<f64>() / width
        }),
    };
    let out = Mat::from_fn(model.outputs.len(), n, |p, i| phi(i, model.outputs[p]));
    let minv = mass.clone().try_inverse().expect("the mass matrix is positive definite");
    let to_coefficients = minv * proj.transpose();
    (mass, stiff, forcing, sens, out, to_coefficients)
}
