//! The H∞-λ filter (seed 002 eqs (5.9)–(5.10), docs/math.md §4; docs/seed002_notes.md), a predictor:
//!
//! ```text
//! M[t]    = P∞[t]⁻¹ + Cᵀ G_D⁻¹ C − λ⁻¹ Czᵀ Cz,   Θ∞[t] = A M⁻¹ Cᵀ G_D⁻¹,
//! P∞[t+1] = A M⁻¹ Aᵀ + G_B,                        P∞[0] = R,
//! ```
//!
//! with the noise split (5.5): G_B = B G Bᵀ, G_D = D G Dᵀ ≻ 0, B G Dᵀ = 0, where R and G are the
//! nominal covariances of x0 and w (the weights of the ellipsoid). It exists while
//! Cz P∞\[t] Czᵀ ≺ λI for t = 0..N−1 and S^½ P∞\[N] S^½ ≺ λI; then for every input, random or not,
//! Σ_{t<N} |e_z\[t]|² + e\[N]ᵀ S e\[N] < λ (|x0 − E x0|²_R + Σ_{t<N} |w\[t]|²_G).
//! λ → ∞ gives the Kalman predictor; `lambda = "min"` bisects for the smallest feasible λ (the
//! generalized H∞-optimal filter) and uses it times (1 + margin).
//! `method = "sdp"` designs through the design form of the SDP (4.7) instead ([`super::hinf_sdp`]):
//! λ_min from one SDP, and with `sdp_filter` the central filter or a non-central one.

use serde::Deserialize;

use super::hinf_sdp::{self, Choice};
use crate::error::{Error, Result};
use crate::filter::design::{Design, DesignInput, Figures, PerTrialBound, Record};
use crate::filter::realization::{Gains, Realization};
use crate::model::plant::{Covariances, Plant};
use crate::numerics::linalg::{Mat, from_rows, min_eigenvalue, symmetrize};
use crate::numerics::solve::line::bisect;

#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
enum Lambda {
    Value(f64),
    Keyword(String),
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// λ > 0, or "min" for the smallest feasible λ.
    lambda: Lambda,
    /// S, the weight of the terminal state error e\[N] (n×n, PSD); default 0.
    terminal_weight: Option<Vec<Vec<f64>>>,
    /// With lambda = "min": the filter uses λ_min (1 + margin), strictly feasible.
    #[serde(default = "default_margin")]
    margin: f64,
    /// How the filter is designed: the Riccati recursion (5.9)–(5.10) with λ_min by bisection
    /// (the default), or the design form of the SDP (4.7) (super::hinf_sdp), λ_min by one SDP.
    #[serde(default)]
    method: Method,
    /// With method = "sdp": which of the filters with norm² ≤ λ (default the central one).
    sdp_filter: Option<Choice>,
}

#[derive(Deserialize, Debug, Clone, Copy, Default, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
enum Method {
    #[default]
    Riccati,
    Sdp,
}

fn default_margin() -> f64 {
    1e-6
}

/// Why a λ is infeasible: the first condition of (5.10) that fails.
#[derive(Clone, Debug)]
pub struct Infeasible {
    pub step: usize,
    pub terminal: bool,
    pub value: f64,
}

impl std::fmt::Display for Infeasible {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.terminal {
            write!(f, "λmax(S^½ P∞[N] S^½) = {:.6} ≥ λ at the final step {}", self.value, self.step)
        } else {
            write!(f, "λmax(Cz P∞ Czᵀ) = {:.6} ≥ λ at step {}", self.value, self.step)
        }
    }
}

/// The H∞-λ recursion (5.9)–(5.10): the gains Θ∞\[t] for t = 0..N, or the first violated condition.
/// It stays apart from [`crate::numerics::riccati`]: it runs in information form (P∞⁻¹ and M⁻¹, not
/// S⁺) with the −λ⁻¹ CzᵀCz term, and checks feasibility at every step.
pub fn recursion(
    plant: &Plant,
    weights: &Covariances,
    s: &Mat,
    lambda: f64,
) -> std::result::Result<Vec<Mat>, Infeasible> {
    let w = weights.w();
    let n = plant.nx();
    let mut p = weights.x0().clone();
    let mut gains = Vec::with_capacity(plant.steps());
    for t in 0..plant.steps() {
        let last = t == plant.horizon;
        let (value, terminal) = if last {
            let sh = crate::numerics::linalg::psd_factor(s);
            (symmetrize(&(sh.transpose() * &p * &sh)).symmetric_eigenvalues().max(), true)
        } else {
            (symmetrize(&(plant.cz_at(t) * &p * plant.cz_at(t).transpose())).symmetric_eigenvalues().max(), false)
        };
        if value >= lambda {
            return Err(Infeasible { step: t, terminal, value });
        }
        let (c, d) = (&*plant.c_at(t), &*plant.d_at(t));
        let pinv = p.clone().try_inverse().ok_or(Infeasible { step: t, terminal: false, value: f64::INFINITY })?;
        let mut m = pinv - plant.cz_at(t).transpose() * plant.cz_at(t) / lambda;
        let mut theta = Mat::zeros(n, plant.ny());
        if plant.measured(t) {
            let gd_inv = (d * &w * d.transpose()).try_inverse().expect("G_D checked positive definite");
            m += c.transpose() * &gd_inv * c;
            let minv = m.clone().try_inverse().ok_or(Infeasible { step: t, terminal: false, value: f64::INFINITY })?;
            theta = plant.a_at(t) * &minv * c.transpose() * gd_inv;
            p = symmetrize(&(plant.a_at(t) * minv * plant.a_at(t).transpose() + plant.b_at(t) * &w * plant.b_at(t).transpose()));
        } else {
            let minv = m.try_inverse().ok_or(Infeasible { step: t, terminal: false, value: f64::INFINITY })?;
            p = symmetrize(&(plant.a_at(t) * minv * plant.a_at(t).transpose() + plant.b_at(t) * &w * plant.b_at(t).transpose()));
        }
        gains.push(theta);
    }
    Ok(gains)
}

/// The smallest feasible λ, by bisection (feasibility is monotone in λ: P∞ decreases as λ grows).
pub fn lambda_min(plant: &Plant, weights: &Covariances, s: &Mat) -> Result<f64> {
    let mut hi = 1.0;
    let mut tries = 0;
    while recursion(plant, weights, s, hi).is_err() {
        hi *= 2.0;
        tries += 1;
        if tries > 200 {
            return Err(Error::invalid("lambda", "no feasible λ found below 2^200"));
        }
    }
    let below = |l: f64| recursion(plant, weights, s, l).is_err();
    let (_, hi) = bisect(0.0, hi, below, |lo, hi| !(hi - lo > 1e-12 * hi), usize::MAX);
    Ok(hi)
}

/// The predictor realization of gains Θ\[t]: s\[t+1] = (A − ΘC) s + Θ y + r, ẑ = Cz s.
pub fn predictor(plant: &Plant, gains: &[Mat]) -> Realization {
    let steps =
        gains.iter().enumerate().map(|(t, th)| Gains::predictor(plant.a_at(t), &plant.c_at(t), th, plant.cz_at(t))).collect();
    Realization::state_estimator(plant.x0_mean.clone(), steps)
}

/// Seed 002's setting: a predictor on a plant with deterministic matrices (no dropouts, modes or
/// multiplicative noise); they may change with the step (§5).
pub(crate) const SEED_002: super::family::Supports = super::family::Supports {
    patterns: super::family::PREDICTION,
    dropouts: false,
    markov_modes: false,
    multiplicative: false,
    time_varying: true,
    varying_weights: false,
    needs_string: false,
    narrowed_by: None,
};

/// Checks that the weights fit seed 002's setting (the plant's features are [`SEED_002`]); returns S.
pub(crate) fn check_setting(input: &DesignInput, key: &str, terminal: &Option<Vec<Vec<f64>>>) -> Result<Mat> {
    let p = input.plant;
    let n = p.nx();
    if (0..p.steps()).any(|k| p.dz_at(k).amax() != 0.0) {
        return Err(Error::invalid(key, "seed 002's plant has z = Cz x: plant.Dz must be zero"));
    }
    let w = input.nominal.w();
    for k in 0..p.steps() {
        let d = p.d.at(k);
        let cross = (p.b_at(k) * &w * d.transpose()).amax();
        if cross > 1e-12 * w.amax().max(1.0) {
            return Err(Error::invalid(
                key,
                format!("needs the noise split (5.5), B G Dᵀ = 0, but max |B G Dᵀ| = {cross:.3e} at step {k}"),
            ));
        }
        if min_eigenvalue(&(d * &w * d.transpose())) <= 0.0 {
            return Err(Error::invalid(key, format!("needs G_D = D G Dᵀ positive definite (5.5), not at step {k}")));
        }
    }
    if min_eigenvalue(input.nominal.x0()) <= 0.0 {
        return Err(Error::invalid(key, "needs R = cov x0 positive definite (P∞[0] = R)"));
    }
    let s = match terminal {
        Some(r) => from_rows(&format!("{key}.terminal_weight"), r, Some((n, n)))?,
        None => Mat::zeros(n, n),
    };
    crate::numerics::linalg::check_psd(&format!("{key}.terminal_weight"), &s)?;
    Ok(s)
}

/// The H∞-λ filter's own figure.
#[derive(Debug, serde::Serialize)]
pub struct HinfFigures {
    /// Seed 002: the H∞ norm² of the designed filter.
    pub hinf_norm_squared: f64,
}

impl Record for HinfFigures {}

/// The family's entry: `family = "hinf"`.
pub(crate) struct HinfLambda;

impl super::family::Family for HinfLambda {
    const NAME: &'static str = "hinf";
    type Params = Params;

    fn supports(_: &Params) -> super::family::Supports {
        SEED_002
    }

    fn check(p: &Params) -> std::result::Result<(), (&'static str, String)> {
        if p.method == Method::Riccati && p.sdp_filter.is_some() {
            return Err(("sdp_filter", "applies only with method = \"sdp\"".into()));
        }
        Ok(())
    }

    /// Its norm checks build the dense operator over the whole horizon.
    fn footprint(_: &Params, plant: super::family::PlantSize) -> super::family::Footprint {
        super::family::Footprint { state: plant.nx, gain_sets: 1, dense_horizon: true }
    }

    fn design(input: &DesignInput, p: &Params) -> Result<Design> {
        let key = format!("filters.{}", input.name);
        let s = check_setting(input, &key, &p.terminal_weight)?;
        let mut diagnostics = serde_json::Map::new();
        let mut min = || match p.method {
            Method::Riccati => lambda_min(input.plant, &input.nominal, &s),
            Method::Sdp => {
                let d = hinf_sdp::minimize_lambda(input.plant, &input.nominal, &s)?;
                diagnostics.insert("lambda_min_sdp_iterations".into(), d.iterations.into());
                diagnostics.insert("lambda_min_sdp_objective_error".into(), d.objective_error.into());
                diagnostics.insert("lambda_min_sdp_seconds".into(), d.seconds.into());
                Ok(d.lambda)
            }
        };
        let (lambda, lmin) = match p.lambda.clone() {
            Lambda::Value(l) if l > 0.0 && l.is_finite() => (l, None),
            Lambda::Keyword(k) if k == "min" => {
                if p.margin.is_nan() || p.margin <= 0.0 {
                    return Err(Error::invalid(format!("{key}.margin"), "must be > 0"));
                }
                let lm = min()?;
                (lm * (1.0 + p.margin), Some(lm))
            }
            _ => return Err(Error::invalid(format!("{key}.lambda"), "must be a positive number or \"min\"")),
        };
        let gains = match p.method {
            Method::Riccati => recursion(input.plant, &input.nominal, &s, lambda)
                .map_err(|e| Error::design(input.name, format!("λ = {lambda} is too small: {e}")))?,
            Method::Sdp => {
                let choice = p.sdp_filter.unwrap_or(Choice::Central);
                let d = hinf_sdp::design_at(input.plant, &input.nominal, &s, lambda, choice)
                    .map_err(|e| Error::design(input.name, e.to_string()))?;
                diagnostics.insert("design_sdp_iterations".into(), d.iterations.into());
                diagnostics.insert("design_sdp_seconds".into(), d.seconds.into());
                d.gains
            }
        };
        let realization = predictor(input.plant, &gains);
        let (norm2, norm_error, _) = crate::analysis::hinf::norm_with_error(input.plant, &realization, &input.nominal, &s)?;
        // The per-trial bound λ is promised only if the norm², computed independently from the
        // gains (the SDP's come from a solver's point), is below it by more than its rounding
        // error: λ is then certified by the eigenvalue route, whatever the design's route.
        if !(norm2 + norm_error < lambda) {
            return Err(Error::design(
                input.name,
                format!(
                    "the SDP (4.7) filter's norm² {norm2} exceeds λ = {lambda}: the solver's point is not feasible enough; raise margin or λ"
                ),
            ));
        }
        diagnostics.insert("lambda".into(), lambda.into());
        diagnostics.insert("hinf_norm_squared_error".into(), norm_error.into());
        if let Some(lm) = lmin {
            diagnostics.insert("lambda_min".into(), lm.into());
        }
        let (sdp, _, iterations, seconds) =
            crate::analysis::hinf::norm_sdp(input.plant, &realization, &input.nominal, &s)?;
        diagnostics.insert("hinf_norm_squared_sdp".into(), sdp.into());
        diagnostics.insert("sdp_iterations".into(), iterations.into());
        diagnostics.insert("sdp_seconds".into(), seconds.into());
        Ok(Design {
            per_trial: Some(PerTrialBound::Ratio { bound: lambda, terminal_weight: s }),
            figures: Figures::of(HinfFigures { hinf_norm_squared: norm2 }),
            ..Design::new(realization, diagnostics)
        })
    }
}
