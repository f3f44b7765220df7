//! Anisotropy analysis (seed 003 §2, docs/math.md §5): the anisotropy of a Gaussian vector, and the
//! a-anisotropic norm of a linear operator F from Λ = E\[FᵀF] by a scalar root-finding problem on the
//! eigenvalues of Λ.
//!
//! For W ~ N(0, Σ) in R^m, A(W) = −½ ln det(m Σ / tr Σ) ≥ 0, zero exactly for white isotropic W.
//! The a-anisotropic norm |||F|||_a = sup { sqrt(tr(ΛΣ)/tr Σ) : A ≤ a } is attained by
//! Σ(q) = (I − qΛ)⁻¹ with q ∈ [0, 1/λmax(Λ)) solving A(Σ(q)) = a; it grows from ‖F‖₂/sqrt(lw)
//! (a → 0) to ‖F‖∞ = sqrt(λmax(Λ)) (a → ∞).

use crate::error::{Error, Result};
use crate::numerics::linalg::{Mat, sym_eigen, symmetrize};
use crate::numerics::solve::line::bisect;

/// A(W) = −½ ln det(m Σ / tr Σ) for W ~ N(0, Σ) (Σ positive definite).
pub fn gaussian_anisotropy(sigma: &Mat) -> f64 {
    let m = sigma.nrows() as f64;
    let tr = sigma.trace();
    let eig = symmetrize(sigma).symmetric_eigenvalues();
    if eig.iter().any(|l| *l <= 0.0) {
        return f64::INFINITY;
    }
    // A ≥ 0 (Hadamard/AM–GM); clamp the rounding of white noise's exact zero.
    (-0.5 * eig.iter().map(|l| (m * l / tr).ln()).sum::<f64>()).max(0.0)
}

/// Anisotropy of Σ(q) = (I − qΛ)⁻¹ from the eigenvalues μ of Λ.
fn anisotropy_at(mu: &[f64], q: f64) -> f64 {
    let s: Vec<f64> = mu.iter().map(|m| 1.0 / (1.0 - q * m)).collect();
    let tr: f64 = s.iter().sum();
    let lw = mu.len() as f64;
    -0.5 * s.iter().map(|v| (lw * v / tr).ln()).sum::<f64>()
}

/// Mean-square gain sqrt(tr(ΛΣ(q))/tr Σ(q)).
fn gain_at(mu: &[f64], q: f64) -> f64 {
    let (num, den) = mu.iter().fold((0.0, 0.0), |(a, b), m| (a + m / (1.0 - q * m), b + 1.0 / (1.0 - q * m)));
    (num / den).sqrt()
}

/// The a-anisotropic norm and the q of the worst covariance Σ(q) = (I − qΛ)⁻¹.
#[derive(Clone, Copy, Debug)]
pub struct AnisotropicNorm {
    pub value: f64,
    pub q: f64,
}

/// |||F|||_a from the eigenvalues μ ≥ 0 of Λ = E\[FᵀF], by bisection on q ∈ [0, 1/μmax) (A(Σ(q)) is
/// increasing in q). When Λ is a multiple of the identity every input is equally bad and the norm is
/// sqrt(μ) for every a.
pub fn anisotropic_norm_from_eigenvalues(mu: &[f64], a: f64) -> Result<AnisotropicNorm> {
    if !(a >= 0.0 && a.is_finite()) {
        return Err(Error::invalid("anisotropy", format!("the anisotropy level must be finite and ≥ 0, got {a}")));
    }
    let top = mu.iter().cloned().fold(0.0, f64::max);
    if mu.is_empty() || top <= 0.0 {
        return Ok(AnisotropicNorm { value: 0.0, q: 0.0 });
    }
    // a = 0 is q = 0 exactly: A(Σ(q)) = O(q²) drowns in rounding near 0, and a bisection there
    // would stop at a q ~ 1e-7/μmax off by ~1e-8 in the norm.
    if a == 0.0 {
        return Ok(AnisotropicNorm { value: gain_at(mu, 0.0), q: 0.0 });
    }
    let qmax = 1.0 / top;
    // Anisotropy reachable below qmax: if even (1 − 1e-15) qmax gives less than a, the sup is the
    // limit ‖F‖∞.
    if anisotropy_at(mu, qmax * (1.0 - 1e-15)) < a {
        return Ok(AnisotropicNorm { value: top.sqrt(), q: qmax });
    }
    let (lo, hi) = bisect(0.0, 1.0, |t| anisotropy_at(mu, t * qmax) < a, |lo, hi| hi - lo < 1e-16, 200);
    let q = 0.5 * (lo + hi) * qmax;
    Ok(AnisotropicNorm { value: gain_at(mu, q), q })
}

/// |||F|||_a for Λ = E\[FᵀF], and the worst input covariance Σ(q) = (I − qΛ)⁻¹ (scaled to unit trace
/// per component, tr Σ = lw).
pub fn anisotropic_norm(lambda: &Mat, a: f64) -> Result<(AnisotropicNorm, Mat)> {
    let (values, vectors) = sym_eigen(lambda)?;
    worst_from_eigen(&GramEigen { values, vectors }, a)
}

/// The eigendecomposition of a realization's Λ = E\[𝓕ᵀ𝓕] ([`error_gram`], [`sym_eigen`]): what
/// every a-anisotropic figure of the filter is read from, at any level a. Kept by the design stage
/// for a filter whose worst input a scenario draws, so that Λ is formed and decomposed once.
#[derive(Clone, Debug)]
pub struct GramEigen {
    pub values: Vec<f64>,
    pub vectors: Mat,
}

/// Λ's eigendecomposition for `real` on `plant` (the same bits wherever it is taken).
pub fn gram_eigen(
    plant: &crate::model::plant::Plant,
    real: &crate::filter::realization::Realization,
) -> Result<GramEigen> {
    let (values, vectors) = sym_eigen(&error_gram(plant, real)?)?;
    Ok(GramEigen { values, vectors })
}

/// [`anisotropic_norm`] from Λ's eigendecomposition.
pub fn worst_from_eigen(eigen: &GramEigen, a: f64) -> Result<(AnisotropicNorm, Mat)> {
    let (values, v) = (&eigen.values, &eigen.vectors);
    let mu: Vec<f64> = values.iter().map(|m| m.max(0.0)).collect();
    let norm = anisotropic_norm_from_eigenvalues(&mu, a)?;
    let d: Vec<f64> = mu.iter().map(|m| 1.0 / (1.0 - norm.q * m).max(f64::MIN_POSITIVE)).collect();
    let tr: f64 = d.iter().sum();
    let lw = mu.len() as f64;
    let scaled = nalgebra::DVector::from_iterator(d.len(), d.iter().map(|x| x * lw / tr));
    let sigma = v * Mat::from_diagonal(&scaled) * v.transpose();
    Ok((norm, symmetrize(&sigma)))
}

/// Λ_w = E\[𝓕ᵀ𝓕] of a realization's error system from W = col(w\[0..N]) (lw = mw(N+1)) to the
/// counted errors, x0 fixed at its mean and the known input set aside (seed 003 §2; exact with
/// dropouts, [`crate::analysis::exact::second_moment_operator`]).
pub fn error_gram(plant: &crate::model::plant::Plant, real: &crate::filter::realization::Realization) -> Result<Mat> {
    let full = crate::analysis::exact::second_moment_operator(plant, real)?;
    let n = plant.nx();
    let lw = full.nrows() - n;
    Ok(full.view((n, n), (lw, lw)).into_owned())
}

/// A realization's exact a-anisotropic norm (docs/math.md §5) with the worst input covariance Σ(q) over
/// W = col(w\[0..N]) (tr Σ = lw).
pub fn realization_norm(
    plant: &crate::model::plant::Plant,
    real: &crate::filter::realization::Realization,
    a: f64,
) -> Result<(AnisotropicNorm, Mat)> {
    anisotropic_norm(&error_gram(plant, real)?, a)
}

/// Σ = T(ρ) ⊗ W: each component an AR(1) sequence in time, w\[k] = ρ w\[k−1] + sqrt(1−ρ²) v\[k] started
/// stationary, with the spatial covariance W of one step. Since det T(ρ) = (1−ρ²)^N for N+1 steps,
/// A(Σ) = (N+1) A(W) − ½ mw N ln(1 − ρ²): the colour adds an anisotropy in closed form, so ρ for a
/// target a is explicit (no root-finding needed). Index order: step-major, w\[k] contiguous.
pub fn coloured_covariance(w: &Mat, steps: usize, a: f64) -> Result<(Mat, f64)> {
    let mw = w.nrows();
    let white = steps as f64 * gaussian_anisotropy(w);
    if !white.is_finite() {
        return Err(Error::invalid("anisotropy", "the noise covariance is singular: its anisotropy is infinite"));
    }
    let extra = a - white;
    if !(a.is_finite() && extra >= -1e-12) {
        return Err(Error::invalid(
            "anisotropy",
            format!(
                "white noise with this covariance already has anisotropy {white:.6}; a coloured input cannot have less (got {a})"
            ),
        ));
    }
    let rho = if steps < 2 { 0.0 } else { (1.0 - (-2.0 * extra.max(0.0) / (mw * (steps - 1)) as f64).exp()).sqrt() };
    let t = Mat::from_fn(steps, steps, |i, j| rho.powi((i as i32 - j as i32).abs()));
    Ok((t.kronecker(w), rho))
}
