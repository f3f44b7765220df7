//! One step of the predictor Riccati recursion in covariance form, the step the Kalman family
//! (seed 000 eqs (4)–(6), seed 002 eqs (5.6)–(5.7)), the Markov-jump family (seed 001 eqs
//! (15)–(16)), the intermittent-observation predictor (seed 003 §4.2.1) and the generalized H2
//! filter share (docs/math.md §0, §1, §3, §4), and seed 004's regularized Galerkin filter (its Kalman–Bucy
//! gain P Cᵀ S_α⁻¹, seed 004 eq (6)) with it:
//!
//! ```text
//! S = C P Cᵀ + D W Dᵀ,   K = (A P Cᵀ + B W Dᵀ) S⁺,   P' = A P Aᵀ + B W Bᵀ − K S Kᵀ.
//! ```
//!
//! The noise terms D W Dᵀ, B W Dᵀ and B W Bᵀ come precomputed: each caller weights them its own way
//! (by the mode probability p_s in seed 001) and keeps the product order it has always used, so
//! its figures stay bit-identical. The recursions that are not this step stay with their family:
//! the H∞-λ recursion (seed 002 (5.9)) is in information form with a λ term, and the
//! intermittent predictor's S and gain carry the arrival probability inside the products.
//!
//! Two ways to apply S⁻¹: [`innovation`] uses the pseudo-inverse S⁺ (a genuinely singular S — a
//! step without measurements, a noise-free channel of a truth model — gets a zero gain in the
//! directions it lacks); `innovation_pd` is for an S that is positive definite by construction
//! (seed 004's S_α = W_m + α I with α > 0): a Cholesky solve that drops nothing, refused when its
//! error bound ([`super::pd`]) exceeds [`super::pd::MAX_SOLVE_ERROR`].

use super::linalg::{Mat, psd_pinv, symmetrize};
use super::pd::{MAX_SOLVE_ERROR, PdSolver};

/// The innovation of one step: S (symmetrized), its (pseudo-)inverse and the gain K.
pub struct Innovation {
    pub s: Mat,
    /// S⁺ ([`innovation`]) or S⁻¹ (`innovation_pd`).
    pub s_inv: Mat,
    pub k: Mat,
    solver: Option<PdSolver>,
}

impl Innovation {
    /// N S⁺ (the product with the pseudo-inverse) or N S⁻¹ (a Cholesky solve), as the step was made.
    pub fn right_solve(&self, n: &Mat) -> Mat {
        match &self.solver {
            Some(solver) => solver.solve_right(n),
            None => n * &self.s_inv,
        }
    }
}

/// S = C P Cᵀ + D W Dᵀ and K = (A P Cᵀ + B W Dᵀ) S⁺ (module docs), given `dwd` = D W Dᵀ and
/// `bwd` = B W Dᵀ.
pub fn innovation(a: &Mat, c: &Mat, p: &Mat, dwd: &Mat, bwd: &Mat) -> Innovation {
    let s = symmetrize(&(c * p * c.transpose() + dwd));
    let s_inv = psd_pinv(&s);
    let k = (a * p * c.transpose() + bwd) * &s_inv;
    Innovation { s, s_inv, k, solver: None }
}

/// Why `innovation_pd` refused a step: S's condition number κ₂ and the worst-case relative
/// error of a solve with it ([`super::pd::solve_error`]; infinite when S is not positive definite).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IllConditioned {
    pub kappa: f64,
    pub error: f64,
}

/// As [`innovation`] for an S that must be positive definite: K = (A P Cᵀ + B W Dᵀ) S⁻¹ by a
/// Cholesky solve. `extra` are further right sides N that will be solved with this S (the
/// filtering form's output gain): when every right side is zero the solve is exact whatever κ₂;
/// otherwise a bound above [`MAX_SOLVE_ERROR`], or an S that is not positive definite, is refused.
pub(crate) fn innovation_pd(
    a: &Mat,
    c: &Mat,
    p: &Mat,
    dwd: &Mat,
    bwd: &Mat,
    extra: &[&Mat],
) -> Result<Innovation, IllConditioned> {
    let s = symmetrize(&(c * p * c.transpose() + dwd));
    let rhs = a * p * c.transpose() + bwd;
    let zero = rhs.amax() == 0.0 && extra.iter().all(|n| n.amax() == 0.0);
    let solver = match PdSolver::new(&s) {
        Ok(solver) if solver.error <= MAX_SOLVE_ERROR || zero => solver,
        Ok(solver) => return Err(IllConditioned { kappa: solver.kappa, error: solver.error }),
        Err(kappa) => return Err(IllConditioned { kappa, error: f64::INFINITY }),
    };
    let k = solver.solve_right(&rhs);
    Ok(Innovation { s_inv: solver.inverse(), s, k, solver: Some(solver) })
}

/// P' = A P Aᵀ + B W Bᵀ − K S Kᵀ (module docs), given `bwb` = B W Bᵀ; not symmetrized, since the
/// Markov-jump recursion mixes the modes' terms first.
pub(crate) fn propagate(a: &Mat, p: &Mat, bwb: &Mat, k: &Mat, s: &Mat) -> Mat {
    a * p * a.transpose() + bwb - k * s * k.transpose()
}
