//! The Markov-jump predictor (seed 001, docs/math.md §3): x̂\[n+1] = A_θ x̂ + K_θ(n)(y − C_θ x̂) + r, ẑ = Cz x̂,
//! with θ = θ\[n] the observed mode. With P_s(n) = E[x̃x̃ᵀ 1{θ\[n] = s}] and p_s(n) = P(θ\[n] = s), written
//! for the stacked noise (B_s w and D_s w may share components, covariance W):
//!
//! ```text
//! S_s = C_s P_s C_sᵀ + p_s D_s W D_sᵀ,   K_s(n) = (A_s P_s C_sᵀ + p_s B_s W D_sᵀ) S_s⁺      (15)
//! P_k(n+1) = Σ_s Π_sk [A_s P_s A_sᵀ + p_s B_s W B_sᵀ − K_s S_s K_sᵀ]                       (16)
//! ```
//!
//! (the printed `P_s(n)` beside G S G* and B R B* is the probability p_s(n); P_s(0) = p_s(0)·cov x0,
//! not 0, for an uncertain x0; Π_sk is the probability of going from s to k). The choice (15)
//! minimizes every P_k(n+1) given P(n), and (16) is monotone in P(n), so these gains are optimal
//! among predictors of this form on the finite horizon.
//!
//! `gains = "steady"`: for an ergodic chain, (17)–(18): iterate (16) with the stationary p_s to its
//! fixed point and use the constant K_s at every step. `gains = "common"`: one K for all modes (the
//! seed's closing remark), chosen to minimize the stationary Σ_s tr(Cz P_s Czᵀ): for fixed K the
//! P_s solve a linear fixed point P = 𝓣_K(P) + N_K, the adjoint V_s = CzᵀCz + M_sᵀ(Σ_k Π_sk V_k)M_s
//! (M_s = A_s − K C_s) gives ∂J/∂K = −2 Σ_s V̄_s [M_s P_s C_sᵀ + p_s (B_s − K D_s) W D_sᵀ], and BFGS
//! with a backtracking line search minimizes it.

use serde::Deserialize;

use crate::filter::design::{Design, DesignInput, Figures, TraceRow};
use crate::error::{Error, Result};
use crate::numerics::linalg::{Mat, symmetrize, weighted_sum};
use crate::numerics::riccati;
use crate::model::plant::{Covariances, Modes, Plant};
use crate::filter::realization::{Gains, Realization};
use crate::model::choice::CovChoiceFile;

#[derive(Deserialize, Default, Clone, Copy, PartialEq, Debug)]
#[serde(rename_all = "snake_case")]
pub(crate) enum GainsKind {
    /// K_s(n) from the coupled recursion on the horizon.
    #[default]
    Finite,
    /// The stationary K_s of an ergodic chain.
    Steady,
    /// One K for every mode, optimal for the stationary error.
    Common,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct Params {
    #[serde(default)]
    gains: GainsKind,
    #[serde(default)]
    design: CovChoiceFile,
}

/// The family's entry: `family = "markov_jump"`.
pub(crate) struct MarkovJump;

impl super::family::Family for MarkovJump {
    const NAME: &'static str = "markov_jump";
    type Params = Params;

    /// A predictor (seed 001 (6)) on noise-free matrices. The finite-horizon recursion (15)–(16)
    /// reads each step's matrices; the stationary gains are fixed points of constant ones.
    fn supports(p: &Params) -> super::family::Supports {
        super::family::Supports {
            patterns: super::family::PREDICTION,
            multiplicative: false,
            time_varying: p.gains == GainsKind::Finite,
            narrowed_by: match p.gains {
                GainsKind::Finite => None,
                GainsKind::Steady => Some(("gains", "steady")),
                GainsKind::Common => Some(("gains", "common")),
            },
            ..super::family::Supports::ALL
        }
    }

    /// One set of gains per mode and the mode-averaged one.
    fn footprint(_: &Params, plant: super::family::PlantSize) -> super::family::Footprint {
        super::family::Footprint { state: plant.nx, gain_sets: plant.modes + 1, dense_horizon: false }
    }

    fn design(input: &DesignInput, p: &Params) -> Result<Design> {
        let name = input.name;
        let Some(modes) = input.plant.modes() else {
            return Err(Error::design(name, "the plant has no modes: add [modes] (or plant.arrival for dropouts)"));
        };
        let cov = super::family::own_design_point(input, &p.design, "this filter")?;
        let plant = input.plant;
        let w = cov.w();
        let mut diagnostics = serde_json::Map::new();
        let mut trace = Vec::new();
        let realization = match p.gains {
            GainsKind::Finite => finite(plant, &cov).0,
            GainsKind::Steady => {
                let st = steady(plant, &modes, &w).map_err(|e| Error::design(name, e))?;
                diagnostics.insert("stationary_probabilities".into(), st.probabilities.clone().into());
                diagnostics.insert("stationary_cost".into(), stationary_cost(plant, &st.p).into());
                diagnostics.insert("riccati_iterations".into(), st.iterations.into());
                constant(plant, &st.k)
            }
            GainsKind::Common => {
                let t = std::time::Instant::now();
                let c = common(plant, &modes, &w).map_err(|e| Error::design(name, e))?;
                diagnostics.insert("stationary_cost".into(), c.cost.into());
                diagnostics.insert("mode_dependent_stationary_cost".into(), c.mode_dependent_cost.into());
                diagnostics.insert("loss_percent".into(), (100.0 * (c.cost / c.mode_dependent_cost - 1.0)).into());
                diagnostics.insert("iterations".into(), c.trace.len().into());
                diagnostics.insert("optimization_seconds".into(), t.elapsed().as_secs_f64().into());
                trace = c.trace;
                constant(plant, &vec![c.k; modes.names.len()])
            }
        };
        let predicted = (p.gains == GainsKind::Finite).then(|| finite(plant, &cov).1);
        let mut design = Design { trace, ..super::family::exact_at_design(plant, realization, cov, diagnostics) };
        if let Some(p) = predicted {
            design.figures = Figures::of(super::family::Predicted { riccati_summed_error: p });
        }
        Ok(design)
    }
}

/// (15)–(16) on the horizon: the mode-indexed predictor and the summed error its recursion
/// predicts, Σ_k Σ_s tr(Cz P_s Czᵀ) + tr(Dz W Dzᵀ).
pub fn finite(plant: &Plant, cov: &Covariances) -> (Realization, f64) {
    let w = cov.w();
    let probs = plant.mode_probabilities();
    let q = plant.n_modes();
    let mut p: Vec<Mat> = probs[0].iter().map(|ps| cov.x0() * *ps).collect();
    let mut predicted = 0.0;
    let mut by_mode = Vec::with_capacity(plant.steps());
    for k in 0..plant.steps() {
        if plant.counts(k) {
            let pk = p.iter().fold(Mat::zeros(plant.nx(), plant.nx()), |a, x| a + x);
            predicted += (plant.cz_at(k) * pk * plant.cz_at(k).transpose() + plant.dz_at(k) * &w * plant.dz_at(k).transpose()).trace();
        }
        let (gains, next) = coupled_step(plant, k, &probs[k], &p, &w);
        by_mode.push((0..q).map(|s| predictor_gains(plant, k, s, &gains[s])).collect());
        p = next;
    }
    (estimator(plant, by_mode), predicted)
}

/// One step of (15)–(16) at step k with mode probabilities `prob`: the gains K_s and P(n+1).
fn coupled_step(plant: &Plant, k: usize, prob: &[f64], p: &[Mat], w: &Mat) -> (Vec<Mat>, Vec<Mat>) {
    let q = p.len();
    let n = plant.nx();
    let mut gains = Vec::with_capacity(q);
    let mut contrib = Vec::with_capacity(q);
    for s in 0..q {
        let (a, b, c, d) = (plant.a_of(k, s), plant.b_of(k, s), &*plant.c_of(k, s), &*plant.d_of(k, s));
        let (dwd, bwd) = (prob[s] * (d * w * d.transpose()), prob[s] * (b * w * d.transpose()));
        let inn = riccati::innovation(a, c, &p[s], &dwd, &bwd);
        contrib.push(riccati::propagate(a, &p[s], &(prob[s] * (b * w * b.transpose())), &inn.k, &inn.s));
        gains.push(inn.k);
    }
    let pi = plant.transition();
    let next = (0..q).map(|kk| symmetrize(&weighted_sum(n, n, (0..q).map(|s| (pi[(s, kk)], &contrib[s]))))).collect();
    (gains, next)
}

/// The gains of the predictor in mode s with gain K: Af = A_s − K C_s, Bf = K, Cf = Cz.
fn predictor_gains(plant: &Plant, k: usize, s: usize, kg: &Mat) -> Gains {
    Gains::predictor(plant.a_of(k, s), &plant.c_of(k, s), kg, plant.cz_at(k))
}

/// The mode-indexed state estimator with gains `by_mode[k][s]`.
fn estimator(plant: &Plant, by_mode: Vec<Vec<Gains>>) -> Realization {
    Realization::mode_indexed(plant.x0_mean.clone(), by_mode).tracking(Mat::identity(plant.nx(), plant.nx()))
}

/// The predictor with constant gains K_s at every step.
fn constant(plant: &Plant, k: &[Mat]) -> Realization {
    let by_mode = (0..plant.steps()).map(|n| (0..k.len()).map(|s| predictor_gains(plant, n, s, &k[s])).collect());
    estimator(plant, by_mode.collect())
}

/// The stationary solution (17)–(18).
pub struct Steady {
    pub k: Vec<Mat>,
    pub p: Vec<Mat>,
    pub probabilities: Vec<f64>,
    pub iterations: usize,
}

/// Iterates (16) with the stationary probabilities to its fixed point (17); the chain must be
/// ergodic and the iteration must converge (relative change below 1e-12 within 100 000 steps).
pub fn steady(plant: &Plant, modes: &Modes, w: &Mat) -> std::result::Result<Steady, String> {
    let probabilities = modes
        .stationary()
        .ok_or("the chain is not ergodic (no unique stationary distribution), so no steady-state gains exist")?;
    let q = probabilities.len();
    let k_meas = plant.horizon.max(plant.first_measurement);
    let mut p: Vec<Mat> = (0..q).map(|s| probabilities[s] * (plant.b_of(0, s) * w * plant.b_of(0, s).transpose())).collect();
    for it in 1..=100_000 {
        let (k, next) = coupled_step(plant, k_meas, &probabilities, &p, w);
        let scale = next.iter().map(|x| x.amax()).fold(1e-300, f64::max);
        let diff = next.iter().zip(&p).map(|(a, b)| (a - b).amax()).fold(0.0, f64::max);
        if !diff.is_finite() {
            break;
        }
        p = next;
        if diff <= 1e-12 * scale {
            return Ok(Steady { k, p, probabilities, iterations: it });
        }
    }
    Err("the coupled Riccati iteration (16) does not converge: the plant is not mean-square detectable with these modes".into())
}

/// Σ_s tr(Cz P_s Czᵀ), the stationary per-step error of z (Dz terms aside).
fn stationary_cost(plant: &Plant, p: &[Mat]) -> f64 {
    p.iter().map(|x| (plant.cz_at(0) * x * plant.cz_at(0).transpose()).trace()).sum()
}

/// The common-gain design.
pub struct Common {
    pub k: Mat,
    pub cost: f64,
    pub mode_dependent_cost: f64,
    pub trace: Vec<TraceRow>,
}

/// The stationary second moments P_s for one gain K: the fixed point of P = 𝓣_K(P) + N_K, solved
/// as one linear system in vec(P) (q·n² unknowns); None when 𝓣_K is not stable (spectral radius ≥ 1).
fn fixed_point(
    plant: &Plant,
    pi: &Mat,
    prob: &[f64],
    k: &Mat,
    w: &Mat,
    adjoint: bool,
    q_weight: &Mat,
) -> Option<Vec<Mat>> {
    let q = prob.len();
    let n = plant.nx();
    let kc = plant.horizon.max(plant.first_measurement);
    let m: Vec<Mat> = (0..q).map(|s| plant.a_of(0, s) - k * &*plant.c_of(kc, s)).collect();
    let dim = q * n * n;
    let mut t = Mat::zeros(dim, dim);
    for s in 0..q {
        let kron = m[s].kronecker(&m[s]);
        for kk in 0..q {
            // forward: P_kk += Π_s,kk M_s P_s M_sᵀ; adjoint: V_s += Π_s,kk M_sᵀ V_kk M_s.
            let (row, col, blk) =
                if adjoint { (s, kk, kron.transpose() * pi[(s, kk)]) } else { (kk, s, &kron * pi[(s, kk)]) };
            let mut v = t.view_mut((row * n * n, col * n * n), (n * n, n * n));
            v += blk;
        }
    }
    let rho = t.complex_eigenvalues().iter().map(|z| z.norm()).fold(0.0, f64::max);
    if !(rho < 1.0 - 1e-12) {
        return None;
    }
    let mut rhs = nalgebra::DVector::zeros(dim);
    for s in 0..q {
        if adjoint {
            // V_s = Q + …
            let mut v = rhs.rows_mut(s * n * n, n * n);
            v += nalgebra::DVector::from_column_slice(q_weight.as_slice());
        } else {
            // N_kk = Σ_s Π_s,kk p_s (B_s − K D_s) W (B_s − K D_s)ᵀ
            let bd = plant.b_of(0, s) - k * &*plant.d_of(kc, s);
            let ns = nalgebra::DVector::from_column_slice((prob[s] * (&bd * w * bd.transpose())).as_slice());
            for kk in 0..q {
                let mut v = rhs.rows_mut(kk * n * n, n * n);
                v += pi[(s, kk)] * &ns;
            }
        }
    }
    let a = Mat::identity(dim, dim) - t;
    let x = a.lu().solve(&rhs)?;
    Some((0..q).map(|s| symmetrize(&Mat::from_column_slice(n, n, x.rows(s * n * n, n * n).as_slice()))).collect())
}

/// J(K) and ∂J/∂K for the common gain.
pub fn cost_and_gradient(plant: &Plant, modes: &Modes, prob: &[f64], k: &Mat, w: &Mat) -> Option<(f64, Mat)> {
    let qz = plant.cz_at(0).transpose() * plant.cz_at(0);
    let p = fixed_point(plant, &modes.transition, prob, k, w, false, &qz)?;
    let v = fixed_point(plant, &modes.transition, prob, k, w, true, &qz)?;
    let q = prob.len();
    let kc = plant.horizon.max(plant.first_measurement);
    let mut grad = Mat::zeros(k.nrows(), k.ncols());
    for s in 0..q {
        let vbar = weighted_sum(plant.nx(), plant.nx(), (0..q).map(|kk| (modes.transition[(s, kk)], &v[kk])));
        let (c, d) = (&*plant.c_of(kc, s), &*plant.d_of(kc, s));
        let ms = plant.a_of(0, s) - k * c;
        let bd = plant.b_of(0, s) - k * d;
        grad -= 2.0 * &vbar * (&ms * &p[s] * c.transpose() + prob[s] * (&bd * w * d.transpose()));
    }
    Some((stationary_cost(plant, &p), grad))
}

/// BFGS on vec(K) from the probability-weighted mean of the steady mode-dependent gains.
pub fn common(plant: &Plant, modes: &Modes, w: &Mat) -> std::result::Result<Common, String> {
    let st = steady(plant, modes, w)?;
    let prob = st.probabilities.clone();
    let mode_dependent_cost = stationary_cost(plant, &st.p);
    let (n, ny) = (plant.nx(), plant.ny());
    let dim = n * ny;
    let mut k = weighted_sum(n, ny, prob.iter().copied().zip(&st.k));
    let (mut j, mut g) = cost_and_gradient(plant, modes, &prob, &k, w).ok_or(
        "the averaged mode-dependent gain is not mean-square stabilizing; no starting point for the common gain",
    )?;
    let mut h = Mat::identity(dim, dim);
    let mut trace = vec![TraceRow { iteration: 0, objective: j, gap: g.norm(), step: 0.0 }];
    for it in 1..=500 {
        let gv = nalgebra::DVector::from_column_slice(g.as_slice());
        if gv.norm() <= 1e-9 * (1.0 + j) {
            break;
        }
        let mut dir = -(&h * &gv);
        if dir.dot(&gv) >= 0.0 {
            h = Mat::identity(dim, dim);
            dir = -gv.clone();
        }
        let mut step = 1.0;
        let accepted = loop {
            let trial = &k + Mat::from_column_slice(n, ny, (step * &dir).as_slice());
            if let Some((jt, gt)) = cost_and_gradient(plant, modes, &prob, &trial, w) {
                if jt <= j + 1e-4 * step * gv.dot(&dir) {
                    break Some((trial, jt, gt));
                }
            }
            step *= 0.5;
            if step < 1e-20 {
                break None;
            }
        };
        let Some((kn, jn, gn)) = accepted else { break };
        let s = nalgebra::DVector::from_column_slice((&kn - &k).as_slice());
        let y = nalgebra::DVector::from_column_slice((&gn - &g).as_slice());
        let sy = s.dot(&y);
        if sy > 1e-300 {
            let rho = 1.0 / sy;
            let i = Mat::identity(dim, dim);
            h = (&i - rho * &s * y.transpose()) * &h * (&i - rho * &y * s.transpose()) + rho * &s * s.transpose();
        }
        let done = (j - jn).abs() <= 1e-15 * j.abs();
        k = kn;
        j = jn;
        g = gn;
        trace.push(TraceRow { iteration: it, objective: j, gap: g.norm(), step });
        if done {
            break;
        }
    }
    Ok(Common { k, cost: j, mode_dependent_cost, trace })
}
