//! The minimax filter under covariance uncertainty (seed 000 §§3–4, docs/math.md §2): the Kalman filter
//! built at the worst covariance K̂ = argmax_{K ∈ set} I(K), where I(K) = J(Kalman(K), K) is the
//! concave dual functional of eq (14).
//!
//! K̂ comes from Theorem 1.2a when every set has a largest element, and otherwise from Algorithm 1
//! (conditional gradient on the dual): at K(s) build the Kalman gains; the gradient λ(s) =
//! ∂J(F(s), K)/∂K of eq (27) by one backward adjoint pass ([`exact::gradient`]); the linear oracle
//! K̃ = argmax_{K ∈ set} ⟨λ(s), K⟩ (sign pattern, closed-form ball, or clarabel); the gap
//! δ(s) = ⟨λ(s), K̃ − K(s)⟩, an upper bound on I(K̂) − I(K(s)), as the stopping rule; and an exact
//! line search of the concave I on the segment K(s) → K̃, by bisection on its derivative
//! ⟨∇I(K_τ), K̃ − K(s)⟩ (the envelope theorem: ∇I(K) is λ at the Kalman filter of K).
//!
//! Guarantee (eq (22), Theorem 1): for every covariance in the set and any distribution,
//! E J ≤ I(K̂). It holds because K̂ is a saddle point, which the tests check: max over the set of
//! J(F̂, ·) equals I(K̂). The reported bound is that maximum, computed exactly for the designed F̂,
//! so it stays a valid bound when Algorithm 1 stops before the gap closes (then it exceeds the
//! last I(K(s)) by at most the gap), rounded up past its recursion's rounding bound. Only the sum
//! is guaranteed: F̂'s error at K̂ step by step is its `claimed` error, not a per-step bound.

use serde::Deserialize;

use super::kalman::kalman;
use crate::analysis::exact;
use crate::error::{Error, Result};
use crate::filter::design::{Design, DesignInput, Figures, Guarantee, GuaranteeKind, LineSearch, Record, TraceRow};
use crate::model::choice::CovChoiceFile;
use crate::model::plant::Pattern;
use crate::model::plant::{Covariances, Plant};
use crate::model::uncertainty::CovSet;
use crate::numerics::accuracy;
use crate::numerics::linalg::{Mat, frob_dot};
use crate::numerics::solve::line::maximize_concave_01;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// Stop when the gap δ ≤ tolerance · I(K(s)).
    #[serde(default = "default_tolerance")]
    tolerance: f64,
    #[serde(default = "default_max_iterations")]
    max_iterations: usize,
    /// K(0), the starting point of Algorithm 1 (must lie in the set).
    #[serde(default)]
    start: CovChoiceFile,
}

fn default_tolerance() -> f64 {
    1e-9
}
fn default_max_iterations() -> usize {
    500
}

/// The solution of the dual problem (14).
#[derive(Clone, Debug)]
pub struct DualSolution {
    pub k_hat: Covariances,
    /// I(K̂).
    pub value: f64,
    pub trace: Vec<TraceRow>,
    /// The first `LINE_SEARCHES_KEPT` line searches, sampled (seed 000 Fig. 1).
    pub line_searches: Vec<LineSearch>,
    /// The last gap δ (0 when Theorem 1.2a applied).
    pub gap: f64,
    pub converged: bool,
    /// Whether K̂ is the largest element of the set (Theorem 1.2a) rather than Algorithm 1's result.
    pub largest_element: bool,
}

/// The minimax filter's own figures.
#[derive(Debug, serde::Serialize)]
pub struct MinimaxFigures {
    /// Seed 000 Algorithm 1: the duality gap δ(s) at the last iteration.
    pub final_gap: f64,
    /// Seed 000 Theorem 1.2: which condition (a: a largest element; b: R_z(K̂) ≻ 0) makes the
    /// filter at K̂ minimax, or that neither does.
    pub theorem_1_2: &'static str,
    /// λmin(R_z(K̂)) / λmax, Theorem 1.2b's condition.
    pub rz_min_eigenvalue: f64,
}

impl Record for MinimaxFigures {}

/// The family's entry: `family = "minimax"`.
pub(crate) struct Minimax;

impl super::family::Family for Minimax {
    const NAME: &'static str = "minimax";
    type Params = Params;

    /// Theorem 3's saddle point rests on the Kalman filter being optimal at every K, which
    /// multiplicative noise breaks; the surrogate of a disturbance may vary with the step.
    fn supports(_: &Params) -> super::family::Supports {
        super::family::Supports { multiplicative: false, varying_weights: true, ..super::family::Supports::ALL }
    }

    /// Theorem 1.2b's check (`observation_covariance_min_eigenvalue`) forms the covariance of every
    /// measurement of the horizon stacked: dense over the whole horizon.
    fn footprint(_: &Params, plant: super::family::PlantSize) -> super::family::Footprint {
        super::family::Footprint { state: plant.nx, gain_sets: 1, dense_horizon: true }
    }

    fn check(p: &Params) -> std::result::Result<(), (&'static str, String)> {
        if !(p.tolerance > 0.0 && p.tolerance.is_finite()) {
            return Err(("tolerance", "must be a positive number".into()));
        }
        if p.max_iterations == 0 {
            return Err(("max_iterations", "must be at least 1".into()));
        }
        if matches!(p.start, CovChoiceFile::WorstFor { .. } | CovChoiceFile::DesignOf { .. }) {
            return Err(("start", "Algorithm 1 cannot start at another filter's covariance".into()));
        }
        Ok(())
    }

    fn design(input: &DesignInput, p: &Params) -> Result<Design> {
        let key = format!("filters.{}", input.name);
        if !input.has_sets() {
            return Err(Error::design(input.name, "the minimax family needs an uncertainty set: add [sets.BLOCK]"));
        }
        let start = input.design_point(&format!("{key}.start"), &p.start, true)?;
        let sol = dual_solve(input.plant, input.pattern, input.sets, start, p.tolerance, p.max_iterations)
            .map_err(|e| Error::design(input.name, e.to_string()))?;
        let realization = kalman(input.plant, &sol.k_hat, input.pattern);
        // The certified guarantee is F̂'s exact worst case over the set, max_K J(F̂, K): it holds for any
        // filter, and for the minimax one it equals I(K̂) up to the final gap δ ≥ I(K̂) − I(K(s)).
        // Rounded up past the first-order rounding bound of the moment recursion behind it
        // (numerics::accuracy::recursion_error); the oracle's part is exact (a closed form) or a
        // weak-duality bound (an SDP over a set ∩ PSD).
        let certified = exact::worst_case(input.plant, &realization, &input.nominal, input.sets)?
            .map(|w| {
                let n = input.plant.nx() + realization.ns();
                accuracy::round_up(w.total, accuracy::recursion_error(input.plant.steps(), n, w.total))
            })
            .ok_or_else(|| Error::design(input.name, "no uncertainty set"))?;
        let mut diagnostics = serde_json::Map::new();
        diagnostics.insert("iterations".into(), sol.trace.len().into());
        diagnostics.insert("dual_value".into(), sol.value.into());
        diagnostics.insert("converged".into(), sol.converged.into());
        diagnostics.insert(
            "method".into(),
            if sol.largest_element { "largest element (Theorem 1.2a)" } else { "Algorithm 1 (conditional gradient)" }
                .into(),
        );
        // Theorem 1.2: the Kalman filter at K̂ is minimax when the set has a largest element (a) or
        // when R_z(K̂) ≻ 0 (b); with neither, K̂ still maximizes I but the filter is not proven minimax.
        let rz_min = observation_covariance_min_eigenvalue(input.plant, &sol.k_hat)?;
        let rz_positive = rz_min > 0.0;
        let theorem_1_2 = match (sol.largest_element, rz_positive) {
            (true, _) => "a: the set has a largest element",
            (false, true) => "b: R_z(K̂) ≻ 0",
            (false, false) => "neither a nor b: K̂ maximizes I, but the filter at K̂ is not proven minimax",
        };
        let figures = Figures::of(MinimaxFigures { final_gap: sol.gap, theorem_1_2, rz_min_eigenvalue: rz_min });
        Ok(Design {
            realization,
            // Only the sum is guaranteed (eq (22)): F̂'s per-step error at K̂ is what it claims at its
            // design covariance (`claimed`), which another covariance of the set may exceed at a step.
            guarantee: Some(Guarantee { kind: GuaranteeKind::Minimax, total: certified, per_step: Vec::new() }),
            design_covariance: Some(sol.k_hat),
            claimed_error: None,
            trace: sol.trace,
            line_searches: sol.line_searches,
            figures,
            diagnostics,
            per_trial: None,
            gain_bound: None,
        })
    }
}

/// The smallest eigenvalue of R_z(K) = cov(Z_N) = Ψ R_ρ(K) Ψ*, the covariance of every measurement
/// of the horizon stacked (seed 000 before eq (17); Theorem 1.2b asks R_z(K̂) ≻ 0), relative to its
/// largest (0 when it is singular to rounding). Z is built column by column as a linear map of
/// (x0, w\[0..N]), so no filter is involved.
pub fn observation_covariance_min_eigenvalue(plant: &Plant, k: &Covariances) -> Result<f64> {
    let (nx, nw, ny) = (plant.nx(), plant.nw(), plant.ny());
    let cols = nx + plant.steps() * nw;
    let measured: Vec<usize> = (0..plant.steps()).filter(|n| plant.measured(*n)).collect();
    let mut m = Mat::zeros(measured.len() * ny, cols);
    // x[n] as a linear map of (x0, w): starts at [I 0 …].
    let mut x = Mat::zeros(nx, cols);
    x.view_mut((0, 0), (nx, nx)).fill_with_identity();
    let mut row = 0;
    for n in 0..plant.steps() {
        let wn = nx + n * nw;
        if plant.measured(n) {
            let mut z = &*plant.c_at(n) * &x;
            let mut zw = z.view_mut((0, wn), (ny, nw));
            zw += &*plant.d_at(n);
            m.view_mut((row, 0), (ny, cols)).copy_from(&z);
            row += ny;
        }
        let mut next = plant.a_at(n) * &x;
        let mut nw_view = next.view_mut((0, wn), (nx, nw));
        nw_view += plant.b_at(n);
        x = next;
    }
    let mut full = Mat::zeros(cols, cols);
    full.view_mut((0, 0), (nx, nx)).copy_from(k.x0());
    for n in 0..plant.steps() {
        full.view_mut((nx + n * nw, nx + n * nw), (nw, nw)).copy_from(&k.w_at(n));
    }
    let (eig, _) = crate::numerics::linalg::sym_eigen(&(&m * full * m.transpose()))?;
    let top = eig.iter().cloned().fold(0.0, f64::max);
    let low = eig.iter().cloned().fold(f64::INFINITY, f64::min);
    Ok(if top > 0.0 && low > crate::numerics::linalg::PSD_TOL * top { low / top } else { 0.0 })
}

/// I(K) = J(Kalman(K), K), the dual functional (eq (14)).
pub fn dual_value(plant: &Plant, pattern: Pattern, k: &Covariances) -> f64 {
    exact::error(plant, &kalman(plant, k, pattern), k).total
}

/// ∇I(K) = ∂J(F, K)/∂K at F = Kalman(K) (envelope theorem; eq (27)).
pub fn dual_gradient(plant: &Plant, pattern: Pattern, k: &Covariances) -> Vec<Mat> {
    exact::gradient(plant, &kalman(plant, k, pattern))
}

fn along(k: &Covariances, dir: &[Mat], tau: f64) -> Covariances {
    Covariances { blocks: k.blocks.iter().zip(dir).map(|(a, d)| a + d * tau).collect(), varying: k.varying.clone() }
}

/// Solves the dual problem (14) over the sets (blocks without a set stay as in `start`).
pub fn dual_solve(
    plant: &Plant,
    pattern: Pattern,
    sets: &[Option<CovSet>],
    start: Covariances,
    tolerance: f64,
    max_iterations: usize,
) -> Result<DualSolution> {
    let largest: Option<Vec<Option<Mat>>> =
        sets.iter().map(|s| s.as_ref().map_or(Some(None), |s| s.largest().map(Some))).collect();
    if let Some(largest) = largest {
        let mut k_hat = start;
        for (i, l) in largest.into_iter().enumerate() {
            if let Some(l) = l {
                k_hat.blocks[i] = l;
            }
        }
        let value = dual_value(plant, pattern, &k_hat);
        let trace = vec![TraceRow { iteration: 0, objective: value, gap: 0.0, step: 0.0 }];
        return Ok(DualSolution {
            k_hat,
            value,
            trace,
            line_searches: Vec::new(),
            gap: 0.0,
            converged: true,
            largest_element: true,
        });
    }

    let mut k = start;
    let mut trace = Vec::new();
    let mut line_searches = Vec::new();
    for s in 0..max_iterations {
        let value = dual_value(plant, pattern, &k);
        let grad = dual_gradient(plant, pattern, &k);
        let mut dir: Vec<Mat> = k.blocks.iter().map(|b| Mat::zeros(b.nrows(), b.ncols())).collect();
        let mut gap = 0.0;
        for (i, set) in sets.iter().enumerate() {
            if let Some(set) = set {
                let (gain, corner) = set.linear_gain(&grad[i], &k.blocks[i])?;
                gap += gain;
                dir[i] = corner - &k.blocks[i];
            }
        }
        if gap <= tolerance * value.abs().max(f64::MIN_POSITIVE) {
            trace.push(TraceRow { iteration: s, objective: value, gap, step: 0.0 });
            return Ok(DualSolution {
                k_hat: k,
                value,
                trace,
                line_searches,
                gap,
                converged: true,
                largest_element: false,
            });
        }
        let dphi = |tau: f64| {
            let g = dual_gradient(plant, pattern, &along(&k, &dir, tau));
            g.iter().zip(&dir).map(|(g, d)| frob_dot(g, d)).sum::<f64>()
        };
        let tau = maximize_concave_01(dphi, 1e-10);
        trace.push(TraceRow { iteration: s, objective: value, gap, step: tau });
        if line_searches.len() < LINE_SEARCHES_KEPT {
            line_searches.push(line_search(plant, pattern, &k, &dir, s, tau));
        }
        k = along(&k, &dir, tau);
    }
    let value = dual_value(plant, pattern, &k);
    let gap = trace.last().map_or(f64::INFINITY, |r| r.gap);
    Ok(DualSolution { k_hat: k, value, trace, line_searches, gap, converged: false, largest_element: false })
}

/// How many line searches a design keeps sampled (seed 000's Fig. 1 is the second, s = 1).
pub(crate) const LINE_SEARCHES_KEPT: usize = 3;
/// Samples of τ on [0, 1] per kept line search (besides the step taken).
const LINE_SEARCH_SAMPLES: usize = 41;

/// I(K(s) + τ dir)/N on a grid of τ and at the step taken (seed 000 Fig. 1), N the number of
/// steps the criterion sums.
fn line_search(plant: &Plant, pattern: Pattern, k: &Covariances, dir: &[Mat], s: usize, step: f64) -> LineSearch {
    let n = (0..plant.steps()).filter(|&j| plant.counts(j)).count().max(1) as f64;
    let mut tau: Vec<f64> = (0..LINE_SEARCH_SAMPLES).map(|i| i as f64 / (LINE_SEARCH_SAMPLES - 1) as f64).collect();
    tau.push(step);
    tau.sort_by(f64::total_cmp);
    tau.dedup();
    let value = tau.iter().map(|&t| dual_value(plant, pattern, &along(k, dir, t)) / n).collect();
    LineSearch { iteration: s, tau, value }
}
