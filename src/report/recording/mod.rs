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
mod decimate;
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
    for run in &runs {
        let mut w = Writer { rec: &rec, pending: Vec::new(), buckets: decimate::buckets(run.exp.plant.steps()) };
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
    /// The run's buckets of steps when its horizon is decimated for display ([`decimate`]).
    buckets: Option<Vec<std::ops::Range<usize>>>,
}

/// The envelope of a decimated series: per instance its colour (drawn faded and thin) and name.
#[derive(Clone)]
struct Envelope {
    colours: Vec<style::Rgba>,
    names: Vec<String>,
    visible: Option<Vec<bool>>,
}

impl Envelope {
    fn one(colour: style::Rgba, name: &str) -> Self {
        Envelope { colours: vec![colour], names: vec![name.to_string()], visible: None }
    }
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

    /// A per-step series of `rows` rows of `per_row` instances (`value(k, i)`): written whole when the
    /// horizon is not decimated, else one row per bucket with each instance's bucket mean (or the
    /// minimum or maximum `how` asks for) and, with `envelope`, the buckets' minimum and maximum
    /// of every instance in the child entity `envelope`.
    #[allow(clippy::too_many_arguments)]
    fn per_step(
        &mut self,
        entity: String,
        style: &dyn rerun::AsComponents,
        rows: usize,
        per_row: usize,
        value: impl Fn(usize, usize) -> f64,
        how: Option<&[decimate::Reduce]>,
        envelope: Option<Envelope>,
    ) -> RecResult {
        let Some(buckets) = self.buckets.clone().filter(|b| b.last().is_some_and(|r| r.end == rows)) else {
            let steps: Vec<i64> = (0..rows as i64).collect();
            return self.series(entity, style, &steps, interleave(rows, per_row, value), per_row);
        };
        let steps: Vec<i64> = buckets.iter().map(|r| r.start as i64).collect();
        let mut line = Vec::with_capacity(buckets.len() * per_row);
        let mut edges = Vec::with_capacity(buckets.len() * 2 * per_row);
        for r in &buckets {
            for i in 0..per_row {
                let (mean, lo, hi) = decimate::reduce(r.clone(), |k| value(k, i));
                line.push(match how.map_or(decimate::Reduce::Mean, |h| h[i]) {
                    decimate::Reduce::Mean => mean,
                    decimate::Reduce::Min => lo,
                    decimate::Reduce::Max => hi,
                });
                edges.extend([lo, hi]);
            }
        }
        self.series(entity.clone(), style, &steps, line, per_row)?;
        if let Some(env) = envelope {
            let twice = |v: &[style::Rgba]| v.iter().flat_map(|c| [style::faded(*c); 2]).collect::<Vec<_>>();
            let mut s = rerun::SeriesLines::new()
                .with_colors(twice(&env.colours))
                .with_widths(vec![style::BAND_WIDTH; 2 * per_row])
                // The line's own name: one legend entry per series, as for the band.
                .with_names(env.names.iter().flat_map(|n| [n.clone(), n.clone()]));
            if let Some(v) = env.visible {
                s = s.with_visible_series(v.iter().flat_map(|b| [*b, *b]));
            }
            self.series(format!("{entity}/envelope"), &s, &steps, edges, 2 * per_row)?;
        }
        Ok(())
    }

    /// Markers at `marked` steps (lost measurements): every one, or one per bucket holding any, at
    /// the bucket's step and the value of its first.
    fn markers(
        &mut self,
        entity: String,
        style: &dyn rerun::AsComponents,
        marked: &[usize],
        value: impl Fn(usize) -> f64,
    ) -> RecResult {
        let kept: Vec<(i64, usize)> = match &self.buckets {
            None => marked.iter().map(|k| (*k as i64, *k)).collect(),
            Some(b) => {
                let mut out: Vec<(i64, usize)> = Vec::new();
                let mut bi = 0;
                for k in marked {
                    while b[bi].end <= *k {
                        bi += 1;
                    }
                    if out.last().is_none_or(|(s, _)| *s != b[bi].start as i64) {
                        out.push((b[bi].start as i64, *k));
                    }
                }
                out
            }
        };
        let steps: Vec<i64> = kept.iter().map(|(s, _)| *s).collect();
        self.series(entity, style, &steps, kept.iter().map(|(_, k)| value(*k)).collect(), 1)
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
        let at = |leaf: &str| run.at(&["mse", &sc.name, name, leaf]);
        // The mean, its band and the exact dots share the filter's name, so the legend has one
        // entry per filter (the view's title says which mark is which) and leaves the curves visible.
        let emp = rerun::SeriesLines::new()
            .with_colors([c, style::faded(c), style::faded(c)])
            .with_widths([style::EMPIRICAL_WIDTH, style::BAND_WIDTH, style::BAND_WIDTH])
            .with_names([name; 3]);
        // Decimated, the band's edges are the buckets' extremes: it covers every step's band.
        let band = [decimate::Reduce::Mean, decimate::Reduce::Min, decimate::Reduce::Max];
        let value = |k: usize, i: usize| {
            let w = st.at(k);
            [w.mean, w.ci95().0, w.ci95().1][i]
        };
        w.per_step(at("empirical"), &emp, st.len(), 3, value, Some(&band), None)?;
        let exact = marker_style(c, MarkerShape::Circle, 1.5, name);
        let ex = &sc.exact[f].per_step;
        w.per_step(at("exact"), &exact, ex.len(), 1, |k, _| ex[k], None, Some(Envelope::one(c, name)))?;
        if let Some(p) = &sc.filters[f].promise {
            let entity = run.at(&["promise", &sc.name, name, p.label()]);
            let label = format!("{name} · {}", p.label());
            let s = series_style(c, style::EXACT_WIDTH, &label);
            let v = p.values();
            w.per_step(entity, &s, v.len(), 1, |k, _| v[k], None, Some(Envelope::one(c, &label)))?;
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
    let every = Envelope {
        colours: (0..nf).map(style::filter_colour).collect(),
        names: exp.filters.iter().map(|f| f.name.clone()).collect(),
        visible: Some((0..nf).map(|f| show.contains(&f)).collect()),
    };
    for tr in &sc.trajectories {
        let trial = format!("trial_{}", tr.trial);
        let n = tr.z.ncols();
        let lost: Vec<usize> = match exp.plant.arrival() {
            Some(_) => (0..tr.modes.len()).filter(|k| tr.modes[*k] == 0).collect(),
            None => Vec::new(),
        };
        let lost_style = marker_style(style::DROPOUT, MarkerShape::Cross, 8.0, "measurement lost");
        for j in 0..tr.z.nrows() {
            let (z, e) = (format!("z{}", j + 1), format!("e{}", j + 1));
            let at = |comp: &str, leaf: &str| run.at(&["trajectories", &sc.name, &trial, comp, leaf]);
            let truth = series_style(style::TRUTH, style::TRUTH_WIDTH, "truth");
            let env = Some(Envelope::one(style::TRUTH, "truth"));
            w.per_step(at(&z, "truth"), &truth, n, 1, |k, _| tr.z[(j, k)], None, env)?;
            if let Some(nfz) = &sc.noise_free {
                let s = series_style(style::NOISE_FREE, style::NOISE_FREE_WIDTH, "noise-free z");
                let env = Some(Envelope::one(style::NOISE_FREE, "noise-free z"));
                w.per_step(at(&z, "noise_free"), &s, n, 1, |k, _| nfz[(j, k)], None, env)?;
            }
            let est = |k: usize, f: usize| tr.zhat[f][(j, k)];
            w.per_step(at(&z, "estimates"), &styled(""), n, nf, est, None, Some(every.clone()))?;
            let err = |k: usize, f: usize| tr.z[(j, k)] - tr.zhat[f][(j, k)];
            let env =
                Envelope { names: every.names.iter().map(|m| format!("{m} · error")).collect(), ..every.clone() };
            w.per_step(at(&e, "errors"), &styled(" · error"), n, nf, err, None, Some(env))?;
            w.markers(at(&z, "dropouts"), &lost_style, &lost, |k| tr.z[(j, k)])?;
            w.markers(at(&e, "dropouts"), &lost_style, &lost, |_| 0.0)?;
        }
        if exp.plant.arrival().is_none() && exp.plant.switches() {
            let entity = run.at(&["trajectories", &sc.name, &trial, "mode"]);
            let s = series_style(style::MODE, style::ESTIMATE_WIDTH, "Markov mode")
                .with_interpolation_mode(rerun::components::InterpolationMode::StepAfter);
            let env = Some(Envelope::one(style::MODE, "Markov mode"));
            w.per_step(entity, &s, tr.modes.len(), 1, |k, _| tr.modes[k] as f64, None, env)?;
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
