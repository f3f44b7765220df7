//! The Rerun recording (`recording.rrd`), on the `step` timeline:
//!
//! - `mse/<scenario>/<filter>/{empirical, ci_low, ci_high, exact, bound}`: per-step mean squared
//!   error from Monte Carlo with its 95 % interval, the exact value and the family's bound;
//! - `trajectories/<scenario>/trial_<t>/z<j>/{truth, <filter>}`: sample trials, truth and every
//!   estimate of each component of z; `…/e<j>/<filter>` the errors z_j − ẑ_j; with measurement
//!   dropouts, `…/z<j>/dropouts` and `…/e<j>/dropouts` mark the steps whose measurement was lost
//!   (points on the truth and on the first filter's error: seed 003's Figs. 1–12);
//! - `design/<filter>/{objective, gap, step}` on the `iteration` timeline: iterative designs
//!   (minimax: I(K(s)), δ(s), τ(s));
//! - `compare/<scenario>/{empirical_summed, exact_summed, exact_terminal}` on the `filter` timeline
//!   (filter index in the file's order): every filter of a scenario side by side;
//! - `summary`: one text line per (scenario, filter) with the summed figures.
//!
//! When the experiment file has variants (e.g. one dropout probability each), every path above is
//! prefixed by `<variant>/`.

use std::path::Path;

use crate::error::{Error, Result};
use crate::run::RunOutcome;
use crate::spec::Experiment;

/// Entity-path-safe form of a user-given name.
fn part(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' || c == '-' { c } else { '_' }).collect()
}

/// Writes one recording holding every run (one per variant).
pub fn write(runs: &[(&Experiment, &RunOutcome)], path: &Path) -> Result<()> {
    let what = path.display().to_string();
    let rec = rerun::RecordingStreamBuilder::new("filterbench").save(path).map_err(|e| Error::output(&what, e))?;
    for (exp, out) in runs {
        let prefix = exp.variant.as_deref().map_or(String::new(), |v| format!("{}/", part(v)));
        write_run(&rec, exp, out, &prefix).map_err(|e| Error::output(&what, e))?;
    }
    rec.flush_blocking().map_err(|e| Error::output(&what, e))?;
    Ok(())
}

type RecResult = std::result::Result<(), rerun::RecordingStreamError>;

/// Marks the dropout instants of a trial (mode 0 of a dropout plant) as points on `entity`'s
/// series (values at those steps).
fn dropouts(rec: &rerun::RecordingStream, entity: &str, modes: &[usize], value: impl Fn(usize) -> f64) -> RecResult {
    rec.log_static(
        entity,
        &rerun::SeriesPoints::new()
            .with_markers([rerun::components::MarkerShape::Circle])
            .with_marker_sizes([4.0])
            .with_names(["dropout"]),
    )?;
    for (k, m) in modes.iter().enumerate() {
        if *m == 0 {
            rec.set_time_sequence("step", k as i64);
            rec.log(entity, &rerun::Scalars::single(value(k)))?;
        }
    }
    Ok(())
}

fn write_run(rec: &rerun::RecordingStream, exp: &Experiment, out: &RunOutcome, prefix: &str) -> RecResult {
    for sc in &out.scenarios {
        for (f, spec) in exp.filters.iter().enumerate() {
            let base = format!("{prefix}mse/{}/{}", part(&sc.name), part(&spec.name));
            let g = out.filters[f].design.guarantee.as_ref();
            for (k, w) in sc.mc.filters[f].steps.iter().enumerate() {
                rec.set_time_sequence("step", k as i64);
                let (lo, hi) = w.ci95();
                rec.log(format!("{base}/empirical"), &rerun::Scalars::single(w.mean))?;
                rec.log(format!("{base}/ci_low"), &rerun::Scalars::single(lo))?;
                rec.log(format!("{base}/ci_high"), &rerun::Scalars::single(hi))?;
                rec.log(format!("{base}/exact"), &rerun::Scalars::single(sc.exact[f].per_step[k]))?;
                if let Some(b) = g.and_then(|g| g.per_step.get(k)) {
                    rec.log(format!("{base}/bound"), &rerun::Scalars::single(*b))?;
                }
            }
        }
        for tr in &sc.trajectories {
            for j in 0..tr.z.nrows() {
                let base = format!("{prefix}trajectories/{}/trial_{}/z{}", part(&sc.name), tr.trial, j + 1);
                let ebase = format!("{prefix}trajectories/{}/trial_{}/e{}", part(&sc.name), tr.trial, j + 1);
                for k in 0..tr.z.ncols() {
                    rec.set_time_sequence("step", k as i64);
                    rec.log(format!("{base}/truth"), &rerun::Scalars::single(tr.z[(j, k)]))?;
                    for (f, spec) in exp.filters.iter().enumerate() {
                        rec.log(format!("{base}/{}", part(&spec.name)), &rerun::Scalars::single(tr.zhat[f][(j, k)]))?;
                        rec.log(
                            format!("{ebase}/{}", part(&spec.name)),
                            &rerun::Scalars::single(tr.z[(j, k)] - tr.zhat[f][(j, k)]),
                        )?;
                    }
                }
                if exp.plant.arrival.is_some() {
                    dropouts(rec, &format!("{base}/dropouts"), &tr.modes, |k| tr.z[(j, k)])?;
                    dropouts(rec, &format!("{ebase}/dropouts"), &tr.modes, |k| tr.z[(j, k)] - tr.zhat[0][(j, k)])?;
                }
            }
            if exp.plant.arrival.is_none() && exp.plant.modes.is_some() {
                let base = format!("{prefix}trajectories/{}/trial_{}/mode", part(&sc.name), tr.trial);
                for (k, m) in tr.modes.iter().enumerate() {
                    rec.set_time_sequence("step", k as i64);
                    rec.log(base.as_str(), &rerun::Scalars::single(*m as f64))?;
                }
            }
        }
    }
    for (spec, d) in exp.filters.iter().zip(&out.filters) {
        let base = format!("{prefix}design/{}", part(&spec.name));
        for r in &d.design.trace {
            rec.set_time_sequence("iteration", r.iteration as i64);
            rec.log(format!("{base}/objective"), &rerun::Scalars::single(r.objective))?;
            rec.log(format!("{base}/gap"), &rerun::Scalars::single(r.gap))?;
            rec.log(format!("{base}/step"), &rerun::Scalars::single(r.step))?;
        }
    }
    // Across filters, in the file's order (for hinf_tradeoff: λ from λ_min up to ∞): the summed and
    // terminal errors side by side, the trade-off seed 002 describes.
    for sc in &out.scenarios {
        let base = format!("{prefix}compare/{}", part(&sc.name));
        for (f, _) in exp.filters.iter().enumerate() {
            rec.set_time_sequence("filter", f as i64);
            let (st, ex) = (&sc.mc.filters[f].total, &sc.exact[f]);
            rec.log(format!("{base}/empirical_summed"), &rerun::Scalars::single(st.mean))?;
            rec.log(format!("{base}/exact_summed"), &rerun::Scalars::single(ex.total))?;
            if let Some(last) = ex.per_step.last() {
                rec.log(format!("{base}/exact_terminal"), &rerun::Scalars::single(*last))?;
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
            rec.log_static(format!("{prefix}summary"), &rerun::TextLog::new(line))?;
        }
    }
    Ok(())
}
