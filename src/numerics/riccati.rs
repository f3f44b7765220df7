//! One step of the predictor Riccati recursion in covariance form, the step the Kalman family
//! (seed 000 eqs (4)–(6), seed 002 eqs (5.6)–(5.7)), the Markov-jump family (seed 001 eqs
//! (15)–(16)), the intermittent-observation predictor (seed 003 §4.2.1) and the generalized H2
//! filter share (SPEC §0, §1, §3, §4):
//!
//!     S = C P Cᵀ + D W Dᵀ,   K = (A P Cᵀ + B W Dᵀ) S⁺,   P' = A P Aᵀ + B W Bᵀ − K S Kᵀ.
//!
//! The noise terms D W Dᵀ, B W Dᵀ and B W Bᵀ come precomputed: each caller weights them its own way
//! (by the mode probability p_s in seed 001) and keeps the product order it has always used, so
//! its figures stay bit-identical. The recursions that are not this step stay with their family:
//! the H∞-λ recursion (seed 002 (5.9)) is in information form with a λ term, and the
//! intermittent predictor's S and gain carry the arrival probability inside the products.

use super::linalg::{Mat, psd_pinv, symmetrize};

/// The innovation of one step: S (symmetrized), its pseudo-inverse S⁺ and the gain K.
pub struct Innovation {
    pub s: Mat,
    pub s_inv: Mat,
    pub k: Mat,
}

/// S = C P Cᵀ + D W Dᵀ and K = (A P Cᵀ + B W Dᵀ) S⁺ (module docs), given `dwd` = D W Dᵀ and
/// `bwd` = B W Dᵀ.
pub fn innovation(a: &Mat, c: &Mat, p: &Mat, dwd: &Mat, bwd: &Mat) -> Innovation {
    let s = symmetrize(&(c * p * c.transpose() + dwd));
    let s_inv = psd_pinv(&s);
    let k = (a * p * c.transpose() + bwd) * &s_inv;
    Innovation { s, s_inv, k }
}

/// P' = A P Aᵀ + B W Bᵀ − K S Kᵀ (module docs), given `bwb` = B W Bᵀ; not symmetrized, since the
/// Markov-jump recursion mixes the modes' terms first.
pub fn propagate(a: &Mat, p: &Mat, bwb: &Mat, k: &Mat, s: &Mat) -> Mat {
    a * p * a.transpose() + bwb - k * s * k.transpose()
}
