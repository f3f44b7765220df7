//! Exact errors and Monte Carlo on unstable plants (issue 13 §1): the moments of (x, s) grow like
//! |A|^{2k} while the error stays bounded, so the plant-coordinate recursion cancels; the exact
//! analysis must switch to error coordinates s − M x, checked, or refuse.
//!
//! The references are independent Joseph-form Riccati recursions written here from the textbook
//! equations (not the library's): P = (I − K C) P̄ (I − K C)ᵀ + K R Kᵀ, which stays accurate however
//! fast the plant grows. Tolerances: exact against Riccati 1e-8 relative (the issue's requirement;
//! both are accurate to ~1e-12 when correct, while the plant-coordinate recursion is off by O(1) on
//! these plants); Monte Carlo within 4σ of exact (σ its standard error; the families of comparisons
//! below are a few dozen, so a correct engine fails one with probability below 0.3 %).

use filterbench::analysis::exact;
use filterbench::config::{self, Experiment, Pattern};
use filterbench::numerics::linalg::Mat;
use filterbench::pipeline;
use rand::SeedableRng;
use rand_distr::{Distribution, Uniform};

use crate::common;

/// Σ_{k counted} tr(Cz P Czᵀ) for the Kalman filter of a plant with uncorrelated process and
/// measurement noise (B W Dᵀ = 0), Dz = 0, no modes, from the Joseph form: P[k|k] when filtering,
/// P[k|k−1] when predicting.
fn joseph_kalman(exp: &Experiment) -> f64 {
    let pl = &exp.plant;
    let w = exp.nominal.w();
    let (q, r) = (pl.b.at(0) * &w * pl.b.at(0).transpose(), pl.d.at(0) * &w * pl.d.at(0).transpose());
    assert!(
        (pl.b.at(0) * &w * pl.d.at(0).transpose()).amax() == 0.0 && pl.dz.at(0).amax() == 0.0,
        "test plant has B W Dᵀ = 0, Dz = 0"
    );
    let n = pl.nx();
    let mut pbar = exp.nominal.x0().clone();
    let mut total = 0.0;
    for k in 0..pl.steps() {
        let c = &*pl.c_at(k);
        let (p, kg) = if pl.measured(k) {
            let s = c * &pbar * c.transpose() + &r;
            let kg = &pbar * c.transpose() * s.try_inverse().expect("S ≻ 0");
            let ikc = Mat::identity(n, n) - &kg * c;
            (&ikc * &pbar * ikc.transpose() + &kg * &r * kg.transpose(), kg)
        } else {
            (pbar.clone(), Mat::zeros(n, pl.ny()))
        };
        let _ = kg;
        let counted = match exp.pattern {
            Pattern::Filtering => &p,
            Pattern::Prediction => &pbar,
        };
        if pl.counts(k) {
            total += (pl.cz.at(0) * counted * pl.cz.at(0).transpose()).trace();
        }
        pbar = pl.a.at(0) * &p * pl.a.at(0).transpose() + &q;
    }
    total
}

/// The mode-dependent predictor on a dropout plant (it sees λ[k]): with independent modes the
/// error covariance P obeys, in Joseph form with K_λ = A P Cλᵀ (Cλ P Cλᵀ + R)⁻¹ (Cλ = λ C),
/// P' = Σ_λ P(λ) [(A − K_λ Cλ) P (·)ᵀ + K_λ R K_λᵀ] + Q; returns Σ tr(Cz P Czᵀ).
fn joseph_dropout_predictor(exp: &Experiment) -> f64 {
    let pl = &exp.plant;
    let p_arr = pl.arrival().expect("dropout plant");
    let w = exp.nominal.w();
    let (q, r) = (pl.b.at(0) * &w * pl.b.at(0).transpose(), pl.d.at(0) * &w * pl.d.at(0).transpose());
    let mut p = exp.nominal.x0().clone();
    let mut total = 0.0;
    for k in 0..pl.steps() {
        if pl.counts(k) {
            total += (pl.cz.at(0) * &p * pl.cz.at(0).transpose()).trace();
        }
        let c = &*pl.c_at(k);
        let s = c * &p * c.transpose() + &r;
        let kg = pl.a.at(0) * &p * c.transpose() * s.try_inverse().expect("S ≻ 0");
        let akc = pl.a.at(0) - &kg * c;
        let arrived = &akc * &p * akc.transpose() + &kg * &r * kg.transpose();
        let lost = pl.a.at(0) * &p * pl.a.at(0).transpose();
        p = p_arr * arrived + (1.0 - p_arr) * lost + &q;
    }
    total
}

fn matrix(m: &Mat) -> String {
    let rows: Vec<String> = (0..m.nrows())
        .map(|i| format!("[{}]", (0..m.ncols()).map(|j| format!("{:e}", m[(i, j)])).collect::<Vec<_>>().join(", ")))
        .collect();
    format!("[{}]", rows.join(", "))
}

/// The largest |eigenvalue| of a square matrix.
fn spectral_radius(a: &Mat) -> f64 {
    a.complex_eigenvalues().iter().map(|z| z.norm()).fold(0.0, f64::max)
}

/// An experiment on a plant with the given A (process noise on every state, one noisy measurement
/// per row of C, Cz = I), with the given filters' TOML.
fn experiment(a: &Mat, c: &Mat, horizon: usize, pattern: &str, arrival: Option<f64>, filters: &str) -> Experiment {
    let (n, ny) = (a.nrows(), c.nrows());
    let mut b = Mat::zeros(n, n + ny);
    let mut d = Mat::zeros(ny, n + ny);
    for i in 0..n {
        b[(i, i)] = 0.5 + 0.1 * i as f64;
    }
    for i in 0..ny {
        d[(i, n + i)] = 0.4;
    }
    let arrival = arrival.map_or(String::new(), |p| format!("arrival = {p}\n"));
    let text = format!(
        r#"
description = "random unstable plant"
seed = 11
trials = 3000
pattern = "{pattern}"
sample_trajectories = 0

[plant]
horizon = {horizon}
noise_blocks = ["w"]
A = {a}
B = {b}
C = {c}
D = {d}
{arrival}
[nominal]
x0 = {x0}
w = {w}

{filters}

[[scenarios]]
name = "gaussian"

[[scenarios]]
name = "laplace"
shape = {{ kind = "laplace" }}
"#,
        a = matrix(a),
        b = matrix(&b),
        c = matrix(c),
        d = matrix(&d),
        x0 = matrix(&Mat::identity(n, n)),
        w = matrix(&Mat::identity(n + ny, n + ny)),
    );
    config::parse("unstable", "unstable.toml", &text).unwrap_or_else(|e| panic!("test plant parses: {e}"))
}

/// A random n×n matrix with spectral radius `rho`, and a random ny×n measurement matrix.
fn random_plant(rng: &mut rand_chacha::ChaCha8Rng, n: usize, ny: usize, rho: f64) -> (Mat, Mat) {
    let g = Mat::from_fn(n, n, |_, _| uniform(rng, -1.0, 1.0));
    let a = &g * (rho / spectral_radius(&g));
    let c = Mat::from_fn(ny, n, |_, _| uniform(rng, -1.0, 1.0));
    (a, c)
}

fn uniform(rng: &mut rand_chacha::ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    Uniform::new(lo, hi).expect("lo < hi").sample(rng)
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Asserts exact = Riccati to 1e-8 relative; returns the relative difference.
fn within_1e8(exact: f64, riccati: f64, what: &str) -> f64 {
    let rel = relative(exact, riccati);
    assert!(rel <= 1e-8, "{what}: exact {exact} vs Riccati {riccati} ({rel:.2e} relative)");
    rel
}

#[test]
fn seed000_plant_with_a_1_5_matches_joseph_riccati_and_monte_carlo() {
    let mut exp = common::baseline(4000);
    exp.plant.a = filterbench::model::plant::Steps::constant(Mat::identity(3, 3) * 1.5);
    exp.plant.horizon = 50;
    let reference = joseph_kalman(&exp);
    let filters = pipeline::design_all(&exp).expect("designs");
    let ours = exact::error(&exp.plant, &filters[0].design.realization, &exp.nominal);
    assert!(
        relative(ours.total, reference) <= 1e-8,
        "A = 1.5·I: exact {} vs Joseph-form Riccati {reference} (coordinates {:?})",
        ours.total,
        ours.coordinates
    );
    assert_eq!(ours.coordinates, exact::Coordinates::Error, "the plant coordinates lose digits here");
    eprintln!("A = 1.5·I, N = 50: exact {:.6} vs Riccati {reference:.6}", ours.total);
    // The mis-specified Kalman filter tracks the plant as well: its exact error is resolved too,
    // and Monte Carlo agrees with both (the guarantee is the exact error at the design covariance).
    crate::exact_vs_mc::check(&exp);
}

#[test]
fn a_10_and_a_long_horizon_stay_finite_and_exact() {
    for (rho, horizon) in [(10.0, 50), (10.0, 350), (2.0, 200)] {
        let mut exp = common::baseline(2000);
        exp.plant.a = filterbench::model::plant::Steps::constant(Mat::identity(3, 3) * rho);
        exp.plant.horizon = horizon;
        let reference = joseph_kalman(&exp);
        let filters = pipeline::design_all(&exp).expect("designs");
        let ours = exact::error(&exp.plant, &filters[0].design.realization, &exp.nominal);
        assert!(
            relative(ours.total, reference) <= 1e-8,
            "A = {rho}·I, N = {horizon}: exact {} vs Riccati {reference}",
            ours.total
        );
        if horizon <= 50 {
            crate::exact_vs_mc::check(&exp);
        }
    }
}

#[test]
fn random_unstable_plants_without_dropouts() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(13);
    let mut worst: f64 = 0.0;
    let mut cases = 0;
    for case in 0..24 {
        let n = 2 + case % 3;
        let ny = 1 + case % 2;
        let rho = uniform(&mut rng, 1.05, 2.0);
        let horizon = [20, 60, 120, 200][case % 4];
        let pattern = if case % 2 == 0 { "filtering" } else { "prediction" };
        let (a, c) = random_plant(&mut rng, n, ny, rho);
        let filters = "[[filters]]\nname = \"kalman\"\nfamily = \"kalman\"\n";
        let exp = experiment(&a, &c, horizon, pattern, None, filters);
        let real = &pipeline::design_all(&exp).expect("designs")[0].design.realization;
        let reference = joseph_kalman(&exp);
        let ours = exact::error(&exp.plant, real, &exp.nominal).total;
        worst = worst.max(within_1e8(
            ours,
            reference,
            &format!("case {case}: n = {n}, ρ(A) = {rho:.3}, N = {horizon}, {pattern}"),
        ));
        cases += 1;
        // Monte Carlo on a third of them (each costs a full run).
        if case % 3 == 0 {
            crate::exact_vs_mc::check(&exp);
        }
    }
    eprintln!("{cases} random unstable plants without dropouts: largest relative error vs Riccati {worst:.2e}");
}

#[test]
fn random_unstable_plants_with_dropouts_resolved_or_refused() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(31);
    let tracking = "[[filters]]\nname = \"mode_dependent\"\nfamily = \"markov_jump\"\n";
    let ignoring = "[[filters]]\nname = \"kalman_ignoring_dropouts\"\nfamily = \"kalman\"\n";
    let (mut worst, mut refused, mut resolved, mut checked): (f64, usize, usize, usize) = (0.0, 0, 0, 0);
    for case in 0..12 {
        let n = 2 + case % 3;
        // Every third plant milder (ρ ≤ 1.4, p ≥ 0.97), so that Monte Carlo is valid on it (below).
        let mild = case % 3 == 1;
        let rho = if mild { uniform(&mut rng, 1.05, 1.4) } else { uniform(&mut rng, 1.05, 2.0) };
        let horizon = [30, 100, 200][case % 3];
        let arrival = if mild { uniform(&mut rng, 0.97, 0.99) } else { uniform(&mut rng, 0.9, 0.99) };
        let (a, c) = random_plant(&mut rng, n, 1 + case % 2, rho);
        // The predictor that sees the dropouts tracks the plant in both modes: exact equals the
        // Riccati recursion and Monte Carlo agrees.
        let exp = experiment(&a, &c, horizon, "prediction", Some(arrival), tracking);
        let designed = pipeline::design_all(&exp).expect("designs");
        let reference = joseph_dropout_predictor(&exp);
        let ours = exact::error(&exp.plant, &designed[0].design.realization, &exp.nominal).total;
        let what = format!("case {case}: n = {n}, ρ(A) = {rho:.3}, N = {horizon}, p = {arrival:.3}");
        worst = worst.max(within_1e8(ours, reference, &what));
        // Monte Carlo where its 4σ test is valid: e grows by A over each run of lost measurements,
        // so E|e|⁴ (the variance of the squared error the standard error estimates) is finite only
        // for (1 − p) ρ(A)⁴ < 1; with a margin, (1 − p) ρ⁴ < 0.25. Beyond it the squared error is so
        // heavy-tailed that 3000 trials are far from normal (measured: −4.7σ at one step of 200).
        if (1.0 - arrival) * rho.powi(4) < 0.25 {
            crate::exact_vs_mc::check(&exp);
            checked += 1;
        }
        // The Kalman filter that ignores them does not track x when a measurement is lost: its
        // error grows with x, genuinely. A run is either resolved (then its numbers are the plant
        // coordinates' with at most 6 digits lost) or refused with one line naming the filter, the
        // step and the digits lost. Its Monte Carlo is not compared here: the error is dominated by
        // rare runs of lost measurements on a growing state, so 3000 trials are far from the normal
        // approximation behind a 4σ test (measured on case 0: −1.0σ at 2000 trials, within 1.3σ at
        // 200 000).
        let mut exp = experiment(&a, &c, horizon, "prediction", Some(arrival), ignoring);
        exp.trials = 100;
        match pipeline::run(&exp, false) {
            Ok(out) => {
                for sc in &out.scenarios {
                    assert!(sc.exact[0].resolution.digits_lost <= exact::MAX_DIGITS_LOST);
                    assert!(sc.exact[0].total.is_finite());
                }
                resolved += 1;
            }
            Err(e) => {
                let msg = e.to_string();
                assert!(
                    msg.contains("kalman_ignoring_dropouts")
                        && msg.contains("at step")
                        && (msg.contains("digits lost") || msg.contains("overflowed")),
                    "case {case}: refusal should name the filter, the step and the digits lost: {msg}"
                );
                assert!(!msg.contains('\n'), "one line: {msg}");
                refused += 1;
            }
        }
    }
    eprintln!(
        "12 random unstable dropout plants: mode-dependent predictor within {worst:.2e} of Riccati, Monte Carlo \
         checked on {checked}; runs with the dropout-ignoring Kalman filter resolved {resolved}, refused {refused}"
    );
    assert!(checked >= 3, "too few plants within the Monte Carlo test's validity: {checked}");
}

#[test]
fn error_coordinates_agree_with_the_reference_where_it_is_accurate() {
    // On the shipped stable plant the plant-coordinate recursion is accurate: the error-coordinate
    // one must give the same numbers to rounding.
    for pattern in ["filtering", "prediction"] {
        let exp = common::shapes(pattern);
        let real = &pipeline::design_all(&exp).expect("designs")[0].design.realization;
        let reference = exact::error(&exp.plant, real, &exp.nominal);
        assert_eq!(reference.coordinates, exact::Coordinates::Plant);
        let ours = exact::error_in_error_coordinates(&exp.plant, real, &exp.nominal).expect("Kalman tracks x");
        for (k, (a, b)) in ours.per_step.iter().zip(&reference.per_step).enumerate() {
            assert!(relative(*a, *b) <= 1e-10, "{pattern} step {k}: {a} vs {b}");
        }
    }
}

#[test]
fn a_declared_m_that_does_not_hold_is_not_used() {
    // A filter that claims to track x but whose gains do not satisfy Af + Bf C − A = 0.
    let mut exp = common::baseline(10);
    exp.plant.a = filterbench::model::plant::Steps::constant(Mat::identity(3, 3) * 1.5);
    let mut real = pipeline::design_all(&exp).expect("designs")[0].design.realization.clone();
    real.gains_mut(10)[0].af[(0, 0)] += 1e-3;
    let why = exact::error_form(&exp.plant, &real).expect_err("the identity is checked");
    assert!(why.contains("step 10") && why.contains("Af M + Bf C − M A"), "{why}");
    let e = exact::error(&exp.plant, &real, &exp.nominal);
    assert_eq!(e.coordinates, exact::Coordinates::Plant, "no error coordinates without the identity");
}

#[test]
fn an_error_double_precision_cannot_resolve_is_refused_with_the_step_and_digits() {
    // Off by 1e-7 of the tracking identity at one step: the true error grows with x but is 1e-14 of
    // x's second moment at N = 100, which double precision cannot difference.
    let mut exp = common::baseline(10);
    exp.plant.a = filterbench::model::plant::Steps::constant(Mat::identity(3, 3) * 1.5);
    exp.plant.horizon = 100;
    let mut real = pipeline::design_all(&exp).expect("designs")[0].design.realization.clone();
    real.gains_mut(1)[0].af[(0, 0)] += 1e-7;
    let e = exact::error(&exp.plant, &real, &exp.nominal);
    let msg = e.trusted("perturbed").expect_err("refused").to_string();
    assert!(
        msg.contains("filter `perturbed`")
            && msg.contains("at step")
            && msg.contains("digits lost")
            && msg.contains("step 1"),
        "{msg}"
    );
    eprintln!("{msg}");
}
