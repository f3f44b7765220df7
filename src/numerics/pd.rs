//! Solving with a symmetric positive definite matrix, with the accuracy of the result stated: the
//! Kalman–Bucy step of seed 004's regularized filter, where S = C P Cᵀ + (W_m + α I)/Δ is positive
//! definite for every α > 0 however singular W_m is, so nothing may be dropped (as
//! [`super::linalg::psd_pinv`] drops eigenvalues below its relative cutoff), yet S can be very
//! ill-conditioned as α → 0.
//!
//! **Error analysis.** With the Cholesky factor S = L Lᵀ and two triangular solves, the computed x̂
//! of S x = b is the exact solution of (S + E) x̂ = b with |E| ≤ γ_{3m+1} |L| |Lᵀ| (Higham,
//! *Accuracy and Stability of Numerical Algorithms*, 2nd ed., Thm 10.4; γ_j = j u/(1 − j u), u the
//! unit roundoff ε/2). Since ‖ |L| |Lᵀ| ‖₂ ≤ ‖L‖_F² = tr(L Lᵀ) = tr S (to first order in u),
//! ‖E‖₂ ≤ γ_{3m+1} tr S, and the standard perturbation bound gives the relative error
//!
//! ```text
//! ‖x̂ − x‖ / ‖x‖ ≤ t / (1 − t),     t = γ_{3m+1} tr S / λ_min(S) ≤ m γ_{3m+1} κ₂(S),
//! ```
//!
//! the condition number κ₂(S) = λ_max/λ_min times a multiple of ε: [`solve_error`]. (tr S rather
//! than m λ_max: where few eigenvalues are large, as with a low-rank W_m, the bound is m times
//! sharper and still rigorous.) The rounding in forming S itself (C P Cᵀ + R) is a perturbation of
//! the same kind and of the order of ε ‖S‖₂, inside the same bound. A zero right side is solved
//! exactly (x̂ = 0), whatever κ₂.
//!
//! **Threshold.** [`MAX_SOLVE_ERROR`]: a solve whose bound exceeds it is refused, never used.

use nalgebra::{Cholesky, Dyn, SymmetricEigen};

use super::linalg::{Mat, symmetrize};

/// The largest admissible worst-case relative error of a gain computed by a positive definite
/// solve ([`solve_error`]): 10⁻³, so every gain keeps at least three correct significant digits in
/// the worst case. The backward form of the same bound says more: the gain is the exact gain for an
/// innovation covariance within a factor 1 ± 10⁻³ of S (‖E‖₂ ≤ t λ_min(S), so −10⁻³ S ⪯ E ⪯
/// 10⁻³ S), a filter whose noise intensities and α are those given to 0.1 %, much finer than α is
/// ever given.
pub const MAX_SOLVE_ERROR: f64 = 1e-3;

/// The worst-case relative error of a Cholesky solve with the m × m symmetric positive definite
/// matrix of eigenvalues `eigenvalues` (module docs): t/(1 − t), t = γ_{3m+1} tr S / λ_min;
/// infinite when λ_min ≤ 0 or t ≥ 1 (the bound says nothing).
pub fn solve_error(eigenvalues: &[f64]) -> f64 {
    let m = eigenvalues.len();
    let u = f64::EPSILON / 2.0;
    let j = (3 * m + 1) as f64;
    let gamma = j * u / (1.0 - j * u);
    let min = eigenvalues.iter().copied().fold(f64::INFINITY, f64::min);
    let trace: f64 = eigenvalues.iter().sum();
    let t = gamma * trace / min;
    if min > 0.0 && t < 1.0 { t / (1.0 - t) } else { f64::INFINITY }
}

/// A symmetric positive definite S, factored, with its condition number and the error bound of
/// solves with it.
pub(crate) struct PdSolver {
    chol: Cholesky<f64, Dyn>,
    /// κ₂(S) = λ_max / λ_min.
    pub kappa: f64,
    /// [`solve_error`] of S.
    pub error: f64,
}

impl PdSolver {
    /// The factored S, or None with κ₂(S) (infinite when λ_min ≤ 0) when S is not positive definite
    /// in floating point.
    pub fn new(s: &Mat) -> std::result::Result<Self, f64> {
        let s = symmetrize(s);
        let eig = SymmetricEigen::new(s.clone()).eigenvalues;
        let (lo, hi) = (eig.min(), eig.max());
        let kappa = if lo > 0.0 { hi / lo } else { f64::INFINITY };
        match Cholesky::new(s) {
            Some(chol) if kappa.is_finite() => Ok(PdSolver { chol, kappa, error: solve_error(eig.as_slice()) }),
            _ => Err(kappa),
        }
    }
    /// N S⁻¹, by solving S Xᵀ = Nᵀ (a solve, not a product with an inverse, which could lose κ₂²).
    pub(crate) fn solve_right(&self, n: &Mat) -> Mat {
        self.chol.solve(&n.transpose()).transpose()
    }
    /// S⁻¹ (for quadratic forms νᵀ S⁻¹ ν; gains use [`PdSolver::solve_right`]).
    pub fn inverse(&self) -> Mat {
        self.chol.inverse()
    }
}
