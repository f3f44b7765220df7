//! `filterbench bench`: throughput of the Monte Carlo engine on an experiment's first scenario, and
//! how much of a trial is spent drawing its random numbers. Measured, not asserted. The scenario is
//! set up and simulated exactly as `experiment` runs it ([`super::scenarios::setup`],
//! [`super::evaluate::Engine`]).

use std::fmt::Write;
use std::time::Instant;

use crate::config::Experiment;
use crate::error::Result;
use crate::sim::montecarlo::{self, Workspace};
use crate::sim::noise::trial_rng;

use super::evaluate::{Engine, exact_errors};

pub fn run(exp: &Experiment) -> Result<String> {
    let filters = super::design_all(exp)?;
    let covs = super::scenario_covariances(exp, &filters)?;
    let setup = super::scenarios::setup(exp, &filters, 0, &covs[0])?;
    let engine = Engine::new(exp, &filters);
    let (_, forms) = exact_errors(&engine, &setup)?;
    let sc = engine.scenario(&setup, 0, &forms);
    let sampler = &setup.sampler;
    let trials = exp.trials as u64;
    let steps = exp.plant.steps() as f64;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "bench {}{}: scenario `{}`, {} filters, N = {}, {} trials, {} thread(s)",
        exp.name,
        exp.variant.as_deref().map_or(String::new(), |v| format!(" [{v}]")),
        exp.scenarios[0].name,
        filters.len(),
        exp.plant.horizon,
        trials,
        rayon::current_num_threads()
    );

    // Warm up once, then time the parallel engine as `experiment` runs it.
    montecarlo::run(&sc, trials.min(montecarlo::BLOCK), &|_| {});
    let t = Instant::now();
    let st = montecarlo::run(&sc, trials, &|_| {});
    let par = t.elapsed().as_secs_f64();
    std::hint::black_box(&st);

    // One thread, whole trials versus drawing only, over the same trial indices.
    let mut ws = Workspace::new(&sc);
    let mut sink = 0.0;
    let t = Instant::now();
    for i in 0..trials {
        montecarlo::run_trial(&sc, &mut ws, i, |_, _, _, _, e| sink += e[0]);
    }
    let one = t.elapsed().as_secs_f64();
    let mut draw = sampler.workspace();
    let t = Instant::now();
    for i in 0..trials {
        let mut rng = trial_rng(exp.seed, 0, i);
        sampler.draw_into(&mut rng, &mut draw);
        sink += draw.w[(0, 0)];
    }
    let rnd = t.elapsed().as_secs_f64();
    std::hint::black_box(sink);

    let _ = writeln!(
        s,
        "engine (parallel, with accumulators): {:.3} s, {:.3e} trial-steps/s",
        par,
        trials as f64 * steps / par
    );
    let _ = writeln!(
        s,
        "one thread, whole trials:             {:.3} s, {:.2} µs per trial",
        one,
        one / trials as f64 * 1e6
    );
    let _ = writeln!(
        s,
        "one thread, drawing only:             {:.3} s, {:.2} µs per trial ({} scalars), {:.0} % of a trial",
        rnd,
        rnd / trials as f64 * 1e6,
        sampler.scalars_per_trial(),
        100.0 * rnd / one
    );
    Ok(s)
}
