//! The Galerkin filter's model and realization (module docs of [`super`]): the basis, the projected,
//! regularized and sampled model, and its Kalman filter solved by Cholesky.

use serde::Deserialize;

use crate::filter::design::Record;
use crate::filter::realization::Realization;
use crate::model::plant::Pattern;
use crate::model::plant::{Covariances, Plant};
use crate::model::string::{Observation, StringModel};
use crate::numerics::linalg::{Mat, Vector, symmetrize};
use crate::numerics::pd::MAX_SOLVE_ERROR;
use crate::numerics::riccati::IllConditioned;

#[derive(Deserialize, Clone, Copy, PartialEq, Debug)]
#[serde(rename_all = "snake_case")]
pub enum Basis {
    Eigen,
    Hat,
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
    realization.map_gains(|g| g.gf = Mat::zeros(2 * n, 0));
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
