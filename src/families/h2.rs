//! The generalized H2 filter (seed 002 eqs (5.6)–(5.7), docs/math.md §4; docs/seed002_notes.md): the Kalman
//! predictor for the weights R = cov x0, G = cov w with the noise split (5.5),
//!
//! ```text
//! P2[t+1] = A (P2⁻¹ + Cᵀ G_D⁻¹ C)⁻¹ Aᵀ + G_B,   P2[0] = R,   Θ* = A P2 Cᵀ (C P2 Cᵀ + G_D)⁻¹,
//! ```
//!
//! (computed here in the equivalent covariance form, without inverting P2). Theorem 3.1 applied to
//! the error system (5.3): at every step t and for every input, random or not,
//! e_z\[t]ᵀ (Cz P2\[t] Czᵀ)⁻¹ e_z\[t] ≤ |x0 − E x0|²_R + Σ_{k<t} |w\[k]|²_G, i.e. the error lies in the
//! ellipsoid of Cz P2\[t] Czᵀ scaled by the input energy so far, and the worst gain is
//! λmax(Cz P2\[t] Czᵀ).

use serde::Deserialize;

use super::hinf_lambda::check_setting;
use super::kalman::design_at;
use crate::filter::design::{Design, DesignInput, Figures, PerTrialBound, Record};
use crate::error::Result;
use crate::numerics::linalg::{Mat, psd_pinv, symmetrize};
use crate::numerics::riccati;
use crate::model::plant::{Covariances, Plant};
use crate::model::plant::Pattern;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct Params {}

/// P2\[t] for t = 0..N.
pub fn riccati(plant: &Plant, weights: &Covariances) -> Vec<Mat> {
    let w = weights.w();
    let mut p = weights.x0().clone();
    let mut out = Vec::with_capacity(plant.steps());
    for t in 0..plant.steps() {
        out.push(p.clone());
        let (c, d) = (&*plant.c_at(t), &*plant.d_at(t));
        // Not riccati::innovation: seed 002's gain has no B G Dᵀ term (the split (5.5) makes it
        // zero) and S is used as computed, unsymmetrized, so P2 keeps its figures.
        let s = c * &p * c.transpose() + d * &w * d.transpose();
        let k = plant.a_at(t) * &p * c.transpose() * psd_pinv(&s);
        let gb = plant.b_at(t) * &w * plant.b_at(t).transpose();
        p = symmetrize(&riccati::propagate(plant.a_at(t), &p, &gb, &k, &s));
    }
    out
}

/// The generalized H2 filter's own figure.
#[derive(Debug, serde::Serialize)]
pub struct H2Figures {
    /// Seed 002: the generalized H2 level the filter is designed for.
    pub h2_level: f64,
}

impl Record for H2Figures {}

/// The family's entry: `family = "h2"`.
pub struct H2;

impl super::family::Family for H2 {
    const NAME: &'static str = "h2";
    type Params = Params;

    fn supports(_: &Params) -> super::family::Supports {
        super::hinf_lambda::SEED_002
    }

    fn design(input: &DesignInput, _p: &Params) -> Result<Design> {
        check_setting(input, &format!("filters.{}", input.name), &None)?;
        let p2 = riccati(input.plant, &input.nominal);
        let cz = |t: usize| input.plant.cz_at(t);
        let weights: Vec<Mat> =
            p2.iter().enumerate().map(|(t, p)| psd_pinv(&(cz(t) * p * cz(t).transpose()))).collect();
        let level = p2
            .iter()
            .enumerate()
            .map(|(t, p)| symmetrize(&(cz(t) * p * cz(t).transpose())).symmetric_eigenvalues().max())
            .fold(0.0, f64::max);
        let mut design = design_at(input.plant, input.nominal.clone(), Pattern::Prediction);
        design.figures = Figures::of(H2Figures { h2_level: level });
        design.per_trial = Some(PerTrialBound::Ellipsoid { weights });
        Ok(design)
    }
}
