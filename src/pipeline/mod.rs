//! Layer 8: one experiment end to end, in stages written once (`execute`): design every filter
//! ([`design`]), resolve every scenario's covariance and make it concrete ([`scenarios`]), its
//! exact errors, its Monte Carlo from the one source the command chose ([`MonteCarlo`]), and one
//! typed [`RunOutcome`] ([`outcome`]) for every report. Shard runs ([`shards`]) and `bench`
//! ([`mod@bench`]) go through the same stages (`each_scenario`).

pub mod bench;
pub mod budget;
pub mod design;
pub mod evaluate;
pub mod findings;
pub mod outcome;
pub mod scenarios;
pub mod shards;
pub(crate) mod table;

use std::time::Instant;

pub use design::{AnisotropicFigures, Claimed, DesignedFilter, design_all, worst_case};
pub use evaluate::{MonteCarlo, Prepared, three_figures};
pub use outcome::{FilterOutcome, Gain, NeesAverage, Promise, RunOutcome, ScenarioOutcome};
pub use scenarios::{guarantee_holds, scenario_covariances};

use crate::config::Experiment;
use crate::error::Result;

use evaluate::Engine;

/// Runs the whole experiment on the current rayon pool.
pub fn run(exp: &Experiment, show_progress: bool) -> Result<RunOutcome> {
    execute(exp, MonteCarlo::Run { progress: show_progress.then(indicatif::MultiProgress::new) })
}

/// Runs every variant of one experiment file ([`crate::config::load`]'s list) side by side on the
/// current rayon pool, each as [`run`] would alone (so the same bits), one progress bar per
/// variant. One after the other, each variant's serial stretches (its last design, a scenario's
/// setup) leave cores idle that another variant's work now fills. The memory budget
/// ([`budget::check`]) already adds up the variants' peaks. The first failure in file order is the
/// one reported.
pub fn run_variants(exps: &[Experiment], show_progress: bool) -> Result<Vec<RunOutcome>> {
    use rayon::prelude::*;
    let bars = show_progress.then(indicatif::MultiProgress::new);
    let outcomes: Vec<Result<RunOutcome>> =
        exps.par_iter().with_max_len(1).map(|e| execute(e, MonteCarlo::Run { progress: bars.clone() })).collect();
    outcomes.into_iter().collect()
}

/// The pipeline: the designs, then scenario by scenario its setup, exact errors, Monte Carlo
/// statistics from `mc` and outcome. A merge computes everything but the Monte Carlo as a run does,
/// so its tables are those of one run.
pub(crate) fn execute(exp: &Experiment, mc: MonteCarlo) -> Result<RunOutcome> {
    let start = Instant::now();
    let filters = design_all(exp)?;
    let design_seconds = start.elapsed().as_secs_f64();
    let mut source = evaluate::Source::new(exp, mc, || fingerprint(&filters))?;
    let count = exp.scenarios.len();
    let scenarios = each_scenario(exp, &filters, |engine, p| {
        source.start(p.index, count, &exp.scenarios[p.index].name);
        evaluate::outcome(engine, p, &mut source)
    })?;
    source.finish();
    let findings = findings::after_run(exp, &filters, &scenarios)?;
    Ok(RunOutcome {
        filters,
        scenarios,
        findings,
        threads: rayon::current_num_threads(),
        design_seconds,
        total_seconds: start.elapsed().as_secs_f64(),
    })
}

/// The stages between the designs and the Monte Carlo, for every command: each scenario's
/// covariance resolved (all first: a worst case is refused before any trial runs), then one
/// scenario at a time its setup and exact errors (a filter whose error double precision cannot
/// resolve is refused before its Monte Carlo), handed to `each` with the engine. One scenario's
/// setup is alive at a time.
pub(crate) fn each_scenario<T>(
    exp: &Experiment,
    filters: &[DesignedFilter],
    mut each: impl FnMut(&Engine, Prepared) -> Result<T>,
) -> Result<Vec<T>> {
    let covs = scenario_covariances(exp, filters)?;
    let engine = Engine::new(exp, filters);
    let mut out = Vec::with_capacity(covs.len());
    for (index, cov) in covs.iter().enumerate() {
        let setup = scenarios::setup(exp, filters, index, cov)?;
        let (exact, forms) = evaluate::exact_errors(&engine, &setup)?;
        let stacked = engine.stacked(&forms);
        out.push(each(&engine, Prepared { index, setup, exact, forms, stacked })?);
    }
    Ok(out)
}

/// The designs' fingerprint: SHA-256 over every filter's realization, as bits, in file order.
pub fn fingerprint(filters: &[DesignedFilter]) -> String {
    use sha2::Digest;
    let mut h = sha2::Sha256::new();
    for f in filters {
        f.design.realization.digest(&mut h);
    }
    crate::numerics::linalg::hex(&h.finalize())
}
