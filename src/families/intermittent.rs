//! The linear minimum-variance predictor for intermittent observations (seed 003 §4.2.1's plant
//! (4.30); the H2-optimal reference of the `aniso_dropout` experiment). It has the structure of
//! (4.31) with W = A, x̂\[k+1] = A x̂ + H(y − p Cy x̂) + r, and the gain that minimizes E|e\[k+1]|²
//! given the error covariance P and the raw state moment X = E\[xxᵀ]:
//!
//! ```text
//! ν = y − pCy x̂ = pCy e + (λ − p) Cy x + Dy w,    S = p² Cy P Cyᵀ + p(1−p) Cy X Cyᵀ + Dy W Dyᵀ,
//! H = (p A P Cyᵀ + B W Dyᵀ) S⁺,    P' = A P Aᵀ + B W Bᵀ − H S Hᵀ,
//! X' = A X Aᵀ + B W Bᵀ + A m rᵀ + r mᵀ Aᵀ + r rᵀ,  m' = A m + r   (m = E x),
//! ```
//!
//! P\[0] = cov x0, X\[0] = P\[0] + m0 m0ᵀ. The p(1−p) term is the price of not knowing λ: the filter
//! sees a measurement whose signal part is missing with probability 1 − p. With p = 1 it is the
//! Kalman predictor. Its guarantee is its exact error at the design covariance, Σ_k tr(Cz P Czᵀ)
//! plus the Dz terms.

use serde::Deserialize;

use crate::filter::design::{Design, DesignInput, Figures};
use crate::error::Result;
use crate::numerics::linalg::{psd_pinv, symmetrize};
use crate::numerics::riccati;
use crate::model::plant::{Covariances, Plant};
use crate::filter::realization::{Gains, Realization};
use crate::model::choice::CovChoiceFile;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct Params {
    #[serde(default)]
    design: CovChoiceFile,
}

/// The family's entry: `family = "intermittent"`.
pub(crate) struct Intermittent;

impl super::family::Family for Intermittent {
    const NAME: &'static str = "intermittent";
    type Params = Params;

    /// A predictor for dropouts (plant.arrival), not general Markov modes or multiplicative noise.
    fn supports(_: &Params) -> super::family::Supports {
        super::family::Supports {
            patterns: super::family::PREDICTION,
            markov_modes: false,
            multiplicative: false,
            ..super::family::Supports::ALL
        }
    }

    fn design(input: &DesignInput, p: &Params) -> Result<Design> {
        let cov = super::family::own_design_point(input, &p.design, "this filter")?;
        let (realization, predicted) = predictor(input.plant, &cov);
        let mut design = super::family::exact_at_design(input.plant, realization, cov, serde_json::Map::new());
        design.figures = Figures::of(super::family::Predicted { riccati_summed_error: predicted });
        Ok(design)
    }
}

/// The predictor of the module docs and the summed error its Riccati recursion predicts,
/// Σ_k tr(Cz P\[k] Czᵀ + Dz W Dzᵀ).
pub fn predictor(plant: &Plant, cov: &Covariances) -> (Realization, f64) {
    let w = cov.w();
    let (p, v) = (plant.arrival_mean(), plant.dropout_variance());
    let mut pe = cov.x0().clone();
    let mut m = plant.x0_mean.clone();
    let mut x = &pe + &m * m.transpose();
    let mut predicted = 0.0;
    let mut steps = Vec::with_capacity(plant.steps());
    for k in 0..plant.steps() {
        let (c, d) = (&*plant.c_at(k), &*plant.d_at(k));
        if plant.counts(k) {
            predicted += (plant.cz_at(k) * &pe * plant.cz_at(k).transpose() + plant.dz_at(k) * &w * plant.dz_at(k).transpose()).trace();
        }
        // S and H carry p inside the products (not riccati::innovation's C P Cᵀ): p² C P Cᵀ is
        // computed as ((p²C) P) Cᵀ, and the figures must stay as they were.
        let s = symmetrize(&(p * p * c * &pe * c.transpose() + v * c * &x * c.transpose() + d * &w * d.transpose()));
        let h = (p * plant.a_at(k) * &pe * c.transpose() + plant.b_at(k) * &w * d.transpose()) * psd_pinv(&s);
        steps.push(Gains::predicting(plant.a_at(k) - p * &h * c, h.clone(), plant.cz_at(k)));
        let bwb = plant.b_at(k) * &w * plant.b_at(k).transpose();
        pe = symmetrize(&riccati::propagate(plant.a_at(k), &pe, &bwb, &h, &s));
        let mut xn = plant.a_at(k) * &x * plant.a_at(k).transpose() + &bwb;
        let mut mn = plant.a_at(k) * &m;
        if let Some(r) = plant.r_at(k) {
            let am = plant.a_at(k) * &m;
            xn += &am * r.transpose() + r * am.transpose() + r * r.transpose();
            mn += r;
        }
        x = symmetrize(&xn);
        m = mn;
    }
    (Realization::state_estimator(plant.x0_mean.clone(), steps), predicted)
}
