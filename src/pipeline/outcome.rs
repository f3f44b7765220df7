//! The typed records the pipeline hands to every report: one [`RunOutcome`] per run, one
//! [`ScenarioOutcome`] per scenario and, in it, one [`FilterOutcome`] per filter with every figure
//! the reports print, each computed here once. The reports only format them.

use std::sync::Arc;

use crate::analysis::exact::ExactError;
use crate::analysis::nees::PerStep;
use crate::filter::design::GuaranteeKind;
use crate::model::plant::{Covariances, Plant};
use crate::numerics::linalg::Mat;
use crate::sim::montecarlo::{FilterStats, McStats, Trajectory};
use crate::sim::series::Series;

use super::design::DesignedFilter;

pub struct RunOutcome {
    pub filters: Vec<DesignedFilter>,
    pub scenarios: Vec<ScenarioOutcome>,
    /// What the families add to the finished run ([`crate::families::Family::after_run`]).
    pub findings: Vec<crate::families::Finding>,
    pub threads: usize,
    pub design_seconds: f64,
    pub total_seconds: f64,
}

/// One scenario's results.
pub struct ScenarioOutcome {
    pub name: String,
    pub covariance_label: String,
    pub shape_label: String,
    /// The covariances noise was drawn with (disturbance blocks zero).
    pub covariances: Covariances,
    pub disturbance_label: String,
    /// The deterministic disturbance (column k added to w\[k]), if any.
    pub disturbance: Option<Mat>,
    pub exact: Vec<ExactError>,
    /// E|W|² of W = col(w\[0..N]) (noise and any deterministic disturbance).
    pub input_power: f64,
    /// The anisotropy of a Gaussian W with the scenario's covariance (None when W is degenerate).
    pub input_anisotropy: Option<f64>,
    pub mc: McStats,
    pub mc_seconds: f64,
    pub trajectories: Vec<Trajectory>,
    /// The noise-free z̄\[k] the sample trials scatter around (seed 003 Figs. 3–4, columns are
    /// steps: `crate::analysis::noise_free::noise_free_output`); None without a known input.
    pub noise_free: Option<Mat>,
    /// With `--per-trial`: per filter, the summed error J of every trial in trial order (else empty).
    pub per_trial: Vec<Vec<f64>>,
    /// Per filter, in the file's order: the figures derived from its exact error and Monte Carlo.
    pub filters: Vec<FilterOutcome>,
}

/// What a filter promises about its per-step error in a scenario: the family's bound where it
/// holds in that scenario (`guaranteed`), else the filter's own belief, its error at its design
/// covariance (`claimed`), which this scenario's input may exceed. A claim is the filter's
/// [`Claimed::per_step`](super::Claimed), shared by every scenario rather than copied into each.
#[derive(Clone, Debug, PartialEq)]
pub enum Promise {
    Guaranteed(Arc<[f64]>),
    Claimed(Arc<[f64]>),
}

impl Promise {
    pub fn label(&self) -> &'static str {
        match self {
            Promise::Guaranteed(_) => "guaranteed",
            Promise::Claimed(_) => "claimed",
        }
    }

    pub fn values(&self) -> &[f64] {
        match self {
            Promise::Guaranteed(v) | Promise::Claimed(v) => v,
        }
    }

    /// The guaranteed bound at step k (None for a claim).
    pub fn bound(&self, k: usize) -> Option<f64> {
        match self {
            Promise::Guaranteed(v) => v.get(k).copied(),
            Promise::Claimed(_) => None,
        }
    }
}

/// Seed 003's mean-square gain E|Z̃|²/E|W|² in a scenario whose input has power E|W|² > 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gain {
    /// The Monte Carlo mean over E|W|², with its 95 % interval.
    pub empirical: f64,
    pub ci_low: f64,
    pub ci_high: f64,
    pub exact: f64,
    /// The exact gain of the noise alone (the deterministic error taken out); None with a
    /// deterministic disturbance, whose error is not the noise's.
    pub exact_noise: Option<f64>,
}

/// A filter's NEES (or NIS) averaged over the steps that count and where it claims an error.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NeesAverage {
    pub exact: Option<f64>,
    /// The mean of the per-step Monte Carlo means.
    pub empirical: Option<f64>,
}

/// One filter in one scenario.
#[derive(Clone, Debug)]
pub struct FilterOutcome {
    /// Its guaranteed summed error where the promise holds in this scenario
    /// ([`super::scenarios::guarantee_holds`]), else None.
    pub guaranteed: Option<f64>,
    /// The kind of that guarantee, where it holds.
    pub guarantee_kind: Option<GuaranteeKind>,
    /// Its per-step promise ([`Promise`]), if it has a non-empty one.
    pub promise: Option<Promise>,
    /// exact / claimed: how far its own belief is from its error here.
    pub consistency: Option<f64>,
    /// Where it claims a covariance: the exact NEES per step (None at a step where it claims no
    /// error).
    pub nees_exact: Option<PerStep>,
    pub nees_average: NeesAverage,
    /// Where it has an innovation and claims its covariance: the exact NIS per step.
    pub nis_exact: Option<PerStep>,
    pub nis_average: NeesAverage,
    /// The mean-square gain, where the input has power.
    pub gain: Option<Gain>,
    /// Whether the input's anisotropy is within its γ²'s level (seed 003), if it guarantees one.
    pub guarantee_applies: Option<bool>,
}

/// What [`FilterOutcome::new`] derives its figures from: a scenario's input and one filter's
/// exact error and Monte Carlo statistics there.
pub struct Evaluated<'a> {
    pub plant: &'a Plant,
    pub input_power: f64,
    pub input_anisotropy: Option<f64>,
    pub disturbed: bool,
    pub holds: bool,
    pub exact: &'a ExactError,
    pub mc: &'a FilterStats,
    pub nees_exact: Option<PerStep>,
    pub nis_exact: Option<PerStep>,
}

impl FilterOutcome {
    /// Every figure of `f` in one scenario (docs/math.md §5's columns of `summary.parquet`).
    pub fn new(f: &DesignedFilter, e: Evaluated) -> Self {
        let g = f.design.guarantee.as_ref().filter(|_| e.holds);
        let promise = match (g, &f.claimed) {
            (Some(g), _) if !g.per_step.is_empty() => Some(Promise::Guaranteed(g.per_step.as_slice().into())),
            (_, Some(c)) if !c.per_step.is_empty() => Some(Promise::Claimed(Arc::clone(&c.per_step))),
            _ => None,
        };
        let st = &e.mc.total;
        let (lo, hi) = st.ci95();
        let gain = (e.input_power > 0.0).then(|| {
            let p = e.input_power;
            Gain {
                empirical: st.mean / p,
                ci_low: lo / p,
                ci_high: hi / p,
                exact: e.exact.total / p,
                exact_noise: (!e.disturbed).then(|| (e.exact.total - f.deterministic_error) / p),
            }
        });
        let (nees_avg, nis_avg) = (
            nees_average(e.plant, e.nees_exact.as_ref(), &e.mc.nees),
            nees_average(e.plant, e.nis_exact.as_ref(), &e.mc.nis),
        );
        FilterOutcome {
            guaranteed: g.map(|g| guaranteed_total(f, g)),
            guarantee_kind: g.map(|g| g.kind),
            promise,
            consistency: f.claimed.as_ref().map(|cl| e.exact.total / cl.total),
            nees_exact: e.nees_exact,
            nees_average: nees_avg,
            nis_exact: e.nis_exact,
            nis_average: nis_avg,
            gain,
            guarantee_applies: f
                .design
                .gain_bound
                .map(|gb| e.input_anisotropy.is_some_and(|a| a <= gb.anisotropy + 1e-9)),
        }
    }
}

/// The summed bound a guarantee prints. With deterministic disturbances a bound over the sets
/// (`minimax`) is the filter's own certified worst case over the sets and the sequences jointly
/// ([`crate::analysis::exact::WorstCase::certified`]): proven for the filter returned, with any
/// number of disturbance blocks, unlike seed 000 Theorem 3's Ĥ (the design's `guarantee.total`,
/// kept in the manifest), whose surrogate drops the cross terms between blocks. Elsewhere the
/// family's own total.
fn guaranteed_total(f: &DesignedFilter, g: &crate::filter::design::Guarantee) -> f64 {
    match f.worst.as_ref().and_then(|w| w.certified) {
        Some(c) if g.kind.bounds_the_sets() => c,
        _ => g.total,
    }
}

/// A filter's NEES (or NIS) averaged over the steps that count and where it claims an error:
/// exact, and the mean of the per-step Monte Carlo means `mc`.
fn nees_average(plant: &Plant, exact: Option<&PerStep>, mc: &Series) -> NeesAverage {
    let Some(exact) = exact else { return NeesAverage::default() };
    let ks: Vec<usize> = (0..exact.len()).filter(|k| plant.counts(*k) && exact.get(*k).is_some()).collect();
    if ks.is_empty() {
        return NeesAverage::default();
    }
    let n = ks.len() as f64;
    let ex = ks.iter().map(|k| exact.get(*k).unwrap_or(0.0)).sum::<f64>() / n;
    let emp = mc.get(ks[0]).map(|_| ks.iter().map(|k| mc.at(*k).mean).sum::<f64>() / n);
    NeesAverage { exact: Some(ex), empirical: emp }
}
