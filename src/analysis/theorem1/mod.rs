//! Seed 003's Theorem 1, (4.25)–(4.29): the LMIs that bound the a-anisotropic norm of a system with
//! multiplicative noise, X(k+1) = 𝒜(k) X + ℬ(k) w, z̃ = 𝒞(k) X + 𝒟(k) w with
//! (𝒜, ℬ, 𝒞, 𝒟)(k) = (𝒜₀, ℬ₀, 𝒞₀, 𝒟₀) + Σᵢ ζᵢ(k) (𝒜ᵢ, ℬᵢ, 𝒞ᵢ, 𝒟ᵢ), ζᵢ(k) zero-mean, unit variance,
//! independent over i and k.
//!
//! One piece of code writes them for the analysis of a given filter ([`analyze`]: the filter's
//! matrices are data, the LMIs are linear in P(k), Ψ(k), η, γ²) and for every synthesis of
//! `families::anisotropic` (the filter's matrices enter through each structure's change of
//! variables): a caller gives, per step, P(k), P(k+1) and the products P(k+1)𝒜ᵢ, P(k+1)ℬᵢ, 𝒞ᵢ, 𝒟ᵢ as
//! affine matrices, and `Conditions::add` writes
//!
//! ```text
//! (4.25)  [[P(k), ·, ·, ·], [0, ηI, ·, ·], [P'𝒜ᵢ, P'ℬᵢ, P', ·]ᵢ, [𝒞ᵢ, 𝒟ᵢ, 0, I]ᵢ] ⪰ 0
//! (4.27)  [[ηI − Ψ(k), ·, ·], [P'ℬᵢ, P', ·]ᵢ, [𝒟ᵢ, 0, I]ᵢ] ⪰ 0
//! (4.26), (4.28): the same at k = N with P(N+1) = 0
//! (4.29)  ∏ det Ψ(k) ≥ e^{2a} (η − γ²)^{lw},  lw = mw(N+1)
//! ```
//!
//! **One row per factor, carrying all four matrices.** The paper writes 𝒜ᵢ, ℬᵢ, 𝒞ᵢ, 𝒟ᵢ in separate
//! rows, which is exact when every matrix has its own factors ((4.12)–(4.13) and the condition
//! (4.14) HGᵀ = 0 that keeps them independent). Here a factor that multiplies several matrices (the
//! shared ζ of (2.1); a dropout enters 𝒜 and 𝒞 of a filtering structure at once) has one block row
//! [P'𝒜ᵢ, P'ℬᵢ; 𝒞ᵢ, 𝒟ᵢ]: the Schur complement of (4.25) is then
//! diag(P, ηI) − Σᵢ [𝒜ᵢ ℬᵢ; 𝒞ᵢ 𝒟ᵢ]ᵀ diag(P', I) [𝒜ᵢ ℬᵢ; 𝒞ᵢ 𝒟ᵢ] ⪰ 0, which is η times the Riccati
//! inequality (4.21)–(4.23) with E\[·] taken over the correlated factors exactly, so (4.14) is not
//! needed. The bound itself (Lemma 1 with R = R1 + R2 and Jensen on the mean) is derived in the
//! module docs of `families::anisotropic`.
//!
//! **The determinant condition in clarabel.** det Ψ ≥ ∏ Z_ii for every lower-triangular Z with
//! [[Ψ, Z], [Zᵀ, Diag Z]] ⪰ 0 (PSD cone), and the geometric mean of the lw diagonal entries is
//! bounded below by a binary tree of rotated second-order cones u² ≤ ab, padded with copies of the
//! bound itself to a power of two. At a = ∞ (H∞) the condition forces η = γ² and Ψ drops out. At
//! a = 0 the infimum lies at η → ∞, and the program written is that limit (`Conditions::h2_limit`):
//! (4.25) without its η row and column, (4.27) with N(k) in place of ηI − Ψ(k), and Σₖ tr N(k)/lw
//! minimized — no determinant condition.

use std::time::Instant;

use crate::analysis::exact::{Augmented, augmented};
use crate::error::{Error, Result};
use crate::filter::realization::Realization;
use crate::model::plant::Plant;
use crate::numerics::linalg::{Mat, symmetrize, symmetrize_mut};
use crate::numerics::solve::affine::{AffMat, Vars};
use crate::numerics::solve::conic::{Conic, Failure, Tuning};
use crate::numerics::solve::line::{bisect, minimize_on_open};

mod conditions;

pub use conditions::Level;
pub(crate) use conditions::{Conditions, Step, Term};

/// What Theorem 1 certifies for a given filter by [`analyze_sdp`]: the least γ² clarabel finds for
/// (4.25)–(4.29) over P(k), Ψ(k), η, and the size and cost of the program.
#[derive(Clone, Debug)]
pub struct SdpAnalysis {
    pub gamma_sq: f64,
    /// clarabel's first-order bound on |γ² − the program's optimum| (`Solution::objective_error`).
    pub objective_error: f64,
    /// clarabel stopped at its reduced tolerances (AlmostSolved).
    pub almost: bool,
    pub iterations: u32,
    pub variables: usize,
    pub rows: usize,
    pub seconds: f64,
}

/// What Theorem 1 certifies for a given filter by [`analyze`]: the least γ² of (4.25)–(4.29), the q
/// that attains it, a bound on the rounding error of γ² at that q, and the time taken.
#[derive(Clone, Copy, Debug)]
pub struct Analysis {
    pub gamma_sq: f64,
    pub q: f64,
    /// First-order bound on |computed γ²(q) − γ²(q)| ([`analyze`]'s error analysis).
    pub error: f64,
    pub seconds: f64,
}

impl Analysis {
    /// The certified bound: γ²(q) rounded up past its error. Theorem 1 proves |||F|||²_a ≤ γ²(q)
    /// for every q at which every S̃(k) ≻ 0, and [`analyze`] only accepts a q whose S̃(k) are
    /// positive definite by more than their eigenvalues' error, so this is a bound on the filter's
    /// norm, not a value within a tolerance of one. At a = 0 (q = 0) γ² is the exact |||F|||²₀ and
    /// the error its recursion's, so this is again a bound.
    pub fn certified(&self) -> f64 {
        crate::numerics::accuracy::round_up(self.gamma_sq, self.error)
    }
}

/// Theorem 1 as an analysis condition: the filter `real` is given, so (4.25)–(4.29) are LMIs in a
/// full P(k) on the augmented state ξ = (x, s) of [`crate::analysis::exact`] (no restriction of P,
/// unlike the syntheses), and their least γ² bounds |||F|||²_a from above. The error system's terms
/// are the factors' (seed 003 (2.1)) and, on a plant with dropouts, the mode's deviation from its
/// mean: with θ\[k] independent over k, Σⱼ pⱼ 𝒜ⱼᵀR𝒜ⱼ = 𝒜̄ᵀR𝒜̄ + Σⱼ pⱼ(𝒜ⱼ − 𝒜̄)ᵀR(𝒜ⱼ − 𝒜̄). Refuses a
/// Markov plant (noise with memory is outside seed 003).
pub fn analyze_sdp(plant: &Plant, real: &Realization, level: Level) -> Result<SdpAnalysis> {
    if plant.switches() && !plant.independent_modes() {
        return Err(Error::invalid(
            "modes",
            "Theorem 1 of seed 003 needs noise independent over time; a Markov-switching plant has memory",
        ));
    }
    let probs = plant.mode_probabilities();
    let mw = plant.nw();
    let mut vars = Vars::default();
    let mut cond = Conditions::new(&mut vars, level);
    let n = plant.nx() + real.ns();
    let p: Vec<AffMat> = (0..plant.steps()).map(|_| vars.symmetric(n)).collect();
    cond.determinant_variables(&mut vars, plant.steps(), mw);
    let steps: Vec<Step> = (0..plant.steps())
        .map(|k| {
            let next = (k < plant.horizon).then(|| p[k + 1].clone());
            let counted = if plant.counts(k) { 1.0 } else { 0.0 };
            let terms = error_terms(plant, real, k, &probs[k])
                .into_iter()
                .map(|a| {
                    let some = |m: Mat| (m.amax() != 0.0).then(|| AffMat::constant(m));
                    Term {
                        pa: next.as_ref().and_then(|pn| (a.f.amax() != 0.0).then(|| pn.rmul(&a.f))),
                        pb: next.as_ref().and_then(|pn| (a.e.amax() != 0.0).then(|| pn.rmul(&a.e))),
                        c: some(a.h * counted),
                        d: some(a.g * counted),
                    }
                })
                .collect();
            Step { p: p[k].clone(), next, terms, extra_psd: Vec::new() }
        })
        .collect();
    let mut conic = Conic::default();
    cond.add(&mut vars, &mut conic, &steps, mw);
    let cost = cond.cost(vars.count);
    let (rows, _) = conic.size();
    let t = Instant::now();
    let sol = conic
        .minimize_tuned(&cost, &Tuning::default())
        .or_else(|_| conic.minimize_tuned(&cost, &Tuning::robust()))
        .map_err(|f: Failure| Error::invalid("anisotropy", format!("Theorem 1's analysis LMIs (4.25)–(4.29): {f}")))?;
    Ok(SdpAnalysis {
        gamma_sq: cond.gamma_sq(&sol.x),
        objective_error: sol.objective_error,
        almost: sol.almost,
        iterations: sol.iterations,
        variables: vars.count,
        rows,
        seconds: t.elapsed().as_secs_f64(),
    })
}

/// The error system of step k as a mean and zero-mean unit-variance terms: the mode's deviation
/// (one term √(p₀p₁)(𝒜₁ − 𝒜₀) for dropouts, √pⱼ(𝒜ⱼ − 𝒜̄) per mode otherwise) and every factor's
/// term (weighted √pⱼ per mode when the filter reads the mode, once otherwise).
fn error_terms(plant: &Plant, real: &Realization, k: usize, probs: &[f64]) -> Vec<Augmented> {
    let augs: Vec<Augmented> = (0..plant.n_modes()).map(|j| augmented(plant, real, k, j)).collect();
    let combine = |w: &[(f64, &Augmented)]| -> Augmented {
        let mut out = augs[0].clone();
        out.terms.clear();
        out.f *= 0.0;
        out.e *= 0.0;
        out.h *= 0.0;
        out.g *= 0.0;
        for (c, a) in w {
            out.f += &a.f * *c;
            out.e += &a.e * *c;
            out.h += &a.h * *c;
            out.g += &a.g * *c;
        }
        out
    };
    let weighted: Vec<(f64, &Augmented)> = probs.iter().copied().zip(&augs).collect();
    let mean = combine(&weighted);
    let mut out = vec![mean.clone()];
    match augs.len() {
        1 => {}
        2 => out.push(combine(&[(-(probs[0] * probs[1]).sqrt(), &augs[0]), ((probs[0] * probs[1]).sqrt(), &augs[1])])),
        _ => out.extend(augs.iter().zip(probs).map(|(a, p)| combine(&[(p.sqrt(), a), (-p.sqrt(), &mean)]))),
    }
    if real.is_mode_indexed() {
        for (a, p) in augs.iter().zip(probs) {
            out.extend(a.terms.iter().map(|t| combine(&[(p.sqrt(), t)])));
        }
    } else {
        out.extend(augs[0].terms.iter().cloned());
    }
    out
}

/// What Theorem 1 certifies for a given filter, found exactly: for a fixed q = 1/η the least
/// solution of (4.25) is the Riccati equation (4.21)–(4.23) with equality, R(N+1) = 0,
///
/// ```text
/// S̃(k) = I − E[ℬᵀR'ℬ + q𝒟ᵀ𝒟],  L̃(k) = E[ℬᵀR'𝒜 + q𝒟ᵀ𝒞],  R(k) = E[𝒜ᵀR'𝒜 + q𝒞ᵀ𝒞] + L̃ᵀS̃⁻¹L̃,
/// ```
///
/// (every right-hand side grows with R', so the least R(k+1) gives the largest S̃(k) at every step
/// at once — the monotonicity the paper invokes below (4.24)), Ψ(k) = ηS̃(k) is the best Ψ, and
/// (4.29) then gives γ²(q) = (1 − e^{(Σₖ ln det S̃(k) − 2a)/lw})/q. The least γ² over q ∈ (0, q̄),
/// q̄ = sup{q : every S̃ ≻ 0}, is Theorem 1's bound for this filter with a full P(k); at a = ∞ it is
/// 1/q̄. This is the optimum of the LMIs [`analyze_sdp`] hands to clarabel. At a = 0 the optimum is
/// the limit q → 0 (η → ∞): R is carried divided by q, and the bound tends to
/// tr E\[ℬᵀR̃ℬ + 𝒟ᵀ𝒟]/lw = ‖F‖₂²/lw, the exact H2 limit (Jensen's gap vanishes with the quadratic
/// term), which is returned directly (q = 0) with its own error bound; it is also the optimum of
/// the H2 limit program the synthesis and [`analyze_sdp`] write at a = 0.
///
/// **Error analysis.** Each step forms R(k) from R(k+1) by a fixed number of products of
/// (n_ξ × n_ξ) and (n_ξ × m_w) matrices, a relative rounding of about n_ξ ε; carried through the m
/// steps after k by a stable error system, R(k)'s relative error is at most about m n_ξ ε to first
/// order, and so is that of N̂(k) = E\[ℬᵀR̃'ℬ + 𝒟ᵀ𝒟], whose eigenvalues μ are computed to
/// [`crate::numerics::accuracy::eigenvalue_error`] besides. So each μ carries an error
/// δμ = (m + 1) n ε ‖N̂(k)‖_F (n = max(n_ξ, m_w)); a q is accepted only where q(μ + δμ) < 1 for every
/// μ (S̃ ≻ 0 for certain), ln det S̃ errs by at most Σ qδμ/(1 − q(μ + δμ)), and γ²(q) by e^L/q times
/// the summed error over lw (L the exponent of γ²(q)), plus the last roundings.
pub fn analyze(plant: &Plant, real: &Realization, level: Level) -> Result<Analysis> {
    if plant.switches() && !plant.independent_modes() {
        return Err(Error::invalid(
            "modes",
            "Theorem 1 of seed 003 needs noise independent over time; a Markov-switching plant has memory",
        ));
    }
    let t = Instant::now();
    let probs = plant.mode_probabilities();
    let steps: Vec<Vec<Augmented>> = (0..plant.steps())
        .map(|k| {
            let counted = if plant.counts(k) { 1.0 } else { 0.0 };
            error_terms(plant, real, k, &probs[k])
                .into_iter()
                .map(|mut a| {
                    a.h *= counted;
                    a.g *= counted;
                    a
                })
                .collect()
        })
        .collect();
    let lw = (plant.nw() * plant.steps()) as f64;
    let n = plant.nx() + real.ns();
    let passes: Vec<RiccatiStep> = steps.iter().rev().map(|terms| RiccatiStep::new(terms)).collect();
    let nw = passes.first().map_or(0, |p| p.gg.nrows());
    // The q search runs about 150 passes over the N + 1 steps: one workspace for all of them.
    let work = std::cell::RefCell::new(Work::new(n, nw));
    // Σ ln det S̃(k) at q and its error bound, or None when some S̃(k) is not positive definite
    // beyond its eigenvalues' error.
    let ln_det = |q: f64| -> Option<(f64, f64)> {
        let w = &mut *work.borrow_mut();
        w.r.fill(0.0);
        let mut total = 0.0;
        let mut error = 0.0;
        for (after, step) in passes.iter().enumerate() {
            step.moments(w);
            // S̃ = I − qN̂ with N̂ = N/q's eigenvalues μ: ln det S̃ = Σ ln(1 − qμ) by log1p, which
            // keeps its digits for the q ~ 1e-12 q̄ where the a = 0 bound is taken.
            let eig = symmetrize(&w.nn).symmetric_eigen();
            let dmu = (after + 1) as f64 * crate::numerics::accuracy::eigenvalue_error_of(n.max(nw), w.nn.norm());
            if eig.eigenvalues.iter().any(|m| q * (m + dmu) >= 1.0) {
                return None;
            }
            total += eig.eigenvalues.iter().map(|m| (-q * m).ln_1p()).sum::<f64>();
            error += eig.eigenvalues.iter().map(|m| q * dmu / (1.0 - q * (m + dmu)) + f64::EPSILON).sum::<f64>();
            // S̃⁻¹ = V diag(1/(1 − qμ)) Vᵀ.
            w.vd.copy_from(&eig.eigenvectors);
            for (mut col, m) in w.vd.column_iter_mut().zip(eig.eigenvalues.iter()) {
                col /= 1.0 - q * m;
            }
            w.s_inv.gemm(1.0, &w.vd, &eig.eigenvectors.transpose(), 0.0);
            // R̃ = R/q: R̃(k) = E[𝒜ᵀR̃'𝒜 + 𝒞ᵀ𝒞] + q L̂ᵀ S̃⁻¹ L̂ with L̂ = L̃/q.
            w.sb.gemm(1.0, &w.s_inv, &w.bb, 0.0);
            w.r.copy_from(&w.rr);
            w.r.gemm_tr(q, &w.bb, &w.sb, 1.0);
            symmetrize_mut(&mut w.r);
            if !w.r.iter().all(|v| v.is_finite()) {
                return None;
            }
        }
        Some((total, error))
    };
    let trace = {
        let mut r = Mat::zeros(n, n);
        let mut tr = 0.0;
        for terms in steps.iter().rev() {
            let mut rr = Mat::zeros(n, n);
            for a in terms {
                tr += (a.e.transpose() * &r * &a.e + a.g.transpose() * &a.g).trace();
                rr += a.f.transpose() * &r * &a.f + a.h.transpose() * &a.h;
            }
            r = rr;
        }
        tr
    };
    if !(trace > 0.0) {
        return Ok(Analysis { gamma_sq: 0.0, q: 0.0, error: 0.0, seconds: t.elapsed().as_secs_f64() });
    }
    if level == Level::Anisotropy(0.0) {
        // The limit q → 0 itself, tr Λ/lw = ‖F‖₂²/lw: the only input of anisotropy 0 is white and
        // isotropic, so this is the exact |||F|||²₀ and no q is needed. Its error is the analysis
        // above summed over the steps: tr N̂(k) to (m + 1) n ε of itself (‖N̂‖_F ≤ tr N̂ for N̂ ⪰ 0),
        // m + 1 ≤ N + 1, then the division by lw.
        let nw = plant.nw();
        let gamma_sq = trace / lw;
        let error =
            crate::numerics::accuracy::recursion_error(plant.steps(), n.max(nw), gamma_sq) + f64::EPSILON * gamma_sq;
        return Ok(Analysis { gamma_sq, q: 0.0, error, seconds: t.elapsed().as_secs_f64() });
    }
    // q̄ ≤ 1/λmax(Λ) ≤ lw/tr Λ (Theorem 1's H∞ bound 1/q̄ is at least the exact λmax), and every
    // S̃ = I at q = 0.
    let (q_bar, _) =
        bisect(0.0, 2.0 * lw / trace, |q| ln_det(q).is_some(), |lo, hi| hi - lo <= 4.0 * f64::EPSILON * hi, 400);
    let (gamma_sq, q, error) = match level {
        // 1/q̄ with every S̃(q̄) ≻ 0 beyond its error: only the division rounds.
        Level::Hinf => (1.0 / q_bar, q_bar, 2.0 * f64::EPSILON / q_bar),
        Level::Anisotropy(a) => {
            let at = |q: f64| ln_det(q).map_or(f64::INFINITY, |(ld, _)| -((ld - 2.0 * a) / lw).exp_m1() / q);
            let (gamma_sq, q) = minimize_on_open(&at, q_bar);
            let (ld, ld_error) = ln_det(q).expect("the minimizer is a feasible q");
            let l = (ld - 2.0 * a) / lw;
            (gamma_sq, q, l.exp() / q * ld_error / lw + 4.0 * f64::EPSILON * gamma_sq.abs())
        }
    };
    Ok(Analysis { gamma_sq, q, error, seconds: t.elapsed().as_secs_f64() })
}

/// One step of [`analyze`]'s Riccati pass: its terms (𝒜, ℬ) and the sums over the terms that do not
/// depend on R', E[𝒟ᵀ𝒟], E[𝒟ᵀ𝒞], E[𝒞ᵀ𝒞].
struct RiccatiStep {
    /// (𝒜, ℬ) of each term.
    terms: Vec<(Mat, Mat)>,
    gg: Mat,
    gh: Mat,
    hh: Mat,
}

impl RiccatiStep {
    fn new(terms: &[Augmented]) -> Self {
        let (nw, n) = (terms[0].e.ncols(), terms[0].f.ncols());
        let (mut gg, mut gh, mut hh) = (Mat::zeros(nw, nw), Mat::zeros(nw, n), Mat::zeros(n, n));
        for a in terms {
            gg.gemm_tr(1.0, &a.g, &a.g, 1.0);
            gh.gemm_tr(1.0, &a.g, &a.h, 1.0);
            hh.gemm_tr(1.0, &a.h, &a.h, 1.0);
        }
        let terms = terms.iter().map(|a| (a.f.clone(), a.e.clone())).collect();
        RiccatiStep { terms, gg, gh, hh }
    }

    /// N = E[ℬᵀR'ℬ + 𝒟ᵀ𝒟], L = E[ℬᵀR'𝒜 + 𝒟ᵀ𝒞] and E[𝒜ᵀR'𝒜 + 𝒞ᵀ𝒞] from R' = `w.r`, into `w`.
    fn moments(&self, w: &mut Work) {
        w.nn.copy_from(&self.gg);
        w.bb.copy_from(&self.gh);
        w.rr.copy_from(&self.hh);
        for (f, e) in &self.terms {
            w.rf.gemm(1.0, &w.r, f, 0.0);
            w.re.gemm(1.0, &w.r, e, 0.0);
            w.nn.gemm_tr(1.0, e, &w.re, 1.0);
            w.bb.gemm_tr(1.0, e, &w.rf, 1.0);
            w.rr.gemm_tr(1.0, f, &w.rf, 1.0);
        }
    }
}

/// The matrices of one Riccati pass, reused from step to step and from pass to pass.
struct Work {
    r: Mat,
    rf: Mat,
    re: Mat,
    nn: Mat,
    bb: Mat,
    rr: Mat,
    vd: Mat,
    s_inv: Mat,
    sb: Mat,
}

impl Work {
    fn new(n: usize, nw: usize) -> Self {
        Work {
            r: Mat::zeros(n, n),
            rf: Mat::zeros(n, n),
            re: Mat::zeros(n, nw),
            nn: Mat::zeros(nw, nw),
            bb: Mat::zeros(nw, n),
            rr: Mat::zeros(n, n),
            vd: Mat::zeros(nw, nw),
            s_inv: Mat::zeros(nw, nw),
            sb: Mat::zeros(nw, n),
        }
    }
}
