//! The Rerun recording (`recording.rrd`), on the `step` timeline:
//!
//! - `mse/<scenario>/<filter>/{empirical, ci_low, ci_high, exact, bound}`: per-step mean squared
//!   error from Monte Carlo with its 95 % interval, the exact value and the family's bound;
//! - `trajectories/<scenario>/trial_<t>/z<j>/{truth, <filter>}`: sample trials, truth and every
//!   estimate of each component of z;
//! - `design/<filter>/{objective, gap, step}` on the `iteration` timeline: iterative designs
//!   (minimax: I(K(s)), δ(s), τ(s));
//! - `compare/<scenario>/{empirical_summed, exact_summed, exact_terminal}` on the `filter` timeline
//!   (filter index in the file's order): every filter of a scenario side by side;
//! - `summary`: one text line per (scenario, filter) with the summed figures.

use std::path::Path;

use crate::error::{Error, Result};
use crate::run::RunOutcome;
use crate::spec::Experiment;

/// Entity-path-safe form of a user-given name.
fn part(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' || c == '-' { c } else { '_' }).collect()
}

pub fn write(exp: &Experiment, out: &RunOutcome, path: &Path) -> Result<()> {
    let what = path.display().to_string();
    let err = |e: &dyn std::fmt::Display| Error::output(&what, e);
    let rec = rerun::RecordingStreamBuilder::new("filterbench").save(path).map_err(|e| err(&e))?;
    for sc in &out.scenarios {
        let s = part(&sc.name);
        for (f, spec) in exp.filters.iter().enumerate() {
            let base = format!("mse/{s}/{}", part(&spec.name));
            let g = out.filters[f].design.guarantee.as_ref();
            for (k, w) in sc.mc.filters[f].steps.iter().enumerate() {
                rec.set_time_sequence("step", k as i64);
                let (lo, hi) = w.ci95();
                rec.log(format!("{base}/empirical"), &rerun::Scalars::single(w.mean)).map_err(|e| err(&e))?;
                rec.log(format!("{base}/ci_low"), &rerun::Scalars::single(lo)).map_err(|e| err(&e))?;
                rec.log(format!("{base}/ci_high"), &rerun::Scalars::single(hi)).map_err(|e| err(&e))?;
                rec.log(format!("{base}/exact"), &rerun::Scalars::single(sc.exact[f].per_step[k]))
                    .map_err(|e| err(&e))?;
                if let Some(b) = g.and_then(|g| g.per_step.get(k)) {
                    rec.log(format!("{base}/bound"), &rerun::Scalars::single(*b)).map_err(|e| err(&e))?;
                }
            }
        }
        for tr in &sc.trajectories {
            for j in 0..tr.z.nrows() {
                let base = format!("trajectories/{s}/trial_{}/z{}", tr.trial, j + 1);
                for k in 0..tr.z.ncols() {
                    rec.set_time_sequence("step", k as i64);
                    rec.log(format!("{base}/truth"), &rerun::Scalars::single(tr.z[(j, k)])).map_err(|e| err(&e))?;
                    for (f, spec) in exp.filters.iter().enumerate() {
                        rec.log(format!("{base}/{}", part(&spec.name)), &rerun::Scalars::single(tr.zhat[f][(j, k)]))
                            .map_err(|e| err(&e))?;
                    }
                }
            }
        }
    }
    for (spec, d) in exp.filters.iter().zip(&out.filters) {
        let base = format!("design/{}", part(&spec.name));
        for r in &d.design.trace {
            rec.set_time_sequence("iteration", r.iteration as i64);
            rec.log(format!("{base}/objective"), &rerun::Scalars::single(r.objective)).map_err(|e| err(&e))?;
            rec.log(format!("{base}/gap"), &rerun::Scalars::single(r.gap)).map_err(|e| err(&e))?;
            rec.log(format!("{base}/step"), &rerun::Scalars::single(r.step)).map_err(|e| err(&e))?;
        }
    }
    // Across filters, in the file's order (for hinf_tradeoff: λ from λ_min up to ∞): the summed and
    // terminal errors side by side, the trade-off seed 002 describes.
    for sc in &out.scenarios {
        let base = format!("compare/{}", part(&sc.name));
        for (f, _) in exp.filters.iter().enumerate() {
            rec.set_time_sequence("filter", f as i64);
            let (st, ex) = (&sc.mc.filters[f].total, &sc.exact[f]);
            rec.log(format!("{base}/empirical_summed"), &rerun::Scalars::single(st.mean)).map_err(|e| err(&e))?;
            rec.log(format!("{base}/exact_summed"), &rerun::Scalars::single(ex.total)).map_err(|e| err(&e))?;
            if let Some(last) = ex.per_step.last() {
                rec.log(format!("{base}/exact_terminal"), &rerun::Scalars::single(*last)).map_err(|e| err(&e))?;
            }
        }
    }
    rec.reset_time();
    for sc in &out.scenarios {
        for (f, spec) in exp.filters.iter().enumerate() {
            let st = &sc.mc.filters[f].total;
            let (lo, hi) = st.ci95();
            let line = format!(
                "{} / {}: empirical {:.6} [{:.6}, {:.6}], exact {:.6}",
                sc.name, spec.name, st.mean, lo, hi, sc.exact[f].total
            );
            rec.log_static("summary", &rerun::TextLog::new(line)).map_err(|e| err(&e))?;
        }
    }
    rec.flush_blocking().map_err(|e| err(&e))?;
    Ok(())
}
