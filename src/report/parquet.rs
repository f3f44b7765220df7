//! Parquet tables (polars). Column names and meanings are listed in the README.

use super::rows::{col, frame};
use std::path::Path;

use polars::io::parquet::write::BatchedWriter;
use polars::prelude::*;

use crate::config::Experiment;
use crate::error::{Error, Result};
use crate::pipeline::RunOutcome;
use crate::sim::montecarlo::McStats;

/// One run's part of a table, handed over in batches (the gains one filter at a time, so a large
/// run never holds the whole table in memory).
type Part = fn(&Experiment, &RunOutcome, &mut Batches) -> Result<()>;

/// The tables, by file name.
pub(crate) const TABLES: &[(&str, Part)] = &[
    ("summary.parquet", |e, o, b| b.put(summary(e, o)?)),
    ("steps.parquet", steps),
    ("gains.parquet", gains),
    ("paired.parquet", |e, o, b| b.put(paired(e, o)?)),
    ("design_trace.parquet", |e, o, b| b.put(trace(e, o)?)),
    (super::trials::FILE, |e, o, b| b.put(super::trials::table(e, o)?)),
];

/// Rows per row group, as polars' own writer cuts a whole frame.
const ROW_GROUP: usize = 512 * 512;

/// A table being written batch by batch: each batch gets its run's `variant` column (null when the
/// file has no variants) after `experiment` and is appended in order.
pub(crate) struct Batches {
    path: std::path::PathBuf,
    file: Option<std::fs::File>,
    writer: Option<BatchedWriter<std::fs::File>>,
    variant: Option<String>,
}

impl Batches {
    /// Whether a batch has been written (the file has its columns).
    fn started(&self) -> bool {
        self.writer.is_some()
    }

    fn put(&mut self, mut df: DataFrame) -> Result<()> {
        let what = self.path.display().to_string();
        let name = "variant".into();
        let variant = match &self.variant {
            Some(v) => StringChunked::full(name, v, df.height()),
            None => StringChunked::full_null(name, df.height()),
        };
        df.insert_column(1, variant.into_column()).map_err(|e| Error::output(&what, e))?;
        if self.writer.is_none() {
            let f = self.file.take().expect("a file until the first batch");
            self.writer = Some(ParquetWriter::new(f).batched(df.schema()).map_err(|e| Error::output(&what, e))?);
        }
        let w = self.writer.as_mut().expect("just made");
        for start in (0..df.height().max(1)).step_by(ROW_GROUP) {
            w.write_batch(&df.slice(start as i64, ROW_GROUP)).map_err(|e| Error::output(&what, e))?;
        }
        Ok(())
    }
}

/// Writes every table for the runs of one experiment (one run per variant): each run's rows with a
/// `variant` column, stacked in run order.
pub fn write_tables(runs: &[(&Experiment, &RunOutcome)], dir: &Path) -> Result<()> {
    for (file, part) in TABLES {
        if *file == super::trials::FILE && !runs.iter().any(|(e, _)| e.per_trial) {
            continue;
        }
        let path = dir.join(file);
        let what = path.display().to_string();
        let f = std::fs::File::create(&path).map_err(|e| Error::io(&path, e))?;
        let mut b = Batches { path, file: Some(f), writer: None, variant: None };
        for (exp, out) in runs {
            b.variant = exp.variant.clone();
            part(exp, out, &mut b)?;
        }
        b.writer.expect("every table has a batch per run").finish().map_err(|e| Error::output(&what, e))?;
    }
    Ok(())
}

/// One row per (scenario, filter): summed error over the horizon.
fn summary(exp: &Experiment, out: &RunOutcome) -> Result<DataFrame> {
    let mut c = SummaryCols::default();
    for sc in &out.scenarios {
        for (f, spec) in exp.filters.iter().enumerate() {
            let st = &sc.mc.filters[f].total;
            let d = &out.filters[f];
            let o = &sc.filters[f];
            let (lo, hi) = st.ci95();
            c.experiment.push(exp.name.clone());
            c.scenario.push(sc.name.clone());
            c.covariance.push(sc.covariance_label.clone());
            c.shape.push(sc.shape_label.clone());
            c.disturbance.push(sc.disturbance_label.clone());
            c.filter.push(spec.name.clone());
            c.family.push(spec.family.clone());
            c.params.push(serde_json::to_string(&spec.params).unwrap_or_default());
            c.n_trials.push(st.n);
            c.empirical_mean.push(st.mean);
            c.std_error.push(st.std_error());
            c.ci_low.push(lo);
            c.ci_high.push(hi);
            c.exact.push(Some(sc.exact[f].total));
            c.exact_terminal.push(sc.exact[f].per_step.last().copied());
            // A promise only where it holds in this scenario; the filter's belief is `claimed`.
            c.guaranteed.push(o.guaranteed);
            c.guarantee_kind.push(o.guarantee_kind.map(|k| k.name()));
            c.claimed.push(d.claimed.as_ref().map(|cl| cl.total));
            c.consistency.push(o.consistency);
            c.generalized_h2_norm_sq.push(d.generalized_h2_sq);
            c.nees_exact.push(o.nees_average.exact);
            c.nees_empirical.push(o.nees_average.empirical);
            c.nis_exact.push(o.nis_average.exact);
            c.nis_empirical.push(o.nis_average.empirical);
            c.worst_case.push(d.worst.as_ref().map(|w| w.total));
            c.worst_case_psd.push(d.worst.as_ref().map(|w| w.psd));
            let pt = d.design.per_trial.as_ref();
            c.violations.push(pt.map(|_| sc.mc.filters[f].violations));
            c.ratio_bound.push(pt.map(|b| b.bound()));
            c.max_ratio.push(pt.map(|_| sc.mc.filters[f].max_ratio));
            // Seed 003's figures: the mean-square gain E|Z̃|²/E|W|², exact and empirical, against the
            // filter's a-anisotropic norm² and its guaranteed γ².
            c.input_power.push(sc.input_power);
            c.input_anisotropy.push(sc.input_anisotropy);
            c.gain_empirical.push(o.gain.map(|g| g.empirical));
            c.gain_ci_low.push(o.gain.map(|g| g.ci_low));
            c.gain_ci_high.push(o.gain.map(|g| g.ci_high));
            c.gain_exact.push(o.gain.map(|g| g.exact));
            c.deterministic_error.push(d.deterministic_error);
            c.gain_exact_noise.push(o.gain.and_then(|g| g.exact_noise));
            c.anisotropic_norm_sq.push(d.anisotropic.map(|x| x.norm_sq));
            c.h2_norm_sq.push(d.anisotropic.map(|x| x.h2_sq));
            c.hinf_norm_sq.push(d.anisotropic.map(|x| x.hinf_sq));
            let gb = d.design.gain_bound;
            c.guaranteed_gain.push(gb.map(|g| g.gamma_sq));
            c.guarantee_anisotropy.push(gb.map(|g| g.anisotropy));
            c.design_gain.push(gb.map(|g| g.design_gamma_sq));
            c.theorem1_gain.push(gb.map(|g| g.theorem1_sq));
            c.guarantee_applies.push(o.guarantee_applies);
            c.design_seconds.push(d.seconds);
            c.mc_seconds.push(sc.mc_seconds);
        }
    }
    let mut df = frame(vec![
        col("experiment", c.experiment),
        col("scenario", c.scenario),
        col("covariance", c.covariance),
        col("shape", c.shape),
        col("disturbance", c.disturbance),
        col("filter", c.filter),
        col("family", c.family),
        col("params", c.params),
        col("n_trials", c.n_trials),
        col("empirical_mean", c.empirical_mean),
        col("std_error", c.std_error),
        col("ci_low", c.ci_low),
        col("ci_high", c.ci_high),
        col("exact", c.exact),
        col("exact_terminal", c.exact_terminal),
        col("guaranteed", c.guaranteed),
        col("guarantee_kind", c.guarantee_kind),
        col("claimed", c.claimed),
        col("consistency", c.consistency),
        col("nees_exact", c.nees_exact),
        col("nees_empirical", c.nees_empirical),
        col("nis_exact", c.nis_exact),
        col("nis_empirical", c.nis_empirical),
        col("generalized_h2_norm_sq", c.generalized_h2_norm_sq),
        col("worst_case", c.worst_case),
        col("worst_case_psd", c.worst_case_psd),
        col("violations", c.violations),
        col("ratio_bound", c.ratio_bound),
        col("max_ratio", c.max_ratio),
        col("input_power", c.input_power),
        col("input_anisotropy", c.input_anisotropy),
        col("gain_empirical", c.gain_empirical),
        col("gain_ci_low", c.gain_ci_low),
        col("gain_ci_high", c.gain_ci_high),
        col("gain_exact", c.gain_exact),
        col("deterministic_error", c.deterministic_error),
        col("gain_exact_noise", c.gain_exact_noise),
        col("anisotropic_norm_sq", c.anisotropic_norm_sq),
        col("h2_norm_sq", c.h2_norm_sq),
        col("hinf_norm_sq", c.hinf_norm_sq),
        col("guaranteed_gain", c.guaranteed_gain),
        col("design_gain", c.design_gain),
        col("guarantee_anisotropy", c.guarantee_anisotropy),
        col("theorem1_gain", c.theorem1_gain),
        col("guarantee_applies", c.guarantee_applies),
        col("design_seconds", c.design_seconds),
        col("mc_seconds", c.mc_seconds),
    ])?;
    if exp.per_trial {
        super::trials::add_quantiles(&mut df, out)?;
    }
    add_figures(&mut df, out)?;
    Ok(df)
}

/// One column `figure_NAME` per figure a family shows in the summary
/// ([`crate::filter::design::Record::summary`]), in the order the filters first give them; null
/// for a filter without it. The built-in families show none, so their tables keep their columns.
fn add_figures(df: &mut DataFrame, out: &RunOutcome) -> Result<()> {
    let figures: Vec<Vec<(&'static str, f64)>> = out.filters.iter().map(|d| d.design.figures.summary()).collect();
    let mut names: Vec<&'static str> = Vec::new();
    for (name, _) in figures.iter().flatten() {
        if !names.contains(name) {
            names.push(name);
        }
    }
    for name in names {
        let per_filter: Vec<Option<f64>> =
            figures.iter().map(|f| f.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)).collect();
        let values: Vec<Option<f64>> = out.scenarios.iter().flat_map(|_| per_filter.iter().copied()).collect();
        df.with_column(col(&format!("figure_{name}"), values)).map_err(|e| Error::output("summary table", e))?;
    }
    Ok(())
}

#[derive(Default)]
struct SummaryCols {
    experiment: Vec<String>,
    scenario: Vec<String>,
    covariance: Vec<String>,
    shape: Vec<String>,
    disturbance: Vec<String>,
    filter: Vec<String>,
    family: Vec<String>,
    params: Vec<String>,
    n_trials: Vec<u64>,
    empirical_mean: Vec<f64>,
    std_error: Vec<f64>,
    ci_low: Vec<f64>,
    ci_high: Vec<f64>,
    exact: Vec<Option<f64>>,
    exact_terminal: Vec<Option<f64>>,
    guaranteed: Vec<Option<f64>>,
    guarantee_kind: Vec<Option<&'static str>>,
    claimed: Vec<Option<f64>>,
    consistency: Vec<Option<f64>>,
    nees_exact: Vec<Option<f64>>,
    nees_empirical: Vec<Option<f64>>,
    nis_exact: Vec<Option<f64>>,
    nis_empirical: Vec<Option<f64>>,
    generalized_h2_norm_sq: Vec<Option<f64>>,
    worst_case: Vec<Option<f64>>,
    worst_case_psd: Vec<Option<bool>>,
    violations: Vec<Option<u64>>,
    ratio_bound: Vec<Option<f64>>,
    max_ratio: Vec<Option<f64>>,
    input_power: Vec<f64>,
    input_anisotropy: Vec<Option<f64>>,
    gain_empirical: Vec<Option<f64>>,
    gain_ci_low: Vec<Option<f64>>,
    gain_ci_high: Vec<Option<f64>>,
    gain_exact: Vec<Option<f64>>,
    deterministic_error: Vec<f64>,
    gain_exact_noise: Vec<Option<f64>>,
    anisotropic_norm_sq: Vec<Option<f64>>,
    h2_norm_sq: Vec<Option<f64>>,
    hinf_norm_sq: Vec<Option<f64>>,
    guaranteed_gain: Vec<Option<f64>>,
    design_gain: Vec<Option<f64>>,
    theorem1_gain: Vec<Option<f64>>,
    guarantee_anisotropy: Vec<Option<f64>>,
    guarantee_applies: Vec<Option<bool>>,
    design_seconds: Vec<f64>,
    mc_seconds: Vec<f64>,
}

/// One row per (scenario, filter, step), in that order, built a slice of one (scenario, filter)
/// pair at a time and written a row group at a time, so a long horizon never holds the whole
/// table (10⁷ rows at N = 10⁶ with 5 scenarios and 2 filters) in memory; the row groups are those
/// of the whole table written at once. Each slice ends where a row group does, so the rows alive
/// are one row group's and its copy in one chunk.
fn steps(exp: &Experiment, out: &RunOutcome, batches: &mut Batches) -> Result<()> {
    let mut groups = Grouped::default();
    for sc in &out.scenarios {
        for (f, spec) in exp.filters.iter().enumerate() {
            let (mut start, n) = (0, sc.mc.filters[f].steps.len());
            while start < n {
                let end = (start + ROW_GROUP - groups.pending_rows()).min(n);
                groups.add(batches, super::rows::steps(exp, out, sc, f, &spec.name, start..end)?)?;
                start = end;
            }
        }
    }
    groups.finish(batches, || super::rows::steps(exp, out, &out.scenarios[0], 0, &exp.filters[0].name, 0..0))
}

/// Slices of one run's part of a table, written in row groups of [`ROW_GROUP`] rows as the whole
/// part written at once would be: the rows waiting, the slice added and the copy of a row group
/// in one chunk (at most three row groups' worth; two when a slice ends at a row group's end).
#[derive(Default)]
struct Grouped {
    pending: Option<DataFrame>,
}

impl Grouped {
    /// The rows waiting for the next row group (fewer than [`ROW_GROUP`]).
    fn pending_rows(&self) -> usize {
        self.pending.as_ref().map_or(0, DataFrame::height)
    }

    fn add(&mut self, batches: &mut Batches, rows: DataFrame) -> Result<()> {
        let mut all = match self.pending.take() {
            Some(mut p) => {
                p.vstack_mut_owned(rows).map_err(|e| Error::output(batches.path.display().to_string(), e))?;
                p
            }
            None => rows,
        };
        while all.height() >= ROW_GROUP {
            // One chunk, so one row group (the writer makes a row group per chunk).
            let mut group = all.slice(0, ROW_GROUP);
            group.rechunk_mut();
            batches.put(group)?;
            all = all.slice(ROW_GROUP as i64, all.height() - ROW_GROUP);
        }
        self.pending = Some(all);
        Ok(())
    }

    /// Writes the last rows; a part without rows writes `empty()`, so the file has its columns.
    fn finish(self, batches: &mut Batches, empty: impl FnOnce() -> Result<DataFrame>) -> Result<()> {
        match self.pending {
            Some(mut p) if p.height() > 0 => {
                p.rechunk_mut();
                batches.put(p)
            }
            _ if batches.started() => Ok(()),
            _ => batches.put(empty()?),
        }
    }
}

/// Long format: filter, step, mode, matrix ∈ {Af, Bf, Cf, Df, Gf, s0}, row, col, value; entries that
/// are exactly zero are left out (a missing entry is 0), so sparse gains cost no rows. One batch
/// per filter.
fn gains(exp: &Experiment, out: &RunOutcome, batches: &mut Batches) -> Result<()> {
    for (spec, d) in exp.filters.iter().zip(&out.filters) {
        let r = &d.design.realization;
        let mut groups = Grouped::default();
        // A slice of steps at a time (a long horizon has millions of rows per filter).
        let entries =
            |g: &crate::filter::realization::Gains| g.af.len() + g.bf.len() + g.cf.len() + g.df.len() + g.gf.len();
        let per_step = r.gains.first().map_or(1, |gs| gs.iter().map(entries).sum::<usize>()).max(1);
        let slice = (ROW_GROUP / per_step).max(1);
        for start in (0..r.gains.len()).step_by(slice) {
            groups.add(batches, super::rows::gains(&spec.name, r, start..(start + slice).min(r.gains.len()))?)?;
        }
        groups.finish(batches, || super::rows::gains(&spec.name, r, 0..0))?;
    }
    Ok(())
}

/// Paired differences of the summed error between every two filters on the same draws.
fn paired(exp: &Experiment, out: &RunOutcome) -> Result<DataFrame> {
    let (mut sc_, mut a, mut b, mut n, mut mean, mut se, mut lo, mut hi, mut ex) =
        (vec![], vec![], vec![], vec![], vec![], vec![], vec![], vec![], vec![]);
    let pairs = McStats::pairs(exp.filters.len());
    for sc in &out.scenarios {
        for (w, &(i, j)) in sc.mc.paired.iter().zip(&pairs) {
            let (l, h) = w.ci95();
            sc_.push(sc.name.clone());
            a.push(exp.filters[i].name.clone());
            b.push(exp.filters[j].name.clone());
            n.push(w.n);
            mean.push(w.mean);
            se.push(w.std_error());
            lo.push(l);
            hi.push(h);
            ex.push(sc.exact[i].total - sc.exact[j].total);
        }
    }
    let rows = n.len();
    frame(vec![
        col("experiment", vec![exp.name.as_str(); rows]),
        col("scenario", sc_),
        col("filter_a", a),
        col("filter_b", b),
        col("n_trials", n),
        col("mean_diff", mean),
        col("std_error", se),
        col("ci_low", lo),
        col("ci_high", hi),
        col("exact_diff", ex),
    ])
}

/// The iterations of every iterative design: filter, iteration, objective (I(K(s)) for minimax),
/// gap (δ(s)), step (τ(s)).
fn trace(exp: &Experiment, out: &RunOutcome) -> Result<DataFrame> {
    let (mut fl, mut it, mut obj, mut gap, mut step) = (vec![], vec![], vec![], vec![], vec![]);
    for (spec, d) in exp.filters.iter().zip(&out.filters) {
        for r in &d.design.trace {
            fl.push(spec.name.clone());
            it.push(r.iteration as u32);
            obj.push(r.objective);
            gap.push(r.gap);
            step.push(r.step);
        }
    }
    frame(vec![col("filter", fl), col("iteration", it), col("objective", obj), col("gap", gap), col("step", step)])
}
