//! The Rerun recording (`recording.rrd`): the run's figures on the `step` timeline, styled (one
//! colour per filter, see [`style`]) and sent with a default layout (`layout`) so the viewer
//! opens it readable. Entity paths (each user-given name is one escaped path part, so `k.1` and
//! `k_1` stay two entities), with `<variant>/` in front when the file has variants:
//!
//! - `mse/<scenario>/<filter>/{empirical, ci_low, ci_high, exact}`: per-step mean squared error
//!   from Monte Carlo with its 95 % band, and the exact value;
//! - `promise/<scenario>/<filter>/{guaranteed | claimed}`: the family's per-step bound, or, for a
//!   filter whose only promise is its error at its own design covariance, that claim;
//! - `trajectories/<scenario>/trial_<t>/z<j>/{truth, noise_free, estimates, dropouts}` and
//!   `…/e<j>/{errors, dropouts}`: sample trials (seed 003's Figs. 1–12), the noise-free z (only
//!   with a known input), one series per filter in `estimates` and `errors`, the lost measurements
//!   as markers; `…/mode` the Markov mode;
//! - `compare/<scenario>/<filter>`: the exact summed error as one bar per filter;
//! - `tables/<scenario>` and `summary`: the summed figures as Markdown tables;
//! - `design/<filter>/{objective, gap}`: iterative designs (minimax: I(K(s)) and δ(s) per
//!   iteration), as bar charts; `design/<filter>/line_search_<s>`: I/N along Algorithm 1's line
//!   search s against τ ∈ [0, 1] (seed 000 Fig. 1 is s = 1), one bar per sampled τ, less its value
//!   at τ = 0 (bars start at zero: the rise of I, a fraction of a percent after the first step,
//!   would not show on top of I itself; the view's title gives the start);
//! - for a string (seed 004), `galerkin/<scenario>/{surface/<basis>/<α>, surface_table,
//!   string/<filter>, string/truth}`: the exact error over (basis, n, α) and the first sample
//!   trial's u along ξ at every step.
//!
//! The recording is presentation only: every number in it is also in the Parquet tables, except
//! the sample trials (`trajectories/…`, a string's `galerkin/…/string/…`), which only it holds.

mod blueprint;
mod galerkin;
mod layout;
mod run;
pub mod style;
mod tables;

use std::path::Path;

use crate::config::Experiment;
use crate::error::{Error, Result};
use crate::pipeline::{RunOutcome, ScenarioOutcome};
use run::{APP, RecResult, Run, line_search_leaf};
pub use run::{MAX_SHOWN, path, shown};

/// Writes one recording holding every run (one per variant), with its default layout.
pub fn write(runs: &[(&Experiment, &RunOutcome)], path: &Path) -> Result<()> {
    let what = path.display().to_string();
    let rec = rerun::RecordingStreamBuilder::new(APP).save(path).map_err(|e| Error::output(&what, e))?;
    let runs: Vec<Run> = runs.iter().map(|(exp, out)| Run { exp, out }).collect();
    // The layout goes first: a viewer that is still reading the data has already switched to it
    // (viewer 0.36.3 keeps its own heuristic layout when the blueprint comes last).
    layout::send(&rec, &runs).map_err(|e| Error::output(&what, e))?;
    let mut w = Writer { rec: &rec, pending: Vec::new() };
    for run in &runs {
        write_run(&mut w, run).map_err(|e| Error::output(&what, e))?;
    }
    rec.flush_blocking().map_err(|e| Error::output(&what, e))?;
    Ok(())
}

/// A whole series, waiting for its style to be written first.
struct Pending {
    entity: String,
    steps: Vec<i64>,
    values: Vec<f64>,
    per_row: usize,
}

/// Writes styles (static, through the SDK's batcher) before the series they style (columnar, one
/// chunk per entity, straight to the file): a viewer that shows a file while reading it then never
/// draws a series without its colour and name.
struct Writer<'r> {
    rec: &'r rerun::RecordingStream,
    pending: Vec<Pending>,
}

impl Writer<'_> {
    /// A series of `values.len() / per_row` rows at `steps` (one scalar per instance of the
    /// style); nothing at all when there is no row, since a chunk with zero rows crashes the
    /// viewer's time panel.
    fn series(
        &mut self,
        entity: String,
        style: &dyn rerun::AsComponents,
        steps: &[i64],
        values: Vec<f64>,
        per_row: usize,
    ) -> RecResult {
        if values.is_empty() {
            return Ok(());
        }
        self.rec.log_static(entity.as_str(), style)?;
        let steps = steps[..values.len() / per_row].to_vec();
        self.pending.push(Pending { entity, steps, values, per_row });
        Ok(())
    }

    /// Sends what waits, after the styles logged so far.
    fn flush(&mut self) -> RecResult {
        self.rec.flush_blocking()?;
        for p in self.pending.drain(..) {
            let t = rerun::TimeColumn::new_sequence("step", p.steps.clone());
            let cols = rerun::Scalars::new(p.values).columns(std::iter::repeat_n(p.per_row, p.steps.len()))?;
            self.rec.send_columns(p.entity.as_str(), [t], cols)?;
        }
        Ok(())
    }
}

fn series_style(colour: style::Rgba, width: f32, name: &str) -> rerun::SeriesLines {
    rerun::SeriesLines::new().with_colors([colour]).with_widths([width]).with_names([name])
}

fn marker_style(
    colour: style::Rgba,
    marker: rerun::components::MarkerShape,
    size: f32,
    name: &str,
) -> rerun::SeriesPoints {
    rerun::SeriesPoints::new().with_colors([colour]).with_markers([marker]).with_marker_sizes([size]).with_names([name])
}

/// Row-major values of `rows` rows: instance i of row k is `value(k, i)`.
fn interleave(rows: usize, per_row: usize, value: impl Fn(usize, usize) -> f64) -> Vec<f64> {
    (0..rows).flat_map(|k| (0..per_row).map(move |i| (k, i))).map(|(k, i)| value(k, i)).collect()
}

fn write_run(w: &mut Writer, run: &Run) -> RecResult {
    let (exp, out) = (run.exp, run.out);
    for sc in &out.scenarios {
        mse(w, run, sc)?;
        trajectories(w, run, sc)?;
        compare(w.rec, run, sc)?;
        let table = tables::scenario(exp, out, sc);
        w.rec.log_static(run.at(&["tables", &sc.name]), &rerun::TextDocument::from_markdown(table))?;
        w.flush()?;
    }
    design_traces(w.rec, run)?;
    if exp.string.is_some() {
        galerkin::write(w.rec, run)?;
    }
    w.rec.log_static(run.at(&["summary"]), &rerun::TextDocument::from_markdown(tables::summary(exp, out)))?;
    Ok(())
}

/// Per-step MSE of every filter: the empirical mean with its 95 % band (one entity, three
/// series), the exact value as dots, and the promise.
fn mse(w: &mut Writer, run: &Run, sc: &ScenarioOutcome) -> RecResult {
    use rerun::components::MarkerShape;
    for (f, spec) in run.exp.filters.iter().enumerate() {
        let (c, name) = (style::filter_colour(f), spec.name.as_str());
        let st = &sc.mc.filters[f].steps;
        let steps: Vec<i64> = (0..st.len().max(sc.exact[f].per_step.len()) as i64).collect();
        let at = |leaf: &str| run.at(&["mse", &sc.name, name, leaf]);
        // The mean, its band and the exact dots share the filter's name, so the legend has one
        // entry per filter (the view's title says which mark is which) and leaves the curves visible.
        let emp = rerun::SeriesLines::new()
            .with_colors([c, style::faded(c), style::faded(c)])
            .with_widths([style::EMPIRICAL_WIDTH, style::BAND_WIDTH, style::BAND_WIDTH])
            .with_names([name; 3]);
        let values = interleave(st.len(), 3, |k, i| [st[k].mean, st[k].ci95().0, st[k].ci95().1][i]);
        w.series(at("empirical"), &emp, &steps, values, 3)?;
        let exact = marker_style(c, MarkerShape::Circle, 1.5, name);
        w.series(at("exact"), &exact, &steps, sc.exact[f].per_step.clone(), 1)?;
        if let Some(p) = &sc.filters[f].promise {
            let entity = run.at(&["promise", &sc.name, name, p.label()]);
            let s = series_style(c, style::EXACT_WIDTH, &format!("{name} · {}", p.label()));
            w.series(entity, &s, &steps, p.values().to_vec(), 1)?;
        }
    }
    Ok(())
}

/// Sample trials: per component of z the truth, the noise-free z where the plant has a known
/// input (seed 003 Figs. 3–4), every filter's estimate (one entity, one series per filter in the
/// file's order) and error, with the lost measurements (mode 0 of a dropout plant) marked on the
/// truth and on the zero line of the errors. Filters beyond the scenario's
/// [`shown`] ones start hidden.
fn trajectories(w: &mut Writer, run: &Run, sc: &ScenarioOutcome) -> RecResult {
    use rerun::components::MarkerShape;
    let exp = run.exp;
    let nf = exp.filters.len();
    let show = shown(exp, sc);
    let styled = |suffix: &str| {
        rerun::SeriesLines::new()
            .with_colors((0..nf).map(style::filter_colour))
            .with_widths(vec![style::ESTIMATE_WIDTH; nf])
            .with_names(exp.filters.iter().map(|f| format!("{}{suffix}", f.name)))
            .with_visible_series((0..nf).map(|f| show.contains(&f)))
    };
    for tr in &sc.trajectories {
        let trial = format!("trial_{}", tr.trial);
        let n = tr.z.ncols();
        let steps: Vec<i64> = (0..n as i64).collect();
        let lost: Vec<usize> = match exp.plant.arrival() {
            Some(_) => (0..tr.modes.len()).filter(|k| tr.modes[*k] == 0).collect(),
            None => Vec::new(),
        };
        let lost_steps: Vec<i64> = lost.iter().map(|k| *k as i64).collect();
        let lost_style = marker_style(style::DROPOUT, MarkerShape::Cross, 8.0, "measurement lost");
        for j in 0..tr.z.nrows() {
            let (z, e) = (format!("z{}", j + 1), format!("e{}", j + 1));
            let at = |comp: &str, leaf: &str| run.at(&["trajectories", &sc.name, &trial, comp, leaf]);
            let truth = series_style(style::TRUTH, style::TRUTH_WIDTH, "truth");
            w.series(at(&z, "truth"), &truth, &steps, tr.z.row(j).iter().copied().collect(), 1)?;
            if let Some(nf) = &sc.noise_free {
                let s = series_style(style::NOISE_FREE, style::NOISE_FREE_WIDTH, "noise-free z");
                w.series(at(&z, "noise_free"), &s, &steps, nf.row(j).iter().copied().collect(), 1)?;
            }
            w.series(at(&z, "estimates"), &styled(""), &steps, interleave(n, nf, |k, f| tr.zhat[f][(j, k)]), nf)?;
            let err = interleave(n, nf, |k, f| tr.z[(j, k)] - tr.zhat[f][(j, k)]);
            w.series(at(&e, "errors"), &styled(" · error"), &steps, err, nf)?;
            w.series(at(&z, "dropouts"), &lost_style, &lost_steps, lost.iter().map(|k| tr.z[(j, *k)]).collect(), 1)?;
            w.series(at(&e, "dropouts"), &lost_style, &lost_steps, vec![0.0; lost.len()], 1)?;
        }
        if exp.plant.arrival().is_none() && exp.plant.switches() {
            let entity = run.at(&["trajectories", &sc.name, &trial, "mode"]);
            let s = series_style(style::MODE, style::ESTIMATE_WIDTH, "Markov mode")
                .with_interpolation_mode(rerun::components::InterpolationMode::StepAfter);
            w.series(entity, &s, &steps, tr.modes.iter().map(|m| *m as f64).collect(), 1)?;
        }
    }
    Ok(())
}

/// The exact summed error of every filter as one bar each, at the filter's place in the file, in
/// its colour; the legend names it.
fn compare(rec: &rerun::RecordingStream, run: &Run, sc: &ScenarioOutcome) -> RecResult {
    for (f, spec) in run.exp.filters.iter().enumerate() {
        let bar = rerun::BarChart::new(vec![sc.exact[f].total])
            .with_abscissa(vec![f as f64])
            .with_widths([0.8])
            .with_color(style::filter_colour(f));
        rec.log_static(run.at(&["compare", &sc.name, &spec.name]), &bar)?;
    }
    Ok(())
}

/// The iterations of iterative designs (seed 000 Algorithm 1: I(K(s)) and the gap δ(s)), one bar
/// per iteration in the filter's colour: static, so they show whatever timeline is selected.
fn design_traces(rec: &rerun::RecordingStream, run: &Run) -> RecResult {
    for (f, (spec, d)) in run.exp.filters.iter().zip(&run.out.filters).enumerate() {
        let trace = &d.design.trace;
        if trace.is_empty() {
            continue;
        }
        let x: Vec<f64> = trace.iter().map(|r| r.iteration as f64).collect();
        for (leaf, v) in [
            ("objective", trace.iter().map(|r| r.objective).collect::<Vec<f64>>()),
            ("gap", trace.iter().map(|r| r.gap).collect()),
        ] {
            let bar =
                rerun::BarChart::new(v).with_abscissa(x.clone()).with_widths([0.8]).with_color(style::filter_colour(f));
            rec.log_static(run.at(&["design", &spec.name, leaf]), &bar)?;
        }
        for ls in &d.design.line_searches {
            let width = 0.9 / (ls.tau.len().max(2) - 1) as f32;
            let rise: Vec<f64> = ls.value.iter().map(|v| v - ls.value[0]).collect();
            let bar = rerun::BarChart::new(rise)
                .with_abscissa(ls.tau.clone())
                .with_widths([width])
                .with_color(style::filter_colour(f));
            rec.log_static(run.at(&["design", &spec.name, &line_search_leaf(ls.iteration)]), &bar)?;
        }
    }
    Ok(())
}
