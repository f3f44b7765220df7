//! The Kalman family (docs/math.md §1): seed 000 eqs (4)–(6) in filtering form and seed 002 eqs (5.6)–(5.7)
//! in prediction form, designed at a stated covariance. Both forms share the one-step predictor
//! state s\[k] = x̂\[k|k−1]; they differ only in the output map.
//!
//! The recursion is written for the stacked noise of docs/math.md §0, where the same w\[k] may enter both
//! x\[k+1] (through B) and y\[k] (through D): with innovation covariance S = C P̄ Cᵀ + D W Dᵀ,
//!
//! ```text
//! L  = (A P̄ Cᵀ + B W Dᵀ) S⁺                 (predictor gain)
//! Lz = (Cz P̄ Cᵀ + Dz W Dᵀ) S⁺               (filtering output gain: ẑ = E[z[k] | y[0..k]])
//! P̄[k+1] = A P̄ Aᵀ + B W Bᵀ − L S Lᵀ,       P̄[0] = S_x0,   s[0] = E x0.
//! ```
//!
//! With D = [0 d] and B = [b 0] (uncorrelated noises) this is exactly seed 000's k\[n] and P\[n]; the
//! pseudo-inverse ⁺ is the seed's and gives a zero gain at steps without measurements.

use serde::Deserialize;

use crate::error::{Error, Result};
use crate::filter::design::{Design, DesignInput};
use crate::filter::realization::{Gains, Realization, push_step};
use crate::model::choice::CovChoiceFile;
use crate::model::plant::Pattern;
use crate::model::plant::{Covariances, Plant, Steps};
use crate::numerics::linalg::{Mat, symmetrize, weighted_sum};
use crate::numerics::riccati;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// The covariance the filter is designed at (same forms as a scenario's `covariance`).
    #[serde(default)]
    design: CovChoiceFile,
    /// `"mode_averaged"`: design on the plant whose matrices are the stationary averages Σ_s π_s A_s,
    /// … over the Markov modes (a filter that ignores the modes). Default: the plant's base matrices.
    #[serde(default)]
    plant: PlantChoice,
}

#[derive(Deserialize, Default, Debug, PartialEq)]
#[serde(rename_all = "snake_case")]
enum PlantChoice {
    #[default]
    Base,
    ModeAveraged,
}

/// The plant with every switching matrix replaced by its stationary average, modes removed.
fn mode_averaged(plant: &Plant, name: &str) -> Result<Plant> {
    let m = plant.modes().ok_or_else(|| Error::design(name, "`plant = \"mode_averaged\"` needs a plant with modes"))?;
    let pi = m.stationary().ok_or_else(|| Error::design(name, "the chain is not ergodic: no stationary average"))?;
    // Averaged step by step when some mode's matrix varies.
    let avg = |ms: &[Steps]| {
        let at =
            |k: usize| weighted_sum(ms[0].nrows(), ms[0].ncols(), pi.iter().copied().zip(ms.iter().map(|s| s.at(k))));
        if ms.iter().any(Steps::varies) {
            Steps::per_step((0..plant.steps()).map(at).collect())
        } else {
            Steps::constant(at(0))
        }
    };
    let mut out = plant.clone();
    out.a = avg(&m.a);
    out.b = avg(&m.b);
    out.c = avg(&m.c);
    out.d = avg(&m.d);
    out.measurement = crate::model::plant::Measurement::Always;
    Ok(out)
}

/// The family's entry: `family = "kalman"`.
pub struct Kalman;

impl super::family::Family for Kalman {
    const NAME: &'static str = "kalman";
    type Params = Params;

    /// Any plant: on one with modes, dropouts or factors it is designed on the base (or
    /// mode-averaged) matrices and promises nothing; its surrogate may vary with the step.
    fn supports(_: &Params) -> super::family::Supports {
        super::family::Supports { varying_weights: true, ..super::family::Supports::ALL }
    }

    fn design(input: &DesignInput, p: &Params) -> Result<Design> {
        let cov = super::family::own_design_point(input, &p.design, "a Kalman filter")?;
        if p.plant == PlantChoice::ModeAveraged {
            let avg = mode_averaged(input.plant, input.name)?;
            let mut d = design_at(&avg, cov, input.pattern);
            d.guarantee = None;
            d.diagnostics.insert("plant".into(), "mode-averaged (stationary weights): ignores the modes".into());
            return Ok(d);
        }
        Ok(design_at(input.plant, cov, input.pattern))
    }
}

/// The Kalman filter designed at `cov`, with its guarantee: its exact error at `cov`. On a plant
/// with dropouts it is designed as if every measurement arrived (the usual mistake the anisotropic
/// and intermittent filters are compared with), so it promises nothing there.
pub fn design_at(plant: &Plant, cov: Covariances, pattern: Pattern) -> Design {
    let realization = kalman(plant, &cov, pattern);
    let mut diagnostics = serde_json::Map::new();
    let ignored = if plant.arrival().is_some() {
        Some(("dropouts", "ignored: designed as if every measurement arrived"))
    } else if plant.switches() {
        Some(("modes", "ignored: designed on the plant's base matrices"))
    } else if !plant.factors.is_empty() {
        Some(("multiplicative", "ignored: designed on the mean matrices"))
    } else {
        None
    };
    match ignored {
        Some((key, what)) => {
            diagnostics.insert(key.into(), what.into());
            Design { design_covariance: Some(cov), ..Design::new(realization, diagnostics) }
        }
        None => super::family::exact_at_design(plant, realization, cov, diagnostics),
    }
}

/// The Kalman filter of `plant` for the covariances `cov`, as a realization (module docs).
pub fn kalman(plant: &Plant, cov: &Covariances, pattern: Pattern) -> Realization {
    let step = |a: &Mat, c: &Mat, p: &Mat, dwd: &Mat, bwd: &Mat, _: &Mat| {
        Ok::<_, std::convert::Infallible>(riccati::innovation(a, c, p, dwd, bwd))
    };
    match recursion(plant, cov, pattern, step) {
        Ok(realization) => realization,
        Err((_, never)) => match never {},
    }
}

/// As [`kalman`] for a model whose innovation covariance S is positive definite at every step by
/// construction (seed 004's regularized S_α): S⁻¹ by a Cholesky solve that drops no direction
/// (`riccati::innovation_pd`), or the first step k whose solve would not be accurate, with why.
pub(crate) fn kalman_pd(
    plant: &Plant,
    cov: &Covariances,
    pattern: Pattern,
) -> std::result::Result<Realization, (usize, riccati::IllConditioned)> {
    let step = |a: &Mat, c: &Mat, p: &Mat, dwd: &Mat, bwd: &Mat, lz_rhs: &Mat| {
        riccati::innovation_pd(a, c, p, dwd, bwd, &[lz_rhs])
    };
    recursion(plant, cov, pattern, step)
}

/// The recursion of [`kalman`] with the innovation step `step(A, C, P̄, D W Dᵀ, B W Dᵀ, N_z)`, where
/// N_z = Cz P̄ Cᵀ + Dz W Dᵀ is the filtering form's output-gain right side (zero in prediction).
fn recursion<E>(
    plant: &Plant,
    cov: &Covariances,
    pattern: Pattern,
    step: impl Fn(&Mat, &Mat, &Mat, &Mat, &Mat, &Mat) -> std::result::Result<riccati::Innovation, E>,
) -> std::result::Result<Realization, (usize, E)> {
    let mut w = cov.w();
    let mut pbar = cov.x0().clone();
    // Appended step by step, so a steady state's repeated gains are never held (filter::realization).
    let mut steps = Vec::with_capacity(plant.steps());
    for k in 0..plant.steps() {
        // A disturbance surrogate with time-varying weights (seed 000 eq (39)): W[k] per step.
        if cov.varies() {
            w = cov.w_at(k);
        }
        let bwb = plant.b_at(k) * &w * plant.b_at(k).transpose();
        let (c, d) = (&*plant.c_at(k), &*plant.d_at(k));
        let wd = &w * d.transpose();
        let lz_rhs = match pattern {
            Pattern::Filtering => plant.cz_at(k) * &pbar * c.transpose() + plant.dz_at(k) * &wd,
            Pattern::Prediction => Mat::zeros(0, c.nrows()),
        };
        let inn = step(plant.a_at(k), c, &pbar, &(d * &wd), &(plant.b_at(k) * &wd), &lz_rhs).map_err(|e| (k, e))?;
        let predictor = Gains::predictor(plant.a_at(k), c, &inn.k, plant.cz_at(k));
        let gains = match pattern {
            Pattern::Filtering => {
                let lz = inn.right_solve(&lz_rhs);
                Gains { cf: plant.cz_at(k) - &lz * c, df: lz, ..predictor }
            }
            Pattern::Prediction => predictor,
        };
        push_step(&mut steps, vec![gains]);
        pbar = symmetrize(&riccati::propagate(plant.a_at(k), &pbar, &bwb, &inn.k, &inn.s));
    }
    let n = plant.x0_mean.len();
    Ok(Realization::from_shared(plant.x0_mean.clone(), steps).tracking(Mat::identity(n, n)))
}
