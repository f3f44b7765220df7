//! Error bounds of computed figures: one function per idea, used by the product when it certifies
//! a bound and by the tests when they compare two routes to the same number (docs/families.md,
//! "What is certified, and how").
//!
//! Two sources of error are bounded here:
//! - **Rounding in dense symmetric eigenvalue problems.** The symmetric QR algorithm (nalgebra's
//!   and LAPACK's) is backward stable: the computed eigenvalues are the exact ones of M + E with
//!   ‖E‖₂ ≤ p(n) ε ‖M‖₂, and Weyl's inequality moves each eigenvalue by at most ‖E‖₂ (LAPACK Users'
//!   Guide §4.7, "p(n) is a modestly growing function of n"). We take p(n) = n and bound ‖M‖₂ by
//!   ‖M‖_F, which over-estimates both.
//! - **An interior-point solver's point.** clarabel stops at a point (x, s, z) that is optimal for
//!   a program whose right-hand side is moved by the primal residual r_p = Ax + s − b and whose
//!   cost is moved by the dual residual r_d = Aᵀz + c, with a duality gap between the primal and
//!   dual objectives. To first order the optimum moves by zᵀr_p (z is the derivative of the optimal
//!   value in b) and by xᵀr_d (x its derivative in c), so the distance of the reported objective
//!   from the program's optimum is at most |gap| + |zᵀr_p| + |xᵀr_d|
//!   (`crate::numerics::solve::conic::Solution`'s `objective_error`). When clarabel stops at
//!   its reduced tolerances (AlmostSolved) the figure is at least its reduced relative gap
//!   tolerance times the objective: that is all the solver then vouches for. Two routes to one optimum, one of them a solver's, therefore agree to
//!   that figure plus the other route's own error.

use crate::numerics::linalg::Mat;

/// An upper bound on the error of every computed eigenvalue of the symmetric matrix `m`:
/// n ε ‖M‖_F (backward stability and Weyl's inequality, module docs).
pub fn eigenvalue_error(m: &Mat) -> f64 {
    m.nrows() as f64 * f64::EPSILON * m.norm()
}

/// The same bound from the matrix's size and Frobenius norm, where the matrix is not kept.
pub(crate) fn eigenvalue_error_of(n: usize, frobenius: f64) -> f64 {
    n as f64 * f64::EPSILON * frobenius
}

/// A first-order bound on the rounding error of a figure computed by a recursion over `steps` steps
/// of n × n products (a Riccati or Lyapunov recursion, an exact moment recursion): a relative
/// rounding of about n ε per step, carried through the later steps by a stable recursion, adds up to
/// steps · n · ε relative.
pub fn recursion_error(steps: usize, n: usize, value: f64) -> f64 {
    (steps * n) as f64 * f64::EPSILON * value.abs()
}

/// `value` rounded outward past an absolute error `error`: the next double above value + |error|,
/// so that a computed upper bound stays one after its own rounding.
pub(crate) fn round_up(value: f64, error: f64) -> f64 {
    (value + error.abs()).next_up()
}

/// Whether `lower` ≤ `upper` holds within the stated absolute error of the two routes that computed
/// them: a check that fails only when the two disagree by more than their accuracy.
pub fn ordered(lower: f64, upper: f64, error: f64) -> bool {
    lower <= upper + error.abs()
}

/// Whether two routes to one number agree within their stated absolute errors.
pub fn agree(a: f64, b: f64, error: f64) -> bool {
    (a - b).abs() <= error.abs()
}
