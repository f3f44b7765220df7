//! `filterbench bench`: throughput of the Monte Carlo engine on every scenario of an experiment,
//! and where one thread's time goes (drawing, simulation, statistics). Measured, not asserted. Each
//! scenario is designed, set up and simulated exactly as `experiment` runs it, through the same
//! stages ([`super::design_all`], `super::each_scenario`); only the timed loops are its own.

use std::fmt::Write;
use std::time::Instant;

use crate::config::Experiment;
use crate::error::Result;
use crate::sim::block::{self, Workspace};
use crate::sim::montecarlo::{self, BLOCK, Scenario};

pub fn run(exp: &Experiment) -> Result<String> {
    let filters = super::design_all(exp)?;
    let trials = exp.trials as u64;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "bench {}{}: {} filters, N = {}, {} trials per scenario, {} thread(s), {} trials per lane block, {:?} build",
        exp.name,
        exp.variant.as_deref().map_or(String::new(), |v| format!(" [{v}]")),
        filters.len(),
        exp.plant.horizon,
        trials,
        rayon::current_num_threads(),
        BLOCK,
        crate::sim::lanes::build(),
    );
    let lines = super::each_scenario(exp, &filters, |engine, p| {
        Ok(scenario(&p.scenario(engine), &exp.scenarios[p.index].name, trials))
    })?;
    s.extend(lines);
    Ok(s)
}

/// One scenario: the parallel engine as `experiment` runs it, then one thread timed in three
/// nested passes over the same trials — drawing only, drawing and simulating, and the whole
/// engine with its statistics — whose differences split a trial's time.
fn scenario(sc: &Scenario, name: &str, trials: u64) -> String {
    let steps = sc.plant.steps() as f64;
    montecarlo::run(sc, trials.min(BLOCK), &|_| {});
    let t = Instant::now();
    std::hint::black_box(montecarlo::run(sc, trials, &|_| {}));
    let par = t.elapsed().as_secs_f64();

    let blocks = || (0..trials.div_ceil(BLOCK)).map(|b| (b * BLOCK, (trials - b * BLOCK).min(BLOCK) as usize));
    let mut ws = Workspace::new(sc);
    let t = Instant::now();
    for (first, active) in blocks() {
        sc.sampler.start(sc.seed, sc.index, first, active, &mut ws.draw);
        for k in 0..sc.plant.steps() {
            sc.sampler.step(k, &mut ws.draw);
        }
        std::hint::black_box(&ws.draw.w);
    }
    let draw = t.elapsed().as_secs_f64();
    let mut sink = 0.0;
    let t = Instant::now();
    for (first, active) in blocks() {
        block::simulate(sc, &mut ws, first, active, |v| sink += v.e[0][0]);
    }
    let sim = t.elapsed().as_secs_f64();
    std::hint::black_box(sink);
    let t = Instant::now();
    for (first, active) in blocks() {
        std::hint::black_box(montecarlo::run_block(sc, &mut ws, first, active));
    }
    let whole = t.elapsed().as_secs_f64();

    let us = |x: f64| x / trials as f64 * 1e6;
    let pct = |x: f64| 100.0 * x / whole;
    format!(
        "scenario `{name}`: {:.3e} trial-steps/s ({:.3} s, parallel, with statistics)\n  one thread: {:.2} µs per \
         trial = drawing {:.2} ({:.0} %, {} scalars) + simulation {:.2} ({:.0} %) + statistics {:.2} ({:.0} %)\n",
        trials as f64 * steps / par,
        par,
        us(whole),
        us(draw),
        pct(draw),
        sc.sampler.scalars_per_trial(),
        us(sim - draw),
        pct(sim - draw),
        us(whole - sim),
        pct(whole - sim),
    )
}
