//! The a-anisotropic norm by seed 003's Lemma 1, (2.7)–(2.11): a backward Riccati recursion and a
//! forward Lyapunov recursion per value of q, O(N n³) instead of the eigenvalues of the lw × lw
//! matrix Λ = E\[𝓕ᵀ𝓕] ([`crate::analysis::anisotropy`], which stays the reference).
//!
//! The error system of a realization on a plant whose modes are independent over time (no
//! switching, or dropouts) is a system with multiplicative noise: ξ\[k+1] = F ξ + E w,
//! e = H ξ + G w with (F, E, H, G) = those of the mode θ\[k] ([`crate::analysis::exact`]), drawn
//! afresh each step. Write E\[·] for the mean over θ\[k] and F̄ = E F, Ē = E E. For a deterministic
//! W = col(w\[0..N]) and ξ\[0] = 0, completing squares backward in k gives
//!
//! ```text
//! q E|𝓕W|² − |W|² = −Σ_k (w[k] − L(k) m[k])ᵀ S(k)⁻¹ (w[k] − L(k) m[k]),   m[k+1] = F̄ m + Ē w,
//! ```
//!
//! with (seed 003 (2.7)–(2.10), written with E\[·] for the sums over i = 0..M):
//!
//! ```text
//! R1(k) = E[Fᵀ R1(k+1) F] + q E[HᵀH]                                   (2.7)
//! R2(k) = F̄ᵀ R2(k+1) F̄ + L(k)ᵀ S(k)⁻¹ L(k)                             (2.8)
//! S(k)⁻¹ = I − E[q GᵀG + Eᵀ R1(k+1) E] − Ēᵀ R2(k+1) Ē                  (2.9)
//! L(k) = S(k) (E[Eᵀ R1(k+1) F + q GᵀH] + Ēᵀ R2(k+1) F̄)                 (2.10)
//! ```
//!
//! (H, G counted only at the steps J sums). The map W ↦ (w\[k] − L m\[k])_k is unit block triangular,
//! so I − qΛ = Tᵀ diag(S(k)⁻¹) T: q < 1/λmax(Λ) exactly when every S(k) ≻ 0, and
//! ln det(I − qΛ) = −Σ_k ln det S(k). The worst input of [`crate::analysis::anisotropy`],
//! W ~ N(0, Σ(q)), Σ(q) = (I − qΛ)⁻¹ = T⁻¹ diag S(k) T⁻ᵀ, is the shaping filter
//! w\[k] = L(k) m\[k] + v\[k], v\[k] ~ N(0, S(k)); the forward Lyapunov recursion
//! P(k+1) = (F̄ + Ē L) P (F̄ + Ē L)ᵀ + Ē S Ēᵀ, P(0) = 0, gives tr Σ(q) = Σ_k tr(L P Lᵀ + S). Since
//! ΛΣ(q) = (Σ(q) − I)/q, with τ(q) = tr(ΛΣ(q)) = (tr Σ − lw)/q:
//!
//! ```text
//! |||F|||_a² = τ / (lw + q τ),   A(q) = −½ Σ_k ln det S(k) + (lw/2) ln(1 + q τ/lw),
//! ```
//!
//! and q solves A(q) = a. Everything is carried scaled by q (R̃1 = R1/q, R̃2 = R2/q, L̃ = L/q, so
//! R̃1 is q-free and computed once, and τ = Σ_k [tr(S Ñ) + q tr(L̃ P L̃ᵀ)] with S⁻¹ = I − q Ñ
//! has no cancellation as q → 0). At the solution, (2.11) holds with equality at γ = |||F|||_a in
//! the form −Σ ln det S(k) = 2a + lw ln(1 − qγ²) (see docs/architecture.md for the sign).

use crate::analysis::anisotropy::AnisotropicNorm;
use crate::analysis::exact::augmented;
use crate::error::{Error, Result};
use crate::filter::realization::Realization;
use crate::model::plant::{Measurement, Plant};
use crate::numerics::linalg::{Mat, symmetrize};
use crate::numerics::solve::line::{bisect, maximize_concave_01};

/// The q-free part of one step of (2.7)–(2.10): the means F̄, Ē and, with R̃1(k+1),
/// N1 = E\[GᵀG + Eᵀ R̃1 E] and B1 = E\[GᵀH + Eᵀ R̃1 F].
struct Step {
    f: Mat,
    e: Mat,
    n1: Mat,
    b1: Mat,
}

/// A realization's error system prepared for Lemma 1: R̃1 of (2.7) is independent of q, so only
/// (2.8)–(2.10) and the forward recursion are rerun for each q.
pub struct Lemma1 {
    steps: Vec<Step>,
    lw: usize,
    q_max: std::sync::OnceLock<f64>,
}

/// What one q gives: Σ_k ln det S(k)⁻¹ = ln det(I − qΛ), and τ = tr(Λ Σ(q)).
#[derive(Clone, Copy, Debug)]
pub struct AtQ {
    pub ln_det: f64,
    pub tau: f64,
}

impl Lemma1 {
    /// The backward recursion (2.7) for R̃1 = R1/q and the per-step means. Refuses a Markov plant
    /// (seed 003's noise is independent over time; a chain with memory is seed 001's).
    pub fn new(plant: &Plant, real: &Realization) -> Result<Self> {
        if matches!(plant.measurement, Measurement::Markov(_)) {
            return Err(Error::invalid(
                "modes",
                "Lemma 1 of seed 003 covers multiplicative noise independent over time (no switching, or \
                 dropouts); a Markov-switching plant has memory: use the eigenvalue route",
            ));
        }
        let probs = plant.mode_probabilities();
        let mut steps = Vec::with_capacity(plant.steps());
        let mut r1: Option<Mat> = None;
        for k in (0..plant.steps()).rev() {
            let counted = if plant.counts(k) { 1.0 } else { 0.0 };
            let augs: Vec<_> = (0..plant.n_modes()).map(|j| augmented(plant, real, k, j)).collect();
            let (nxi, nw) = (augs[0].f.nrows(), augs[0].e.ncols());
            let next = r1.take().unwrap_or_else(|| Mat::zeros(nxi, nxi));
            let mut step = Step {
                f: Mat::zeros(nxi, nxi),
                e: Mat::zeros(nxi, nw),
                n1: Mat::zeros(nw, nw),
                b1: Mat::zeros(nw, nxi),
            };
            let mut here = Mat::zeros(nxi, nxi);
            for (mean, p) in augs.iter().zip(&probs[k]) {
                // E[·] over the mode and the multiplicative factors: each factor's term adds its
                // second moment, nothing to the means F̄, Ē.
                for a in mean.with_terms() {
                    let (rf, re) = (&next * &a.f, &next * &a.e);
                    here += *p * (counted * a.h.transpose() * &a.h + a.f.transpose() * &rf);
                    step.n1 += *p * (counted * a.g.transpose() * &a.g + a.e.transpose() * &re);
                    step.b1 += *p * (counted * a.g.transpose() * &a.h + a.e.transpose() * &rf);
                }
                step.f += *p * &mean.f;
                step.e += *p * &mean.e;
            }
            if !here.iter().all(|v| v.is_finite()) {
                return Err(Error::invalid("horizon", format!("the second moments overflow at step {k}")));
            }
            step.n1 = symmetrize(&step.n1);
            r1 = Some(symmetrize(&here));
            steps.push(step);
        }
        steps.reverse();
        let lw = steps.iter().map(|s| s.e.ncols()).sum();
        Ok(Lemma1 { steps, lw, q_max: std::sync::OnceLock::new() })
    }

    /// lw = mw (N + 1), the dimension of W.
    pub fn lw(&self) -> usize {
        self.lw
    }

    /// tr Λ = ‖F‖₂² (q = 0: S = I, Ñ = N1).
    pub fn trace(&self) -> f64 {
        self.steps.iter().map(|s| s.n1.trace()).sum()
    }

    /// (2.8)–(2.10) backward and the forward Lyapunov recursion at q, or None when some S(k) is not
    /// positive definite (q ≥ 1/λmax(Λ)).
    pub fn at(&self, q: f64) -> Option<AtQ> {
        let nxi = self.steps.first()?.f.nrows();
        let (kept, ln_det) = self.backward(q)?;
        let mut p = Mat::zeros(nxi, nxi);
        let mut tau = 0.0;
        for (st, (s, lt, nt)) in self.steps.iter().zip(kept.iter().rev()) {
            let lp = lt * &p;
            tau += (s * nt).trace() + q * (&lp * lt.transpose()).trace();
            let closed = &st.f + q * &st.e * lt;
            p = symmetrize(&(&closed * &p * closed.transpose() + &st.e * s * st.e.transpose()));
        }
        (ln_det.is_finite() && tau.is_finite()).then_some(AtQ { ln_det, tau })
    }

    /// The worst input's shaping filter at q (module docs): per step (F̄, Ē, L(k) = q L̃(k),
    /// S(k)^½ its Cholesky factor), w\[k] = L m\[k] + S^½ v\[k], m\[k+1] = F̄ m + Ē w\[k]; None where
    /// some S(k) is not positive definite. Its input has covariance Σ(q) = (I − qΛ)⁻¹ unscaled.
    pub fn shaping(&self, q: f64) -> Option<Vec<[Mat; 4]>> {
        let (kept, _) = self.backward(q)?;
        self.steps
            .iter()
            .zip(kept.iter().rev())
            .map(|(st, (s, lt, _))| Some([st.f.clone(), st.e.clone(), q * lt, s.clone().cholesky()?.l()]))
            .collect()
    }

    /// (2.8)–(2.10) backward at q: (S(k), L̃(k), Ñ(k)) in backward order and Σ_k ln det S(k)⁻¹,
    /// or None where some S(k) is not positive definite.
    #[allow(clippy::type_complexity)]
    fn backward(&self, q: f64) -> Option<(Vec<(Mat, Mat, Mat)>, f64)> {
        let nxi = self.steps.first()?.f.nrows();
        let mut r2 = Mat::zeros(nxi, nxi);
        let mut ln_det = 0.0;
        // (S(k), L̃(k), Ñ(k)) for the forward pass, in backward order.
        let mut kept = Vec::with_capacity(self.steps.len());
        for st in self.steps.iter().rev() {
            let r2e = &r2 * &st.e;
            let nt = symmetrize(&(&st.n1 + st.e.transpose() * &r2e));
            let bt = &st.b1 + r2e.transpose() * &st.f;
            let nw = nt.nrows();
            let sinv = Mat::identity(nw, nw) - q * &nt;
            let chol = sinv.cholesky()?;
            ln_det += 2.0 * chol.l().diagonal().iter().map(|d| d.ln()).sum::<f64>();
            let s = symmetrize(&chol.inverse());
            let lt = &s * &bt;
            r2 = symmetrize(&(st.f.transpose() * &r2 * &st.f + q * bt.transpose() * &lt));
            kept.push((s, lt, nt));
        }
        Some((kept, ln_det))
    }

    /// A(Σ(q)) = ½ ln det(I − qΛ) + (lw/2) ln(1 + qτ/lw) (module docs), with the gain² τ/(lw + qτ).
    fn anisotropy_and_gain_sq(&self, q: f64) -> Option<(f64, f64)> {
        let lw = self.lw as f64;
        let v = self.at(q)?;
        Some((0.5 * v.ln_det + 0.5 * lw * (q * v.tau / lw).ln_1p(), v.tau / (lw + q * v.tau)))
    }

    /// 1/λmax(Λ): the supremum of the q at which every S(k) ≻ 0, by bisection in
    /// [1/(2 tr Λ), 2 lw/tr Λ] (λmax lies between tr Λ/lw and tr Λ) to a relative 4 rounding units;
    /// computed once.
    pub fn q_max(&self) -> f64 {
        *self.q_max.get_or_init(|| self.bisect_q_max())
    }

    fn bisect_q_max(&self) -> f64 {
        let tr = self.trace();
        bisect(
            0.5 / tr,
            2.0 * self.lw as f64 / tr,
            |q| self.at(q).is_some(),
            |lo, hi| hi - lo <= 4.0 * f64::EPSILON * hi,
            400,
        )
        .0
    }

    /// |||F|||_a (seed 003 (2.6)) with the q of the worst covariance, as
    /// [`crate::analysis::anisotropy::anisotropic_norm_from_eigenvalues`] defines both: a = 0 gives
    /// ‖F‖₂/√lw (q = 0); a level not reached below (1 − 1e-15)/λmax, and a = ∞, give
    /// ‖F‖∞ = √λmax (q = 1/λmax); otherwise q solves A(Σ(q)) = a by the line search of
    /// `maximize_concave_01` on a − A (A increases in q).
    pub fn norm(&self, a: f64) -> Result<AnisotropicNorm> {
        if !(a >= 0.0) {
            return Err(Error::invalid("anisotropy", format!("the anisotropy level must be ≥ 0, got {a}")));
        }
        let tr = self.trace();
        if self.lw == 0 || tr <= 0.0 {
            return Ok(AnisotropicNorm { value: 0.0, q: 0.0 });
        }
        if a == 0.0 {
            return Ok(AnisotropicNorm { value: (tr / self.lw as f64).sqrt(), q: 0.0 });
        }
        let qmax = self.q_max();
        let hinf = AnisotropicNorm { value: (1.0 / qmax).sqrt(), q: qmax };
        if a.is_infinite() {
            return Ok(hinf);
        }
        // The last q where A is evaluated, as near (1 − 1e-15)/λmax as the pivots allow: so close to
        // singular, whether a Cholesky factor exists is decided by rounding (q_max's own bracket
        // end always succeeds).
        let (top, at_top) = [1e-15, 1e-14, 1e-13, 1e-12, 0.0]
            .iter()
            .find_map(|d| self.anisotropy_and_gain_sq(qmax * (1.0 - d)).map(|v| (qmax * (1.0 - d), v.0)))
            .ok_or_else(|| {
                Error::invalid(
                    "anisotropy",
                    format!("the Riccati recursion (2.8)–(2.10) broke down below q = {qmax:e}"),
                )
            })?;
        if at_top < a {
            return Ok(hinf);
        }
        let t = maximize_concave_01(
            |t| self.anisotropy_and_gain_sq(t * top).map_or(f64::NEG_INFINITY, |(an, _)| a - an),
            1e-16,
        );
        let q = t * top;
        let (_, gain_sq) = self.anisotropy_and_gain_sq(q).ok_or_else(|| {
            Error::invalid("anisotropy", format!("the Riccati recursion (2.8)–(2.10) broke down at q = {q:e} < 1/λmax"))
        })?;
        Ok(AnisotropicNorm { value: gain_sq.sqrt(), q })
    }
}

/// A realization's a-anisotropic norm on a plant without switching or with dropouts by Lemma 1
/// (seed 003 (2.7)–(2.11); module docs), a = ∞ giving the H∞ norm. Same value as
/// [`crate::analysis::anisotropy::realization_norm`] without forming Λ.
pub fn anisotropic_norm_riccati(plant: &Plant, real: &Realization, a: f64) -> Result<AnisotropicNorm> {
    Lemma1::new(plant, real)?.norm(a)
}
