//! The statistics core of `filterbench check` against values known in closed form. Tolerance: 1e-9
//! relative, from statrs's erfc, whose error measured here is 4.5e-11 relative at z = 1.96 (its
//! rational approximations are not correctly rounded); a p-value needs far fewer digits than that.

use filterbench::verdict::stats::{self, Sided};

const TOL: f64 = 1e-9;

#[test]
fn holm_steps_down_and_stops_at_the_first_acceptance() {
    // sorted: 0.005 ≤ 0.05/4, 0.01 ≤ 0.05/3, 0.03 > 0.05/2 → stop, 0.04 is not rejected even though
    // it is below 0.05/1.
    let h = stats::holm(&[0.01, 0.04, 0.03, 0.005], 0.05);
    assert_eq!(h.rejected, vec![true, false, false, true]);
    assert_eq!(h.threshold, vec![0.05 / 3.0, 0.05, 0.05 / 2.0, 0.05 / 4.0]);
    // A NaN p-value is never rejected and does not block the others.
    let h = stats::holm(&[f64::NAN, 1e-9], 0.01);
    assert_eq!(h.rejected, vec![false, true]);
    assert!(stats::holm(&[], 0.01).rejected.is_empty());
}

#[test]
fn normal_tails_quantiles_and_chi2() {
    let z975 = 1.959963984540054;
    let p2 = stats::normal_p(z975, Sided::TwoSided);
    assert!((p2 - 0.05).abs() < TOL, "{p2:e}");
    assert!((stats::normal_p(-z975, Sided::TwoSided) - 0.05).abs() < TOL);
    assert!((stats::normal_p(z975, Sided::Upper) - 0.025).abs() < TOL);
    assert!((stats::normal_p(z975, Sided::Lower) - 0.975).abs() < TOL);
    let q = stats::normal_quantile(0.975);
    assert!((q - z975).abs() < TOL, "{q:e} {:e}", q - z975);
    // far tail: 1 − Φ(30) ≈ 4.906e-198 from erfc, not 0.
    let p = stats::normal_p(30.0, Sided::Upper);
    assert!(p > 4.8e-198 && p < 5.0e-198, "{p}");
    // χ²(2): P[X ≥ x] = exp(−x/2).
    for x in [0.1, 1.0, 5.0, 40.0] {
        let (lo, hi) = stats::chi2_tails(x, 2.0);
        assert!((hi - (-x / 2.0f64).exp()).abs() <= TOL * hi.max(1e-300), "{x}: {hi}");
        assert!((lo + hi - 1.0).abs() < TOL);
    }
    assert!((stats::chi2_p(2.0 * 20f64.ln(), 2.0, Sided::Upper) - 0.05).abs() < TOL);
    assert!((stats::chi2_p(2.0 * 20f64.ln(), 2.0, Sided::TwoSided) - 0.1).abs() < TOL);
}

#[test]
fn detectable_size_and_trials_are_inverse() {
    // z_{0.975} + z_{0.95} = 1.95996 + 1.64485
    let d = stats::detectable(1.0, 0.05, 0.05, Sided::TwoSided);
    assert!((d - (1.959963984540054 + 1.6448536269514722)).abs() < TOL, "{d}");
    let d1 = stats::detectable(2.0, 0.05, 0.05, Sided::Upper);
    assert!((d1 - 2.0 * 2.0 * 1.6448536269514722).abs() < TOL, "{d1}");
    // n trials make se = σ/√n, and the detectable size at that se is at most δ.
    let (sigma, delta, level, beta) = (3.0, 0.1, 1e-4, 0.05);
    let n = stats::trials_for(sigma, delta, level, beta, Sided::TwoSided);
    assert!(stats::detectable(sigma / n.sqrt(), level, beta, Sided::TwoSided) <= delta);
    assert!(stats::detectable(sigma / (n - 1.0).sqrt(), level, beta, Sided::TwoSided) > delta);
    assert!(stats::trials_for(sigma, 0.0, level, beta, Sided::TwoSided).is_infinite());
}
