//! Anisotropic designs on ordinary plants (issue 13 §2): a generated set of plants (2–4 states;
//! stable, marginally stable (eigenvalues on the unit circle, the constant-velocity target among
//! them) and mildly unstable (growing by a factor 2–20 over the horizon); Cz of full and deficient column rank;
//! N ∈ {50, 100, 150, 200}; arrival 0.8–0.99; levels a ∈ {0, middle, ∞}). At least 99 % must
//! solve, every solved design's exact norm (from Λ, not from the solver) must be ≤ γ(1 + 1e-6),
//! and a failure must say whether it is infeasibility or a numerical failure.
//!
//! The full set of 216 plants takes minutes, so the suite runs a representative subset (every class,
//! rank, level and arrival range, N = 50 and 100); the full set, with design times per plant size,
//! is `cargo test --release aniso_design_full -- --ignored --nocapture` (a benchmark, not a timed
//! test).

use std::time::Instant;

use filterbench::families::anisotropic::{self, Level, Structure};
use filterbench::model::plant::Plant;
use filterbench::numerics::accuracy;
use filterbench::numerics::linalg::{Mat, Vector};
use rand::SeedableRng;
use rand_distr::{Distribution, Uniform};

fn uniform(rng: &mut rand_chacha::ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    Uniform::new(lo, hi).expect("lo < hi").sample(rng)
}

/// One generated case.
struct Case {
    label: String,
    plant: Plant,
    level: Level,
}

/// The i-th plant of the generated set: the class, size, rank, horizon, arrival and level cycle
/// independently, so any prefix of a few dozen covers every combination of each pair.
fn case(i: usize) -> Case {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1000 + i as u64);
    let n = 2 + i % 3;
    let class = (i / 3) % 3;
    let full_rank = (i / 9) % 2 == 0;
    let horizon = [50, 100, 150, 200][(i / 2) % 4];
    let level = [Level::Anisotropy(0.0), Level::Anisotropy(10.0), Level::Hinf][(i / 4) % 3];
    let arrival = uniform(&mut rng, 0.8, 0.99);
    let a = match class {
        // Stable: a random matrix scaled to spectral radius 0.6–0.95.
        0 => {
            let rho = uniform(&mut rng, 0.6, 0.95);
            random_with_radius(&mut rng, n, rho)
        }
        // Marginally stable: eigenvalues on the unit circle. Half of them contain the constant-velocity
        // target's double integrator [[1, 1], [0, 1]] (alone for n = 2, beside a random rotation
        // otherwise), half are a random orthogonal matrix. Longer chains of integrators are not
        // marginally stable (their state grows like k^{m−1/2}); they are outside this set (see the
        // README).
        1 => {
            let mut m = Mat::zeros(n, n);
            let start = if i % 2 == 0 {
                m[(0, 0)] = 1.0;
                m[(0, 1)] = 1.0;
                m[(1, 1)] = 1.0;
                2
            } else {
                0
            };
            if start < n {
                let q = random_orthogonal(&mut rng, n - start);
                m.view_mut((start, start), (n - start, n - start)).copy_from(&q);
            }
            m
        }
        // Mildly unstable: the state may grow by a factor g ∈ [2, 20] over the horizon, ρ = g^{1/N}
        // (1.014–1.062 at N = 50, 1.0035–1.015 at N = 200). The anisotropic predictor does not see
        // the dropouts, so its error grows like the state: at ρ = 1.1 and N = 200 its γ² would be
        // ~1e16 and clarabel reports the LMIs infeasible (measured: 22 of 24 such plants).
        _ => {
            let growth = uniform(&mut rng, 2.0, 20.0);
            random_with_radius(&mut rng, n, growth.powf(1.0 / horizon as f64))
        }
    };
    // w = (process, measurement): process noise on the last state (the acceleration of a chain of
    // integrators) and in one random direction, one noisy measurement of a random combination.
    let mut b = Mat::zeros(n, 3);
    b[(n - 1, 0)] = uniform(&mut rng, 0.3, 1.4);
    for r in 0..n {
        b[(r, 1)] = 0.3 * uniform(&mut rng, -1.0, 1.0);
    }
    let mut c = Mat::from_fn(1, n, |_, _| uniform(&mut rng, -1.0, 1.0));
    c[(0, 0)] = 1.0;
    let mut d = Mat::zeros(1, 3);
    d[(0, 2)] = uniform(&mut rng, 0.2, 1.0);
    let cz = if full_rank {
        Mat::identity(n, n)
    } else {
        // Estimate a subset: the first state alone, or the first two states' sum and the third.
        let rows = if n == 2 { 1 } else { n - 1 };
        Mat::from_fn(rows, n, |r, col| if col == r || (r == 0 && col == 1) { 1.0 } else { 0.0 })
    };
    let nz = cz.nrows();
    let mut plant =
        Plant::new(horizon, a, b, c, d, cz, Mat::zeros(nz, 3), Vector::zeros(n), 0, Vec::new(), vec![("w".into(), 3)]);
    plant.set_arrival(arrival);
    let classes = ["stable", "marginal", "unstable"];
    let label = format!(
        "#{i}: n = {n}, {}, Cz {}, N = {horizon}, p = {arrival:.3}, {level:?}",
        classes[class],
        if full_rank { "full rank" } else { "rank deficient" }
    );
    Case { label, plant, level }
}

fn random_with_radius(rng: &mut rand_chacha::ChaCha8Rng, n: usize, rho: f64) -> Mat {
    let g = Mat::from_fn(n, n, |_, _| uniform(rng, -1.0, 1.0));
    let r = g.complex_eigenvalues().iter().map(|z| z.norm()).fold(0.0, f64::max);
    g * (rho / r)
}

fn random_orthogonal(rng: &mut rand_chacha::ChaCha8Rng, n: usize) -> Mat {
    Mat::from_fn(n, n, |_, _| uniform(rng, -1.0, 1.0)).qr().q()
}

/// Designs every case; returns (solved, failures, design seconds per (n, N)) and prints how many
/// designs each attempt of [`anisotropic::synthesize_checked`] gave.
fn run_cases(indices: impl Iterator<Item = usize>) -> (usize, Vec<String>, Vec<(usize, usize, f64)>) {
    let mut by_attempt = [0usize; 4];
    let mut solved = 0;
    let mut failures = Vec::new();
    let mut times = Vec::new();
    for i in indices {
        let c = case(i);
        let t = Instant::now();
        match anisotropic::synthesize_checked(&c.plant, Structure::Predictor, c.level) {
            Ok(anisotropic::Checked { synthesis: syn, norm_sq, norm_error, certified_sq, attempt, .. }) => {
                by_attempt[attempt - 1] += 1;
                // The check inside synthesize_checked, restated on its outputs, and the certified
                // bound above the exact norm with nothing but the exact route's own rounding.
                assert!(
                    accuracy::ordered(norm_sq, syn.gamma_sq, norm_error + syn.objective_error),
                    "{}: exact norm² {norm_sq} > γ² {} (±{:.2e})",
                    c.label,
                    syn.gamma_sq,
                    syn.objective_error
                );
                assert!(
                    accuracy::ordered(norm_sq, certified_sq, norm_error),
                    "{}: {norm_sq} > {certified_sq}",
                    c.label
                );
                solved += 1;
            }
            Err(msg) => {
                assert!(
                    msg.contains("reports the anisotropic LMIs (4.42)–(4.43) infeasible")
                        || msg.contains("numerical failure"),
                    "{}: the message must tell infeasibility from numerical failure: {msg}",
                    c.label
                );
                assert!(!msg.contains('\n'));
                failures.push(format!("{}: {msg}", c.label));
            }
        }
        times.push((c.plant.nx(), c.plant.horizon, t.elapsed().as_secs_f64()));
    }
    eprintln!(
        "solved at attempt 1 (default settings) {}, 2 (robust settings) {}, 3 (balanced) {}, 4 (balanced, robust) {}",
        by_attempt[0], by_attempt[1], by_attempt[2], by_attempt[3]
    );
    (solved, failures, times)
}

#[test]
fn generated_subset_solves_within_gamma() {
    // Every 4th case of the full set with N ≤ 100: 27 designs covering each class, rank and level.
    let picked: Vec<usize> = (0..216).filter(|i| [50, 100].contains(&case(*i).plant.horizon)).step_by(4).collect();
    let total = picked.len();
    let (solved, failures, _) = run_cases(picked.into_iter());
    for f in &failures {
        eprintln!("{f}");
    }
    eprintln!("generated subset: {solved}/{total} solved");
    // 99 % of 27 means all of them.
    assert!(solved as f64 >= 0.99 * total as f64, "{solved}/{total} solved");
}

#[test]
fn constant_velocity_target_solves_at_every_horizon() {
    // The plant: A = [[1, 1], [0, 1]], process noise on the acceleration, position measured,
    // arrival 0.9; it failed with NumericalError at N = 100, 140 and 180.
    for horizon in [99, 100, 140, 180] {
        for q in [0.1, 2.0] {
            let b = Mat::from_row_slice(2, 2, &[0.5 * f64::sqrt(q), 0.0, f64::sqrt(q), 0.0]);
            let mut plant = Plant::new(
                horizon,
                Mat::from_row_slice(2, 2, &[1.0, 1.0, 0.0, 1.0]),
                b,
                Mat::from_row_slice(1, 2, &[1.0, 0.0]),
                Mat::from_row_slice(1, 2, &[0.0, 1.0]),
                Mat::identity(2, 2),
                Mat::zeros(2, 2),
                Vector::zeros(2),
                0,
                Vec::new(),
                vec![("w".into(), 2)],
            );
            plant.set_arrival(0.9);
            let anisotropic::Checked { synthesis: syn, norm_sq, attempt: attempts, .. } =
                anisotropic::synthesize_checked(&plant, Structure::Predictor, Level::Anisotropy(20.0))
                    .unwrap_or_else(|e| panic!("N = {horizon}, q = {q}: {e}"));
            eprintln!(
                "N = {horizon}, q = {q}: γ² = {:.6}, exact norm² = {norm_sq:.6}, attempts {attempts}",
                syn.gamma_sq
            );
        }
    }
}

#[test]
#[ignore = "benchmark: the full generated set, minutes; run with --ignored --nocapture"]
fn aniso_design_full() {
    let (solved, failures, times) = run_cases(0..216);
    for f in &failures {
        eprintln!("{f}");
    }
    eprintln!("generated set: {solved}/216 solved ({:.1} %)", 100.0 * solved as f64 / 216.0);
    for n in 2..=4 {
        for horizon in [50, 100, 150, 200] {
            let mut t: Vec<f64> = times.iter().filter(|x| x.0 == n && x.1 == horizon).map(|x| x.2).collect();
            t.sort_by(f64::total_cmp);
            if !t.is_empty() {
                eprintln!(
                    "design time n = {n}, N = {horizon}: median {:.2} s, max {:.2} s ({} designs)",
                    t[t.len() / 2],
                    t[t.len() - 1],
                    t.len()
                );
            }
        }
    }
    let mut all: Vec<f64> = times.iter().map(|x| x.2).collect();
    all.sort_by(f64::total_cmp);
    eprintln!("all designs: median {:.2} s, max {:.2} s", all[all.len() / 2], all[all.len() - 1]);
    assert!(solved as f64 >= 0.99 * 216.0, "{solved}/216 solved");
}
