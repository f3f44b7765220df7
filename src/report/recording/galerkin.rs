//! Seed 004's views: the exact error over (basis, n, α) and the string's profile along ξ.

use super::run::{RecResult, Run};
use super::style;
use crate::families::galerkin::GalerkinPoint;
use crate::families::galerkin::sweep::Sweep;

/// A Galerkin filter's place in the sweep.
pub(crate) struct Point {
    pub filter: usize,
    pub basis: String,
    pub n: usize,
    pub alpha: f64,
}

/// The Galerkin filters of a run (those whose design reports its place in the sweep).
pub fn points(run: &Run) -> Vec<Point> {
    (0..run.exp.filters.len())
        .filter_map(|f| {
            let g = run.out.filters[f].design.figures.get::<GalerkinPoint>()?;
            Some(Point { filter: f, basis: g.basis.clone(), n: g.n, alpha: g.alpha })
        })
        .collect()
}

fn sorted<T: PartialOrd + Copy>(mut v: Vec<T>) -> Vec<T> {
    v.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
    v.dedup();
    v
}

/// The bases of a run's sweep, in order.
pub fn bases(pts: &[Point]) -> Vec<String> {
    let mut b: Vec<String> = pts.iter().map(|p| p.basis.clone()).collect();
    b.sort();
    b.dedup();
    b
}

pub fn write(rec: &rerun::RecordingStream, run: &Run) -> RecResult {
    let Some(model) = run.exp.string.as_ref() else { return Ok(()) };
    let pts = points(run);
    let ns = sorted(pts.iter().map(|p| p.n).collect());
    let alphas = sorted(pts.iter().map(|p| p.alpha).collect::<Vec<f64>>());
    let steps = run.exp.plant.steps() as f64;
    let sweep = run.out.findings.iter().find_map(|f| f.get::<Sweep>());
    for (i, sc) in run.out.scenarios.iter().enumerate() {
        let err = |p: &Point| sc.exact[p.filter].total / steps;
        // Grouped bars: one group per α (largest first, as the regularization weakens), one bar per
        // n inside it, one colour per α.
        for basis in bases(&pts) {
            for (g, alpha) in alphas.iter().rev().enumerate() {
                let group: Vec<&Point> = pts.iter().filter(|p| p.basis == basis && p.alpha == *alpha).collect();
                if group.is_empty() {
                    continue;
                }
                let x =
                    group.iter().map(|p| (g * (ns.len() + 1) + ns.iter().position(|n| *n == p.n).unwrap_or(0)) as f64);
                let bar = rerun::BarChart::new(group.iter().map(|p| err(p)).collect::<Vec<f64>>())
                    .with_abscissa(x.collect::<Vec<f64>>())
                    .with_color(style::filter_colour(g));
                rec.log_static(run.at(&["galerkin", &sc.name, "surface", &basis, &format!("alpha={alpha:e}")]), &bar)?;
            }
        }
        let mut table = surface_table(&pts, &ns, &alphas, &err);
        if let Some(sweep) = sweep {
            table.push_str(&optimum_and_alpha_rule(sweep, &sc.name, i, steps));
        }
        rec.log_static(run.at(&["galerkin", &sc.name, "surface_table"]), &rerun::TextDocument::from_markdown(table))?;
        // The string along ξ at every step of the first sample trial: the truth and the finest
        // filter (largest n, then smallest α) against the coarsest at the same α and basis.
        let finest = pts.iter().max_by(|a, b| a.n.cmp(&b.n).then(b.alpha.total_cmp(&a.alpha)));
        let coarsest = finest.and_then(|fin| {
            pts.iter().filter(|x| x.basis == fin.basis && x.alpha == fin.alpha && x.n < fin.n).min_by_key(|x| x.n)
        });
        let Some(tr) = sc.trajectories.first() else { continue };
        let xs = &model.outputs;
        let strip = |v: &dyn Fn(usize) -> f64| -> Vec<[f32; 2]> {
            std::iter::once([0.0, 0.0])
                .chain(xs.iter().enumerate().map(|(p, x)| [*x as f32, v(p) as f32]))
                .chain(std::iter::once([model.length as f32, 0.0]))
                .collect()
        };
        // A decimated horizon shows the string at each bucket's first step (docs/output-columns.md).
        let frames: Vec<usize> = match super::decimate::buckets(tr.z.ncols()) {
            Some(b) => b.iter().map(|r| r.start).collect(),
            None => (0..tr.z.ncols()).collect(),
        };
        for k in frames {
            rec.set_time_sequence("step", k as i64);
            let truth = rerun::LineStrips2D::new([strip(&|p| tr.z[(p, k)])])
                .with_colors([style::TRUTH])
                .with_radii([rerun::Radius::new_ui_points(1.5)]);
            rec.log(run.at(&["galerkin", &sc.name, "string", "truth"]), &truth)?;
            for p in finest.into_iter().chain(coarsest) {
                let est = rerun::LineStrips2D::new([strip(&|q| tr.zhat[p.filter][(q, k)])])
                    .with_colors([style::filter_colour(p.filter)])
                    .with_radii([rerun::Radius::new_ui_points(1.0)]);
                rec.log(run.at(&["galerkin", &sc.name, "string", &run.exp.filters[p.filter].name]), &est)?;
            }
        }
        rec.reset_time();
    }
    Ok(())
}

/// Below the surface: m(z) (a `kalman` filter on the string is the Kalman filter of the exact
/// truth, seed 004 Theorem 3's optimum) with the gap of the best Galerkin filter to it, and per
/// (basis, n) the α the discrepancy principle chooses from one record against the sweep's best
/// ([`Sweep`], computed by the pipeline).
fn optimum_and_alpha_rule(sweep: &Sweep, scenario: &str, i: usize, steps: f64) -> String {
    let mut s = String::new();
    for o in sweep.optimum.iter().filter(|o| o.scenario == scenario) {
        s.push_str(&format!(
            "\n**m(z)** (`{}`, the Kalman filter of the exact truth): {:.6}; the best Galerkin filter is {:.3e} above it (relative)\n",
            o.filter, o.error, o.best_galerkin_gap
        ));
    }
    for r in &sweep.alpha_rule {
        let (basis, n) = (&r.basis, r.n);
        let (best, best_alpha) = r.best[i];
        match (&r.choice, &r.refused) {
            (Some(c), _) => s.push_str(&format!(
                "\n{basis}, n = {n}: the discrepancy principle picks α = {:.2e} (D = {} on the sweep's α), exact error {:.6} at the nominal covariances; the sweep's smallest is {best:.6} at α = {best_alpha:e}\n",
                c.alpha,
                c.discrepancy.iter().map(|d| format!("{d:.3}")).collect::<Vec<_>>().join(", "),
                c.exact / steps,
            )),
            (None, e) => s.push_str(&format!("\n{basis}, n = {n}: no α by the discrepancy principle: {}\n", e.as_deref().unwrap_or("?"))),
        }
    }
    s
}

/// Rows (basis, n), columns α: the time-averaged exact error, the README's error surface.
fn surface_table(pts: &[Point], ns: &[usize], alphas: &[f64], err: &dyn Fn(&Point) -> f64) -> String {
    let mut s =
        String::from("### exact error, time-averaged (Σ_k E|u − û|² over the points, / steps)\n\n| basis | n |");
    for a in alphas.iter().rev() {
        s.push_str(&format!(" α = {a:e} |"));
    }
    s.push_str("\n|---|---:|");
    s.push_str(&"---:|".repeat(alphas.len()));
    s.push('\n');
    for basis in bases(pts) {
        for n in ns {
            s.push_str(&format!("| {basis} | {n} |"));
            for a in alphas.iter().rev() {
                match pts.iter().find(|p| p.basis == basis && p.n == *n && p.alpha == *a) {
                    Some(p) => s.push_str(&format!(" {:.6} |", err(p))),
                    None => s.push_str(" |"),
                }
            }
            s.push('\n');
        }
    }
    s
}
