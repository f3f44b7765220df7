//! Runs one experiment end to end: design every filter, resolve every scenario's covariance, compute
//! the exact and worst-case errors, run the Monte Carlo, and hand everything to the reports.

use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::exact::{self, ExactError, WorstCase};
use crate::families::{Design, registry};
use crate::montecarlo::{self, McStats, Trajectory};
use crate::noise::NoiseSampler;
use crate::plant::Covariances;
use crate::spec::Experiment;

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
    pub covariances: Covariances,
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
            let worst = exact::worst_case(&exp.plant, &design.realization, &exp.nominal, &exp.sets)
                .map_err(|e| Error::design(&f.name, format!("worst case over the set: {e}")))?;
            Ok(DesignedFilter { design, seconds, worst })
        })
        .collect()
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
        let sampler = NoiseSampler::new(&exp.plant, &cov, &s.shape);
        let sc =
            montecarlo::Scenario { plant: &exp.plant, filters: &reals, sampler: &sampler, seed: exp.seed, index: i };
        let t = Instant::now();
        let mc = montecarlo::run(&sc, exp.trials as u64, &|n| bar.inc(n));
        let mc_seconds = t.elapsed().as_secs_f64();
        let trajectories = montecarlo::trajectories(&sc, exp.sample_trajectories as u64);
        let exact = reals.iter().map(|r| exact::error(&exp.plant, r, &cov)).collect();
        scenarios.push(ScenarioOutcome {
            name: s.name.clone(),
            covariance_label: s.covariance.label(exp),
            shape_label: s.shape.label(),
            covariances: cov,
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
