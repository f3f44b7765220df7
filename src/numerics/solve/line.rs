//! Searches on an interval: the exact line search of seed 000 Algorithm 1 step 4, as a root of
//! the derivative (the envelope theorem gives the derivative of the dual functional I for the
//! price of one gradient), and bisection on a monotone predicate.

/// argmax over τ ∈ [0, 1] of a concave φ, given φ'(τ) (non-increasing). Regula falsi with the
/// Illinois modification on φ', which keeps a bracket and converges superlinearly; stops when the
/// bracket is shorter than `tol`. An endpoint is returned when φ' does not change sign.
pub fn maximize_concave_01(dphi: impl Fn(f64) -> f64, tol: f64) -> f64 {
    let (mut a, mut fa) = (0.0, dphi(0.0));
    if fa <= 0.0 {
        return 0.0;
    }
    let (mut b, mut fb) = (1.0, dphi(1.0));
    if fb >= 0.0 {
        return 1.0;
    }
    let mut side = 0i8;
    for _ in 0..200 {
        let c = (a * fb - b * fa) / (fb - fa);
        // Fall back to bisection if the secant point is not strictly inside the bracket.
        let c = if c > a && c < b { c } else { 0.5 * (a + b) };
        let fc = dphi(c);
        if fc == 0.0 {
            return c;
        }
        if fc > 0.0 {
            a = c;
            fa = fc;
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        } else {
            b = c;
            fb = fc;
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        }
        if b - a < tol {
            break;
        }
    }
    if fa.abs() < fb.abs() { a } else { b }
}

/// Bisection for the threshold t* of a monotone predicate on [lo, hi]: `below(t)` holds for t < t*
/// and fails above it. Halves the bracket at its midpoint 0.5 (lo + hi) until `narrow(lo, hi)`
/// holds or `max_halvings` halvings are done, and returns the bracket.
pub fn bisect(
    mut lo: f64,
    mut hi: f64,
    mut below: impl FnMut(f64) -> bool,
    narrow: impl Fn(f64, f64) -> bool,
    max_halvings: usize,
) -> (f64, f64) {
    for _ in 0..max_halvings {
        if narrow(lo, hi) {
            break;
        }
        let mid = 0.5 * (lo + hi);
        if below(mid) { lo = mid } else { hi = mid }
    }
    (lo, hi)
}
