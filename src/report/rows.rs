//! The rows of the per-step tables, a slice at a time (`report::parquet` writes them in row
//! groups, so a long horizon never holds a whole table).

use polars::prelude::*;

use crate::config::Experiment;
use crate::error::{Error, Result};
use crate::pipeline::{RunOutcome, ScenarioOutcome};

/// A table from its columns (one height).
pub(super) fn frame(cols: Vec<Column>) -> Result<DataFrame> {
    DataFrame::new_infer_height(cols).map_err(|e| Error::output("parquet table", e))
}

/// A named column of any type polars takes.
pub(super) fn col<T, P>(name: &str, v: T) -> Column
where
    Series: NamedFrom<T, P>,
    P: ?Sized,
{
    Column::new(name.into(), v)
}

/// The rows of steps `ks` of filter `f` in scenario `sc`.
pub(crate) fn steps(
    exp: &Experiment,
    out: &RunOutcome,
    sc: &ScenarioOutcome,
    f: usize,
    filter: &str,
    ks: std::ops::Range<usize>,
) -> Result<DataFrame> {
    let n = ks.len();
    let (mut step, mut mean, mut lo, mut hi, mut se, mut ex, mut bound, mut claimed) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    let promise = sc.filters[f].promise.as_ref();
    let cl = out.filters[f].claimed.as_ref();
    let st = &sc.mc.filters[f];
    let (of, df) = (&sc.filters[f], &out.filters[f]);
    let nees = square("nees", of.nees_exact.as_ref(), &st.nees, df.nees.as_ref(), ks.clone());
    let nis = square("nis", of.nis_exact.as_ref(), &st.nis, df.nis.as_ref(), ks.clone());
    for k in ks {
        let w = st.steps.at(k);
        let (l, h) = w.ci95();
        step.push(k as u32);
        mean.push(w.mean);
        lo.push(l);
        hi.push(h);
        se.push(w.std_error());
        ex.push(Some(sc.exact[f].per_step[k]));
        bound.push(promise.and_then(|p| p.bound(k)));
        claimed.push(cl.and_then(|c| c.per_step.get(k).copied()));
    }
    let text = |name: &str, v: &str| StringChunked::full(name.into(), v, n).into_column();
    let mut cols = vec![
        text("experiment", &exp.name),
        text("scenario", &sc.name),
        text("filter", filter),
        col("step", step),
        col("mse_mean", mean),
        col("mse_ci_low", lo),
        col("mse_ci_high", hi),
        col("mse_std_error", se),
        col("exact_mse", ex),
        col("bound", bound),
        col("claimed", claimed),
    ];
    cols.extend(nees);
    cols.extend(nis);
    frame(cols)
}

/// The columns `{name}_exact`, `_mean`, `_ci_low`, `_ci_high`, `_std_error` and `_rank` of a
/// normalized square (NEES or NIS) at steps `ks`: null at a step where the filter claims nothing.
fn square(
    name: &str,
    exact: Option<&crate::analysis::nees::PerStep>,
    mc: &crate::sim::series::Series,
    claim: Option<&crate::analysis::nees::Normalized>,
    ks: std::ops::Range<usize>,
) -> Vec<Column> {
    let ws: Vec<_> = ks.clone().map(|k| mc.get(k).filter(|w| w.n > 0)).collect();
    let by = |f: &dyn Fn(&crate::sim::stats::Welford) -> f64| ws.iter().map(|w| w.as_ref().map(f)).collect::<Vec<_>>();
    let rank: Vec<Option<u32>> = ks
        .clone()
        .zip(&ws)
        .map(|(k, w)| w.as_ref().and(claim.and_then(|c| c.ranks.get(k))).map(|r| *r as u32))
        .collect();
    vec![
        col(&format!("{name}_exact"), ks.map(|k| exact.and_then(|v| v.get(k))).collect::<Vec<_>>()),
        col(&format!("{name}_mean"), by(&|w| w.mean)),
        col(&format!("{name}_ci_low"), by(&|w| w.ci95().0)),
        col(&format!("{name}_ci_high"), by(&|w| w.ci95().1)),
        col(&format!("{name}_std_error"), by(&|w| w.std_error())),
        col(&format!("{name}_rank"), rank),
    ]
}

/// The rows of filter `name`'s gains at steps `ks` (with s0, counted as step 0, in the slice
/// starting at 0).
pub(crate) fn gains<'a>(
    name: &'a str,
    r: &crate::filter::realization::Realization,
    ks: std::ops::Range<usize>,
) -> Result<DataFrame> {
    let (mut fl, mut step, mut mode, mut mat, mut row, mut coln, mut val): (Vec<&'a str>, _, _, _, _, _, _) =
        (vec![], vec![], vec![], vec![], vec![], vec![], vec![]);
    let mut push = |f: &'a str, k: usize, md: Option<u32>, name: &'static str, m: &nalgebra::DMatrix<f64>| {
        for j in 0..m.ncols() {
            for i in 0..m.nrows() {
                if m[(i, j)] == 0.0 {
                    continue;
                }
                fl.push(f);
                step.push(k as u32);
                mode.push(md);
                mat.push(name);
                row.push(i as u32);
                coln.push(j as u32);
                val.push(m[(i, j)]);
            }
        }
    };
    if ks.start == 0 && !ks.is_empty() {
        push(name, 0, None, "s0", &nalgebra::DMatrix::from_column_slice(r.ns(), 1, r.s0.as_slice()));
    }
    // A mode-indexed realization has one set of gains per (step, mode); others have mode null.
    let sets: Vec<(usize, Option<u32>, &crate::filter::realization::Gains)> = if !r.is_mode_indexed() {
        ks.map(|k| (k, None, &r.gains[k][0])).collect()
    } else {
        ks.map(|k| (k, r.gains[k].as_slice()))
            .flat_map(|(k, gs)| gs.iter().enumerate().map(move |(j, g)| (k, Some(j as u32), g)))
            .collect()
    };
    for (k, md, g) in sets {
        push(name, k, md, "Af", &g.af);
        push(name, k, md, "Bf", &g.bf);
        push(name, k, md, "Cf", &g.cf);
        push(name, k, md, "Df", &g.df);
        push(name, k, md, "Gf", &g.gf);
    }
    frame(vec![
        col("filter", fl),
        col("step", step),
        col("mode", mode),
        col("matrix", mat),
        col("row", row),
        col("col", coln),
        col("value", val),
    ])
}
