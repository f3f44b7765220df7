//! Layer 8: one experiment end to end. [`run`] reads as the whole pipeline: design every filter
//! ([`design`]), make each scenario concrete ([`scenarios`]), evaluate it exactly and by Monte Carlo
//! ([`evaluate`]), and hand one typed [`RunOutcome`] ([`outcome`]) to every report.

pub mod bench;
pub mod budget;
pub mod design;
pub mod evaluate;
pub mod findings;
pub mod outcome;
pub mod scenarios;

use std::time::Instant;

pub use design::{AnisotropicFigures, Claimed, DesignedFilter, design_all, worst_case};
pub use evaluate::three_figures;
pub use outcome::{FilterOutcome, Gain, NeesAverage, Promise, RunOutcome, ScenarioOutcome};
pub use scenarios::{guarantee_holds, scenario_covariances};

use crate::config::Experiment;
use crate::error::{Error, Result};
use crate::sim::montecarlo::{self, Partial};

/// Runs the whole experiment on the current rayon pool.
pub fn run(exp: &Experiment, show_progress: bool) -> Result<RunOutcome> {
    run_inner(exp, show_progress, None)
}

/// The experiment's run from its shards' Monte Carlo (`filterbench merge`): the designs are made
/// again and must have `fingerprint`; `given` holds per scenario every shard's tree nodes in block
/// order and the per-trial J in trial order. Everything else is computed as in [`run`], so the
/// tables are those of one run.
pub fn merged(exp: &Experiment, fingerprint: &str, given: Vec<Partial>) -> Result<RunOutcome> {
    run_inner(exp, false, Some((fingerprint, given)))
}

fn run_inner(exp: &Experiment, show_progress: bool, given: Option<(&str, Vec<Partial>)>) -> Result<RunOutcome> {
    let start = Instant::now();
    let filters = design_all(exp)?;
    let design_seconds = start.elapsed().as_secs_f64();
    let mut given = match given {
        None => None,
        Some((expected, given)) => {
            let ours = fingerprint(&filters);
            if ours != expected {
                return Err(Error::invalid(
                    "merge",
                    format!("the shards' designs (fingerprint {expected}) differ from this machine's ({ours})"),
                ));
            }
            Some(given.into_iter())
        }
    };
    let covs = scenario_covariances(exp, &filters)?;
    let engine = evaluate::Engine::new(exp, &filters);
    let bar = evaluate::progress_bar(exp.trials as u64, show_progress);
    let mut scenarios = Vec::with_capacity(exp.scenarios.len());
    for (i, (s, cov)) in exp.scenarios.iter().zip(&covs).enumerate() {
        bar.reset();
        bar.set_message(format!("scenario {}/{} {}", i + 1, exp.scenarios.len(), s.name));
        let setup = scenarios::setup(exp, &filters, i, cov)?;
        let mc = given.as_mut().map(|g| g.next().expect("one partial per scenario"));
        scenarios.push(evaluate::evaluate(&engine, setup, i, &bar, mc)?);
    }
    bar.finish_and_clear();
    drop(engine);
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

/// An experiment designed for running shards (`--shard I/N`): the filters, and per scenario its
/// setup and the coordinates each filter is simulated in, made once for any number of shards.
pub struct ShardDesigns<'a> {
    exp: &'a Experiment,
    filters: Vec<DesignedFilter>,
    scenarios: Vec<(scenarios::Setup, Vec<Option<crate::analysis::exact::ErrorForm>>)>,
    /// The designs' [`fingerprint`].
    pub fingerprint: String,
}

impl<'a> ShardDesigns<'a> {
    pub fn new(exp: &'a Experiment) -> Result<Self> {
        let filters = design_all(exp)?;
        let covs = scenario_covariances(exp, &filters)?;
        let engine = evaluate::Engine::new(exp, &filters);
        let scenarios = covs
            .iter()
            .enumerate()
            .map(|(i, cov)| {
                let setup = scenarios::setup(exp, &filters, i, cov)?;
                let (_, forms) = evaluate::exact_errors(&engine, &setup)?;
                Ok((setup, forms))
            })
            .collect::<Result<Vec<_>>>()?;
        drop(engine);
        let fingerprint = fingerprint(&filters);
        Ok(ShardDesigns { exp, filters, scenarios, fingerprint })
    }

    /// Blocks `blocks` of the experiment's Monte Carlo: per scenario, the tree nodes and per-trial J
    /// of those blocks alone.
    pub fn run(&self, blocks: std::ops::Range<u64>) -> Vec<Partial> {
        let exp = self.exp;
        let engine = evaluate::Engine::new(exp, &self.filters);
        let trials = exp.trials as u64;
        let mut out = Vec::with_capacity(self.scenarios.len());
        for (i, (setup, forms)) in self.scenarios.iter().enumerate() {
            let sc = engine.scenario(setup, i, forms);
            out.push(montecarlo::run_range(&sc, trials, blocks.clone(), exp.per_trial, &|_| {}));
        }
        out
    }
}

/// The designs' fingerprint: SHA-256 over every filter's realization, as bits, in file order.
pub fn fingerprint(filters: &[DesignedFilter]) -> String {
    use sha2::Digest;
    let mut h = sha2::Sha256::new();
    for f in filters {
        f.design.realization.digest(&mut h);
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}
