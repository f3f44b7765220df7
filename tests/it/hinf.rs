//! The H∞-λ family (seed 002 §5): convergence to the Kalman predictor, the norm below λ, the worst
//! input attaining the norm, the smallest λ, refusals, and the per-trial guarantee under Monte Carlo.
use crate::common::Patch;

use filterbench::analysis::hinf;
use filterbench::config::{self, Experiment, Pattern};
use filterbench::families::h2::H2Figures;
use filterbench::families::hinf_lambda::{HinfFigures, lambda_min, predictor, recursion};
use filterbench::families::kalman::kalman;
use filterbench::numerics::accuracy;
use filterbench::numerics::linalg::{Mat, Vector};
use filterbench::pipeline;

fn load(trials: usize) -> Experiment {
    crate::common::load("hinf_tradeoff", trials)
}

/// Gains differ from the Kalman predictor's by O(1/λ): below 1e-6 at λ = 1e8.
#[test]
fn large_lambda_gives_the_kalman_predictor() {
    let exp = load(10);
    let s = Mat::identity(3, 3);
    let gains = recursion(&exp.plant, &exp.nominal, &s, 1e8).unwrap();
    let k = kalman(&exp.plant, &exp.nominal, Pattern::Prediction);
    let diff =
        gains.iter().zip(k.gains.iter().flat_map(|g| g.iter())).map(|(g, kg)| (g - &kg.bf).amax()).fold(0.0, f64::max);
    assert!(diff <= 1e-6, "max |Θ∞ − L_kalman| = {diff} at λ = 1e8");
}

/// The designed filter's norm² is below its λ, and equals λ_min at the smallest λ (to 1e-6
/// relative); below λ_min the recursion fails.
#[test]
fn norm_below_lambda_and_lambda_min_is_tight() {
    let exp = load(10);
    let s = Mat::identity(3, 3);
    let lmin = lambda_min(&exp.plant, &exp.nominal, &s).unwrap();
    for factor in [1.0 + 1e-6, 1.5, 2.0, 10.0] {
        let l = lmin * factor;
        let r = predictor(&exp.plant, &recursion(&exp.plant, &exp.nominal, &s, l).unwrap());
        let (n2, _) = hinf::norm(&exp.plant, &r, &exp.nominal, &s).unwrap();
        assert!(n2 < l, "norm² {n2} not below λ = {l}");
        if factor < 1.01 {
            assert!((n2 - lmin).abs() <= 1e-6 * lmin, "norm² {n2} vs λ_min {lmin}");
        }
    }
    assert!(recursion(&exp.plant, &exp.nominal, &s, lmin * (1.0 - 1e-6)).is_err());
}

/// The worst input ξ* on the ellipsoid, run through the filter by plain simulation (not through
/// Ψ), gives the ratio λmax(ΨKΨᵀ) to 1e-9.
#[test]
fn worst_input_attains_the_norm() {
    let exp = load(10);
    let s = Mat::identity(3, 3);
    let pl = &exp.plant;
    let r = predictor(pl, &recursion(pl, &exp.nominal, &s, 7.5).unwrap());
    let (n2, xi) = hinf::norm(pl, &r, &exp.nominal, &s).unwrap();
    let (n, nw) = (pl.nx(), pl.nw());
    let mut x = &pl.x0_mean + xi.rows(0, n);
    let mut st = r.s0.clone();
    let (mut num, mut zhat, mut next) = (0.0, Vector::zeros(pl.nz()), Vector::zeros(n));
    for k in 0..pl.horizon {
        let w = xi.rows(n + k * nw, nw).into_owned();
        let y = &*pl.c_at(k) * &x + &*pl.d_at(k) * &w;
        let z = pl.cz.at(0) * &x;
        r.output(k, 0, &st, &y, &mut zhat);
        num += (z - &zhat).norm_squared();
        r.advance(k, 0, &st, &y, pl.r_at(k), &mut next);
        st.copy_from(&next);
        x = pl.a.at(0) * &x + pl.b.at(0) * &w + pl.r_at(k).cloned().unwrap_or_else(|| Vector::zeros(n));
    }
    let e = &x - &st;
    num += (e.transpose() * &s * &e)[(0, 0)];
    let k_inv = hinf::input_weight(pl, &exp.nominal).try_inverse().unwrap();
    let den = (xi.transpose() * k_inv * &xi)[(0, 0)];
    assert!((num / den - n2).abs() <= 1e-9 * n2, "ratio {} vs norm² {n2}", num / den);
}

/// Monte Carlo against the exact error for joint inputs (ellipsoid, random covariance, fixed).
#[test]
fn monte_carlo_matches_the_exact_error_for_joint_inputs() {
    crate::exact_vs_mc::check(&load(4000));
}

#[test]
fn too_small_lambda_and_wrong_settings_are_refused() {
    let text = crate::common::text("hinf_tradeoff");
    let bad = text.patch("lambda = 7.5", "lambda = 1.0");
    let e = config::parse("h", "h.toml", &bad).unwrap();
    let err = pipeline::design_all(&e).err().expect("λ = 1 is infeasible").to_string();
    assert!(err.contains("hinf_7.5") && err.contains("too small") && err.contains("step 0"), "{err}");
    let filt = text.patch("pattern = \"prediction\"", "pattern = \"filtering\"");
    let err = config::parse("h", "h.toml", &filt).err().expect("refused when loaded").to_string();
    assert!(err.contains("does not design for the filtering pattern"), "{err}");
    let corr = text.patch("D = [[0.0, 0.0, 0.0, 0.5]]", "D = [[0.3, 0.0, 0.0, 0.5]]");
    let err = pipeline::design_all(&config::parse("h", "h.toml", &corr).unwrap()).err().unwrap().to_string();
    assert!(err.contains("noise split"), "{err}");
}

/// No trial of any scenario breaks the per-trial guarantee: 4000 trials × 10 scenarios per filter,
/// white noise of three shapes, random full covariances over the horizon, points on and inside the
/// ellipsoid, and each filter's worst input, whose ratio must equal the norm² (to 1e-9 relative).
#[test]
fn no_trial_violates_the_guarantee() {
    let exp = load(4000);
    let out = pipeline::run(&exp, false).unwrap();
    let mut checked = 0;
    for (f, spec) in exp.filters.iter().enumerate() {
        let Some(norm2) = out.filters[f].design.figures.get::<HinfFigures>().map(|x| x.hinf_norm_squared) else {
            continue;
        };
        let Some(sc) = out.scenarios.iter().find(|s| s.name == format!("worst_for_{}", spec.name)) else { continue };
        let r = sc.mc.filters[f].max_ratio;
        assert!((r - norm2).abs() <= 1e-9 * norm2, "{}: worst input ratio {r} vs norm² {norm2}", spec.name);
        checked += 1;
    }
    assert_eq!(checked, 2, "hinf_min and hinf_7.5 have a worst-input scenario");
    for sc in &out.scenarios {
        for (f, spec) in exp.filters.iter().enumerate() {
            if let Some(b) = &out.filters[f].design.per_trial {
                let st = &sc.mc.filters[f];
                assert_eq!(st.violations, 0, "{}/{}", sc.name, spec.name);
                assert!(
                    st.max_ratio > 0.0 && st.max_ratio <= b.bound() * (1.0 + 1e-9),
                    "{}/{}: max ratio {}",
                    sc.name,
                    spec.name,
                    st.max_ratio
                );
            }
        }
    }
}

/// The two independent computations of the generalized H∞ norm² agree within their stated
/// accuracies (the eigenvalue's rounding bound, clarabel's objective error): λmax of the stacked
/// operator (faer) and the SDP (4.7) (clarabel), on the experiment's filters and on
/// random plants (noise split (5.5), random gains of the H∞-λ family).
#[test]
fn operator_and_sdp_norms_agree() {
    let exp = load(10);
    let s = Mat::identity(3, 3);
    let filters = pipeline::design_all(&exp).unwrap();
    let mut cases: Vec<(Experiment, filterbench::filter::realization::Realization)> =
        filters.iter().map(|f| (exp.clone(), f.design.realization.clone())).collect();
    for e in random_plants(&exp, 11, 3, 0.5) {
        let l = lambda_min(&e.plant, &e.nominal, &s).unwrap();
        let r = predictor(&e.plant, &recursion(&e.plant, &e.nominal, &s, 1.7 * l).unwrap());
        cases.push((e, r));
    }
    for (e, r) in &cases {
        let (a, a_error, _) = hinf::norm_with_error(&e.plant, r, &e.nominal, &s).unwrap();
        let (b, b_error, it, secs) = hinf::norm_sdp(&e.plant, r, &e.nominal, &s).unwrap();
        assert!(accuracy::agree(a, b, a_error + b_error), "λmax {a} (±{a_error:.1e}) vs SDP {b} (±{b_error:.1e})");
        eprintln!("norm² λmax {a:.9} SDP {b:.9} ({it} iterations, {secs:.3} s, N = {})", e.plant.horizon);
    }
}

/// `count` random plants on `base`'s dimensions (hinf_tradeoff: n = 3, w = (process 3,
/// measurement 1)) that keep the noise split (5.5): N = 15, no known input, A with N(0, a_scale²)
/// entries, B's process block 0.4 N(0, 1), C and Cz N(0, 1).
use filterbench::model::plant::Steps;

pub fn random_plants(base: &Experiment, seed: u64, count: usize, a_scale: f64) -> Vec<Experiment> {
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut g = |r: usize, c: usize, scale: f64| {
        Mat::from_fn(r, c, |_, _| {
            let x: f64 = StandardNormal.sample(&mut rng);
            scale * x
        })
    };
    (0..count)
        .map(|_| {
            let mut e = base.clone();
            e.plant.horizon = 15;
            e.plant.known_input.clear();
            e.plant.a = Steps::constant(g(3, 3, a_scale));
            let b = g(3, 3, 0.4);
            e.plant.b = e.plant.b.map(|old| {
                let mut new = old.clone();
                new.view_mut((0, 0), (3, 3)).copy_from(&b);
                new
            });
            e.plant.c = Steps::constant(g(1, 3, 1.0));
            e.plant.cz = Steps::constant(g(2, 3, 1.0));
            e
        })
        .collect()
}

/// Theorem 3.1 for the generalized H2 filter: at every step the worst gain of e_z[t] over inputs up
/// to t, λmax(Ψ_t K Ψ_tᵀ) from the stacked operator, equals λmax(Cz P2[t] Czᵀ) (1e-9 relative).
#[test]
fn h2_worst_gain_per_step_is_lambda_max_of_cz_p2_czt() {
    let exp = load(10);
    let pl = &exp.plant;
    let p2 = filterbench::families::h2::riccati(pl, &exp.nominal);
    let r = kalman(pl, &exp.nominal, Pattern::Prediction);
    let psi = hinf::operator_with(pl, &r, hinf::Terminal::Output).unwrap();
    let k = hinf::input_weight(pl, &exp.nominal);
    let nz = pl.nz();
    for (t, p) in p2.iter().enumerate() {
        let pt = psi.rows(t * nz, nz);
        let a = (pt * &k * pt.transpose()).symmetric_eigenvalues().max();
        let b = (pl.cz.at(0) * p * pl.cz.at(0).transpose()).symmetric_eigenvalues().max();
        assert!((a - b).abs() <= 1e-9 * b, "step {t}: operator {a} vs Cz P2 Czᵀ {b}");
    }
}

/// Seed 002 eqs (5.11)–(5.15) written out for the regression y[t] = Φ[t] ζ + v[t]: recursive
/// weighted least squares, P⁻¹[t+1] = P⁻¹ + ΦᵀG⁻¹Φ, Θ = P[t+1]ΦᵀG⁻¹, and its H∞-λ version with
/// − λ⁻¹ I added, against the h2 and hinf families' gains (1e-10); and no trial of hinf_regression
/// breaks a per-trial bound (4000 trials × 6 scenarios).
#[test]
fn regression_rls_and_its_hinf_version() {
    let exp = crate::common::load("hinf_regression", 4000);
    let filters = pipeline::design_all(&exp).unwrap();
    let g_inv = 1.0 / exp.nominal.w()[(0, 0)];
    for (name, lambda) in [("rls", f64::INFINITY), ("hinf_60", 60.0)] {
        let f = exp.filter_index(name).unwrap();
        let r = &filters[f].design.realization;
        let mut p_inv = exp.nominal.x0().clone().try_inverse().unwrap();
        for t in 0..exp.plant.horizon {
            let phi = &*exp.plant.c_at(t);
            p_inv += phi.transpose() * phi * g_inv - Mat::identity(3, 3) / lambda;
            let theta = p_inv.clone().try_inverse().unwrap() * phi.transpose() * g_inv;
            let d = (&theta - &r.gains[t][0].bf).amax();
            assert!(d <= 1e-10 * theta.amax().max(1.0), "{name} step {t}: gain differs by {d}");
        }
    }
    let out = pipeline::run(&exp, false).unwrap();
    for sc in &out.scenarios {
        for (f, spec) in exp.filters.iter().enumerate() {
            assert_eq!(sc.mc.filters[f].violations, 0, "{}/{}", sc.name, spec.name);
        }
    }
}

/// The generalized H2 norm of every filter (seed 002 Theorem 3.1): for the generalized H2 filter it
/// is its design level max_t λmax(Cz P2[t] Czᵀ) (1e-9), and no other filter of the experiment has a
/// smaller one (the Kalman predictor's error covariance is the smallest in the Loewner order at
/// every step).
#[test]
fn generalized_h2_norm_of_every_filter() {
    let exp = crate::common::load("hinf_tradeoff", 10);
    let filters = filterbench::pipeline::design_all(&exp).unwrap();
    let h2 = exp.filter_index("h2").unwrap();
    let level = filters[h2].design.figures.get::<H2Figures>().unwrap().h2_level;
    let own = filters[h2].generalized_h2_sq.unwrap();
    assert!((own - level).abs() <= 1e-9 * level, "h2 filter: {own} vs its level {level}");
    for (spec, f) in exp.filters.iter().zip(&filters) {
        let g = f.generalized_h2_sq.expect("a plant that does not switch");
        assert!(g >= own * (1.0 - 1e-9), "{}: {g} below the H2 filter's {own}", spec.name);
    }
}
