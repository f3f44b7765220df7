//! The Monte Carlo engine: every filter of the experiment on the same draws (common random
//! numbers), blocks of trials in parallel with rayon, streaming per-step accumulators.
//!
//! Trials are cut into fixed blocks of [`BLOCK`] trials, simulated together in lanes
//! ([`crate::sim::block`]). A block's statistics per (filter, step) are computed over its lanes;
//! blocks run in parallel and their statistics are merged with Chan's formula in the fixed order of
//! a dyadic tree over block indices ([`crate::sim::tree`]), which any cut into shards reproduces.
//! Together with per-trial random streams ([`crate::sim::noise::trial_rng`]) this makes every
//! figure bit-identical for any number of threads and any cut into shards. Memory is
//! O(filters × steps × log blocks) (the tree's stack), not growing with the trials beyond that log.

use rayon::prelude::*;

use crate::analysis::exact::ErrorForm;
use crate::filter::design::PerTrialBound;
use crate::filter::realization::Realization;
use crate::model::plant::Plant;
use crate::numerics::linalg::Mat;
use crate::sim::block::{Workspace, simulate};
use crate::sim::checks;
use crate::sim::lanes::{self, LANES};
use crate::sim::noise::NoiseSampler;
pub use crate::sim::plant_ops::PlantOps;
use crate::sim::stats::Welford;
use crate::sim::tree::{Node, Tree};

/// Trials per block: the lanes simulated together, the unit of parallel work and of the fixed
/// reduction order.
pub const BLOCK: u64 = LANES as u64;

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
    pub fn new(sc: &Scenario) -> Self {
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
    pub(crate) fn merge(&mut self, o: &McStats) {
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
    /// Whether `o` has the same accumulators (filters, steps, NEES, pairs): only then do they merge.
    pub fn same_shape(&self, o: &McStats) -> bool {
        let f = |m: &McStats| m.filters.iter().map(|f| (f.steps.len(), f.nees.len())).collect::<Vec<_>>();
        self.paired.len() == o.paired.len() && f(self) == f(o)
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
    pub(super) fn nees_weights(&self, f: usize) -> Option<&[Option<Mat>]> {
        self.nees.get(f)?.as_deref()
    }
    pub(super) fn form(&self, f: usize) -> Option<&ErrorForm> {
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

/// Runs block `first..first + active` and returns its statistics: per (filter, step) the mean and
/// spread over the block's lanes ([`Welford::of`]), ready to be merged in block order; and per
/// filter each lane's summed error J.
pub fn run_block(sc: &Scenario, ws: &mut Workspace, first: u64, active: usize) -> (McStats, Vec<[f64; LANES]>) {
    let nf = sc.filters.len();
    let mut st = McStats::new(sc);
    let plant = sc.plant;
    let mut totals = vec![[0.0; LANES]; nf];
    let mut sums = vec![[0.0; LANES]; if sc.ratios.is_some() { nf } else { 0 }];
    let mut broke = vec![[0.0; LANES]; sums.len()];
    let mut e2 = [0.0; LANES];
    let mut q = [0.0; LANES];
    let per_filter = &mut st.filters;
    simulate(sc, ws, first, active, |v| {
        let (k, f, e) = (v.k, v.f, v.e);
        lanes::squared_norm(e, &mut e2);
        let acc = &mut per_filter[f];
        acc.steps[k] = Welford::of(&e2[..active]);
        if let Some(Some(w)) = sc.nees_weights(f).map(|ws| &ws[k]) {
            lanes::quadratic(w, e, &mut q);
            acc.nees[k] = Welford::of(&q[..active]);
        }
        if plant.counts(k) {
            lanes::axpy(1.0, &e2, &mut totals[f]);
        }
        if sc.ratios.is_some() {
            if k < plant.horizon {
                lanes::axpy(1.0, &e2, &mut sums[f]);
            }
            checks::ellipsoid(sc, f, k, e, v.energy, active, acc, &mut broke[f]);
        }
    });
    for f in 0..sums.len() {
        checks::terminal(sc, ws, f, &sums[f], active, &mut st.filters[f]);
        st.filters[f].violations += broke[f][..active].iter().filter(|b| **b != 0.0).count() as u64;
    }
    for (acc, v) in st.filters.iter_mut().zip(&totals) {
        acc.total = Welford::of(&v[..active]);
    }
    for (acc, (i, j)) in st.paired.iter_mut().zip(McStats::pairs(nf)) {
        let mut d = [0.0; LANES];
        lanes::difference(&totals[i..=i], &totals[j..=j], std::slice::from_mut(&mut d));
        *acc = Welford::of(&d[..active]);
    }
    (st, totals)
}

/// Blocks run in parallel per wave; a wave's results are merged before the next starts, so memory
/// stays bounded by `WAVE` accumulators whatever the number of trials.
pub const WAVE: u64 = 256;

/// The number of blocks of a run of `trials` trials.
pub fn blocks(trials: u64) -> u64 {
    trials.div_ceil(BLOCK)
}

/// What a run of a range of blocks hands on: its maximal tree nodes ([`crate::sim::tree`]) and,
/// when asked for, per filter the summed error J of each of its trials in trial order.
pub struct Partial {
    pub nodes: Vec<Node>,
    pub per_trial: Vec<Vec<f64>>,
}

/// Runs blocks `range` of a run of `trials` trials of one scenario on the current rayon pool.
/// `progress` is called with the number of trials finished by each block.
pub fn run_range(
    sc: &Scenario,
    trials: u64,
    range: std::ops::Range<u64>,
    per_trial: bool,
    progress: &(dyn Fn(u64) + Sync),
) -> Partial {
    let mut tree = Tree::default();
    let mut per = vec![Vec::new(); if per_trial { sc.filters.len() } else { 0 }];
    for wave in range.clone().step_by(WAVE as usize) {
        let parts: Vec<_> = (wave..(wave + WAVE).min(range.end))
            .into_par_iter()
            .map_init(
                || Workspace::new(sc),
                |ws, b| {
                    let (first, last) = (b * BLOCK, ((b + 1) * BLOCK).min(trials));
                    let active = (last - first) as usize;
                    let (st, totals) = run_block(sc, ws, first, active);
                    progress(last - first);
                    (b, st, totals, active)
                },
            )
            .collect();
        for (b, stats, totals, active) in parts {
            for (p, t) in per.iter_mut().zip(&totals) {
                p.extend_from_slice(&t[..active]);
            }
            tree.push(Node { level: 0, index: b, stats });
        }
    }
    Partial { nodes: tree.into_nodes(), per_trial: per }
}

/// The statistics of a whole run from its tree nodes in block order (one range's or every
/// shard's, shard after shard): the same merges whoever computed the nodes.
pub fn reduce(sc: &Scenario, nodes: impl IntoIterator<Item = Node>) -> McStats {
    Tree::from_nodes(nodes).finish(McStats::new(sc))
}

/// Runs `trials` trials of one scenario on the current rayon pool. `progress` is called with the
/// number of trials finished by each block.
pub fn run(sc: &Scenario, trials: u64, progress: &(dyn Fn(u64) + Sync)) -> McStats {
    reduce(sc, run_range(sc, trials, 0..blocks(trials), false, progress).nodes)
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

/// Re-runs trials 0..count (same streams and blocks as in [`run`]) and records their trajectories.
pub fn trajectories(sc: &Scenario, count: u64) -> Vec<Trajectory> {
    let mut ws = Workspace::new(sc);
    let (nz, steps) = (sc.plant.nz(), sc.plant.steps());
    let mut out: Vec<Trajectory> = (0..count)
        .map(|t| Trajectory {
            trial: t,
            z: Mat::zeros(nz, steps),
            zhat: vec![Mat::zeros(nz, steps); sc.filters.len()],
            modes: vec![0; steps],
        })
        .collect();
    for (b, block) in out.chunks_mut(LANES).enumerate() {
        simulate(sc, &mut ws, b as u64 * BLOCK, block.len(), |v| {
            for (l, tr) in block.iter_mut().enumerate() {
                for i in 0..nz {
                    if v.f == 0 {
                        tr.z[(i, v.k)] = v.z[i][l];
                    }
                    tr.zhat[v.f][(i, v.k)] = v.zhat[i][l];
                }
                tr.modes[v.k] = v.modes[l] as usize;
            }
        });
    }
    out
}
