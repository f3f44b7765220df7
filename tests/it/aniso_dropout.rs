//! Seed 003: measurement dropouts, the exact Λ = E[𝓕ᵀ𝓕], the anisotropic generators, the
//! anisotropic SDP synthesis and the intermittent minimum-variance predictor.
//!
//! Tolerances: Monte Carlo figures within 4σ (σ = the standard error of the mean; a few dozen
//! comparisons per test, family-wise below 0.3 %); sample covariances entrywise within 4.5σ
//! (σ_ij = sqrt((Σ_ii Σ_jj + Σ_ij²)/n) for Gaussian draws; 903 entries, family-wise about 0.6 %);
//! deterministic identities to rounding (1e-9 relative); the SDP's guarantee to the solver's
//! tolerance (1e-6 relative).
use crate::common::Patch;

use filterbench::analysis::anisotropy::{coloured_covariance, error_gram, gaussian_anisotropy, realization_norm};
use filterbench::analysis::exact;
use filterbench::config::{self, Experiment, Pattern};
use filterbench::families::{anisotropic, intermittent, kalman};
use filterbench::model::shape::Shape;
use filterbench::numerics::accuracy;
use filterbench::numerics::linalg::{Mat, Vector, block_diag, psd_factor};
use filterbench::sim::noise::{JointInput, NoiseSampler};

use crate::common;

/// The shapes test plant with dropouts (p = 0.7) and anisotropic inputs added, as text.
pub(crate) fn dropout_shapes_text(pattern: &str) -> String {
    common::SHAPES_TOML
        .patch("PATTERN", pattern)
        .patch("known_input = {", "arrival = 0.7\nknown_input = {")
        .patch("trials = 6000", "trials = 5000")
        + r#"
[[scenarios]]
name = "coloured"
input = { kind = "coloured", anisotropy = 12.0 }

[[scenarios]]
name = "worst_for_kalman"
input = { kind = "anisotropic_worst_for", filter = "kalman", anisotropy = 4.0 }
"#
}

pub(crate) fn dropout_shapes(pattern: &str) -> Experiment {
    config::parse("dropout_shapes", "dropout_shapes.toml", &dropout_shapes_text(pattern)).expect("test plant parses")
}

#[test]
fn dropouts_exact_matches_monte_carlo_in_both_patterns() {
    // Filtering makes Df ≠ 0, so the dropout also multiplies the output map (the H1 terms).
    crate::exact_vs_mc::check(&dropout_shapes("prediction"));
    crate::exact_vs_mc::check(&dropout_shapes("filtering"));
}

#[test]
fn lambda_agrees_with_the_forward_moment_recursion() {
    for pattern in ["prediction", "filtering"] {
        let exp = dropout_shapes(pattern);
        let pat = if pattern == "filtering" { Pattern::Filtering } else { Pattern::Prediction };
        let real = kalman::kalman(&exp.plant, &exp.nominal, pat);
        let lambda = exact::second_moment_operator(&exp.plant, &real).unwrap();
        let d = lambda.nrows();
        let JointInput::Correlated { factor } = JointInput::random_covariance(&Mat::identity(d, d), 11) else {
            unreachable!()
        };
        let sigma = &factor * factor.transpose();
        let forward = exact::error_joint(&exp.plant, &real, &Vector::zeros(d), &sigma).unwrap().total;
        // E|e|² = tr(ΛΣ) + the deterministic part (x0's mean and r): no cross term, since the input
        // has zero mean and is independent of the dropouts.
        let via_lambda = (&lambda * &sigma).trace() + exact::deterministic_error(&exp.plant, &real);
        assert!(
            (forward - via_lambda).abs() <= 1e-9 * forward,
            "{pattern}: forward {forward} vs tr(ΛΣ) + deterministic {via_lambda}"
        );
        // White nominal noise through the joint path equals the white recursion.
        let white = block_diag(&[
            exp.nominal.x0(),
            &Mat::identity(exp.plant.steps(), exp.plant.steps()).kronecker(&exp.nominal.w()),
        ]);
        let joint = exact::error_joint(&exp.plant, &real, &Vector::zeros(d), &white).unwrap().total;
        let direct = exact::error(&exp.plant, &real, &exp.nominal).total;
        assert!((joint - direct).abs() <= 1e-9 * direct, "{pattern}: joint white {joint} vs white {direct}");
    }
}

#[test]
fn norm_limits_on_random_dropout_systems() {
    for seed in 0..3u64 {
        let exp = dropout_shapes("prediction");
        let mut plant = exp.plant.clone();
        plant.horizon = 6;
        plant.known_input.truncate(6);
        plant.set_arrival(0.5 + 0.1 * seed as f64);
        let real = kalman::kalman(&plant, &exp.nominal, Pattern::Prediction);
        crate::anisotropy::check_gram(&error_gram(&plant, &real).unwrap(), &format!("dropout system {seed}"));
    }
}

/// The experiment's plant on a shorter horizon (the SDP sweep is then quick).
fn short(p: &str, horizon: usize) -> Experiment {
    let mut e = common::variant("aniso_dropout", p, 100);
    e.plant.horizon = horizon;
    e.plant.known_input.truncate(horizon);
    e
}

#[test]
fn synthesized_norm_within_gamma_and_gamma_monotone_in_a() {
    let exp = short("p=0.95", 40);
    let mut last = (0.0, 0.0);
    for level in [
        anisotropic::Level::Anisotropy(0.0),
        anisotropic::Level::Anisotropy(2.0),
        anisotropic::Level::Anisotropy(8.0),
        anisotropic::Level::Anisotropy(30.0),
        anisotropic::Level::Hinf,
    ] {
        let syn = anisotropic::synthesize(&exp.plant, level).expect("feasible");
        let real = anisotropic::realization(&exp.plant, &syn);
        let norm_sq = match level {
            anisotropic::Level::Anisotropy(a) => realization_norm(&exp.plant, &real, a).unwrap().0.value.powi(2),
            anisotropic::Level::Hinf => error_gram(&exp.plant, &real).unwrap().symmetric_eigenvalues().max(),
        };
        let norm_error = accuracy::eigenvalue_error(&error_gram(&exp.plant, &real).unwrap());
        eprintln!("{level:?}: γ² = {:.6} (±{:.1e}), exact norm² = {norm_sq:.6}", syn.gamma_sq, syn.objective_error);
        assert!(
            accuracy::ordered(norm_sq, syn.gamma_sq, norm_error + syn.objective_error),
            "{level:?}: norm² {norm_sq} > γ² {}",
            syn.gamma_sq
        );
        assert!(
            accuracy::ordered(last.0, syn.gamma_sq, last.1 + syn.objective_error),
            "{level:?}: γ² {} below the smaller level's {last:?}",
            syn.gamma_sq
        );
        last = (syn.gamma_sq, syn.objective_error);
    }
}

#[test]
fn coloured_and_worst_generators_hit_anisotropy_power_and_covariance() {
    let w = Mat::from_row_slice(2, 2, &[1.0, 0.3, 0.3, 0.5]);
    let steps = 21;
    let white = steps as f64 * gaussian_anisotropy(&w);
    for a in [white, white + 0.5, white + 10.0, white + 60.0] {
        let (sigma, rho) = coloured_covariance(&w, steps, a).unwrap();
        assert!((gaussian_anisotropy(&sigma) - a).abs() <= 1e-9 * a.max(1.0), "a = {a}, ρ = {rho}");
        assert!((sigma.trace() - steps as f64 * w.trace()).abs() <= 1e-12 * sigma.trace());
    }
    assert!(coloured_covariance(&w, steps, white - 0.1).is_err(), "below white noise's anisotropy");

    // Sample covariance of the draws, through the sampler the engine uses (x0 block zero).
    let exp = short("p=0.95", steps - 1);
    let real = kalman::kalman(&exp.plant, &exp.nominal, Pattern::Prediction);
    let (_, worst) = realization_norm(&exp.plant, &real, 5.0).unwrap();
    let (coloured, _) = coloured_covariance(&exp.nominal.w(), steps, 8.0).unwrap();
    for (name, sigma) in [("coloured", coloured), ("worst for Kalman", worst)] {
        let factor = block_diag(&[&Mat::zeros(2, 2), &psd_factor(&sigma)]);
        let sampler = NoiseSampler::new(&exp.plant, &exp.nominal, &Shape::Gaussian)
            .with_joint(Some(JointInput::Correlated { factor }));
        let mut draw = sampler.workspace();
        let n = 20000;
        let lw = sigma.nrows();
        let mut acc = Mat::zeros(lw, lw);
        for t in 0..n {
            sampler.draw_trial(5, 0, t, &mut draw);
            let v = Vector::from_column_slice(draw.w.as_slice());
            acc += &v * v.transpose();
        }
        acc /= n as f64;
        let mut worst_z: f64 = 0.0;
        for i in 0..lw {
            for j in 0..=i {
                let se = ((sigma[(i, i)] * sigma[(j, j)] + sigma[(i, j)].powi(2)) / n as f64).sqrt();
                worst_z = worst_z.max((acc[(i, j)] - sigma[(i, j)]).abs() / se);
            }
        }
        eprintln!("{name}: largest entrywise |z| {worst_z:.2}");
        assert!(worst_z <= 4.5, "{name}: sample covariance off by {worst_z:.2}σ");
    }
}

#[test]
fn monte_carlo_gain_under_worst_inputs_matches_trace_formula() {
    let mut exp = common::variant("aniso_dropout", "p=0.95", 3000);
    // The guarantee and tr(ΛΣ)/tr Σ concern the noise alone: no known input here.
    exp.plant.known_input.clear();
    exp.scenarios.retain(|s| s.name.starts_with("worst_for_"));
    let out = filterbench::pipeline::run(&exp, false).unwrap();
    let a = exp.anisotropy.unwrap();
    let grams: Vec<Mat> = out.filters.iter().map(|f| error_gram(&exp.plant, &f.design.realization).unwrap()).collect();
    for sc in &out.scenarios {
        let owner = exp.filters.iter().position(|f| sc.name == format!("worst_for_{}", f.name)).unwrap();
        let (norm, sigma) = realization_norm(&exp.plant, &out.filters[owner].design.realization, a).unwrap();
        for (f, spec) in exp.filters.iter().enumerate() {
            let expected = (&grams[f] * &sigma).trace() / sigma.trace();
            let st = &sc.mc.filters[f].total;
            let (gain, se) = (st.mean / sc.input_power, st.std_error() / sc.input_power);
            let z = (gain - expected) / se;
            assert!(z.abs() <= 4.0, "{}/{}: gain {gain} vs tr(ΛΣ)/trΣ {expected}: {z:.2}σ", sc.name, spec.name);
            if f == owner {
                assert!((expected - norm.value.powi(2)).abs() <= 1e-9 * expected, "the owner's gain is its norm²");
            }
        }
    }
    // Each SDP filter's exact norm at the design level is within its γ².
    for (f, d) in out.filters.iter().enumerate() {
        if let Some(g) = d.design.gain_bound {
            let norm_sq = if g.anisotropy.is_finite() {
                realization_norm(&exp.plant, &d.design.realization, g.anisotropy).unwrap().0.value.powi(2)
            } else {
                grams[f].symmetric_eigenvalues().max()
            };
            // The printed γ² is certified: above the exact norm² up to the eigenvalues' rounding.
            let err = accuracy::eigenvalue_error(&grams[f]);
            assert!(
                accuracy::ordered(norm_sq, g.gamma_sq, err),
                "{}: {norm_sq} > γ² {}",
                exp.filters[f].name,
                g.gamma_sq
            );
            assert!(g.gamma_sq >= g.design_gamma_sq, "{}: guaranteed below the solver's γ²", exp.filters[f].name);
        }
    }
}

#[test]
fn intermittent_riccati_is_its_exact_error_and_without_dropouts_is_kalman() {
    let exp = common::variant("aniso_dropout", "p=0.95", 100);
    let (real, predicted) = intermittent::predictor(&exp.plant, &exp.nominal);
    let exact = exact::error(&exp.plant, &real, &exp.nominal).total;
    assert!((predicted - exact).abs() <= 1e-9 * exact, "Riccati {predicted} vs exact {exact}");
    // Perturbing its gain at one step makes it worse (it is the minimum-variance filter of its form).
    let mut worse = real.clone();
    let g = &mut worse.gains_mut(50)[0];
    g.bf[(0, 0)] += 0.05;
    g.af = exp.plant.a.at(0) - 0.95 * &g.bf * exp.plant.c.at(0);
    assert!(exact::error(&exp.plant, &worse, &exp.nominal).total > exact);
    let mut plant = exp.plant.clone();
    plant.measurement = filterbench::model::plant::Measurement::Always;
    let (mv, _) = intermittent::predictor(&plant, &exp.nominal);
    let kf = kalman::kalman(&plant, &exp.nominal, Pattern::Prediction);
    for (a, b) in mv.gains.iter().flat_map(|g| g.iter()).zip(kf.gains.iter().flat_map(|g| g.iter())) {
        assert!((&a.bf - &b.bf).amax() <= 1e-12 && (&a.af - &b.af).amax() <= 1e-12);
    }
}

#[test]
fn a_failed_sdp_is_a_clear_error_with_clarabel_status() {
    // Finite-horizon LMIs are always feasible for η large enough, so a failure is numerical: here
    // a plant scaled beyond what the interior-point method can represent.
    let mut exp = short("p=0.95", 5);
    exp.plant.b = exp.plant.b.map(|x| x * 1e160);
    let err = anisotropic::synthesize(&exp.plant, anisotropic::Level::Anisotropy(1.0)).err().expect("fails");
    eprintln!("{err}");
    assert!(err.contains("clarabel status"), "{err}");
}

#[test]
fn shaping_recursions_draw_what_the_dense_factors_draw() {
    // Every coloured and worst-case scenario of aniso_dropout (p = 0.95, N = 40) is drawn by a
    // recursion (the AR(1) colour, Lemma 1's shaping filter of each filter's worst input); its draws
    // must be the dense Cholesky product's to rounding, trial by trial.
    use filterbench::pipeline::{design_all, scenario_covariances, scenarios};
    let exp = short("p=0.95", 40);
    let filters = design_all(&exp).unwrap();
    let covs = scenario_covariances(&exp, &filters).unwrap();
    let mut shaped = 0;
    for (i, cov) in covs.iter().enumerate() {
        let s = scenarios::setup(&exp, &filters, i, cov).unwrap();
        let Some(joint) = &s.joint else { continue };
        assert!(s.sampler.is_shaped(), "scenario {} keeps the dense product", exp.scenarios[i].name);
        shaped += 1;
        let dense =
            NoiseSampler::new(&exp.plant, &s.covariances, &exp.scenarios[i].shape).with_joint(Some(joint.clone()));
        assert!(!dense.is_shaped());
        let (mut a, mut b) = (s.sampler.workspace(), dense.workspace());
        for t in [0, 7, 63, 64, 1000] {
            s.sampler.draw_trial(exp.seed, i, t, &mut a);
            dense.draw_trial(exp.seed, i, t, &mut b);
            let top = b.w.amax();
            assert!(top > 0.0);
            let diff = (&a.w - &b.w).amax();
            assert!(diff <= 1e-12 * top, "{} trial {t}: |Δw| {diff:e} against {top}", exp.scenarios[i].name);
        }
    }
    assert_eq!(shaped, 8, "two coloured and six worst-case scenarios");
}

#[test]
fn a_recursion_that_is_not_the_factor_is_refused() {
    use filterbench::sim::noise::Shaping;
    // The AR(1) colour at ρ against the factor of another ρ: the implied factors differ, so the run
    // must keep the dense product.
    let w = Mat::from_row_slice(2, 2, &[1.0, 0.3, 0.3, 0.5]);
    let steps = 30;
    let (sigma, rho) = coloured_covariance(&w, steps, 20.0).unwrap();
    let factor = block_diag(&[&Mat::zeros(2, 2), &psd_factor(&sigma)]);
    let lw = w.clone().cholesky().unwrap().l();
    let ar1 = |r: f64| Shaping::ar1(Mat::zeros(2, 2), &lw, r, steps);
    assert!(ar1(rho).matching(&factor).is_some(), "the right ρ matches");
    assert!(ar1(rho * 0.999).matching(&factor).is_none(), "another ρ is refused");
}
