//! Layer 8: one experiment end to end. [`run`] reads as the whole pipeline: design every filter
//! ([`design`]), make each scenario concrete ([`scenarios`]), evaluate it exactly and by Monte Carlo
//! ([`evaluate`]), and hand one typed [`RunOutcome`] ([`outcome`]) to every report.

pub mod bench;
pub mod budget;
pub mod design;
pub mod discrepancy;
pub mod evaluate;
pub mod outcome;
pub mod scenarios;

use std::time::Instant;

pub use design::{AnisotropicFigures, Claimed, DesignedFilter, design_all, worst_case};
pub use evaluate::three_figures;
pub use outcome::{FilterOutcome, Gain, NeesAverage, Promise, RunOutcome, ScenarioOutcome};
pub use scenarios::{guarantee_holds, scenario_covariances};

use crate::config::Experiment;
use crate::error::Result;

/// Runs the whole experiment on the current rayon pool.
pub fn run(exp: &Experiment, show_progress: bool) -> Result<RunOutcome> {
    let start = Instant::now();
    let filters = design_all(exp)?;
    let design_seconds = start.elapsed().as_secs_f64();
    let covs = scenario_covariances(exp, &filters)?;
    let engine = evaluate::Engine::new(exp, &filters);
    let bar = evaluate::progress_bar(exp.trials as u64, show_progress);
    let mut scenarios = Vec::with_capacity(exp.scenarios.len());
    for (i, (s, cov)) in exp.scenarios.iter().zip(&covs).enumerate() {
        bar.reset();
        bar.set_message(format!("scenario {}/{} {}", i + 1, exp.scenarios.len(), s.name));
        let setup = scenarios::setup(exp, &filters, i, cov)?;
        scenarios.push(evaluate::evaluate(&engine, setup, i, &bar)?);
    }
    bar.finish_and_clear();
    drop(engine);
    Ok(RunOutcome {
        filters,
        scenarios,
        threads: rayon::current_num_threads(),
        design_seconds,
        total_seconds: start.elapsed().as_secs_f64(),
    })
}
