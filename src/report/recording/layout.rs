//! The default layout: an overview tab (the summary tables), then one tab per variant holding one
//! tab per scenario (or the scenario tabs directly when the file has no variants). A scenario tab:
//!
//! - top row: the per-step MSE (empirical with its 95 % band, exact as dots) from step 1 on, so the
//!   initial transient does not squash the curves; the promises (guaranteed bounds or claims)
//!   against the exact error; the exact summed error per filter as bars beside the scenario's table;
//! - bottom row: the first sample trial's truth and estimates of z₁ (and z₂), with lost
//!   measurements marked and, with a known input, the noise-free z, and the matching errors; for a string, its profile along ξ and the error
//!   surface over (basis, n, α) instead.
//!
//! Experiments with iterative designs get a `design` tab. Large experiments show at most
//! [`super::MAX_SHOWN`] filters per per-step view (the best by exact error; the view's title says so).

use rerun::external::re_sdk_types::blueprint::components::{ContainerKind, Corner2D};

use super::blueprint::{Layout, Node, ViewKind};
use super::galerkin;
use super::run::{APP, Run, line_search_leaf, shown};
use crate::pipeline::ScenarioOutcome;

type BpResult<T> = std::result::Result<T, Box<dyn std::error::Error + Send + Sync>>;

/// Trajectory components shown by default (each is a pair of views).
const COMPONENTS_SHOWN: usize = 2;

/// Horizons at least this long hide step 0 in the per-step views.
const MIN_STEPS_TO_SKIP_TRANSIENT: usize = 10;

fn plus(path: &str) -> String {
    format!("+ /{path}")
}

/// The entity and, when the run's horizon is decimated for display, its min/max envelope.
fn plus_env(run: &Run, path: &str) -> Vec<String> {
    let mut v = vec![plus(path)];
    if super::decimate::buckets(run.exp.plant.steps()).is_some() {
        v.push(plus(&format!("{path}/envelope")));
    }
    v
}

fn plus_tree(path: &str) -> String {
    format!("+ /{path}/**")
}

/// Builds the layout of every run and sends it into `rec`.
pub(crate) fn send(rec: &rerun::RecordingStream, runs: &[Run]) -> BpResult<()> {
    let mut l = Layout::new(APP)?;
    let mut tabs = vec![overview(&mut l, runs)?];
    for run in runs {
        let inner = run_tabs(&mut l, run)?;
        match &run.exp.variant {
            Some(v) => tabs.push(l.container(ContainerKind::Tabs, &format!("variant {v}"), &inner)?),
            None => tabs.extend(inner),
        }
    }
    let name = runs.first().map_or("filterbench", |r| r.exp.name.as_str());
    let root = l.container(ContainerKind::Tabs, name, &tabs)?;
    l.send(&root, runs.iter().any(|r| r.exp.string.is_some()), rec)
}

fn overview(l: &mut Layout, runs: &[Run]) -> BpResult<Node> {
    let docs: Vec<Node> = runs
        .iter()
        .map(|r| {
            let name = r.exp.variant.as_ref().map_or("summary".to_string(), |v| format!("summary · {v}"));
            l.view(ViewKind::TextDocument, &name, &[plus(&r.at(&["summary"]))])
        })
        .collect::<BpResult<_>>()?;
    if docs.len() == 1 {
        return Ok(docs.into_iter().next().expect("one"));
    }
    l.container(ContainerKind::Tabs, "overview", &docs)
}

fn run_tabs(l: &mut Layout, run: &Run) -> BpResult<Vec<Node>> {
    let mut tabs = Vec::new();
    for sc in &run.out.scenarios {
        tabs.push(scenario(l, run, sc)?);
    }
    if run.out.filters.iter().any(|d| !d.design.trace.is_empty()) {
        tabs.push(design(l, run)?);
    }
    Ok(tabs)
}

fn scenario(l: &mut Layout, run: &Run, sc: &ScenarioOutcome) -> BpResult<Node> {
    let exp = run.exp;
    let show = shown(exp, sc);
    let of = if show.len() < exp.filters.len() {
        format!(" ({} best of {} filters by exact error)", show.len(), exp.filters.len())
    } else {
        String::new()
    };
    let mse_at = |f: usize| run.at(&["mse", &sc.name, &exp.filters[f].name]);
    let mse_contents: Vec<String> = show.iter().map(|f| plus_tree(&mse_at(*f))).collect();
    // Step 0's error is the prior's and can dwarf the rest, so long horizons start at step 1; a
    // short one (seed 000's examples have three steps) keeps every step. Mean-square errors settle
    // high in the plot: the empty corner is at the bottom.
    let from_step = (exp.plant.steps() >= MIN_STEPS_TO_SKIP_TRANSIENT).then_some(1);
    let last_step = exp.plant.horizon as i64;
    let per_step = || ViewKind::TimeSeries { from_step, last_step, legend: Corner2D::RightBottom };
    let from = if from_step.is_some() { " from step 1" } else { "" };
    // A decimated horizon says so (docs/output-columns.md): each point is a bucket of steps.
    let of = match super::decimate::buckets(exp.plant.steps()) {
        Some(b) => format!("{of}; per bucket of {} steps: mean, band from the min to the max", b[1].len()),
        None => of,
    };
    let mut top = vec![l.view(
        per_step(),
        &format!("per-step MSE{from}: empirical (thick) with 95 % band (thin), exact (dots){of}"),
        &mse_contents,
    )?];
    let promised: Vec<String> = show
        .iter()
        .filter_map(|f| {
            let p = sc.filters[*f].promise.as_ref()?;
            let exact = plus_env(run, &format!("{}/exact", mse_at(*f)));
            Some([exact, plus_env(run, &run.at(&["promise", &sc.name, &exp.filters[*f].name, p.label()]))].concat())
        })
        .flatten()
        .collect();
    if !promised.is_empty() {
        top.push(l.view(
            per_step(),
            "per-step promise (guaranteed bound or claimed error, lines) vs exact (dots)",
            &promised,
        )?);
    }
    let bars = l.view(
        ViewKind::BarChart,
        "exact summed error per filter, in the table's order",
        &[plus_tree(&run.at(&["compare", &sc.name]))],
    )?;
    let table = l.view(ViewKind::TextDocument, "summed figures", &[plus(&run.at(&["tables", &sc.name]))])?;
    top.push(l.container(ContainerKind::Vertical, "summed", &[bars, table])?);
    // The table of the summed figures needs about as much width as a plot.
    let shares: Vec<f32> = top.iter().enumerate().map(|(i, _)| if i + 1 == top.len() { 1.3 } else { 1.0 }).collect();
    let top = l.container_with_shares(ContainerKind::Horizontal, "per step", &top, &shares)?;
    let bottom = if exp.string.is_some() { string_row(l, run, sc)? } else { trajectory_row(l, run, sc)? };
    let mut rows = vec![top];
    rows.extend(bottom);
    l.container(ContainerKind::Vertical, &sc.name, &rows)
}

/// The first sample trial: truth and estimates of each shown component, and the errors.
fn trajectory_row(l: &mut Layout, run: &Run, sc: &ScenarioOutcome) -> BpResult<Option<Node>> {
    let Some(tr) = sc.trajectories.first() else { return Ok(None) };
    let exp = run.exp;
    let trial = format!("trial_{}", tr.trial);
    let nf_title = if sc.noise_free.is_some() { ", noise-free z (grey)" } else { "" };
    let mut views = Vec::new();
    for j in 0..tr.z.nrows().min(COMPONENTS_SHOWN) {
        let (z, e) = (format!("z{}", j + 1), format!("e{}", j + 1));
        let at = |comp: &str, leaf: &str| run.at(&["trajectories", &sc.name, &trial, comp, leaf]);
        // The estimates of the filters not shown are in the same entities, hidden series.
        let mut zc = [plus_env(run, &at(&z, "truth")), plus_env(run, &at(&z, "estimates"))].concat();
        zc.push(plus(&at(&z, "dropouts")));
        if sc.noise_free.is_some() {
            zc.extend(plus_env(run, &at(&z, "noise_free")));
        }
        let mut ec = plus_env(run, &at(&e, "errors"));
        ec.push(plus(&at(&e, "dropouts")));
        if exp.plant.arrival().is_none() && exp.plant.switches() {
            zc.extend(plus_env(run, &run.at(&["trajectories", &sc.name, &trial, "mode"])));
        }
        let of = if tr.z.nrows() > COMPONENTS_SHOWN { format!(" of {}", tr.z.nrows()) } else { String::new() };
        views.push(l.view(
            ViewKind::TimeSeries { from_step: None, last_step: exp.plant.horizon as i64, legend: Corner2D::RightTop },
            &format!("trial {}: {z}{of}, truth{} and estimates", tr.trial, nf_title),
            &zc,
        )?);
        views.push(l.view(
            ViewKind::TimeSeries { from_step: None, last_step: exp.plant.horizon as i64, legend: Corner2D::RightTop },
            &format!("trial {}: error {z} − ẑ", tr.trial),
            &ec,
        )?);
    }
    Ok(Some(l.container(ContainerKind::Horizontal, "sample trial", &views)?))
}

/// A string's first sample trial along ξ (move the time cursor to see it move), and the error
/// surface over (basis, n, α) as grouped bars and as a table.
fn string_row(l: &mut Layout, run: &Run, sc: &ScenarioOutcome) -> BpResult<Option<Node>> {
    let base = |rest: &[&str]| run.at(&[&["galerkin", sc.name.as_str()], rest].concat());
    let mut views = vec![l.view(
        ViewKind::Spatial2D,
        "string u(ξ) at the time cursor: truth (grey), finest and coarsest filters",
        &[plus_tree(&base(&["string"]))],
    )?];
    for basis in galerkin::bases(&galerkin::points(run)) {
        views.push(l.view(
            ViewKind::BarChart,
            &format!("{basis} basis: exact error, groups α (large to small), bars n (small to large)"),
            &[plus_tree(&base(&["surface", &basis]))],
        )?);
    }
    views.push(l.view(ViewKind::TextDocument, "error surface", &[plus(&base(&["surface_table"]))])?);
    Ok(Some(l.container(ContainerKind::Horizontal, "string and error surface", &views)?))
}

/// Iterative designs: the objective and the gap per iteration and, below, the objective along each
/// kept line search (seed 000 Fig. 1), one view per search s with every filter that has it.
fn design(l: &mut Layout, run: &Run) -> BpResult<Node> {
    let mut obj = Vec::new();
    let mut gap = Vec::new();
    // Per search s: the entities, and the start values I(K(s))/N of the filters that have it.
    let mut searches: std::collections::BTreeMap<usize, (Vec<String>, Vec<String>)> = Default::default();
    for (spec, d) in run.exp.filters.iter().zip(&run.out.filters) {
        if !d.design.trace.is_empty() {
            obj.push(plus(&run.at(&["design", &spec.name, "objective"])));
            gap.push(plus(&run.at(&["design", &spec.name, "gap"])));
        }
        for ls in &d.design.line_searches {
            let leaf = line_search_leaf(ls.iteration);
            let entry = searches.entry(ls.iteration).or_default();
            entry.0.push(plus(&run.at(&["design", &spec.name, &leaf])));
            entry.1.push(format!("{} {:.4}", spec.name, ls.value[0]));
        }
    }
    let top = vec![
        l.view(ViewKind::BarChart, "design: objective per iteration (minimax: I(K(s)))", &obj)?,
        l.view(ViewKind::BarChart, "design: gap per iteration (minimax: δ(s))", &gap)?,
    ];
    if searches.is_empty() {
        return l.container(ContainerKind::Horizontal, "design", &top);
    }
    let top = l.container(ContainerKind::Horizontal, "design: iterations", &top)?;
    let lines = searches
        .iter()
        .map(|(s, (contents, starts))| {
            let fig = if *s == 1 { "Fig. 1 of seed 000: " } else { "" };
            let name = format!(
                "{fig}I/N along line search s = {s} against τ from 0 to 1, less I/N at τ = 0 ({})",
                starts.join(", ")
            );
            l.view(ViewKind::BarChart, &name, contents)
        })
        .collect::<BpResult<Vec<_>>>()?;
    let bottom = l.container(ContainerKind::Horizontal, "design: line searches", &lines)?;
    l.container(ContainerKind::Vertical, "design", &[top, bottom])
}
