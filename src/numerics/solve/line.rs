//! Searches on an interval: the exact line search of seed 000 Algorithm 1 step 4, as a root of
//! the derivative (the envelope theorem gives the derivative of the dual functional I for the
//! price of one gradient), and bisection on a monotone predicate.

/// argmax over τ ∈ [0, 1] of a concave φ, given φ'(τ) (non-increasing). Regula falsi with the
/// Illinois modification on φ', which keeps a bracket and converges superlinearly; stops when the
/// bracket is shorter than `tol`. An endpoint is returned when φ' does not change sign.
pub(crate) fn maximize_concave_01(dphi: impl Fn(f64) -> f64, tol: f64) -> f64 {
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

/// min over q ∈ (0, q̄) of f(q) and its argument, for seed 003 Theorem 1's γ²(q)
/// (`analysis::theorem1::analyze`): a geometric grid from 1e-12 q̄ to q̄(1 − 1e-12) (γ²(q) is
/// smooth and has one minimum on every filter we have met, but the grid does not rely on it), then
/// golden sections in the grid cell around the best point.
pub(crate) fn minimize_on_open(f: &impl Fn(f64) -> f64, q_bar: f64) -> (f64, f64) {
    let mut grid: Vec<f64> = (0..=24).map(|i| q_bar * 10f64.powf(-12.0 + 12.0 * i as f64 / 24.0)).collect();
    grid.extend((1..=12).map(|j| q_bar * (1.0 - 10f64.powi(-j))));
    grid.sort_by(f64::total_cmp);
    grid.dedup();
    let values: Vec<f64> = grid.iter().map(|q| f(*q)).collect();
    let best = (0..grid.len()).min_by(|i, j| values[*i].total_cmp(&values[*j])).expect("grid");
    let (mut lo, mut hi) = (grid[best.saturating_sub(1)], grid[(best + 1).min(grid.len() - 1)]);
    let mut best_q = (values[best], grid[best]);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..80 {
        if hi - lo <= 1e-12 * hi {
            break;
        }
        if f1 <= f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
        }
        for c in [(f1, x1), (f2, x2)] {
            if c.0 < best_q.0 {
                best_q = c;
            }
        }
    }
    best_q
}
