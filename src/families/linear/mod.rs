//! The `linear` family (docs/families.md): a filter the user gives by its matrices, in one of
//! three forms, on which every analysis of the run is made like on a designed one.
//!
//! - Its realization (docs/math.md §0): s\[k+1] = Af s + Bf y + Gf r, ẑ = Cf s + Df y, with Gf
//!   given, or Gf = I when `known_input` (allowed only when the state has the plant's size) and
//!   Gf = 0 otherwise.
//! - A gain K on the plant's own model (A, C, Cz of each step), in predictor form
//!   x̂\[k+1] = A x̂ + K (y − C x̂) + r, ẑ = Cz x̂ (seed 000 eq (4), seed 002 eq (5.7): the
//!   realization [`crate::filter::realization::Gains::predictor`] builds), or in filter form x̂⁻\[k+1] = A x̂ + r,
//!   x̂ = x̂⁻ + K (y − C x̂⁻), ẑ = Cz x̂, realized on the prior x̂⁻ like the Kalman family's filtering
//!   form (seed 000 eqs (4)–(6)): Af = A − (A K) C, Bf = A K, Cf = Cz − (Cz K) C, Df = Cz K. The
//!   part Dz w\[k] of z is estimated as zero: a gain on x carries no estimate of w.
//! - A filter of an earlier run (`from_run`): the configuration reads its realization from the
//!   run's gains.parquet into the first form, and the design checks that the run's plant model is
//!   this one ([`crate::model::plant::Plant::model_digest`]).
//!
//! Each matrix is constant or given per step (N + 1 of them, first axis k). On a switching plant
//! `modes` gives per-mode matrices, one table per mode in the plant's order, each key defaulting
//! to the filter's own: a filter that observes the mode and uses that mode's matrices, like
//! seed 001's predictor (6) (in the gain form on mode θ's model A_θ, C_θ). The family promises
//! nothing; the user may state the error covariance of x it believes (`claimed`, for the claimed
//! error and NEES) and a bound on its summed error (`claimed_bound`), which the run checks
//! against the exact and Monte Carlo errors and never shows as guaranteed.

mod build;
mod matrices;
mod params;

pub use matrices::Matrices;
pub use params::{GainForm, ModeMatrices, Params, RunOrigin, RunPlant};


use crate::error::Result;
use crate::filter::design::{Design, DesignInput, Figures, Record};

use super::family::{ANY_PATTERN, Family, Finding, Footprint, PlantSize, RunView, Supports};


/// The family's figures: its form, its state size and the bound the user states (the summary's
/// `figure_claimed_bound`, never a guarantee).
#[derive(Debug, serde::Serialize)]
pub struct LinearFigures {
    pub form: &'static str,
    pub state: usize,
    pub claimed_bound: Option<f64>,
}

impl Record for LinearFigures {
    fn summary(&self) -> Vec<(&'static str, f64)> {
        self.claimed_bound.map(|b| vec![("claimed_bound", b)]).unwrap_or_default()
    }
}

/// What the run says of a stated bound: per `linear` filter with a `claimed_bound` and per
/// scenario, whether the exact summed error exceeds it, and whether the Monte Carlo mean does so
/// significantly (its 95 % interval lies wholly above the bound).
#[derive(Debug, serde::Serialize)]
pub struct ClaimedBounds {
    pub checks: Vec<BoundCheck>,
}

#[derive(Debug, serde::Serialize)]
pub struct BoundCheck {
    pub filter: String,
    pub scenario: String,
    pub claimed_bound: f64,
    pub exact: f64,
    pub mc_mean: f64,
    pub mc_ci_low: f64,
    pub broken_by_exact: bool,
    pub broken_by_monte_carlo: bool,
}

impl Record for ClaimedBounds {}

type Check = std::result::Result<(), (&'static str, String)>;

/// The family's entry: `family = "linear"`.
pub struct Linear;

impl Family for Linear {
    const NAME: &'static str = "linear";
    type Params = Params;

    /// Any plant. Dropouts, Markov modes and multiplicative factors are part of the truth the
    /// filter runs on; the gain form uses the plant's mean matrices of each step, or with `modes`
    /// each mode's.
    fn supports(_: &Params) -> Supports {
        Supports { patterns: ANY_PATTERN, varying_weights: true, ..Supports::ALL }
    }

    /// Exactly one form, its keys complete (for the filter or in every mode), and the sizes that
    /// do not need the plant consistent.
    fn check(p: &Params) -> Check {
        let modes: &[ModeMatrices] = p.modes.as_deref().unwrap_or_default();
        if p.modes.as_ref().is_some_and(Vec::is_empty) {
            return Err(("modes", "is empty: give one table per mode of the plant".into()));
        }
        // Whether `key` is given for the filter or in some mode, and whether in every mode.
        let given = |own: bool, pick: fn(&ModeMatrices) -> bool| {
            (own || modes.iter().any(pick), own || (!modes.is_empty() && modes.iter().all(pick)))
        };
        let realization_keys: [(&'static str, (bool, bool)); 5] = [
            ("Af", given(p.af.is_some(), |m| m.af.is_some())),
            ("Bf", given(p.bf.is_some(), |m| m.bf.is_some())),
            ("Cf", given(p.cf.is_some(), |m| m.cf.is_some())),
            ("Df", given(p.df.is_some(), |m| m.df.is_some())),
            ("Gf", given(p.gf.is_some(), |m| m.gf.is_some())),
        ];
        let gain = given(p.gain.is_some(), |m| m.gain.is_some());
        if p.is_gain_form() || gain.0 {
            if let Some((key, _)) = realization_keys.iter().find(|(_, (any, _))| *any) {
                return Err((key, "belongs to the realization form (Af, Bf, Cf), but gain/form of the gain form are given: give one form".into()));
            }
            if p.known_input.is_some() {
                return Err(("known_input", "belongs to the realization form: the gain form adds the known input as the plant does".into()));
            }
            if p.from_run.is_some() {
                return Err(("from_run", "gives a realization, but gain/form of the gain form are given: give one form".into()));
            }
            if !gain.1 {
                return Err(("gain", "missing: the gain form needs gain (n × ny, or one per step; for the filter or in every mode) and form".into()));
            }
            if p.form.is_none() {
                return Err(("form", "missing: \"predictor\" or \"filter\"".into()));
            }
        } else {
            for (key, (_, every)) in &realization_keys[..3] {
                if !every {
                    return Err((
                        key,
                        "missing: a linear filter is given by its realization (Af, Bf, Cf; for the filter or in every mode), by a gain (gain, form) or by from_run"
                            .into(),
                    ));
                }
            }
            if p.known_input.is_some() && realization_keys[4].1.0 {
                return Err(("known_input", "and Gf both say how the known input enters: give one".into()));
            }
            if let (Some(af), Some(bf), Some(cf)) = (&p.af, &p.bf, &p.cf) {
                let (af, bf, cf) = (af.shape(), bf.shape(), cf.shape());
                let ns = af.0;
                if af.1 != ns {
                    return Err(("Af", format!("must be square, found {}×{}", af.0, af.1)));
                }
                if bf.0 != ns {
                    return Err(("Bf", format!("has {} rows, Af has {ns}", bf.0)));
                }
                if cf.1 != ns {
                    return Err(("Cf", format!("has {} columns, Af has {ns} rows", cf.1)));
                }
                if let Some(df) = p.df.as_ref().map(Matrices::shape).filter(|df| *df != (cf.0, bf.1)) {
                    return Err(("Df", format!("is {}×{}, but Cf and Bf make it {}×{}", df.0, df.1, cf.0, bf.1)));
                }
                if let Some(s0) = p.s0.as_ref().filter(|s0| s0.len() != ns) {
                    return Err(("s0", format!("has {} entries, Af has {ns} rows", s0.len())));
                }
            }
        }
        if let Some(x) = p.s0.iter().flatten().find(|x| !x.is_finite()) {
            return Err(("s0", format!("entry {x} is not finite")));
        }
        if let Some((r, c)) = p.claimed.as_ref().map(Matrices::shape).filter(|(r, c)| r != c) {
            return Err(("claimed", format!("an error covariance must be square, found {r}×{c}")));
        }
        match p.claimed_bound {
            Some(b) if !(b.is_finite() && b >= 0.0) => {
                Err(("claimed_bound", format!("must be a finite number ≥ 0, found {b}")))
            }
            _ => Ok(()),
        }
    }

    fn footprint(p: &Params, plant: PlantSize) -> Footprint {
        let first_mode = p.modes.iter().flatten().find_map(|m| m.af.as_ref());
        let state = p.af.as_ref().or(first_mode).map_or(plant.nx, |af| af.shape().0);
        Footprint { state, gain_sets: p.modes.as_ref().map_or(1, Vec::len), dense_horizon: false }
    }

    fn design(input: &DesignInput, p: &Params) -> Result<Design> {
        if let Some(origin) = &p.from_run {
            build::check_origin(input, origin)?;
        }
        let (realization, form) = match p.form {
            Some(form) => (build::from_gain(input, p, form)?, form_name(form)),
            None if p.from_run.is_some() => (build::from_realization(input, p)?, "from_run"),
            None => (build::from_realization(input, p)?, "realization"),
        };
        let mut d = Design::new(realization, serde_json::Map::new());
        if let Some(claimed) = &p.claimed {
            d.claimed_error = Some(build::claimed_output(input, claimed)?);
        }
        let state = d.realization.ns();
        d.figures = Figures::of(LinearFigures { form, state, claimed_bound: p.claimed_bound });
        Ok(d)
    }

    fn after_run(run: &RunView, mine: &[usize]) -> Result<Option<Finding>> {
        let mut checks = Vec::new();
        for &f in mine {
            let (name, _, design) = run.filters[f];
            let Some(bound) = design.figures.get::<LinearFigures>().and_then(|l| l.claimed_bound) else { continue };
            for ((scenario, exact), mc) in run.exact.iter().zip(&run.monte_carlo) {
                let (mean, low, _) = mc[f];
                checks.push(BoundCheck {
                    filter: name.to_string(),
                    scenario: scenario.to_string(),
                    claimed_bound: bound,
                    exact: exact[f],
                    mc_mean: mean,
                    mc_ci_low: low,
                    broken_by_exact: exact[f] > bound,
                    broken_by_monte_carlo: low > bound,
                });
            }
        }
        Ok((!checks.is_empty())
            .then(|| Finding { family: Self::NAME, record: std::sync::Arc::new(ClaimedBounds { checks }) }))
    }
}

fn form_name(form: GainForm) -> &'static str {
    match form {
        GainForm::Predictor => "gain, predictor",
        GainForm::Filter => "gain, filter",
    }
}
