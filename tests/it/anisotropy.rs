//! Anisotropy analysis (seed 003 §2): the Gaussian anisotropy formula, the a-anisotropic norm's
//! limits ‖F‖₂/sqrt(lw) (a → 0) and ‖F‖∞ (a → ∞) on random operators and on a filter's error
//! operator, its monotonicity in a, and the worst covariance Σ(q) reaching exactly the level a.

use filterbench::anisotropy::{anisotropic_norm, gaussian_anisotropy};
use filterbench::linalg::Mat;

fn random(rows: usize, cols: usize, seed: u64) -> Mat {
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    Mat::from_fn(rows, cols, |_, _| {
        let x: f64 = StandardNormal.sample(&mut rng);
        x
    })
}

#[test]
fn gaussian_anisotropy_formula() {
    assert!(gaussian_anisotropy(&Mat::identity(4, 4)).abs() < 1e-15);
    let d = Mat::from_diagonal(&nalgebra::DVector::from_vec(vec![2.0, 1.0]));
    // −½ [ln(2·2/3) + ln(2·1/3)] = −½ ln(8/9).
    assert!((gaussian_anisotropy(&d) + 0.5 * (8.0f64 / 9.0).ln()).abs() < 1e-15);
}

fn check(f: &Mat, name: &str) {
    check_gram(&(f.transpose() * f), name);
}

/// The limits and monotonicity for Λ = E[FᵀF]: ‖F‖₂² = tr Λ and ‖F‖∞² = λmax(Λ) (F may be random).
pub(crate) fn check_gram(lambda: &Mat, name: &str) {
    let lambda = lambda.clone();
    let lw = lambda.ncols() as f64;
    let h2 = (lambda.trace() / lw).sqrt();
    let hinf = lambda.symmetric_eigenvalues().max().sqrt();
    let (small, _) = anisotropic_norm(&lambda, 1e-12).unwrap();
    assert!((small.value - h2).abs() <= 1e-4 * h2, "{name}: a → 0 gives {} vs ‖F‖₂/√lw {h2}", small.value);
    // The gap to ‖F‖∞ closes like e^{−2a/(lw−1)}: "a → ∞" is a = 50 lw here.
    let (large, _) = anisotropic_norm(&lambda, 50.0 * lw).unwrap();
    assert!((large.value - hinf).abs() <= 1e-6 * hinf, "{name}: a → ∞ gives {} vs ‖F‖∞ {hinf}", large.value);
    let mut last = 0.0;
    for a in [0.0, 0.05, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0] {
        let (n, sigma) = anisotropic_norm(&lambda, a).unwrap();
        assert!(n.value >= last * (1.0 - 1e-12), "{name}: norm decreases at a = {a}");
        last = n.value;
        assert!((gaussian_anisotropy(&sigma) - a).abs() <= 1e-8 * a.max(1.0), "{name}: A(Σ(q)) ≠ {a}");
        let gain = ((&lambda * &sigma).trace() / sigma.trace()).sqrt();
        assert!((gain - n.value).abs() <= 1e-9 * n.value, "{name}: gain at Σ(q) {gain} vs norm {}", n.value);
        assert!(n.value >= h2 * (1.0 - 1e-12) && n.value <= hinf * (1.0 + 1e-12));
    }
}

#[test]
fn norm_limits_monotonicity_and_worst_covariance() {
    for seed in 0..4 {
        check(&random(12, 20, seed), &format!("random F {seed}"));
    }
    // A filter's error operator over the horizon (hinf_tradeoff's Kalman predictor).
    let exp = crate::common::load("hinf_tradeoff", 10);
    let r = filterbench::families::kalman::kalman(&exp.plant, &exp.nominal, filterbench::spec::Pattern::Prediction);
    let psi = filterbench::hinf::operator_with(&exp.plant, &r, filterbench::hinf::Terminal::Output).unwrap();
    check(&psi, "Kalman predictor error operator");
}
