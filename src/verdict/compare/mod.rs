//! `filterbench compare OLD NEW`: what changed between two result folders of the same experiment
//! (docs/regression-tests.md, "Comparing two runs"). Every value of the tables is one cell:
//! deterministic values (design, exact, guaranteed, worst case, norms, gains, design traces) are
//! equal within a relative tolerance; Monte Carlo means (summed error, per-step MSE and NEES,
//! paired differences) are compared by a two-sample z with the combined standard error, Holm's
//! procedure over all of them at one family-wise α, so two runs of the same filters on
//! independent draws report a change with probability at most α. Two runs with the same seed and
//! trials drew the same numbers: their Monte Carlo values are then compared like deterministic
//! ones. `matches_baseline` of `filterbench check` is [`compare_folders`] on the run and its
//! baseline.

mod cell;
mod folder;
mod outcome;
mod print;
mod tables;

use std::collections::HashMap;
use std::path::Path;

pub use cell::{Cell, CompareOptions, DEFAULT_ALPHA, DEFAULT_REL_TOL, Kind, Status, Value};
pub use outcome::{ColumnSummary, Comparison};
pub use print::{console, json};

use crate::error::{Error, Result};
use crate::verdict::stats::holm;

fn check_options(opts: &CompareOptions) -> Result<()> {
    if !(opts.alpha > 0.0 && opts.alpha < 1.0) {
        return Err(Error::invalid("--alpha", format!("{} is not a probability in (0, 1)", opts.alpha)));
    }
    if !(opts.rel_tol >= 0.0 && opts.rel_tol.is_finite()) {
        return Err(Error::invalid("--rel-tol", format!("{} is not a finite number ≥ 0", opts.rel_tol)));
    }
    Ok(())
}

/// Compares the result folders `old` and `new` of one experiment. Refused (one line naming the
/// folder or file and the cause) when either is not a result folder or they are of different
/// experiments (another `experiment`, other variants, scenarios or filters); a table that cannot
/// be read is refused naming its file.
pub fn compare_folders(old: &Path, new: &Path, opts: &CompareOptions) -> Result<Comparison> {
    check_options(opts)?;
    let (a, b) = (folder::Folder::open(old)?, folder::Folder::open(new)?);
    folder::same_experiment(&a, &b)?;
    let (ma, mb) = (&a.manifest, &b.manifest);
    let common_draws = !opts.independent_draws
        && ma.seed.is_some()
        && ma.seed == mb.seed
        && ma.trials.is_some()
        && ma.trials == mb.trials;
    let mut frames = vec![];
    for spec in tables::SPECS {
        frames.push((spec, folder::Frame::read(old, spec.file)?, folder::Frame::read(new, spec.file)?));
    }
    let mut ctx = tables::Ctx { opts, common_draws, filter_scale: HashMap::new() };
    for f in frames.iter().filter(|(s, _, _)| s.name == "summary").flat_map(|(_, a, b)| [a, b]).flatten() {
        let key = |c: &str, i: usize| f.column(c).and_then(|c| c.text(i)).unwrap_or_default();
        let num = |c: &str, i: usize| f.column(c).and_then(|c| c.num(i)).unwrap_or(0.0).abs();
        for i in 0..f.height {
            let e = ctx.filter_scale.entry((key("variant", i), key("scenario", i), key("filter", i))).or_default();
            *e = (e.0.max(num("exact", i)), e.1.max(num("empirical_mean", i)));
        }
    }
    let mut sink = tables::Sink::default();
    for (spec, fa, fb) in &frames {
        tables::compare_table(spec, fa.as_ref(), fb.as_ref(), &ctx, &mut sink);
    }
    ctx.filter_scale.clear();
    // Holm over every Monte Carlo cell of independent draws, identical ones included (p = 1).
    let p: Vec<f64> = sink.pending.iter().map(|x| x.p).collect();
    let verdict = holm(&p, opts.alpha);
    let pending = std::mem::take(&mut sink.pending);
    for (k, x) in pending.iter().enumerate() {
        let status = match x.cell {
            Some(i) => {
                let c = &mut sink.cells[i];
                c.holm_threshold = Some(verdict.threshold[k]);
                if verdict.rejected[k] {
                    c.status = Status::Changed;
                } else if c.status != Status::Identical {
                    c.status = Status::WithinNoise;
                }
                c.status
            }
            None => Status::Identical,
        };
        let z = x.cell.and_then(|i| sink.cells[i].z);
        let s = tables::summary_of(&mut sink, x.column.0, &x.column.1, Kind::MonteCarlo);
        s.count(status);
        if let Some(z) = z {
            s.max_abs_z = Some(s.max_abs_z.map_or(z.abs(), |m| m.max(z.abs())));
        }
    }
    Ok(Comparison {
        old: old.to_path_buf(),
        new: new.to_path_buf(),
        experiment: ma.experiment.clone(),
        alpha: opts.alpha,
        rel_tol: opts.rel_tol,
        common_draws,
        tested_cells: p.len(),
        columns: sink.columns,
        cells: sink.cells,
    })
}
