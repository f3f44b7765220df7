//! `--per-trial`: every trial's summed error J in `trials.parquet`, and the summary's median and
//! 95th percentile, exact order statistics of those values.

use polars::prelude::*;

use crate::config::Experiment;
use crate::error::{Error, Result};
use crate::pipeline::RunOutcome;

/// The table's file name; written only when some run keeps per-trial values.
pub const FILE: &str = "trials.parquet";

/// One row per (scenario, filter, trial), in that order: the trial's summed error J over the
/// steps that count (what `summary.parquet`'s mean averages).
pub fn table(exp: &Experiment, out: &RunOutcome) -> Result<DataFrame> {
    let rows: usize = out.scenarios.iter().map(|s| s.per_trial.iter().map(Vec::len).sum::<usize>()).sum();
    let (mut sc, mut fl, mut trial, mut j) =
        (Vec::with_capacity(rows), Vec::with_capacity(rows), Vec::with_capacity(rows), Vec::with_capacity(rows));
    for s in &out.scenarios {
        for (spec, values) in exp.filters.iter().zip(&s.per_trial) {
            sc.extend(std::iter::repeat_n(s.name.as_str(), values.len()));
            fl.extend(std::iter::repeat_n(spec.name.as_str(), values.len()));
            trial.extend(0..values.len() as u64);
            j.extend_from_slice(values);
        }
    }
    DataFrame::new_infer_height(vec![
        Column::new("experiment".into(), vec![exp.name.as_str(); rows]),
        Column::new("scenario".into(), sc),
        Column::new("filter".into(), fl),
        Column::new("trial".into(), trial),
        Column::new("j".into(), j),
    ])
    .map_err(|e| Error::output(FILE, e))
}

/// The p-quantile as the order statistic x₍⌈p·n⌉₎ (nearest rank: a value that occurred; the median
/// of an even count is the lower middle one). None without values.
pub(crate) fn quantile(values: &[f64], p: f64) -> Option<f64> {
    let mut v = values.to_vec();
    v.sort_unstable_by(f64::total_cmp);
    let rank = ((p * v.len() as f64).ceil() as usize).clamp(1, v.len().max(1));
    v.get(rank - 1).copied()
}

/// Adds `median` and `p95` after `ci_high` to a run's summary (rows per scenario, then filter).
pub(crate) fn add_quantiles(df: &mut DataFrame, out: &RunOutcome) -> Result<()> {
    let values = || out.scenarios.iter().flat_map(|s| s.per_trial.iter());
    let median: Vec<Option<f64>> = values().map(|v| quantile(v, 0.5)).collect();
    let p95: Vec<Option<f64>> = values().map(|v| quantile(v, 0.95)).collect();
    let at = df.get_column_index("ci_high").map_or(df.width(), |i| i + 1);
    let err = |e| Error::output("summary.parquet", e);
    df.insert_column(at, Column::new("median".into(), median)).map_err(err)?;
    df.insert_column(at + 1, Column::new("p95".into(), p95)).map_err(err)?;
    Ok(())
}
