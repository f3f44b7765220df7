//! Runs one experiment end to end: design every filter, resolve every scenario's covariance, compute
//! the exact and worst-case errors, run the Monte Carlo, and hand everything to the reports.

use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;

use crate::disturbance::{self, DisturbanceChoice};
use crate::error::{Error, Result};
use crate::exact::{self, ExactError, WorstCase};
use crate::families::{Design, registry};
use crate::linalg::Mat;
use crate::montecarlo::{self, McStats, Trajectory};
use crate::noise::{JointInput, NoiseSampler};
use crate::plant::Covariances;
use crate::realization::Realization;
use crate::spec::{Experiment, InputChoice};

/// A designed filter with its cost and its worst case over the experiment's uncertainty sets.
pub struct DesignedFilter {
    pub design: Design,
    pub seconds: f64,
    pub worst: Option<WorstCase>,
}

/// One scenario's results.
pub struct ScenarioOutcome {
    pub name: String,
    pub covariance_label: String,
    pub shape_label: String,
    /// The covariances noise was drawn with (disturbance blocks zero).
    pub covariances: Covariances,
    pub disturbance_label: String,
    /// The deterministic disturbance (column k added to w[k]), if any.
    pub disturbance: Option<Mat>,
    pub exact: Vec<ExactError>,
    pub mc: McStats,
    pub mc_seconds: f64,
    pub trajectories: Vec<Trajectory>,
}

pub struct RunOutcome {
    pub filters: Vec<DesignedFilter>,
    pub scenarios: Vec<ScenarioOutcome>,
    pub threads: usize,
    pub design_seconds: f64,
    pub total_seconds: f64,
}

/// Designs every filter of `exp` (in parallel; each timed on its own).
pub fn design_all(exp: &Experiment) -> Result<Vec<DesignedFilter>> {
    exp.filters
        .par_iter()
        .map(|f| {
            let t = Instant::now();
            let design = registry::design(exp, f)?;
            let seconds = t.elapsed().as_secs_f64();
            let worst = worst_case(exp, &design.realization)
                .map_err(|e| Error::design(&f.name, format!("worst case over the set: {e}")))?;
            Ok(DesignedFilter { design, seconds, worst })
        })
        .collect()
}

/// A filter's exact worst case over the experiment's uncertainty: covariances over their sets
/// (disturbance blocks carry no covariance) and deterministic disturbances over their energy bounds
/// ([`disturbance::worst`]), evaluated exactly at the joint maximizer. None if the experiment has
/// neither sets nor disturbances.
pub fn worst_case(exp: &Experiment, real: &Realization) -> Result<Option<WorstCase>> {
    let center = exp.sampling(&exp.nominal);
    let sets = exact::worst_case(&exp.plant, real, &center, &exp.sets)?;
    let dist = disturbance::worst(&exp.plant, real, &exp.disturbances)?;
    if sets.is_none() && dist.is_none() {
        return Ok(None);
    }
    let mut wc = sets.unwrap_or(WorstCase { total: 0.0, argmax: center, psd: true, disturbance: None });
    wc.disturbance = dist.map(|(_, wm)| wm);
    wc.total = exact::error_with_mean(&exp.plant, real, &wc.argmax, wc.disturbance.as_ref()).total;
    Ok(Some(wc))
}

/// The per-trial ratio checks of the filters that promise one (seed 002), weighted by the nominal
/// covariances of x0 and w (pseudo-inverses, so a singular block simply carries no weight).
pub fn ratio_check<'a>(exp: &Experiment, filters: &'a [DesignedFilter]) -> Option<montecarlo::RatioCheck<'a>> {
    let bounds: Vec<_> = filters.iter().map(|f| f.design.per_trial.as_ref()).collect();
    bounds.iter().any(Option::is_some).then(|| montecarlo::RatioCheck {
        x0_weight: crate::linalg::psd_pinv(exp.nominal.x0()),
        w_weight: crate::linalg::psd_pinv(&exp.nominal.w()),
        bounds,
    })
}

/// The joint input of a scenario, if it has one, with the ellipsoid weighted by the nominal
/// covariances K = blockdiag(x0, w, …, w) (seed 002).
fn joint_input(exp: &Experiment, filters: &[DesignedFilter], input: &InputChoice) -> Result<Option<JointInput>> {
    let k = || crate::hinf::input_weight(&exp.plant, &exp.sampling(&exp.nominal));
    Ok(match input {
        InputChoice::Independent => None,
        InputChoice::EllipsoidSurface => {
            Some(JointInput::Ellipsoid { k_half: crate::linalg::psd_factor(&k()), surface: true })
        }
        InputChoice::EllipsoidInterior => {
            Some(JointInput::Ellipsoid { k_half: crate::linalg::psd_factor(&k()), surface: false })
        }
        InputChoice::RandomCovariance { seed } => Some(JointInput::random_covariance(&k(), *seed)),
        InputChoice::EllipsoidWorstFor { filter } => {
            let d = &filters[*filter].design;
            let n = exp.plant.nx();
            let s = match &d.per_trial {
                Some(crate::families::PerTrialBound::Ratio { terminal_weight, .. }) => terminal_weight.clone(),
                _ => Mat::zeros(n, n),
            };
            let (_, xi) = crate::hinf::norm(&exp.plant, &d.realization, &exp.sampling(&exp.nominal), &s)?;
            Some(JointInput::Fixed { xi })
        }
    })
}

/// Resolves the concrete covariance of every scenario (a worst case needs the designed filter).
pub fn scenario_covariances(exp: &Experiment, filters: &[DesignedFilter]) -> Result<Vec<Covariances>> {
    exp.scenarios
        .iter()
        .map(|s| s.covariance.covariances(&format!("scenarios.{}.covariance", s.name), exp, Some(filters)))
        .collect()
}

/// Runs the whole experiment on the current rayon pool.
pub fn run(exp: &Experiment, show_progress: bool) -> Result<RunOutcome> {
    let start = Instant::now();
    let filters = design_all(exp)?;
    let design_seconds = start.elapsed().as_secs_f64();
    let covs = scenario_covariances(exp, &filters)?;
    let reals: Vec<&crate::realization::Realization> = filters.iter().map(|f| &f.design.realization).collect();
    let ratios = ratio_check(exp, &filters);

    let total = exp.trials as u64 * exp.scenarios.len() as u64;
    let bar = if show_progress {
        ProgressBar::new(total)
    } else {
        ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::hidden())
    };
    bar.set_style(
        ProgressStyle::with_template("{msg:>24} [{bar:40}] {pos}/{len} trials ({per_sec}, eta {eta})")
            .expect("valid template")
            .progress_chars("=> "),
    );

    let mut scenarios = Vec::with_capacity(exp.scenarios.len());
    for (i, (s, cov)) in exp.scenarios.iter().zip(covs).enumerate() {
        bar.set_message(s.name.clone());
        let cov = exp.sampling(&cov);
        let (disturbance_label, w_mean) = match &s.disturbance {
            DisturbanceChoice::None => ("none".to_string(), None),
            DisturbanceChoice::Random { seed } => {
                (format!("random(seed={seed})"), Some(disturbance::random(&exp.plant, &exp.disturbances, *seed)))
            }
            DisturbanceChoice::WorstFor { filter } => (
                format!("worst_for({})", exp.filters[*filter].name),
                filters[*filter].worst.as_ref().and_then(|w| w.disturbance.clone()),
            ),
        };
        let joint = joint_input(exp, &filters, &s.input)?;
        let sampler = NoiseSampler::new(&exp.plant, &cov, &s.shape).with_mean(w_mean.clone()).with_joint(joint.clone());
        let sc = montecarlo::Scenario {
            plant: &exp.plant,
            filters: &reals,
            sampler: &sampler,
            seed: exp.seed,
            index: i,
            ratios: ratios.as_ref(),
        };
        let t = Instant::now();
        let mc = montecarlo::run(&sc, exp.trials as u64, &|n| bar.inc(n));
        let mc_seconds = t.elapsed().as_secs_f64();
        let trajectories = montecarlo::trajectories(&sc, exp.sample_trajectories as u64);
        let exact = match &joint {
            None => reals.iter().map(|r| Ok(exact::error_with_mean(&exp.plant, r, &cov, w_mean.as_ref()))).collect(),
            Some(j) => {
                let (mean, jcov) = j.moments();
                reals.iter().map(|r| exact::error_joint(&exp.plant, r, &mean, &jcov)).collect::<Result<Vec<_>>>()
            }
        }?;
        let covariance_label = joint.as_ref().map_or_else(|| s.covariance.label(exp), |j| j.label().to_string());
        scenarios.push(ScenarioOutcome {
            name: s.name.clone(),
            covariance_label,
            shape_label: s.shape.label(),
            covariances: cov,
            disturbance_label,
            disturbance: w_mean,
            exact,
            mc,
            mc_seconds,
            trajectories,
        });
    }
    bar.finish_and_clear();
    Ok(RunOutcome {
        filters,
        scenarios,
        threads: rayon::current_num_threads(),
        design_seconds,
        total_seconds: start.elapsed().as_secs_f64(),
    })
}
