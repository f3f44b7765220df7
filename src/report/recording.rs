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
//! - for a string (seed 004), `galerkin/<scenario>/error_vs_n/alpha_<α>/<basis>` on the `n`
//!   timeline and `galerkin/<scenario>/error_vs_alpha/n_<n>/<basis>` on the `neg_log10_alpha`
//!   timeline (the exact time-averaged error of every Galerkin filter), and
//!   `galerkin/<scenario>/string/{truth, <filter>}`: the first sample trial's u along ξ at every
//!   step (line strips through the output points) for the truth and the finest filter.
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

type RecResult = std::result::Result<(), Box<dyn std::error::Error + Send + Sync>>;

/// A whole scalar series in one chunk (columnar): one call per entity instead of one per step,
/// which keeps the recording's memory and size proportional to the data.
fn series(
    rec: &rerun::RecordingStream,
    entity: &str,
    timeline: &'static str,
    times: Vec<i64>,
    values: Vec<f64>,
) -> RecResult {
    let t = rerun::TimeColumn::new_sequence(timeline, times);
    rec.send_columns(entity, [t], rerun::Scalars::new(values).columns_of_unit_batches()?)?;
    Ok(())
}

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
    let lost: Vec<usize> = (0..modes.len()).filter(|k| modes[*k] == 0).collect();
    series(rec, entity, "step", lost.iter().map(|k| *k as i64).collect(), lost.iter().map(|k| value(*k)).collect())
}

fn write_run(rec: &rerun::RecordingStream, exp: &Experiment, out: &RunOutcome, prefix: &str) -> RecResult {
    for sc in &out.scenarios {
        for (f, spec) in exp.filters.iter().enumerate() {
            let base = format!("{prefix}mse/{}/{}", part(&sc.name), part(&spec.name));
            let g = out.filters[f].design.guarantee.as_ref();
            let st = &sc.mc.filters[f].steps;
            let steps: Vec<i64> = (0..st.len() as i64).collect();
            series(rec, &format!("{base}/empirical"), "step", steps.clone(), st.iter().map(|w| w.mean).collect())?;
            series(rec, &format!("{base}/ci_low"), "step", steps.clone(), st.iter().map(|w| w.ci95().0).collect())?;
            series(rec, &format!("{base}/ci_high"), "step", steps.clone(), st.iter().map(|w| w.ci95().1).collect())?;
            series(rec, &format!("{base}/exact"), "step", steps.clone(), sc.exact[f].per_step.clone())?;
            if let Some(g) = g.filter(|g| !g.per_step.is_empty()) {
                series(rec, &format!("{base}/bound"), "step", steps.clone(), g.per_step.clone())?;
            }
        }
        for tr in &sc.trajectories {
            for j in 0..tr.z.nrows() {
                let base = format!("{prefix}trajectories/{}/trial_{}/z{}", part(&sc.name), tr.trial, j + 1);
                let ebase = format!("{prefix}trajectories/{}/trial_{}/e{}", part(&sc.name), tr.trial, j + 1);
                let steps: Vec<i64> = (0..tr.z.ncols() as i64).collect();
                let truth: Vec<f64> = tr.z.row(j).iter().copied().collect();
                series(rec, &format!("{base}/truth"), "step", steps.clone(), truth.clone())?;
                for (f, spec) in exp.filters.iter().enumerate() {
                    let est: Vec<f64> = tr.zhat[f].row(j).iter().copied().collect();
                    let err: Vec<f64> = truth.iter().zip(&est).map(|(a, b)| a - b).collect();
                    series(rec, &format!("{base}/{}", part(&spec.name)), "step", steps.clone(), est)?;
                    series(rec, &format!("{ebase}/{}", part(&spec.name)), "step", steps.clone(), err)?;
                }
                if exp.plant.arrival.is_some() {
                    dropouts(rec, &format!("{base}/dropouts"), &tr.modes, |k| tr.z[(j, k)])?;
                    dropouts(rec, &format!("{ebase}/dropouts"), &tr.modes, |k| tr.z[(j, k)] - tr.zhat[0][(j, k)])?;
                }
            }
            if exp.plant.arrival.is_none() && exp.plant.modes.is_some() {
                let base = format!("{prefix}trajectories/{}/trial_{}/mode", part(&sc.name), tr.trial);
                let steps = (0..tr.modes.len() as i64).collect();
                series(rec, &base, "step", steps, tr.modes.iter().map(|m| *m as f64).collect())?;
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
    if exp.string.is_some() {
        galerkin(rec, exp, out, prefix)?;
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

/// The error surface over (n, α, basis) and the string's profile along ξ (seed 004).
fn galerkin(rec: &rerun::RecordingStream, exp: &Experiment, out: &RunOutcome, prefix: &str) -> RecResult {
    let Some(model) = exp.string.as_ref() else { return Ok(()) };
    let steps = exp.plant.steps() as f64;
    let figures: Vec<(usize, String, usize, f64)> = exp
        .filters
        .iter()
        .enumerate()
        .filter_map(|(f, _)| {
            let d = &out.filters[f].design.diagnostics;
            Some((f, d.get("basis")?.as_str()?.to_string(), d.get("n")?.as_u64()? as usize, d.get("alpha")?.as_f64()?))
        })
        .collect();
    for sc in &out.scenarios {
        let base = format!("{prefix}galerkin/{}", part(&sc.name));
        for (f, basis, n, alpha) in &figures {
            let v = sc.exact[*f].total / steps;
            rec.set_time_sequence("n", *n as i64);
            rec.log(
                format!("{base}/error_vs_n/alpha_{}/{basis}", part(&format!("{alpha:e}"))),
                &rerun::Scalars::single(v),
            )?;
            rec.reset_time();
            if *alpha > 0.0 {
                rec.set_time_sequence("neg_log10_alpha", (-alpha.log10()).round() as i64);
                rec.log(format!("{base}/error_vs_alpha/n_{n}/{basis}"), &rerun::Scalars::single(v))?;
                rec.reset_time();
            }
        }
        // The finest filter (largest n, then smallest α) and, for contrast, the coarsest at that α.
        let finest = figures.iter().max_by(|a, b| a.2.cmp(&b.2).then(b.3.total_cmp(&a.3)));
        let coarsest = finest
            .and_then(|fin| figures.iter().filter(|x| x.1 == fin.1 && x.3 == fin.3 && x.2 < fin.2).min_by_key(|x| x.2));
        let shown: Vec<usize> = finest.into_iter().chain(coarsest).map(|x| x.0).collect();
        if let Some(tr) = sc.trajectories.first() {
            let xs = &model.outputs;
            for k in 0..tr.z.ncols() {
                rec.set_time_sequence("step", k as i64);
                let strip = |v: &dyn Fn(usize) -> f64| -> Vec<[f32; 2]> {
                    std::iter::once([0.0, 0.0])
                        .chain(xs.iter().enumerate().map(|(p, x)| [*x as f32, v(p) as f32]))
                        .chain(std::iter::once([model.length as f32, 0.0]))
                        .collect()
                };
                rec.log(format!("{base}/string/truth"), &rerun::LineStrips2D::new([strip(&|p| tr.z[(p, k)])]))?;
                for &f in &shown {
                    rec.log(
                        format!("{base}/string/{}", part(&exp.filters[f].name)),
                        &rerun::LineStrips2D::new([strip(&|p| tr.zhat[f][(p, k)])]),
                    )?;
                }
            }
        }
    }
    Ok(())
}
