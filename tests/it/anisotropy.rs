//! Anisotropy analysis (seed 003 §2): the Gaussian anisotropy formula, the a-anisotropic norm's
//! limits ‖F‖₂/sqrt(lw) (a → 0) and ‖F‖∞ (a → ∞) on random operators and on a filter's error
//! operator, its monotonicity in a, and the worst covariance Σ(q) reaching exactly the level a.

use filterbench::analysis::anisotropy::{anisotropic_norm, gaussian_anisotropy};
use filterbench::numerics::linalg::Mat;

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
    let r =
        filterbench::families::kalman::kalman(&exp.plant, &exp.nominal, filterbench::model::plant::Pattern::Prediction);
    let psi = filterbench::analysis::hinf::operator_with(&exp.plant, &r, filterbench::analysis::hinf::Terminal::Output)
        .unwrap();
    check(&psi, "Kalman predictor error operator");
}

/// The entropy of each standardized shape: against a direct quadrature of its density (Student-t,
/// from ln Γ, not the digamma closed form), the Gaussian as the limit of the mixture and of a
/// Student-t of many degrees of freedom, and every non-Gaussian shape below the Gaussian (the
/// Gaussian has the largest entropy of a given variance).
#[test]
fn shape_entropies() {
    use filterbench::model::shape::Shape;
    use std::f64::consts::PI;
    let hg = Shape::Gaussian.entropy().unwrap();
    assert!((hg - 0.5 * (2.0 * PI * std::f64::consts::E).ln()).abs() < 1e-15);
    // ∫ −p ln p by Simpson on a wide interval, p the unit-variance Student-t density.
    let t_entropy = |nu: f64| {
        let s = ((nu - 2.0) / nu).sqrt();
        let ln_c = statrs::function::gamma::ln_gamma(0.5 * (nu + 1.0))
            - statrs::function::gamma::ln_gamma(0.5 * nu)
            - 0.5 * (nu * PI).ln()
            - s.ln();
        let lnp = |x: f64| ln_c - 0.5 * (nu + 1.0) * (1.0 + (x / s).powi(2) / nu).ln();
        let (half, n) = (2000.0, 1usize << 22);
        let h = 2.0 * half / n as f64;
        (0..=n)
            .map(|i| {
                let x = -half + i as f64 * h;
                let w = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                let lp = lnp(x);
                -w * lp.exp() * lp
            })
            .sum::<f64>()
            * h
            / 3.0
    };
    for nu in [5.0, 6.0, 30.0] {
        let closed = Shape::StudentT { nu }.entropy().unwrap();
        assert!((closed - t_entropy(nu)).abs() < 1e-6, "ν = {nu}: {closed} vs quadrature {}", t_entropy(nu));
    }
    let big = Shape::StudentT { nu: 1e6 }.entropy().unwrap();
    assert!((big - hg).abs() < 1e-5, "Student-t → Gaussian: {big} vs {hg}");
    for m in [Shape::Mixture { weight: 0.0, ratio: 4.0 }, Shape::Mixture { weight: 0.3, ratio: 1.0 }] {
        assert!((m.entropy().unwrap() - hg).abs() < 1e-10, "{m:?} is the unit Gaussian");
    }
    assert!((Shape::Uniform.entropy().unwrap() - (12f64).sqrt().ln()).abs() < 1e-15);
    assert!((Shape::Laplace.entropy().unwrap() - (1.0 + 0.5 * 2f64.ln())).abs() < 1e-15);
    for s in [Shape::Uniform, Shape::Laplace, Shape::StudentT { nu: 6.0 }, Shape::Mixture { weight: 0.1, ratio: 4.0 }] {
        assert!(s.entropy().unwrap() < hg, "{s:?} has less entropy than the Gaussian");
    }
    assert_eq!(Shape::Rademacher.entropy(), None, "a discrete shape has no differential entropy");
}

/// The anisotropy reported for each scenario of the shapes plant: the same covariance, so every
/// non-Gaussian value is the Gaussian one plus lw times the shape's negentropy, and Rademacher's
/// is infinite.
#[test]
fn non_gaussian_inputs_have_more_anisotropy() {
    use filterbench::model::shape::Shape;
    let mut exp = crate::common::shapes("filtering");
    exp.trials = 2;
    let out = filterbench::pipeline::run(&exp, false).unwrap();
    let lw = (exp.plant.steps() * exp.plant.nw()) as f64;
    let hg = Shape::Gaussian.entropy().unwrap();
    let gaussian = out.scenarios.iter().find(|s| s.shape_label == "gaussian").unwrap().input_anisotropy.unwrap();
    for (spec, sc) in exp.scenarios.iter().zip(&out.scenarios) {
        let a = sc.input_anisotropy.expect("white noise of a nonsingular covariance");
        match spec.shape.entropy() {
            Some(h) => {
                let want = gaussian + lw * (hg - h);
                assert!((a - want).abs() <= 1e-9 * want.abs(), "{}: {a} vs {want}", sc.name);
                assert!(a >= gaussian, "{}", sc.name);
            }
            None => assert_eq!(a, f64::INFINITY, "{}: discrete input", sc.name),
        }
    }
}
