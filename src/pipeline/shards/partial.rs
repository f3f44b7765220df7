//! A shard's partial result (`filterbench experiment NAME --shard I/N`), the input of
//! `filterbench merge`: `partial.json` (what was run), `nodes.parquet` (the accumulator states of
//! the shard's maximal tree nodes, [`crate::sim::tree`]) and, with `--per-trial`,
//! `trials.parquet`. Its size is O(runs × scenarios × filters × steps × log blocks), independent of
//! the number of trials except for the per-trial rows. docs/partial-results.md describes the format.

use crate::pipeline::table::Table;
use std::path::Path;

use polars::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::sim::montecarlo::{FilterStats, McStats, Partial};
use crate::sim::series::Series;
use crate::sim::stats::Welford;
use crate::sim::tree::Node;

use crate::config::Overrides;

/// The files of a partial result.
pub(crate) const META: &str = "partial.json";
pub(crate) const NODES: &str = "nodes.parquet";
pub const TRIALS: &str = "trials.parquet";
/// The version of this format; a merge refuses any other.
pub(crate) const FORMAT: u32 = 2;

/// `partial.json`: everything a merge needs to check that shards belong together and to run the
/// experiment's non-Monte-Carlo parts again.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Meta {
    pub format: u32,
    pub filterbench_version: String,
    /// The experiment's name and its file's text (the variants are resolved from it again).
    pub experiment: String,
    pub experiment_file: String,
    pub variants: Vec<Option<String>>,
    pub seed: u64,
    pub trials: usize,
    pub per_trial: bool,
    /// The command line's overrides: `merge` builds the experiments from the file with them again,
    /// and its manifest records them.
    pub overrides: Overrides,
    pub shard: u64,
    pub shards: u64,
    /// The blocks [first, end) this shard ran, of `blocks.div_ceil` over all trials.
    pub blocks: [u64; 2],
    /// Per variant, the designs' fingerprint ([`super::super::fingerprint`]).
    pub fingerprints: Vec<String>,
}

/// Blocks of shard `i` of `n` among `total`: [⌊i·B/N⌋, ⌊(i+1)·B/N⌋).
pub(crate) fn shard_blocks(i: u64, n: u64, total: u64) -> std::ops::Range<u64> {
    let at = |i: u64| (i as u128 * total as u128 / n as u128) as u64;
    at(i)..at(i + 1)
}

/// Writes a partial result into `dir`: `runs[r][s]` is variant r's scenario s.
pub fn write(dir: &Path, meta: &Meta, runs: &[Vec<Partial>]) -> Result<()> {
    let text = serde_json::to_string_pretty(meta).map_err(|e| Error::output(META, e))?;
    std::fs::write(dir.join(META), text).map_err(|e| Error::io(dir.join(META), e))?;
    let mut c = NodeCols::default();
    for (r, run) in runs.iter().enumerate() {
        for (s, part) in run.iter().enumerate() {
            for node in &part.nodes {
                c.node(r as u32, s as u32, node);
            }
        }
    }
    let mut df = DataFrame::new_infer_height(vec![
        Column::new("run".into(), c.run),
        Column::new("scenario".into(), c.scenario),
        Column::new("level".into(), c.level),
        Column::new("index".into(), c.index),
        Column::new("stat".into(), c.stat),
        Column::new("item".into(), c.item),
        Column::new("step".into(), c.step),
        Column::new("n".into(), c.n),
        Column::new("mean".into(), c.mean),
        Column::new("m2".into(), c.m2),
    ])
    .map_err(|e| Error::output(NODES, e))?;
    put(dir, NODES, &mut df)?;
    if meta.per_trial {
        let (mut run, mut sc, mut filter, mut trial, mut j) = (vec![], vec![], vec![], vec![], vec![]);
        let first = meta.blocks[0] * crate::sim::montecarlo::BLOCK;
        for (r, parts) in runs.iter().enumerate() {
            for (s, part) in parts.iter().enumerate() {
                for (f, values) in part.per_trial.iter().enumerate() {
                    run.extend(std::iter::repeat_n(r as u32, values.len()));
                    sc.extend(std::iter::repeat_n(s as u32, values.len()));
                    filter.extend(std::iter::repeat_n(f as u32, values.len()));
                    trial.extend(first..first + values.len() as u64);
                    j.extend_from_slice(values);
                }
            }
        }
        let mut df = DataFrame::new_infer_height(vec![
            Column::new("run".into(), run),
            Column::new("scenario".into(), sc),
            Column::new("filter".into(), filter),
            Column::new("trial".into(), trial),
            Column::new("j".into(), j),
        ])
        .map_err(|e| Error::output(TRIALS, e))?;
        put(dir, TRIALS, &mut df)?;
    }
    Ok(())
}

fn put(dir: &Path, file: &str, df: &mut DataFrame) -> Result<()> {
    let path = dir.join(file);
    let f = std::fs::File::create(&path).map_err(|e| Error::io(&path, e))?;
    ParquetWriter::new(f).finish(df).map_err(|e| Error::output(file, e))?;
    Ok(())
}

/// The rows of `nodes.parquet`: one per accumulator of a node. `stat` is `total` (item = filter),
/// `step`, `nees` and `nis` (item = filter, at `step`), `paired` (item = the pair's index) with n, mean
/// and m2 of a Welford accumulator; or `checks` (item = filter) with n = violations and
/// mean = max_ratio.
#[derive(Default)]
struct NodeCols {
    run: Vec<u32>,
    scenario: Vec<u32>,
    level: Vec<u32>,
    index: Vec<u64>,
    stat: Vec<&'static str>,
    item: Vec<u32>,
    step: Vec<u32>,
    n: Vec<u64>,
    mean: Vec<f64>,
    m2: Vec<f64>,
}

impl NodeCols {
    fn row(&mut self, at: (u32, u32, &Node), stat: &'static str, item: usize, step: usize, w: Welford) {
        self.run.push(at.0);
        self.scenario.push(at.1);
        self.level.push(at.2.level);
        self.index.push(at.2.index);
        self.stat.push(stat);
        self.item.push(item as u32);
        self.step.push(step as u32);
        self.n.push(w.n);
        self.mean.push(w.mean);
        self.m2.push(w.m2);
    }

    fn node(&mut self, r: u32, s: u32, node: &Node) {
        let at = (r, s, node);
        for (f, st) in node.stats.filters.iter().enumerate() {
            self.row(at, "total", f, 0, st.total);
            let checks = Welford { n: st.violations, mean: st.max_ratio, m2: 0.0 };
            self.row(at, "checks", f, 0, checks);
            for (k, w) in st.steps.iter().enumerate() {
                self.row(at, "step", f, k, w);
            }
            for (k, w) in st.nees.iter().enumerate() {
                self.row(at, "nees", f, k, w);
            }
            for (k, w) in st.nis.iter().enumerate() {
                self.row(at, "nis", f, k, w);
            }
        }
        for (p, w) in node.stats.paired.iter().enumerate() {
            self.row(at, "paired", p, 0, *w);
        }
    }
}

/// Reads `partial.json` of the shard in `dir`.
pub(crate) fn read_meta(dir: &Path) -> Result<Meta> {
    let path = dir.join(META);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        Error::invalid(format!("shard {}", dir.display()), format!("not a partial result ({META}: {e})"))
    })?;
    serde_json::from_str(&text)
        .map_err(|e| Error::invalid(format!("shard {}", dir.display()), format!("{META} is not a partial result: {e}")))
}

/// The nodes of a shard, per run and scenario (`[r][s]`), for `runs` runs of `scenarios[r]`
/// scenarios each, in block order as written.
pub(crate) fn read_nodes(dir: &Path, scenarios: &[usize]) -> Result<Vec<Vec<Vec<Node>>>> {
    let t = Table::read(dir, NODES)?;
    let bad = |why: String| t.bad(why);
    let (run, scenario, level, index) = (t.u32s("run")?, t.u32s("scenario")?, t.u32s("level")?, t.u64s("index")?);
    let (item, step, n, mean, m2) = (t.u32s("item")?, t.u32s("step")?, t.u64s("n")?, t.f64s("mean")?, t.f64s("m2")?);
    let stat: Vec<String> =
        t.column("stat")?.str().map_err(|e| t.bad(e))?.iter().map(|v| v.unwrap_or_default().to_string()).collect();
    let mut out: Vec<Vec<Vec<Node>>> = scenarios.iter().map(|&s| vec![Vec::new(); s]).collect();
    let mut current: Option<(usize, usize, Node)> = None;
    let empty = McStats { filters: Vec::new(), paired: Vec::new() };
    for i in 0..run.len() {
        let (r, s) = (run[i] as usize, scenario[i] as usize);
        if out.get(r).and_then(|x| x.get(s)).is_none() {
            return Err(bad(format!("row {i}: run {r}, scenario {s} is not in the experiment")));
        }
        let same =
            current.as_ref().is_some_and(|(cr, cs, c)| (*cr, *cs, c.level, c.index) == (r, s, level[i], index[i]));
        if !same {
            if let Some((cr, cs, node)) = current.take() {
                out[cr][cs].push(node);
            }
            current = Some((r, s, Node { level: level[i], index: index[i], stats: empty.clone() }));
        }
        let st = &mut current.as_mut().expect("just set").2.stats;
        let w = Welford { n: n[i], mean: mean[i], m2: m2[i] };
        let (it, k) = (item[i] as usize, step[i] as usize);
        let in_order =
            |len: usize, at: usize| if at == len { Ok(()) } else { Err(bad(format!("row {i}: out of order"))) };
        match stat[i].as_str() {
            "paired" => {
                in_order(st.paired.len(), it)?;
                st.paired.push(w);
            }
            kind => {
                if kind == "total" {
                    in_order(st.filters.len(), it)?;
                    let steps = Series::default();
                    let (nees, nis) = (Series::default(), Series::default());
                    st.filters.push(FilterStats { total: w, steps, max_ratio: 0.0, violations: 0, nees, nis });
                    continue;
                }
                let last = st.filters.len().checked_sub(1);
                let f = st.filters.get_mut(it).filter(|_| last == Some(it));
                let f = f.ok_or_else(|| bad(format!("row {i}: out of order")))?;
                match kind {
                    "checks" => (f.violations, f.max_ratio) = (w.n, w.mean),
                    "step" => in_order(f.steps.len(), k).map(|_| f.steps.push(w))?,
                    "nees" => in_order(f.nees.len(), k).map(|_| f.nees.push(w))?,
                    "nis" => in_order(f.nis.len(), k).map(|_| f.nis.push(w))?,
                    other => return Err(bad(format!("row {i}: unknown stat `{other}`"))),
                }
            }
        }
    }
    if let Some((cr, cs, node)) = current {
        out[cr][cs].push(node);
    }
    Ok(out)
}

/// The per-trial J of a shard, `[r][s][f]`, with the first trial of each list; rows must be in
/// (run, scenario, filter, trial) order with consecutive trials.
pub(crate) fn read_trials(dir: &Path, first: u64, scenarios: &[usize]) -> Result<Vec<Vec<Vec<Vec<f64>>>>> {
    let t = Table::read(dir, TRIALS)?;
    let bad = |why: String| t.bad(why);
    let (run, scenario, filter, trial, j) =
        (t.u32s("run")?, t.u32s("scenario")?, t.u32s("filter")?, t.u64s("trial")?, t.f64s("j")?);
    let mut out: Vec<Vec<Vec<Vec<f64>>>> = scenarios.iter().map(|&s| vec![Vec::new(); s]).collect();
    for (i, &v) in j.iter().enumerate() {
        let (r, s, f) = (run[i] as usize, scenario[i] as usize, filter[i] as usize);
        let list =
            out.get_mut(r).and_then(|x| x.get_mut(s)).ok_or_else(|| bad(format!("row {i}: not in the experiment")))?;
        while list.len() <= f {
            list.push(Vec::new());
        }
        if list.len() != f + 1 || trial[i] != first + list[f].len() as u64 {
            return Err(bad(format!("row {i}: trial {} is out of order", trial[i])));
        }
        list[f].push(v);
    }
    Ok(out)
}
