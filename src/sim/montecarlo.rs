//! The Monte Carlo engine: every filter of the experiment on the same draws (common random
//! numbers), blocks of trials in parallel with rayon, streaming per-step accumulators.
//!
//! Trials are cut into fixed blocks of `BLOCK` trials, simulated together in lanes
//! ([`crate::sim::block`]). A block's statistics per (filter, step) are computed over its lanes;
//! blocks run in parallel and their statistics are merged with Chan's formula in the fixed order of
//! a dyadic tree over block indices ([`crate::sim::tree`]), which any cut into shards reproduces.
//! Together with per-trial random streams (`trial_rng`) this makes every
//! figure bit-identical for any number of threads and any cut into shards. Memory is
//! O(filters × steps × log blocks) (the tree's stack), not growing with the trials beyond that log.

use rayon::prelude::*;

use crate::numerics::linalg::Mat;
use crate::sim::block::{StepView, Workspace, simulate};
use crate::sim::checks;
use crate::sim::lanes::{self, LANES, Row};
// The engine's inputs and outputs live below it (so that the block loop, the checks and the tree
// need not import the engine); re-exported here, where callers look for them.
pub use crate::sim::mc_stats::FilterStats;
pub use crate::sim::mc_stats::McStats;
pub use crate::sim::plant_ops::PlantOps;
pub use crate::sim::scenario::{RatioCheck, Scenario};
use crate::sim::stats::Welford;
use crate::sim::tree::{Node, Tree};

/// Trials per block: the lanes simulated together, the unit of parallel work and of the fixed
/// reduction order.
pub(crate) const BLOCK: u64 = LANES as u64;

/// Runs block `first..first + active` and returns its statistics: per (filter, step) the mean and
/// spread over the block's lanes ([`Welford::of`]), ready to be merged in block order; and per
/// filter each lane's summed error J.
pub(crate) fn run_block(sc: &Scenario, ws: &mut Workspace, first: u64, active: usize) -> (McStats, Vec<[f64; LANES]>) {
    let nf = sc.filters.len();
    let mut st = McStats::new(sc);
    let plant = sc.plant;
    let mut totals = vec![[0.0; LANES]; nf];
    let mut sums = vec![[0.0; LANES]; if sc.ratios.is_some() { nf } else { 0 }];
    let mut broke = vec![[0.0; LANES]; sums.len()];
    let mut e2 = [0.0; LANES];
    let mut q = [0.0; LANES];
    let (mut nu, mut tmp) = (lanes::zeros(plant.ny()), lanes::zeros(plant.ny()));
    let per_filter = &mut st.filters;
    // The statistics' kernels with the simulation's lanes per pass (the same bits either way).
    let wide = lanes::build() == lanes::Build::Avx512;
    // Inlined into the build `simulate` picked, so the statistics run with the same vector width as
    // the simulation (the same bits: no kernel's order depends on the width).
    simulate(
        sc,
        ws,
        first,
        active,
        #[inline(always)]
        |v| {
            let (k, f, e) = (v.k, v.f, v.e);
            if wide {
                lanes::squared_norm_in::<{ lanes::WIDE_CHUNK }>(e, &mut e2);
            } else {
                lanes::squared_norm(e, &mut e2);
            }
            let acc = &mut per_filter[f];
            acc.steps.set(k, lanes_of(&e2, active));
            if let Some(Some(w)) = sc.nees_weights(f).map(|ws| &ws[k]) {
                quadratic(wide, w, e, &mut q);
                acc.nees.set(k, lanes_of(&q, active));
            }
            if let Some(Some(w)) = sc.nis_weights(f).map(|ws| &ws[k]) {
                match v.whitened {
                    // νᵀWν = ‖Lᵀν‖², Lᵀν from the filter's own product.
                    Some(white) if wide => lanes::squared_norm_in::<{ lanes::WIDE_CHUNK }>(white, &mut q),
                    Some(white) => lanes::squared_norm(white, &mut q),
                    None => {
                        if wide {
                            innovation::<{ lanes::WIDE_CHUNK }>(sc, &v, &mut nu, &mut tmp);
                        } else {
                            innovation::<{ lanes::CHUNK }>(sc, &v, &mut nu, &mut tmp);
                        }
                        quadratic(wide, w, &nu, &mut q);
                    }
                }
                acc.nis.set(k, lanes_of(&q, active));
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
        },
    );
    for f in 0..sums.len() {
        checks::terminal(sc, ws, f, &sums[f], active, &mut st.filters[f]);
        st.filters[f].violations += broke[f][..active].iter().filter(|b| **b != 0.0).count() as u64;
    }
    for (acc, v) in st.filters.iter_mut().zip(&totals) {
        acc.total = lanes_of(v, active);
    }
    for (acc, (i, j)) in st.paired.iter_mut().zip(McStats::pairs(nf)) {
        let mut d = [0.0; LANES];
        lanes::difference(&totals[i..=i], &totals[j..=j], std::slice::from_mut(&mut d));
        *acc = lanes_of(&d, active);
    }
    (st, totals)
}

/// [`Welford::of`] of a block's active lanes. A full block's length is then a constant the
/// compiler unrolls the two passes over, the same sums in the same order (issue 28: the statistics
/// pass).
#[inline(always)]
fn lanes_of(values: &Row, active: usize) -> Welford {
    if active == LANES { Welford::of(values) } else { Welford::of(&values[..active]) }
}

/// ν = y − C s, the innovation of a filter whose state estimates x ([`crate::analysis::nees`]), into
/// `nu`; in error coordinates ε = s − x it is D w − C ε, which needs no x.
#[inline(always)]
fn innovation<const C: usize>(sc: &Scenario, v: &StepView, nu: &mut [Row], tmp: &mut [Row]) {
    let (c, d) = (sc.ops.c(v.k, 0), sc.ops.d(v.k, 0));
    match (v.error_coordinates, &v.outputs) {
        (true, _) => lanes::apply_in::<C>(d, v.w, false, nu),
        (false, Some(o)) => nu.copy_from_slice(o.y),
        (false, None) => unreachable!("a filter in its own coordinates always has the plant simulated"),
    }
    lanes::apply_in::<C>(c, v.s, false, tmp);
    lanes::subtract(tmp, nu);
}

/// eᵀ W e per lane with the lanes per pass of the build ([`lanes::quadratic`]).
#[inline(always)]
fn quadratic(wide: bool, w: &Mat, e: &[Row], out: &mut Row) {
    if wide { lanes::quadratic_in::<{ lanes::WIDE_CHUNK }>(w, e, out) } else { lanes::quadratic(w, e, out) }
}

/// Blocks run in parallel per wave; a wave's results are merged before the next starts, so memory
/// stays bounded by `WAVE` accumulators whatever the number of trials.
pub(crate) const WAVE: u64 = 256;

/// The most memory a wave's accumulators may take, unless that is less than one per thread: on a
/// long horizon (three accumulators per step and filter, 102 MB per block at N = 10⁶ with 2 filters)
/// a wave is cut to fewer blocks. The tree merges blocks in index order whatever the wave, so the
/// results are the same bits.
pub(crate) const WAVE_BYTES: u64 = 256 << 20;

/// The blocks of one wave of scenario `sc`: [`WAVE`], or fewer on a long horizon ([`WAVE_BYTES`]).
pub(crate) fn wave_blocks(sc: &Scenario) -> u64 {
    let per_block: u64 = (0..sc.filters.len())
        .map(|f| {
            let squares = u64::from(sc.nees_weights(f).is_some()) + u64::from(sc.nis_weights(f).is_some());
            (1 + squares) * sc.plant.steps() as u64 * STEP_BYTES
        })
        .sum();
    let threads = rayon::current_num_threads() as u64;
    (WAVE_BYTES / per_block.max(1)).max(threads).clamp(1, WAVE)
}

/// Bytes of one step's accumulator in a [`crate::sim::series::Series`] (its mean and M2, and a bit).
pub(crate) const STEP_BYTES: u64 = crate::sim::series::STEP_BYTES;

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
pub(crate) fn run_range(
    sc: &Scenario,
    trials: u64,
    range: std::ops::Range<u64>,
    per_trial: bool,
    progress: &(dyn Fn(u64) + Sync),
) -> Partial {
    let mut tree = Tree::default();
    let mut per = vec![Vec::new(); if per_trial { sc.filters.len() } else { 0 }];
    let wave_size = wave_blocks(sc);
    for wave in range.clone().step_by(wave_size as usize) {
        let parts: Vec<_> = (wave..(wave + wave_size).min(range.end))
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
pub(crate) fn reduce(sc: &Scenario, nodes: impl IntoIterator<Item = Node>) -> McStats {
    Tree::from_nodes(nodes).finish(|| McStats::new(sc))
}

/// Runs `trials` trials of one scenario on the current rayon pool. `progress` is called with the
/// number of trials finished by each block.
pub fn run(sc: &Scenario, trials: u64, progress: &(dyn Fn(u64) + Sync)) -> McStats {
    reduce(sc, run_range(sc, trials, 0..blocks(trials), false, progress).nodes)
}

/// One recorded trial: the truth z\[k] and every filter's estimate ẑ\[k] (columns are steps).
#[derive(Clone, Debug)]
pub struct Trajectory {
    pub trial: u64,
    pub z: Mat,
    pub zhat: Vec<Mat>,
    /// θ\[k], the plant's mode at each step (for dropouts 0 = lost), as the lanes carry it.
    pub modes: Vec<u32>,
}

/// Re-runs trials 0..count (same streams and blocks as in [`run`]) and records their trajectories.
pub fn trajectories(sc: &Scenario, count: u64) -> Vec<Trajectory> {
    let mut ws = Workspace::with_outputs(sc);
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
            let Some(o) = &v.outputs else { unreachable!("a workspace with outputs") };
            for (l, tr) in block.iter_mut().enumerate() {
                for i in 0..nz {
                    if v.f == 0 {
                        tr.z[(i, v.k)] = o.z[i][l];
                    }
                    tr.zhat[v.f][(i, v.k)] = o.zhat[i][l];
                }
                tr.modes[v.k] = v.modes[l];
            }
        });
    }
    out
}
