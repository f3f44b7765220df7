//! The Monte Carlo engine: every filter of the experiment on the same draws (common random
//! numbers), trials in parallel with rayon, streaming per-step accumulators.
//!
//! Trials are cut into fixed blocks of [`BLOCK`] trials. A block runs sequentially into its own
//! accumulators; blocks run in parallel; their accumulators are merged in block order. Together
//! with per-trial random streams ([`trial_rng`]) this makes every figure bit-identical for any
//! number of threads. Memory is O(filters × steps), independent of the number of trials.

use rayon::prelude::*;

use crate::analysis::exact::ErrorForm;
use crate::filter::design::PerTrialBound;
use crate::filter::realization::Realization;
use crate::model::plant::Plant;
use crate::numerics::linalg::{Mat, Vector};
use crate::sim::noise::{NoiseSampler, TrialDraw, trial_rng};
pub use crate::sim::plant_ops::PlantOps;
use crate::sim::stats::Welford;

/// Trials per block: the unit of parallel work and of the fixed reduction order.
pub const BLOCK: u64 = 64;

/// Per-filter statistics of one scenario.
#[derive(Clone, Debug, PartialEq)]
pub struct FilterStats {
    /// Summed squared error J over the steps that count, one value per trial.
    pub total: Welford,
    /// Squared error |z[k] − ẑ[k]|² at each step.
    pub steps: Vec<Welford>,
    /// For a filter with a per-trial bound: the largest ratio seen and the trials at or above it.
    pub max_ratio: f64,
    pub violations: u64,
    /// e[k]ᵀ W[k] e[k] at each step, for a filter with a claimed covariance ([`crate::analysis::nees`]);
    /// empty otherwise (and at a step without a weight the accumulator stays empty).
    pub nees: Vec<Welford>,
}

/// Everything one scenario's Monte Carlo run accumulates.
#[derive(Clone, Debug, PartialEq)]
pub struct McStats {
    pub filters: Vec<FilterStats>,
    /// Paired differences J_i − J_j of the summed error on the same draws, for i < j, in the order
    /// (0,1), (0,2), …, (1,2), …: their CI is much narrower than that of either mean.
    pub paired: Vec<Welford>,
}

impl McStats {
    fn new(sc: &Scenario) -> Self {
        let (nf, steps) = (sc.filters.len(), sc.plant.steps());
        McStats {
            filters: (0..nf)
                .map(|f| FilterStats {
                    total: Welford::default(),
                    steps: vec![Welford::default(); steps],
                    max_ratio: 0.0,
                    violations: 0,
                    nees: if sc.nees_weights(f).is_some() { vec![Welford::default(); steps] } else { Vec::new() },
                })
                .collect(),
            paired: vec![Welford::default(); nf * nf.saturating_sub(1) / 2],
        }
    }
    fn merge(&mut self, o: &McStats) {
        for (a, b) in self.filters.iter_mut().zip(&o.filters) {
            a.total.merge(&b.total);
            a.max_ratio = a.max_ratio.max(b.max_ratio);
            a.violations += b.violations;
            for (x, y) in a.steps.iter_mut().zip(&b.steps).chain(a.nees.iter_mut().zip(&b.nees)) {
                x.merge(y);
            }
        }
        for (a, b) in self.paired.iter_mut().zip(&o.paired) {
            a.merge(b);
        }
    }
    /// The pairs (i, j) in the order of `paired`.
    pub fn pairs(nf: usize) -> Vec<(usize, usize)> {
        (0..nf).flat_map(|i| (i + 1..nf).map(move |j| (i, j))).collect()
    }
}

/// What the engine needs to run one scenario.
pub struct Scenario<'a> {
    pub plant: &'a Plant,
    /// The plant's matrices as the trial loop applies them.
    pub ops: &'a PlantOps,
    pub filters: &'a [&'a Realization],
    pub sampler: &'a NoiseSampler,
    pub seed: u64,
    pub index: usize,
    /// Per-trial ratio checks (seed 002), if any filter has one.
    pub ratios: Option<&'a RatioCheck<'a>>,
    /// Per filter, the NEES weights W[k] of a filter with a claimed covariance (empty: none).
    pub nees: &'a [Option<Vec<Option<Mat>>>],
    /// Per filter, its error form when it is simulated in error coordinates ε = s − M x (the plant's
    /// state is then never differenced); empty or None: the filter's own state s.
    pub forms: &'a [Option<ErrorForm>],
}

impl Scenario<'_> {
    fn nees_weights(&self, f: usize) -> Option<&[Option<Mat>]> {
        self.nees.get(f)?.as_deref()
    }
    fn form(&self, f: usize) -> Option<&ErrorForm> {
        self.forms.get(f).and_then(Option::as_ref)
    }
}

/// The weights of the input energy (R⁻¹ for x0 − E x0, G⁻¹ for w[k], k < N) and, per filter, its
/// per-trial bound, if it has one.
pub struct RatioCheck<'a> {
    pub x0_weight: Mat,
    pub w_weight: Mat,
    pub bounds: Vec<Option<&'a PerTrialBound>>,
}

/// Preallocated per-thread buffers: one trial allocates nothing.
pub struct Workspace {
    draw: TrialDraw,
    x: Vector,
    x_next: Vector,
    y: Vector,
    z: Vector,
    zhat: Vector,
    /// e = z − ẑ of the current filter and step.
    err: Vector,
    s: Vec<Vector>,
    s_next: Vec<Vector>,
    e0: Vector,
    wtmp: Vector,
    /// e_z[k] of every filter (column k), kept only when a per-trial check needs the whole path.
    ez: Vec<Mat>,
    energy: Vec<f64>,
    ztmp: Vector,
}

impl Workspace {
    pub fn new(sc: &Scenario) -> Self {
        let p = sc.plant;
        Workspace {
            draw: sc.sampler.workspace(),
            x: Vector::zeros(p.nx()),
            x_next: Vector::zeros(p.nx()),
            y: Vector::zeros(p.ny()),
            z: Vector::zeros(p.nz()),
            zhat: Vector::zeros(p.nz()),
            err: Vector::zeros(p.nz()),
            s: sc.filters.iter().map(|r| r.s0.clone()).collect(),
            s_next: sc.filters.iter().map(|r| r.s0.clone()).collect(),
            e0: Vector::zeros(p.nx()),
            wtmp: Vector::zeros(p.nw()),
            ez: if sc.ratios.is_some() { vec![Mat::zeros(p.nz(), p.steps()); sc.filters.len()] } else { Vec::new() },
            energy: vec![0.0; p.steps()],
            ztmp: Vector::zeros(p.nz()),
        }
    }
}

/// Runs trial `trial`: draws its noise, simulates the plant, runs every filter on the same y, and
/// calls `visit(k, f, z, ẑ, e)` for each step k and filter f, e = z − ẑ. A filter with an error
/// form carries ε = s − M x instead of s and gets e from ε and w directly (seed-independent
/// identity of [`crate::analysis::exact::error_form`]); its ẑ is then z − e, for display only.
#[inline]
pub fn run_trial(
    sc: &Scenario,
    ws: &mut Workspace,
    trial: u64,
    mut visit: impl FnMut(usize, usize, &Vector, &Vector, &Vector),
) {
    let mut rng = trial_rng(sc.seed, sc.index, trial);
    sc.sampler.draw_into(&mut rng, &mut ws.draw);
    let p = sc.plant;
    ws.x.copy_from(&ws.draw.x0);
    for (f, (s, r)) in ws.s.iter_mut().zip(sc.filters).enumerate() {
        s.copy_from(&r.s0);
        if let Some(form) = sc.form(f) {
            s.gemv(-1.0, &form.m, &ws.x, 1.0);
        }
    }
    for k in 0..p.steps() {
        let wk = ws.draw.w.column(k);
        let theta = ws.draw.modes[k];
        let ops = sc.ops;
        ops.c(k, theta).apply(1.0, &ws.x, 0.0, &mut ws.y);
        ops.d(k, theta).apply(1.0, &wk, 1.0, &mut ws.y);
        ops.ops[ops.cz[k]].apply(1.0, &ws.x, 0.0, &mut ws.z);
        ops.ops[ops.dz[k]].apply(1.0, &wk, 1.0, &mut ws.z);
        if !ops.factors.is_empty() {
            let zeta = &ws.draw.zeta;
            ops.add_factors(2, k, zeta, &ws.x, &mut ws.y);
            ops.add_factors(3, k, zeta, &wk, &mut ws.y);
            ops.add_factors(4, k, zeta, &ws.x, &mut ws.z);
            ops.add_factors(5, k, zeta, &wk, &mut ws.z);
        }
        let r = p.r_at(k);
        for (f, real) in sc.filters.iter().enumerate() {
            let form = sc.form(f).map(|form| &form.steps[k][theta]);
            match form {
                None => {
                    real.output(k, theta, &ws.s[f], &ws.y, &mut ws.zhat);
                    ws.err.copy_from(&ws.z);
                    ws.err -= &ws.zhat;
                }
                Some(a) => {
                    ws.err.gemv(1.0, &a.h, &ws.s[f], 0.0);
                    ws.err.gemv(1.0, &a.g, &wk, 1.0);
                    ws.zhat.copy_from(&ws.z);
                    ws.zhat -= &ws.err;
                }
            }
            visit(k, f, &ws.z, &ws.zhat, &ws.err);
            if let Some(ez) = ws.ez.get_mut(f) {
                ez.column_mut(k).copy_from(&ws.err);
            }
            if k < p.horizon {
                match form {
                    None => real.advance(k, theta, &ws.s[f], &ws.y, r, &mut ws.s_next[f]),
                    Some(a) => {
                        let next = &mut ws.s_next[f];
                        next.gemv(1.0, &a.f, &ws.s[f], 0.0);
                        next.gemv(1.0, &a.e, &wk, 1.0);
                        if let Some(r) = r {
                            next.gemv(1.0, &a.r_map, r, 1.0);
                        }
                    }
                }
                std::mem::swap(&mut ws.s[f], &mut ws.s_next[f]);
            }
        }
        if k < p.horizon {
            ops.a(k, theta).apply(1.0, &ws.x, 0.0, &mut ws.x_next);
            ops.b(k, theta).apply(1.0, &wk, 1.0, &mut ws.x_next);
            if !ops.factors.is_empty() {
                ops.add_factors(0, k, &ws.draw.zeta, &ws.x, &mut ws.x_next);
                ops.add_factors(1, k, &ws.draw.zeta, &wk, &mut ws.x_next);
            }
            if let Some(r) = r {
                ws.x_next += r;
            }
            std::mem::swap(&mut ws.x, &mut ws.x_next);
        }
    }
}

/// Seed 002's per-trial promises for every filter that has one (the workspace still holds the
/// trial's draws, its errors e_z[k] and the final states). Energies are prefix sums E_t.
fn check_ratios(sc: &Scenario, rc: &RatioCheck, ws: &mut Workspace, plant: &Plant, stats: &mut [FilterStats]) {
    ws.e0.copy_from(&ws.draw.x0);
    ws.e0 -= &plant.x0_mean;
    ws.x_next.gemv(1.0, &rc.x0_weight, &ws.e0, 0.0);
    ws.energy[0] = ws.e0.dot(&ws.x_next);
    for k in 0..plant.horizon {
        let wk = ws.draw.w.column(k);
        ws.wtmp.gemv(1.0, &rc.w_weight, &wk, 0.0);
        ws.energy[k + 1] = ws.energy[k] + wk.dot(&ws.wtmp);
    }
    for (f, b) in rc.bounds.iter().enumerate() {
        match b {
            None => {}
            Some(PerTrialBound::Ratio { bound, terminal_weight }) => {
                let sum: f64 = (0..plant.horizon).map(|k| ws.ez[f].column(k).norm_squared()).sum();
                // e = x − s; in error coordinates x − s = (I − M) x − ε, = −ε for M = I.
                match sc.form(f) {
                    None => ws.e0.copy_from(&ws.x),
                    Some(form) if form.identity => ws.e0.fill(0.0),
                    Some(form) => {
                        ws.e0.copy_from(&ws.x);
                        ws.e0.gemv(-1.0, &form.m, &ws.x, 1.0);
                    }
                }
                ws.e0 -= &ws.s[f];
                ws.x_next.gemv(1.0, terminal_weight, &ws.e0, 0.0);
                let ratio = (sum + ws.e0.dot(&ws.x_next)) / ws.energy[plant.horizon];
                stats[f].max_ratio = stats[f].max_ratio.max(ratio);
                if ratio >= *bound {
                    stats[f].violations += 1;
                }
            }
            Some(PerTrialBound::Ellipsoid { weights }) => {
                let mut broke = false;
                for (k, q) in weights.iter().enumerate() {
                    let e = ws.ez[f].column(k);
                    ws.ztmp.gemv(1.0, q, &e, 0.0);
                    let ratio = e.dot(&ws.ztmp) / ws.energy[k];
                    stats[f].max_ratio = stats[f].max_ratio.max(ratio);
                    // Equality is attained by the worst input: allow rounding only.
                    broke |= ratio > 1.0 + 1e-9;
                }
                stats[f].violations += broke as u64;
            }
        }
    }
}

/// eᵀ W e.
fn weighted_square(w: &Mat, e: &Vector) -> f64 {
    let n = e.len();
    let mut q = 0.0;
    for j in 0..n {
        for i in 0..n {
            q += e[i] * w[(i, j)] * e[j];
        }
    }
    q
}

fn squared_error(e: &Vector) -> f64 {
    e.iter().map(|v| v * v).sum()
}

fn run_block(sc: &Scenario, ws: &mut Workspace, first: u64, last: u64) -> McStats {
    let nf = sc.filters.len();
    let mut st = McStats::new(sc);
    let pairs = McStats::pairs(nf);
    let plant = sc.plant;
    let mut totals = vec![0.0; nf];
    for t in first..last {
        totals.fill(0.0);
        let per_filter = &mut st.filters;
        run_trial(sc, ws, t, |k, f, _, _, e| {
            let e2 = squared_error(e);
            per_filter[f].steps[k].push(e2);
            if let Some(Some(w)) = sc.nees_weights(f).map(|ws| &ws[k]) {
                per_filter[f].nees[k].push(weighted_square(w, e));
            }
            if plant.counts(k) {
                totals[f] += e2;
            }
        });
        if let Some(rc) = sc.ratios {
            check_ratios(sc, rc, ws, plant, &mut st.filters);
        }
        for (acc, v) in st.filters.iter_mut().zip(&totals) {
            acc.total.push(*v);
        }
        for (acc, &(i, j)) in st.paired.iter_mut().zip(&pairs) {
            acc.push(totals[i] - totals[j]);
        }
    }
    st
}

/// Blocks run in parallel per wave; a wave's results are merged before the next starts, so memory
/// stays bounded by `WAVE` accumulators whatever the number of trials.
const WAVE: u64 = 256;

/// Runs `trials` trials of one scenario on the current rayon pool. `progress` is called with the
/// number of trials finished by each block.
pub fn run(sc: &Scenario, trials: u64, progress: &(dyn Fn(u64) + Sync)) -> McStats {
    let mut out = McStats::new(sc);
    let nblocks = trials.div_ceil(BLOCK);
    for wave in (0..nblocks).step_by(WAVE as usize) {
        let parts: Vec<McStats> = (wave..(wave + WAVE).min(nblocks))
            .into_par_iter()
            .map_init(
                || Workspace::new(sc),
                |ws, b| {
                    let (first, last) = (b * BLOCK, ((b + 1) * BLOCK).min(trials));
                    let st = run_block(sc, ws, first, last);
                    progress(last - first);
                    st
                },
            )
            .collect();
        for p in &parts {
            out.merge(p);
        }
    }
    out
}

/// One recorded trial: the truth z[k] and every filter's estimate ẑ[k] (columns are steps).
#[derive(Clone, Debug)]
pub struct Trajectory {
    pub trial: u64,
    pub z: Mat,
    pub zhat: Vec<Mat>,
    /// θ[k], the plant's mode at each step (for dropouts 0 = lost).
    pub modes: Vec<usize>,
}

/// Re-runs trials 0..count (same streams as in [`run`]) and records their trajectories.
pub fn trajectories(sc: &Scenario, count: u64) -> Vec<Trajectory> {
    let mut ws = Workspace::new(sc);
    let (nz, steps) = (sc.plant.nz(), sc.plant.steps());
    (0..count)
        .map(|t| {
            let mut tr = Trajectory {
                trial: t,
                z: Mat::zeros(nz, steps),
                zhat: vec![Mat::zeros(nz, steps); sc.filters.len()],
                modes: Vec::new(),
            };
            run_trial(sc, &mut ws, t, |k, f, z, zhat, _| {
                if f == 0 {
                    tr.z.set_column(k, z);
                }
                tr.zhat[f].set_column(k, zhat);
            });
            tr.modes = ws.draw.modes.clone();
            tr
        })
        .collect()
}
