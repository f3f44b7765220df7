//! Maximizing a concave function on an interval: the exact line search of seed 000 Algorithm 1
//! step 4, by bisection on the sign of the derivative (the envelope theorem gives the derivative of
//! the dual functional I for the price of one gradient).

/// argmax over τ ∈ [0, 1] of a concave φ, given φ'(τ). Bisection to `tol` in τ: the result is the
/// maximizer to that precision (an endpoint when φ' does not change sign).
pub fn maximize_concave_01(dphi: impl Fn(f64) -> f64, tol: f64) -> f64 {
    if dphi(1.0) >= 0.0 {
        return 1.0;
    }
    if dphi(0.0) <= 0.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    while hi - lo > tol {
        let mid = 0.5 * (lo + hi);
        if dphi(mid) > 0.0 { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}
