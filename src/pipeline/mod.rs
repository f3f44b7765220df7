//! Layer 8: one experiment end to end, in stages written once ([`execute`]): design every filter
//! ([`design`]), resolve every scenario's covariance and make it concrete ([`scenarios`]), its
//! exact errors, its Monte Carlo from the one source the command chose ([`MonteCarlo`]), and one
//! typed [`RunOutcome`] ([`outcome`]) for every report. Shard runs ([`shards`]) and `bench`
//! ([`mod@bench`]) go through the same stages ([`each_scenario`]).

pub mod bench;
pub mod budget;
pub mod design;
pub mod evaluate;
pub mod findings;
pub mod outcome;
pub mod scenarios;
pub mod shards;

use std::time::Instant;

pub use design::{AnisotropicFigures, Claimed, DesignedFilter, design_all, worst_case};
pub use evaluate::three_figures;
pub use outcome::{FilterOutcome, Gain, NeesAverage, Promise, RunOutcome, ScenarioOutcome};
pub use scenarios::{guarantee_holds, scenario_covariances};

use crate::analysis::exact::{ErrorForm, ExactError};
use crate::config::Experiment;
use crate::error::{Error, Result};
use crate::sim::montecarlo::Partial;

use evaluate::Engine;
use scenarios::Setup;

/// Where a run's Monte Carlo statistics come from, chosen once by the command.
pub enum MonteCarlo {
    /// Every block, simulated here; a progress bar per scenario when `progress`.
    Run { progress: bool },
    /// Every block, from a merge's shards (`filterbench merge`): per scenario every shard's tree
    /// nodes in block order and the per-trial J in trial order. The designs made here must have
    /// `fingerprint`, those the shards ran.
    Merged { fingerprint: String, partials: Vec<Partial> },
}

/// Runs the whole experiment on the current rayon pool.
pub fn run(exp: &Experiment, show_progress: bool) -> Result<RunOutcome> {
    execute(exp, MonteCarlo::Run { progress: show_progress })
}

/// The pipeline: the designs, then scenario by scenario its setup, exact errors, Monte Carlo
/// statistics from `mc` and outcome. A merge computes everything but the Monte Carlo as a run does,
/// so its tables are those of one run.
pub fn execute(exp: &Experiment, mc: MonteCarlo) -> Result<RunOutcome> {
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

/// A scenario ready for its Monte Carlo: its setup and every filter's exact error (docs/math.md
/// §4), with the coordinates each filter is simulated in.
pub struct Prepared {
    pub index: usize,
    pub setup: Setup,
    pub exact: Vec<ExactError>,
    pub forms: Vec<Option<ErrorForm>>,
}

impl Prepared {
    /// The scenario as the Monte Carlo engine runs it.
    pub fn scenario<'s>(&'s self, engine: &'s Engine) -> crate::sim::montecarlo::Scenario<'s> {
        engine.scenario(&self.setup, self.index, &self.forms)
    }
}

/// The stages between the designs and the Monte Carlo, for every command: each scenario's
/// covariance resolved (all first: a worst case is refused before any trial runs), then one
/// scenario at a time its setup and exact errors (a filter whose error double precision cannot
/// resolve is refused before its Monte Carlo), handed to `each` with the engine. One scenario's
/// setup is alive at a time.
pub fn each_scenario<T>(
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
        out.push(each(&engine, Prepared { index, setup, exact, forms })?);
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
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// Refuses a merge whose shards ran other designs than those made here.
fn same_designs(expected: &str, ours: &str) -> Result<()> {
    if ours != expected {
        return Err(Error::invalid(
            "merge",
            format!("the shards' designs (fingerprint {expected}) differ from this machine's ({ours})"),
        ));
    }
    Ok(())
}
