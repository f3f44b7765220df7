//! Shards: `filterbench experiment NAME --shard I/N` runs blocks [⌊I·B/N⌋, ⌊(I+1)·B/N⌋) of every
//! variant and scenario through the pipeline's stages (`super::each_scenario`) and writes a
//! partial result ([`partial`]); `filterbench merge` checks that the shards belong together,
//! rebuilds each scenario's statistics from their tree nodes ([`crate::sim::tree`]) and runs the
//! pipeline with them as its Monte Carlo ([`super::MonteCarlo::Merged`]), so the output is that of
//! one run. docs/partial-results.md describes both.

pub mod partial;

use std::ops::Range;
use std::path::PathBuf;

use crate::config::{Experiment, Overrides};
use crate::error::{Error, Result};
use crate::sim::montecarlo::{self, McStats, Partial};
use crate::sim::tree::Tree;

use super::{MonteCarlo, RunOutcome};
use partial::Meta;

/// `--shard I/N`, parsed and checked.
pub fn parse_shard(text: &str) -> Result<(u64, u64)> {
    let bad = |why: &str| Error::invalid(format!("--shard {}", text.escape_debug()), why);
    let (i, n) = text.split_once('/').ok_or_else(|| bad("is not I/N (e.g. 0/8)"))?;
    let (i, n): (u64, u64) = match (i.parse(), n.parse()) {
        (Ok(i), Ok(n)) => (i, n),
        _ => return Err(bad("I and N must be whole numbers (e.g. 0/8)")),
    };
    if n == 0 || i >= n {
        return Err(bad("needs N ≥ 1 and 0 ≤ I < N"));
    }
    Ok((i, n))
}

/// Runs shards `which` of `n` of every variant and writes each into `dir(I)` (the filters are
/// designed once per variant and each scenario set up once for all of them). The command line runs
/// one; a test or a scale measurement many. Every variant was loaded with `overrides`, which the
/// shards record. Returns the last shard's `partial.json`.
pub fn run_shards(
    exps: &[Experiment],
    n: u64,
    which: &[u64],
    overrides: &Overrides,
    dir: impl Fn(u64) -> PathBuf,
) -> Result<Option<Meta>> {
    let exp = &exps[0];
    let total = montecarlo::blocks(exp.trials as u64);
    let ranges: Vec<_> = which.iter().map(|&i| partial::shard_blocks(i, n, total)).collect();
    // Per variant its fingerprint and [scenario][shard]; each shard takes its [variant][scenario].
    let mut runs: Vec<(String, Vec<std::vec::IntoIter<Partial>>)> = exps
        .iter()
        .map(|e| blocks(e, &ranges).map(|(fp, s)| (fp, s.into_iter().map(Vec::into_iter).collect())))
        .collect::<Result<_>>()?;
    let mut last = None;
    for (&i, blocks) in which.iter().zip(&ranges) {
        let parts: Vec<Vec<Partial>> = runs
            .iter_mut()
            .map(|(_, scenarios)| scenarios.iter_mut().map(|s| s.next().expect("one partial per shard")).collect())
            .collect();
        let meta = Meta {
            format: partial::FORMAT,
            filterbench_version: env!("CARGO_PKG_VERSION").into(),
            experiment: exp.name.clone(),
            experiment_file: exp.source.clone(),
            variants: exps.iter().map(|e| e.variant.clone()).collect(),
            seed: exp.seed,
            trials: exp.trials,
            per_trial: exp.per_trial,
            overrides: overrides.clone(),
            shard: i,
            shards: n,
            blocks: [blocks.start, blocks.end],
            fingerprints: runs.iter().map(|(fp, _)| fp.clone()).collect(),
        };
        partial::write(&dir(i), &meta, &parts)?;
        last = Some(meta);
    }
    Ok(last)
}

/// Blocks `ranges` of the experiment's Monte Carlo, through the pipeline's stages: the designs'
/// fingerprint, and per scenario and range the tree nodes and per-trial J of those blocks alone.
fn blocks(exp: &Experiment, ranges: &[Range<u64>]) -> Result<(String, Vec<Vec<Partial>>)> {
    let filters = super::design_all(exp)?;
    let trials = exp.trials as u64;
    let parts = super::each_scenario(exp, &filters, |engine, p| {
        let sc = p.scenario(engine);
        Ok(ranges.iter().map(|r| montecarlo::run_range(&sc, trials, r.clone(), exp.per_trial, &|_| {})).collect())
    })?;
    Ok((super::fingerprint(&filters), parts))
}

/// The shards of one run, checked to belong together and to be complete, in shard order.
pub struct Shards {
    pub exps: Vec<Experiment>,
    pub meta: Meta,
    dirs: Vec<PathBuf>,
}

/// Reads every shard's `partial.json` and refuses, naming the shard, one of another experiment,
/// seed, trial count, version, format or designs, a repeated shard and missing ones.
pub fn check(dirs: &[PathBuf], out: &std::path::Path) -> Result<Shards> {
    if dirs.is_empty() {
        return Err(Error::invalid("merge", "no shard folders given"));
    }
    // A shard is filterbench's own output, which --out may replace: never one being merged.
    let real = |p: &std::path::Path| std::fs::canonicalize(p).ok();
    if let Some(d) = dirs.iter().find(|d| real(d).is_some() && real(d) == real(out)) {
        return Err(Error::invalid(
            format!("--out {}", out.display()),
            format!("is the shard {} being merged; choose another folder", d.display()),
        ));
    }
    let metas = dirs.iter().map(|d| partial::read_meta(d)).collect::<Result<Vec<_>>>()?;
    let name = |i: usize| format!("shard {}", dirs[i].display());
    for (i, m) in metas.iter().enumerate() {
        if m.format != partial::FORMAT || m.filterbench_version != env!("CARGO_PKG_VERSION") {
            return Err(Error::invalid(
                name(i),
                format!(
                    "written by filterbench {} (format {}), this is {} (format {})",
                    m.filterbench_version,
                    m.format,
                    env!("CARGO_PKG_VERSION"),
                    partial::FORMAT
                ),
            ));
        }
    }
    let first = &metas[0];
    for (i, m) in metas.iter().enumerate().skip(1) {
        let differs = |what: &str, a: String, b: String| {
            Error::invalid(name(i), format!("{what} {a} differs from {b} of {}", name(0)))
        };
        if m.experiment != first.experiment
            || m.experiment_file != first.experiment_file
            || m.variants != first.variants
        {
            return Err(differs("experiment", format!("`{}`", m.experiment), format!("`{}`", first.experiment)));
        }
        if m.seed != first.seed {
            return Err(differs("seed", m.seed.to_string(), first.seed.to_string()));
        }
        if m.trials != first.trials {
            return Err(differs("trial count", m.trials.to_string(), first.trials.to_string()));
        }
        if m.shards != first.shards {
            return Err(differs("shard count", m.shards.to_string(), first.shards.to_string()));
        }
        if m.per_trial != first.per_trial {
            return Err(differs("--per-trial", m.per_trial.to_string(), first.per_trial.to_string()));
        }
        if m.fingerprints != first.fingerprints {
            return Err(differs("design fingerprint", m.fingerprints.join(","), first.fingerprints.join(",")));
        }
    }
    let n = first.shards;
    let mut order: Vec<usize> = (0..metas.len()).collect();
    order.sort_by_key(|&i| metas[i].shard);
    for w in order.windows(2) {
        if metas[w[0]].shard == metas[w[1]].shard {
            return Err(Error::invalid(
                name(w[1]),
                format!("repeats shard {}/{n} of {}", metas[w[1]].shard, name(w[0])),
            ));
        }
    }
    let missing: Vec<String> =
        (0..n).filter(|i| !metas.iter().any(|m| m.shard == *i)).take(10).map(|i| format!("{i}/{n}")).collect();
    if !missing.is_empty() {
        return Err(Error::invalid("merge", format!("shard(s) {} missing (of {n})", missing.join(", "))));
    }
    let total = montecarlo::blocks(first.trials as u64);
    for (i, m) in metas.iter().enumerate() {
        let want = partial::shard_blocks(m.shard, n, total);
        if m.blocks != [want.start, want.end] || m.shard >= n {
            return Err(Error::invalid(
                name(i),
                format!("ran blocks {:?}, not those of shard {}/{n}", m.blocks, m.shard),
            ));
        }
    }
    let meta = first.clone();
    // The experiments the shards ran: their file with the command line's overrides, built again.
    let exps = crate::config::variants_of(
        &meta.experiment,
        &format!("{} (from the shards)", meta.experiment),
        &meta.experiment_file,
        &meta.overrides,
        None,
    )?;
    if exps.iter().map(|e| e.variant.clone()).collect::<Vec<_>>() != meta.variants {
        return Err(Error::invalid(name(0), "its variants are not those of its experiment file"));
    }
    if let Some(e) = exps.iter().find(|e| (e.seed, e.trials, e.per_trial) != (meta.seed, meta.trials, meta.per_trial)) {
        return Err(Error::invalid(
            name(0),
            format!(
                "its seed, trial count and --per-trial ({}, {}, {}) are not its experiment file's with its overrides ({}, {}, {})",
                meta.seed, meta.trials, meta.per_trial, e.seed, e.trials, e.per_trial
            ),
        ));
    }
    Ok(Shards { exps, meta, dirs: order.into_iter().map(|i| dirs[i].clone()).collect() })
}

/// Every variant's outcome from the shards' nodes, on the current rayon pool: the same figures, to
/// the bit, as one run of the experiment.
pub fn merge(s: &Shards) -> Result<Vec<RunOutcome>> {
    let counts: Vec<usize> = s.exps.iter().map(|e| e.scenarios.len()).collect();
    // Each shard's nodes go onto its scenario's tree as they are read: memory holds O(log blocks)
    // nodes per scenario, not every shard's.
    let mut trees: Vec<Vec<Tree>> = counts.iter().map(|&c| (0..c).map(|_| Tree::default()).collect()).collect();
    let mut per_trial: Vec<Vec<Vec<Vec<f64>>>> = counts.iter().map(|&c| vec![Vec::new(); c]).collect();
    let mut first: Vec<Vec<Option<McStats>>> = counts.iter().map(|&c| vec![None; c]).collect();
    let total = montecarlo::blocks(s.meta.trials as u64);
    for (i, dir) in s.dirs.iter().enumerate() {
        let blocks = partial::shard_blocks(i as u64, s.meta.shards, total);
        let bad = |why: String| Error::invalid(format!("shard {}", dir.display()), why);
        let nodes = partial::read_nodes(dir, &counts)?;
        for (r, run) in nodes.into_iter().enumerate() {
            for (sc, nodes) in run.into_iter().enumerate() {
                // The nodes must tile the shard's blocks, in order, with the accumulators of the others.
                let mut at = blocks.start;
                for node in nodes {
                    let b = node.blocks();
                    if b.start != at {
                        break;
                    }
                    at = b.end;
                    let like = first[r][sc].get_or_insert_with(|| node.stats.clone());
                    if !like.same_shape(&node.stats) {
                        return Err(bad(format!(
                            "its accumulators of scenario {sc} differ in size from the other shards'"
                        )));
                    }
                    trees[r][sc].push(node);
                }
                if at != blocks.end {
                    return Err(bad(format!(
                        "its nodes of scenario {sc} do not cover blocks {}..{}",
                        blocks.start, blocks.end
                    )));
                }
            }
        }
        if s.meta.per_trial {
            let rows = partial::read_trials(dir, blocks.start * montecarlo::BLOCK, &counts)?;
            for (r, run) in rows.into_iter().enumerate() {
                for (sc, filters) in run.into_iter().enumerate() {
                    let per = &mut per_trial[r][sc];
                    per.resize(per.len().max(filters.len()), Vec::new());
                    for (f, v) in filters.into_iter().enumerate() {
                        per[f].extend(v);
                    }
                }
            }
        }
    }
    let given = trees.into_iter().zip(per_trial).map(|(t, p)| {
        t.into_iter().zip(p).map(|(t, per_trial)| Partial { nodes: t.into_nodes(), per_trial }).collect::<Vec<_>>()
    });
    let mut out = Vec::with_capacity(s.exps.len());
    for ((e, fp), g) in s.exps.iter().zip(&s.meta.fingerprints).zip(given) {
        if e.per_trial {
            let want = e.trials;
            if let Some(bad) = g
                .iter()
                .position(|p| p.per_trial.len() != e.filters.len() || p.per_trial.iter().any(|v| v.len() != want))
            {
                return Err(Error::invalid(
                    "merge",
                    format!("the shards' per-trial rows of scenario {bad} are not {want} per filter"),
                ));
            }
        }
        out.push(super::execute(e, MonteCarlo::Merged { fingerprint: fp.clone(), partials: g })?);
    }
    Ok(out)
}
