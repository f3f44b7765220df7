//! A certified upper bound on the maximum of a convex quadratic |A u|² over a product of balls
//! (seed 000 §5: the deterministic part of a linear filter's error over the disturbances of
//! eq (36), several blocks and per-step bounds of (33) included), by the S-procedure dual solved
//! with clarabel and made exactly feasible afterwards.
//!
//! The coordinates of u are split into groups (one per disturbance block), each a run of `steps`
//! pieces of `size` entries, with per-piece bounds |u_{g,k}|² ≤ r_{g,k} and/or a summed bound
//! Σ_k |u_{g,k}|² ≤ R_g. For any multipliers μ ≥ 0 with D(μ) = Σ_i μ_i P_i ⪰ AᵀA (P_i the 0/1
//! diagonal projector of constraint i) and any admissible u,
//!
//! ```text
//! |A u|² = uᵀ AᵀA u ≤ uᵀ D(μ) u = Σ_i μ_i uᵀ P_i u ≤ Σ_i μ_i c_i      (c_i = r_{g,k} or R_g),
//! ```
//!
//! so Σ_i c_i μ_i is an upper bound whatever μ is, optimal or not: weak Lagrangian duality, valid
//! for any number of groups and constraints. With one constraint (one block, the summed bound
//! alone) its minimum is R·λmax(AᵀA), the exact maximum; with several it may exceed the maximum
//! (a convex quadratic over a product of balls is not a convex problem; the S-lemma is lossless
//! only for one constraint).
//!
//! The dual is solved with clarabel: as one n×n PSD constraint for small n, else by cutting planes
//! whose relaxations are LPs (`cutting_planes`); either way the solver reports a lower bound on
//! the optimum beside its μ̂. (Coordinates under a zero bound are 0 and leave the problem first.)
//! The solver's μ̂ is only feasible to its tolerance, so it is certified: with Ŝ = D(μ̂) − M̂
//! computed in floating point, raise a covering set of multipliers (per group the summed one, or
//! every per-piece one, whichever costs less: both add the identity on the group) by the most
//! negative eigenvalue of Ŝ plus a rounding margin. In the whitened coordinates u of the callers each
//! constraint's matrix is an identity on its pieces, so the metric of the blocks is the Euclidean
//! one and the raise is a plain eigenvalue. The raised μ is then checked (not assumed) to satisfy
//!
//! ```text
//! λ̂min(Ŝ) ≥ p(n)·ε·‖Ŝ‖_F + 2ε(‖D‖_F + ‖M̂‖_F) + γ_r‖A‖_F²,
//! ```
//!
//! which implies D(μ) ⪰ AᵀA exactly: the computed eigenvalue is within p(n)·ε·‖Ŝ‖₂ of the true one
//! (a backward-stable symmetric eigensolver, |λ̂ − λ| ≤ p(n)·ε·‖Ŝ‖₂ by Weyl's inequality; the
//! project's one bound of it, `numerics::accuracy::eigenvalue_error`, takes p(n) = n),
//! forming Ŝ entry by entry costs at most 2ε(|D| + |M̂|), and M̂ = fl(AᵀA) differs from AᵀA by at
//! most γ_r |A|ᵀ|A| entrywise, γ_r = rε/(1 − rε) for r rows (‖·‖₂ ≤ ‖·‖_F bounds every norm). The
//! sum Σ c_i μ_i of nonnegative terms is finally rounded up by its own error bound. The bound is
//! thus for the computed A; A's own rounding is that of the recursion that produced it.

use super::conic::{Conic, Tuning};
use crate::numerics::linalg::Mat;

/// One group of coordinates: `steps` consecutive pieces of `size` entries from `offset`, with the
/// per-piece bounds |u_k|² ≤ step\[k] and/or the summed bound Σ_k |u_k|² ≤ total.
#[derive(Clone, Debug)]
pub struct BallGroup {
    pub offset: usize,
    pub size: usize,
    pub steps: usize,
    pub step: Option<Vec<f64>>,
    pub total: Option<f64>,
}

/// A certified bound and what the solver reported.
#[derive(Clone, Debug)]
pub struct CertifiedBound {
    /// Σ c_i μ_i at the certified multipliers: ≥ max |A u|² over the product of balls.
    pub value: f64,
    /// A lower bound on the S-procedure's optimum, to clarabel's accuracy: the dual objective of
    /// the SDP, or the last relaxation of the cutting planes. `value − lower` is the reported gap.
    pub lower: f64,
    /// clarabel's relative primal and dual residuals at the last solve, the larger.
    pub residual: f64,
    /// How much the covering multipliers were raised (the eigenvalue shift plus the margin).
    pub shift: f64,
    /// The rounding margin of the certificate (module docs).
    pub margin: f64,
    /// clarabel's iterations (the SDP's, or the cutting planes' rounds).
    pub iterations: u32,
}

/// Multipliers from a solver, before the certificate.
struct Solved {
    mu: Vec<f64>,
    lower: f64,
    residual: f64,
    iterations: u32,
}

/// Above this many coordinates the SDP is not solved as one n×n PSD constraint: clarabel's KKT
/// system then holds a dense (n(n+1)/2)² block (a 126-coordinate problem ran for over ten minutes,
/// a 42-coordinate one took 3 s), and the cutting planes take over.
const DIRECT_MAX: usize = 24;
/// Rounds of the cutting planes, and the relative gap at which they stop. Two multipliers (two
/// blocks with summed bounds) take about 17 rounds; forty (per-step bounds on 126 coordinates)
/// leave a gap of about 1e-6 after 150, still a certified bound, with the gap reported.
const CUT_ROUNDS: usize = 150;
const CUT_GAP: f64 = 1e-10;
/// Cuts added per round: the eigenvectors of the most negative eigenvalues of the slack.
const CUTS_PER_ROUND: usize = 8;

/// The diagonal of D(μ) = Σ_i μ_i P_i.
fn diagonal(cons: &[(f64, Vec<usize>)], mu: &[f64], n: usize) -> Vec<f64> {
    let mut d = vec![0.0; n];
    for (i, (_, idx)) in cons.iter().enumerate() {
        idx.iter().for_each(|&j| d[j] += mu[i]);
    }
    d
}

/// The S-procedure SDP min cᵀμ s.t. D(μ) ⪰ M, μ ≥ 0, as one PSD constraint.
fn direct(mm: &Mat, cons: &[(f64, Vec<usize>)], cost: &[f64], tuning: &Tuning) -> Result<Solved, String> {
    let n = mm.nrows();
    let unit = |idx: &[usize]| {
        let mut e = Mat::zeros(n, n);
        idx.iter().for_each(|&i| e[(i, i)] = 1.0);
        e
    };
    let terms: Vec<(usize, Mat)> = cons.iter().enumerate().map(|(i, (_, idx))| (i, unit(idx))).collect();
    let mut p = Conic::default();
    p.nonnegative((0..cost.len()).map(|i| (0.0, vec![(i, 1.0)])).collect());
    p.psd(&-mm, &terms);
    let sol = p.minimize_tuned(cost, tuning).map_err(|f| format!("the S-procedure SDP failed: {f}"))?;
    Ok(Solved { mu: sol.x, lower: sol.dual_objective, residual: sol.residual, iterations: sol.iterations })
}

/// The same SDP by Kelley's cutting planes, each relaxation an LP solved by clarabel: D(μ) ⪰ M is
/// the family of linear constraints Σ_i μ_i |P_i v|² ≥ vᵀ M v over all v; each round adds the
/// ones of the slack's most negative eigenvectors at the relaxation's μ. Each relaxation's value
/// is a lower bound on the optimum; the best μ raised onto feasibility (as the certificate does)
/// an upper one; the rounds stop when they meet to [`CUT_GAP`]. The multipliers are boxed by
/// c_i μ_i ≤ the cost of one feasible μ (every group's cover at λmax(M)), which no optimum
/// exceeds. Cost per round: one n×n eigendecomposition and an LP in the few multipliers.
fn cutting_planes(
    mm: &Mat,
    cons: &[(f64, Vec<usize>)],
    cost: &[f64],
    covers: &[Vec<usize>],
    tuning: &Tuning,
) -> Result<Solved, String> {
    let n = mm.nrows();
    let k = cost.len();
    let raised = |mu: &[f64], by: f64| {
        let mut out = mu.to_vec();
        covers.iter().flatten().for_each(|&i| out[i] += by);
        out
    };
    let value = |mu: &[f64]| cost.iter().zip(mu).map(|(c, m)| c * m).sum::<f64>();
    let (top, vectors) = crate::numerics::linalg::sym_eigen(mm).map_err(|e| e.to_string())?;
    let lmax = top.last().copied().unwrap_or(0.0).max(0.0);
    let mut best = raised(&vec![0.0; k], lmax);
    let mut upper = value(&best);
    let cap: Vec<f64> = cost.iter().map(|c| if *c > 0.0 { upper / c } else { 0.0 }).collect();
    let cut = |v: &[f64]| -> (f64, Vec<(usize, f64)>) {
        let rhs: f64 = (0..n).map(|i| v[i] * (0..n).map(|j| mm[(i, j)] * v[j]).sum::<f64>()).sum();
        let coef = cons.iter().enumerate().map(|(i, (_, idx))| (i, idx.iter().map(|&j| v[j] * v[j]).sum())).collect();
        (-rhs, coef)
    };
    let mut cuts: Vec<(f64, Vec<(usize, f64)>)> = (0..n.min(CUTS_PER_ROUND))
        .map(|i| cut(&vectors.column(n - 1 - i).iter().copied().collect::<Vec<_>>()))
        .collect();
    let (mut lower, mut residual, mut rounds) = (0.0, 0.0, 0);
    for _ in 0..CUT_ROUNDS {
        rounds += 1;
        let mut p = Conic::default();
        let mut rows = cuts.clone();
        rows.extend((0..k).map(|i| (0.0, vec![(i, 1.0)])));
        rows.extend((0..k).map(|i| (cap[i], vec![(i, -1.0)])));
        p.nonnegative(rows);
        let sol =
            p.minimize_tuned(cost, tuning).map_err(|f| format!("the S-procedure relaxation (an LP) failed: {f}"))?;
        lower = sol.dual_objective;
        residual = sol.residual;
        let mu: Vec<f64> = sol.x.iter().map(|v| v.max(0.0)).collect();
        let d = diagonal(cons, &mu, n);
        let mut slack = -mm;
        d.iter().enumerate().for_each(|(i, v)| slack[(i, i)] += v);
        let (lam, vecs) = crate::numerics::linalg::sym_eigen(&slack).map_err(|e| e.to_string())?;
        let candidate = raised(&mu, (-lam[0]).max(0.0));
        if value(&candidate) < upper {
            upper = value(&candidate);
            best = candidate;
        }
        if upper - lower <= CUT_GAP * upper.abs() {
            break;
        }
        for (i, l) in lam.iter().enumerate().take(CUTS_PER_ROUND) {
            if *l < 0.0 {
                cuts.push(cut(&vecs.column(i).iter().copied().collect::<Vec<_>>()));
            }
        }
    }
    Ok(Solved { mu: best, lower, residual, iterations: rounds })
}

/// Tries of the certificate: the margin doubles after each failed check.
const CERTIFY_TRIES: usize = 4;

/// The certified S-procedure bound on max |A u|² over the groups' balls (module docs). The groups
/// must cover A's columns exactly once and each carry at least one bound. A failed solve, or a
/// certificate that does not check, is an error naming the cause.
pub fn quadratic_max_bound(a: &Mat, groups: &[BallGroup], tuning: &Tuning) -> Result<CertifiedBound, String> {
    let n = a.ncols();
    let mut covered = vec![false; n];
    for g in groups {
        if g.step.is_none() && g.total.is_none() {
            return Err("a group of the S-procedure bound has neither per-step nor summed bounds".into());
        }
        if g.step.as_ref().is_some_and(|r| r.len() != g.steps) || g.offset + g.size * g.steps > n {
            return Err("a group of the S-procedure bound does not fit the matrix".into());
        }
        for c in &mut covered[g.offset..g.offset + g.size * g.steps] {
            if *c {
                return Err("groups of the S-procedure bound overlap".into());
            }
            *c = true;
        }
    }
    if covered.iter().any(|c| !c) {
        return Err("the groups of the S-procedure bound do not cover every coordinate".into());
    }
    if a.iter().any(|v| !v.is_finite()) {
        return Err("the quadratic form is not finite".into());
    }
    // The constraints: (cost c_i, the coordinates where P_i has its ones).
    let mut cons: Vec<(f64, Vec<usize>)> = Vec::new();
    // Per group, the options of constraints whose sum is the identity on it.
    let mut options: Vec<Vec<Vec<usize>>> = Vec::new();
    for g in groups {
        let mut opts = Vec::new();
        if let Some(r) = &g.step {
            let first = cons.len();
            cons.extend(
                r.iter().enumerate().map(|(k, r)| (*r, (g.offset + k * g.size..g.offset + (k + 1) * g.size).collect())),
            );
            opts.push((first..cons.len()).collect());
        }
        if let Some(t) = g.total {
            cons.push((t, (g.offset..g.offset + g.size * g.steps).collect()));
            opts.push(vec![cons.len() - 1]);
        }
        options.push(opts);
    }
    if let Some((c, _)) = cons.iter().find(|(c, _)| !(c.is_finite() && *c >= 0.0)) {
        return Err(format!("a bound of the S-procedure is {c}, not a finite number ≥ 0"));
    }
    // A zero bound pins its coordinates to 0: they leave the problem, and so does every constraint
    // with nothing left (a multiplier of zero cost would leave the SDP without a bounded optimum).
    let mut dead = vec![false; n];
    for (c, idx) in &cons {
        if *c == 0.0 {
            idx.iter().for_each(|&i| dead[i] = true);
        }
    }
    let live: Vec<usize> = (0..n).filter(|&i| !dead[i]).collect();
    let mut position = vec![usize::MAX; n];
    live.iter().enumerate().for_each(|(p, &i)| position[i] = p);
    let mut kept = vec![usize::MAX; cons.len()];
    let mut reduced: Vec<(f64, Vec<usize>)> = Vec::new();
    for (i, (c, idx)) in cons.iter().enumerate() {
        let idx: Vec<usize> = idx.iter().filter(|&&j| !dead[j]).map(|&j| position[j]).collect();
        if !idx.is_empty() {
            kept[i] = reduced.len();
            reduced.push((*c, idx));
        }
    }
    // Per group, the cheaper option that covers its live coordinates.
    let covers: Vec<Vec<usize>> = options
        .iter()
        .map(|opts| {
            opts.iter()
                .map(|o| o.iter().filter(|&&i| kept[i] != usize::MAX).map(|&i| kept[i]).collect::<Vec<_>>())
                .min_by(|x, y| {
                    let cost = |o: &Vec<usize>| o.iter().map(|&i| reduced[i].0).sum::<f64>();
                    cost(x).total_cmp(&cost(y))
                })
                .expect("checked above")
        })
        .collect();
    let cons = reduced;
    let n = live.len();
    let a = a.select_columns(live.iter());
    if n == 0 {
        return Ok(CertifiedBound { value: 0.0, lower: 0.0, residual: 0.0, shift: 0.0, margin: 0.0, iterations: 0 });
    }
    let mm = a.transpose() * &a;
    let cost: Vec<f64> = cons.iter().map(|c| c.0).collect();
    let solved = if n <= DIRECT_MAX {
        direct(&mm, &cons, &cost, tuning)?
    } else {
        cutting_planes(&mm, &cons, &cost, &covers, tuning)?
    };
    let mut mu: Vec<f64> = solved.mu.iter().map(|v| v.max(0.0)).collect();

    let eps = f64::EPSILON;
    let rows = a.nrows() as f64;
    let gamma_r = rows * eps / (1.0 - rows * eps);
    let product_error = gamma_r * a.norm_squared();
    let diag = |mu: &[f64]| diagonal(&cons, mu, n);
    // λ̂min(Ŝ) and the margin the check asks of it.
    let check = |mu: &[f64]| {
        let d = diag(mu);
        let mut s = -&mm;
        for (i, v) in d.iter().enumerate() {
            s[(i, i)] += v;
        }
        let lambda = crate::numerics::linalg::min_eigenvalue(&s);
        let d_norm = d.iter().map(|v| v * v).sum::<f64>().sqrt();
        (lambda, crate::numerics::accuracy::eigenvalue_error(&s) + 2.0 * eps * (d_norm + mm.norm()) + product_error)
    };
    let (lambda, mut margin) = check(&mu);
    let mut shift = (-lambda).max(0.0) + margin;
    let base = mu.clone();
    for _ in 0..CERTIFY_TRIES {
        mu = base.clone();
        for ids in &covers {
            for &i in ids {
                mu[i] += shift;
            }
        }
        let (l, need) = check(&mu);
        if l >= need {
            let terms = cost.iter().zip(&mu).map(|(c, m)| c * m);
            let sum: f64 = terms.sum();
            let rounding = 1.0 + 2.0 * (cost.len() + 1) as f64 * eps;
            return Ok(CertifiedBound {
                value: sum * rounding,
                lower: solved.lower,
                residual: solved.residual,
                shift,
                margin,
                iterations: solved.iterations,
            });
        }
        margin *= 2.0;
        shift = (-lambda).max(0.0) + margin;
    }
    Err(format!(
        "the S-procedure multipliers could not be certified feasible (smallest eigenvalue of the slack {lambda:e} \
         after {CERTIFY_TRIES} raises)"
    ))
}
