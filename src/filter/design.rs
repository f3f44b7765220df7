//! What a design hands on: its realization, what its theory promises, the covariance it was
//! designed at, and the iterations of an iterative design.

use crate::error::{Error, Result};
use crate::filter::realization::Realization;
use crate::model::choice::{CovChoice, CovChoiceFile, check_point};
use crate::model::plant::{Covariances, Pattern, Plant};
use crate::model::string::StringModel;
use crate::model::uncertainty::CovSet;
use crate::numerics::linalg::Mat;

/// What a family designs from: the plant and its information pattern, the nominal covariances
/// (a disturbance block holds its design surrogate, seed 000 eq (39)) and their uncertainty sets,
/// and, for seed 004, the string. `name` is the filter's, for the keys in messages.
#[derive(Clone, Copy)]
pub struct DesignInput<'a> {
    pub name: &'a str,
    pub plant: &'a Plant,
    pub pattern: Pattern,
    pub nominal: &'a Covariances,
    pub sets: &'a [Option<CovSet>],
    pub string: Option<&'a StringModel>,
}

impl DesignInput<'_> {
    /// `filters.NAME.sub`, the key a message about this filter's parameter `sub` names.
    pub fn key(&self, sub: &str) -> String {
        format!("filters.{}.{sub}", self.name)
    }

    pub fn has_sets(&self) -> bool {
        self.sets.iter().any(Option::is_some)
    }

    /// The covariance a design parameter names (SPEC §7's choices, without the ones that name
    /// another filter: the caller refuses those with its own reason). `has_sets`: whether the
    /// choices that need an uncertainty set may be taken.
    pub fn design_point(&self, key: &str, choice: &CovChoiceFile, has_sets: bool) -> Result<Covariances> {
        let c = CovChoice::resolve(key, choice, self.plant, self.nominal, has_sets, |_| None)?;
        let cov = c
            .point(self.nominal, self.sets)?
            .ok_or_else(|| Error::invalid(key, "refers to a filter, which is not allowed here"))?;
        check_point(key, &c.label(|_| ""), self.plant, &cov)?;
        Ok(cov)
    }
}

/// What a family's theory promises about its error.
#[derive(Clone, Debug)]
pub struct Guarantee {
    /// Short name of the promise, e.g. `exact_at_design` for Kalman (the summed error it attains
    /// when the noise has its design covariance).
    pub kind: String,
    pub total: f64,
    pub per_step: Vec<f64>,
}

/// One iteration of an iterative design (seed 000 Algorithm 1: s, I(K(s)), the gap δ(s), the step
/// τ(s) taken after it).
#[derive(Clone, Debug)]
pub struct TraceRow {
    pub iteration: usize,
    pub objective: f64,
    pub gap: f64,
    pub step: f64,
}

/// A designed filter.
#[derive(Clone, Debug)]
pub struct Design {
    pub realization: Realization,
    pub guarantee: Option<Guarantee>,
    /// The covariance the filter was designed at (Kalman: its `design`; minimax: K̂), if any.
    pub design_covariance: Option<Covariances>,
    /// Iterations of the design procedure (empty for closed-form designs).
    pub trace: Vec<TraceRow>,
    /// Anything else worth keeping in the manifest (solver figures, which theorem applied, …).
    pub diagnostics: serde_json::Map<String, serde_json::Value>,
    /// A guarantee that holds for every single trial (seed 002's H∞-λ), checked on each one.
    pub per_trial: Option<PerTrialBound>,
    /// A bound on the mean-square gain over inputs of bounded anisotropy (seed 003).
    pub gain_bound: Option<GainBound>,
}

impl Design {
    /// A filter with no promise attached; families add theirs with struct update syntax.
    pub fn new(realization: Realization, diagnostics: serde_json::Map<String, serde_json::Value>) -> Self {
        Design {
            realization,
            guarantee: None,
            design_covariance: None,
            trace: Vec::new(),
            diagnostics,
            per_trial: None,
            gain_bound: None,
        }
    }
}

/// Seed 003's promise: E|Z̃|² ≤ γ² E|W|² for every input W = col(w[0..N]) with anisotropy ≤ a
/// (a = ∞: every input; the H∞-suboptimal filter).
#[derive(Clone, Copy, Debug)]
pub struct GainBound {
    pub gamma_sq: f64,
    pub anisotropy: f64,
}

/// Seed 002's per-realization promises, with the input energy
/// E_t = |x0 − E x0|²_R + Σ_{k<t} |w[k]|²_G (R, G the nominal covariances of x0 and w).
#[derive(Clone, Debug)]
pub enum PerTrialBound {
    /// H∞-λ (eqs (5.9)–(5.10)): (Σ_{k<N} |e_z[k]|² + e[N]ᵀ S e[N]) / E_N < bound, e = x − s.
    Ratio { bound: f64, terminal_weight: Mat },
    /// Generalized H2 (Theorem 3.1 on (5.6)–(5.7)): e_z[t]ᵀ Q[t] e_z[t] ≤ E_t at every step t, with
    /// Q[t] = (Cz P2[t] Czᵀ)⁺: the error lies in the ellipsoid of Cz P2 Czᵀ scaled by the energy.
    Ellipsoid { weights: Vec<Mat> },
}

impl PerTrialBound {
    /// The bound on the reported ratio (1 for the ellipsoid form).
    pub fn bound(&self) -> f64 {
        match self {
            PerTrialBound::Ratio { bound, .. } => *bound,
            PerTrialBound::Ellipsoid { .. } => 1.0,
        }
    }
}
