//! Exact second moments of a realization's error (docs/math.md §0, "exact" column): the augmented state
//! ξ = (x, s) obeys, in mode θ\[k] = j (one mode for a plant that does not switch),
//!
//! ```text
//! ξ[k+1] = F_j ξ[k] + E_j w[k] + c_j[k],   e[k] = z[k] − ẑ[k] = H_j ξ[k] + G_j w[k]
//! F_j = [[A_j, 0], [Bf C_j, Af]],  E_j = [B_j; Bf D_j],  H_j = [Cz − Df C_j, −Cf],  G_j = Dz − Df D_j,
//! c_j = (r, Gf r),
//! ```
//!
//! with the filter's gains those of mode j when it is mode-indexed. The exact error follows from
//! per-mode raw moments m_j = E\[ξ 1{θ = j}], Y_j = E\[ξξᵀ 1{θ = j}] (seed 001 eq (10); docs/math.md §3: "one
//! recursion per mode"), propagated with the mode's matrices and mixed by Π, since θ\[k+1] depends on
//! the past only through θ\[k]. Without modes this is the mean-plus-Lyapunov recursion
//! Σ\[k+1] = F Σ Fᵀ + E W Eᵀ; with dropouts (seed 003 (4.30)–(4.33), two independent modes) it gives
//! exactly the p(1 − p) terms of the multiplicative-noise form ("the Σ_i A_i M A_iᵀ terms").
//!
//! Inputs drawn jointly over the horizon (not white) add the cross moments Z_j = E\[ξ Jᵀ 1{θ = j}]
//! with the whole input J; for white inputs the cross moment with w\[k] is m_j μ_kᵀ.
//!
//! The error is affine in the covariances K, and the backward (adjoint) recursion
//! Λ_j\[k] = H_jᵀH_j + F_jᵀ (Σ_i Π_ji Λ_i\[k+1]) F_j gives ∂J/∂K for every block in one pass (seed 000
//! eq (27), computed as docs/math.md §2 recommends).

mod augmented;
mod exact_error;
mod form;
mod moments;
mod propagate;
mod sensitivity;

pub(crate) use augmented::{Augmented, augmented};
pub use exact_error::{Coordinates, ExactError, MAX_DIGITS_LOST, Resolution};
pub use form::*;
pub use moments::{
    deterministic_error, error, error_joint, error_with_mean, errors, errors_joint, errors_with_mean, mean_error,
};
pub use propagate::joint_offset;
pub use sensitivity::*;
