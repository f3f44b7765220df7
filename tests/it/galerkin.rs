//! Seed 004: the regularized Galerkin filter for the string with degenerate measurement noise.
//!
//! Exact errors are compared as time averages (summed error / (N + 1)), so that different steps are
//! comparable. Tolerances: stated at each assertion; Monte Carlo within 4σ in total and 4.5σ per
//! step (as in `exact_vs_mc`).

use filterbench::analysis::exact;
use filterbench::config::{self, Experiment, FilterSpec};
use filterbench::model::plant::{Covariances, Plant};
use filterbench::numerics::linalg::Mat;

use crate::common::{self, Patch};

/// Time-averaged exact errors of every filter of `exp`, by name.
fn averaged(exp: &Experiment) -> std::collections::BTreeMap<String, f64> {
    let designs = filterbench::pipeline::design_all(exp).unwrap();
    exp.filters
        .iter()
        .zip(&designs)
        .map(|(f, d)| {
            let e = exact::error(&exp.plant, &d.design.realization, &exp.nominal);
            (f.name.clone(), e.total / exp.plant.steps() as f64)
        })
        .collect()
}

fn name(basis: &str, n: usize, alpha: &str) -> String {
    format!("{basis}_n{n}_alpha{alpha}")
}

const ALPHAS: [&str; 4] = ["0.1", "0.0001", "0.00000001", "0.000000000001"];

#[test]
fn error_in_n_alpha_and_basis() {
    let exp = common::variant("galerkin_string", "m6_dt0.0025", 10);
    let e = averaged(&exp);
    for a in ALPHAS {
        for basis in ["eigen", "hat"] {
            // Beyond the 6 sensors' resolvable modes (n = 8 → 16): no increase beyond 0.1 %
            // (a regularized filter is not optimal, so adding modes may cost a little), and
            // converged within 5 %.
            let (e8, e16) = (e[&name(basis, 8, a)], e[&name(basis, 16, a)]);
            eprintln!("{basis} α = {a}: n = 8 {e8:.6}, n = 16 {e16:.6}");
            assert!(e16 <= e8 * 1.001, "{basis} α = {a}: the error grows from n = 8 to 16");
            assert!((e8 - e16).abs() <= 0.05 * e16, "{basis} α = {a}: not converged in n");
        }
        // The eigenfunction and hat bases agree as n grows: their gap shrinks, below 1 % at n = 16.
        let gap = |n| (e[&name("hat", n, a)] - e[&name("eigen", n, a)]).abs() / e[&name("eigen", n, a)];
        eprintln!("α = {a}: basis gap n = 2 {:.4}, 4 {:.4}, 8 {:.4}, 16 {:.4}", gap(2), gap(4), gap(8), gap(16));
        assert!(gap(16) <= gap(8) + 1e-9 && gap(8) <= gap(4) + 1e-9 && gap(16) <= 0.01, "α = {a}: bases do not agree");
    }
    // For fixed large n the error falls as α → 0 and converges: α = 1e-14 changes it by < 0.1 %
    // from α = 1e-12, although W_m is singular.
    let mut last = f64::INFINITY;
    for a in ALPHAS {
        let v = e[&name("eigen", 16, a)];
        assert!(v < last, "α = {a}: the error does not fall");
        last = v;
    }
    let mut tiny = exp.clone();
    tiny.filters = vec![spec_of("eigen", 16, 1e-14)];
    let e14 = averaged(&tiny)["tiny"];
    eprintln!("eigen n = 16: α = 1e-12 {last:.7}, α = 1e-14 {e14:.7}");
    assert!((e14 - last).abs() <= 1e-3 * last);
}

fn spec_of(basis: &str, n: usize, alpha: f64) -> FilterSpec {
    let mut params = toml::Table::new();
    params.insert("basis".into(), basis.into());
    params.insert("n".into(), (n as i64).into());
    params.insert("alpha".into(), alpha.into());
    FilterSpec::new("tiny".into(), "galerkin".into(), params).expect("valid parameters")
}

#[test]
fn alpha_zero_is_refused_when_w_m_is_singular() {
    let mut exp = common::variant("galerkin_string", "m3_dt0.0025", 10);
    exp.filters = vec![spec_of("eigen", 4, 0.0)];
    let err = filterbench::pipeline::design_all(&exp).err().expect("refused").to_string();
    assert!(err.contains("singular") && err.contains("alpha"), "{err}");
}

#[test]
fn halving_the_step_changes_the_error_by_less_than_one_percent() {
    let coarse = averaged(&common::variant("galerkin_string", "m6_dt0.0025", 10));
    let fine = averaged(&common::variant("galerkin_string", "m6_dt0.00125", 10));
    let worst = coarse.iter().map(|(k, v)| ((fine[k] - v) / v).abs()).fold(0.0, f64::max);
    eprintln!("largest relative change when halving dt: {worst:.4}");
    assert!(worst < 0.01);
}

/// A small string (32 truth modes, N = 100) for the Monte Carlo and the fast exact path.
fn small() -> Experiment {
    config::parse("galerkin_small", "galerkin_small.toml", &common::small_string()).unwrap()
}

#[test]
fn monte_carlo_agrees_with_the_exact_error() {
    crate::exact_vs_mc::check(&small());
}

/// The exact analysis finds the string's 2×2 modal blocks and propagates them alone; the same
/// truth with its state reordered as (all displacements, all velocities) has no such blocks and
/// goes through the dense Lyapunov recursion. The error does not depend on the ordering.
#[test]
fn block_recursion_equals_the_dense_lyapunov_recursion() {
    let exp = small();
    let designs = filterbench::pipeline::design_all(&exp).unwrap();
    let nx = exp.plant.nx();
    let perm = filterbench::numerics::linalg::Mat::from_fn(nx, nx, |i, j| {
        let from = if i < nx / 2 { 2 * i } else { 2 * (i - nx / 2) + 1 };
        if j == from { 1.0 } else { 0.0 }
    });
    let mut dense = exp.plant.clone();
    dense.a = filterbench::model::plant::Steps::constant(&perm * exp.plant.a.at(0) * perm.transpose());
    dense.b = filterbench::model::plant::Steps::constant(&perm * exp.plant.b.at(0));
    dense.c = filterbench::model::plant::Steps::constant(exp.plant.c.at(0) * perm.transpose());
    dense.cz = filterbench::model::plant::Steps::constant(exp.plant.cz.at(0) * perm.transpose());
    let mut cov = exp.nominal.clone();
    cov.blocks[0] = &perm * &cov.blocks[0] * perm.transpose();
    for d in &designs {
        let fast = exact::error(&exp.plant, &d.design.realization, &exp.nominal);
        let slow = exact::error(&dense, &d.design.realization, &cov);
        for (a, b) in fast.per_step.iter().zip(&slow.per_step) {
            assert!((a - b).abs() <= 1e-10 * b.abs().max(1e-12), "{a} vs {b}");
        }
    }
}

/// The trial loop applies the string's large, mostly-zero matrices (A, B) in sparse form: the same
/// numbers as nalgebra's dense gemv, to rounding, in the two ways the loop calls them.
#[test]
fn sparse_plant_matrices_give_the_dense_products() {
    use filterbench::numerics::linalg::{Mat, Vector};
    use filterbench::numerics::linop::LinOp;
    let exp = small();
    for m in [exp.plant.a.at(0), exp.plant.b.at(0)] {
        let op = LinOp::new(m);
        assert!(matches!(op, LinOp::Sparse(_)), "a {}×{} modal matrix is stored sparse", m.nrows(), m.ncols());
        let x = Vector::from_fn(m.ncols(), |i, _| (i as f64 * 0.37).sin());
        for beta in [0.0, 1.0] {
            let mut y = Vector::from_fn(m.nrows(), |i, _| (i as f64 * 0.11).cos());
            let mut want = y.clone();
            op.apply(1.0, &x, beta, &mut y);
            want.gemv(1.0, m, &x, beta);
            assert!((&y - &want).amax() <= 1e-14 * want.amax(), "β = {beta}");
        }
    }
    assert!(matches!(LinOp::new(&Mat::from_element(40, 40, 1.0)), LinOp::Dense(_)), "dense stays dense");
    assert!(matches!(LinOp::new(&Mat::identity(8, 8)), LinOp::Dense(_)), "small stays dense");
}

/// Seed 004's random initial state: the truth starts with modal variances (𝒰₀, 𝒰₁), the filters'
/// P(0) is the covariance of their basis coefficients — exactly the truth's for the eigenfunction
/// basis with every mode — and Monte Carlo agrees with the exact error with it (the tolerances of
/// `exact_vs_mc`).
#[test]
fn random_initial_state() {
    let text = common::small_string()
        .patch("truth_modes = 32", "truth_modes = 32\ninitial_displacement = 0.01\ninitial_velocity = 0.1");
    let exp = config::parse("galerkin_random_start", "galerkin_random_start.toml", &text).unwrap();
    let model = exp.string.as_ref().unwrap();
    let m = model.truth_modes;
    let (_, fcov) =
        filterbench::families::galerkin::projected(model, 10, filterbench::families::galerkin::Basis::Eigen, m, 1e-3);
    let truth_x0 = exp.nominal.x0();
    for k in 0..m {
        let (d, v) = model.initial(k + 1);
        assert!(d > 0.0 && v > 0.0);
        assert_eq!(fcov.x0()[(k, k)], d, "P0 of mode {}", k + 1);
        assert_eq!(fcov.x0()[(m + k, m + k)], v, "P10 of mode {}", k + 1);
        assert_eq!(
            (truth_x0[(2 * k, 2 * k)], truth_x0[(2 * k + 1, 2 * k + 1)]),
            (d, v),
            "the truth's x0 of mode {}",
            k + 1
        );
    }
    let (_, hat) =
        filterbench::families::galerkin::projected(model, 10, filterbench::families::galerkin::Basis::Hat, 8, 1e-3);
    assert!(filterbench::numerics::linalg::min_eigenvalue(hat.x0()) > -1e-15, "the hat basis's P(0) is a covariance");
    crate::exact_vs_mc::check(&exp);
}

/// The Galerkin filter's Kalman recursion (filtering form, as `families::kalman`) on its projected
/// model, carried in double-double: per step (K, L_z) rounded to f64 and the eigenvalues of the
/// f64-rounded S.
fn recursion_in_double_double(fp: &Plant, fcov: &Covariances) -> Vec<(Mat, Mat, Vec<f64>)> {
    use crate::double_double::DMat;
    let mut p = DMat::from(fcov.x0());
    let mut out = Vec::new();
    for k in 0..fp.steps() {
        let w = fcov.w_at(k);
        let (a, c, cz) = (DMat::from(fp.a_at(k)), DMat::from(&fp.c_at(k)), DMat::from(fp.cz_at(k)));
        let (b, d) = (fp.b_at(k), &*fp.d_at(k));
        let (bwb, dwd) = (DMat::from(&(b * &w * b.transpose())), DMat::from(&(d * &w * d.transpose())));
        assert_eq!((b * &w * d.transpose()).amax(), 0.0, "the projected model's noises are independent");
        let pct = p.mul(&c.t());
        let s = c.mul(&pct).add(&dwd).symmetrize();
        let kk = DMat::right_solve(&a.mul(&pct), &s);
        let lz = DMat::right_solve(&cz.mul(&pct), &s);
        let eig = nalgebra::SymmetricEigen::new(s.to_mat()).eigenvalues;
        out.push((kk.to_mat(), lz.to_mat(), eig.as_slice().to_vec()));
        p = a.mul(&p).mul(&a.t()).add(&bwb).sub(&kk.mul(&s).mul(&kk.t())).symmetrize();
    }
    out
}

/// α = 1e-14 with W_m singular (issue 24, item A). psd_pinv's relative cutoff of 1e-10 used to drop
/// the innovation directions of the noise-free sensor differences here, silently; the filter now
/// solves C P Cᵀ + (W_m + αI)/Δ by Cholesky and reports nothing dropped. Checked against the same
/// recursion in double-double arithmetic (32 digits; `double_double`), an independent computation
/// whose own rounding is negligible.
#[test]
fn tiny_alpha_is_solved_accurately_not_truncated() {
    use filterbench::families::galerkin::{Basis, projected};
    use filterbench::numerics::pd::{MAX_SOLVE_ERROR, solve_error};
    let mut exp = common::variant("galerkin_string", "m6_dt0.0025", 10);
    exp.filters = vec![spec_of("eigen", 16, 1e-14)];
    let designs = filterbench::pipeline::design_all(&exp).unwrap();
    let product = &designs[0].design.realization;
    let model = exp.string.as_ref().unwrap();
    let (fp, fcov) = projected(model, exp.plant.horizon, Basis::Eigen, 16, 1e-14);
    let reference = recursion_in_double_double(&fp, &fcov);
    let rel = |a: &Mat, b: &Mat| if b.amax() == 0.0 { a.amax() } else { (a - b).norm() / b.norm() };
    let (mut worst_gain, mut worst_bound, mut worst_kappa) = (0.0f64, 0.0f64, 0.0f64);
    for (k, (kk, lz, eig)) in reference.iter().enumerate() {
        let g = &product.gains[k][0];
        let diff = rel(&g.bf, kk).max(rel(&g.df, lz));
        worst_gain = worst_gain.max(diff);
        if kk.amax() > 0.0 || lz.amax() > 0.0 {
            let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), l| (lo.min(*l), hi.max(*l)));
            worst_kappa = worst_kappa.max(hi / lo);
            worst_bound = worst_bound.max(solve_error(eig));
        }
    }
    eprintln!(
        "α = 1e-14: largest κ₂(S) at a step with a nonzero gain {worst_kappa:.3e}, its solve bound \
         {worst_bound:.2e} (≤ {MAX_SOLVE_ERROR:e}); largest relative gain difference to double-double {worst_gain:.2e}"
    );
    // The step's solve error bound (numerics::pd) is ≤ MAX_SOLVE_ERROR, which is why the product
    // accepted α = 1e-14 (a κ₂ above it would have been refused).
    assert!(worst_bound <= MAX_SOLVE_ERROR);
    // Gains: each step's solve is within its bound (numerics::pd: γ_{3m+1} tr S/λ_min); the rounding of
    // earlier steps enters P̄ as a backward perturbation of their S of the same relative size, which
    // the Riccati recursion contracts rather than amplifies (Bougerol 1993), so the largest
    // single-step bound is the tolerance. (The double-double recursion's own error is ~1e-16 of it.)
    assert!(worst_gain <= worst_bound, "gains differ from double-double by {worst_gain:.2e} > {worst_bound:.2e}");
    // What the pseudo-inverse used to do here: its cutoff dropped directions, and its gains are off
    // by far more than the bound (so this check is what catches a silent truncation).
    let truncated = filterbench::families::kalman::kalman(&fp, &fcov, filterbench::model::plant::Pattern::Filtering);
    let truncated_gain = reference
        .iter()
        .enumerate()
        .map(|(k, (kk, lz, _))| rel(&truncated.gains[k][0].bf, kk).max(rel(&truncated.gains[k][0].df, lz)))
        .fold(0.0, f64::max);
    eprintln!("the pseudo-inverse's gains differ from double-double by {truncated_gain:.2e}");
    assert!(truncated_gain > 10.0 * worst_bound);
    // The figure: the exact error of the product's filter against that of the double-double filter.
    let steps: Vec<filterbench::filter::realization::Gains> = reference
        .iter()
        .enumerate()
        .map(|(k, (kk, lz, _))| {
            let g = &product.gains[k][0];
            let (a, c, cz) = (fp.a_at(k), &*fp.c_at(k), fp.cz_at(k));
            filterbench::filter::realization::Gains {
                af: a - kk * c,
                bf: kk.clone(),
                cf: cz - lz * c,
                df: lz.clone(),
                gf: g.gf.clone(),
            }
        })
        .collect();
    let mut dd = filterbench::filter::realization::Realization::state_estimator(product.s0.clone(), steps);
    dd.tracks = None;
    let mut zero = dd.clone();
    zero.map_gains(|g| (g.bf, g.cf, g.df) = (0.0 * &g.bf, 0.0 * &g.cf, 0.0 * &g.df));
    let n = exp.plant.steps() as f64;
    let on_truth = |r| exact::error(&exp.plant, r, &exp.nominal).total / n;
    let (ours, theirs, variance) = (on_truth(product), on_truth(&dd), on_truth(&zero));
    // The estimate is linear in the gains: gains within a relative δ (just checked: worst_gain) move
    // ẑ by about δ|ẑ| (first order), so by Cauchy–Schwarz J moves by at most about
    // 2δ √(J E|ẑ|²), with √E|ẑ|² ≤ √E|z|² + √J and E|z|² the error of the zero filter.
    let tolerance = 2.0 * worst_gain * (theirs * (variance.sqrt() + theirs.sqrt()).powi(2)).sqrt();
    eprintln!(
        "α = 1e-14, eigen n = 16: product {ours:.10}, double-double {theirs:.10} (difference {:.1e}, \
         tolerance {tolerance:.1e}; E|z|² {variance:.6})",
        (ours - theirs).abs()
    );
    assert!((ours - theirs).abs() <= tolerance, "{ours} vs {theirs}");
    // The pseudo-inverse's figure, 0.0014006 in the docs before issue 24, is outside it.
    let old = on_truth(&truncated);
    eprintln!("the pseudo-inverse's figure {old:.7}");
    assert!((old - theirs).abs() > tolerance);
}

/// An α too small for double precision is refused, naming the key and the condition number. On
/// the default step the process noise of one step keeps κ₂(S) near 3e10 at every step with a
/// nonzero gain however small α is; halving the step divides C Q Cᵀ (∝ Δ³) against W_m/Δ by 16, and
/// α = 1e-16 then leaves κ₂ above what the bound accepts.
#[test]
fn alpha_too_small_for_double_precision_is_refused() {
    let mut exp = common::variant("galerkin_string", "m6_dt0.00125", 10);
    exp.filters = vec![spec_of("eigen", 16, 1e-16)];
    let err = filterbench::pipeline::design_all(&exp).err().expect("refused").to_string();
    eprintln!("{err}");
    assert!(err.contains("filters.tiny.alpha: ") && err.contains("condition number") && !err.contains('\n'), "{err}");
}

/// The small string with seed 004's time-varying intensities (issue 24, item B): the forcing's q0
/// rises from 0.2 to 3 by τ = 0.1 and falls to 1 at τ = 0.25, the measurement noise's factor w0
/// falls linearly from 4 to 0.25.
fn time_varying_string() -> String {
    common::small_string()
        .patch("forcing_intensity = 1.0", "forcing_intensity = { times = [0.0, 0.1, 0.25], values = [0.2, 3.0, 1.0] }")
        .patch(
            "sensor_width = 0.05",
            "sensor_width = 0.05\nnoise_intensity = { times = [0.0, 0.25], values = [4.0, 0.25] }",
        )
}

/// Time-varying V(τ), W(τ) reach the truth, the Galerkin filters' design, the exact analysis and
/// the Monte Carlo: Monte Carlo (3000 trials, fixed seed) agrees with the exact error within 4σ in
/// total and 4.5σ per step (`exact_vs_mc`), and every filter differs from its constant-intensity
/// twin (gains and exact error), as does the truth.
#[test]
fn time_varying_intensities_reach_truth_filter_and_analysis() {
    let varying = config::parse("galerkin_varying", "galerkin_varying.toml", &time_varying_string()).unwrap();
    let constant = small();
    let model = varying.string.as_ref().unwrap();
    assert!(model.varies());
    // The per-step factors are the profiles' step means: q0 over [0, Δ) = 0.2 + 28·Δ/2, w0's mean
    // over step k is linear in its midpoint (rounding only).
    let dt = model.dt;
    assert!((model.forcing_scale(0) - (0.2 + 28.0 * dt / 2.0)).abs() <= 1e-14);
    let w_mid = |k: usize| 4.0 - 15.0 * (k as f64 + 0.5) * dt;
    assert!((0..40).all(|k| (model.noise_scale(k) - w_mid(k)).abs() <= 1e-13));
    // The truth's plant carries them: B[k] = [√s_k I, 0], D[k] = [0, √r_k I] at every step.
    let nx = varying.plant.nx();
    for k in 0..varying.plant.steps() {
        let (b, d) = (varying.plant.b_at(k), varying.plant.d_at(k));
        assert!((b[(nx - 1, nx - 1)].powi(2) - model.forcing_scale(k)).abs() <= 1e-14 * model.forcing_scale(k));
        assert!((d[(0, nx)].powi(2) - model.noise_scale(k)).abs() <= 1e-14 * model.noise_scale(k));
    }
    // The truth: the same filter (designed on constants) has another exact error on it.
    let constant_designs = filterbench::pipeline::design_all(&constant).unwrap();
    let varying_designs = filterbench::pipeline::design_all(&varying).unwrap();
    for (f, spec) in varying.filters.iter().enumerate() {
        let on = |exp: &Experiment, r| exact::error(&exp.plant, r, &exp.nominal).total;
        let (cr, vr) = (&constant_designs[f].design.realization, &varying_designs[f].design.realization);
        let (truth_const, truth_varying) = (on(&constant, cr), on(&varying, cr));
        let (designed_const, designed_varying) = (truth_varying, on(&varying, vr));
        let gain_change = (0..varying.plant.steps())
            .map(|k| (&cr.gains[k][0].bf - &vr.gains[k][0].bf).norm() / cr.gains[k][0].bf.norm().max(1e-300))
            .filter(|x| x.is_finite())
            .fold(0.0, f64::max);
        eprintln!(
            "{}: truth const {truth_const:.6} / varying {truth_varying:.6}; on the varying truth, designed for \
             constants {designed_const:.6} / for the profiles {designed_varying:.6}; largest relative gain change {gain_change:.3}",
            spec.name
        );
        // Far beyond rounding (1e-6 relative): the profiles change the model by factors up to 16.
        assert!(
            (truth_const - truth_varying).abs() > 1e-3 * truth_const,
            "{}: the truth ignores the profiles",
            spec.name
        );
        assert!(gain_change > 1e-3, "{}: the filter ignores the profiles", spec.name);
        assert!((designed_const - designed_varying).abs() > 1e-6 * designed_const, "{}", spec.name);
    }
    crate::exact_vs_mc::check(&varying);
}

/// Bad profiles: one error line naming the key.
#[test]
fn bad_intensity_profiles_are_refused_with_the_key() {
    let text = common::small_string();
    let cases = [
        ("forcing_intensity = 1.0", "forcing_intensity = -1.0", "string.forcing_intensity"),
        (
            "forcing_intensity = 1.0",
            "forcing_intensity = { times = [0.0, 0.1], values = [1.0] }",
            "string.forcing_intensity.values",
        ),
        (
            "forcing_intensity = 1.0",
            "forcing_intensity = { times = [0.0, 0.1], values = [1.0, nan] }",
            "string.forcing_intensity.values[1]",
        ),
        (
            "forcing_intensity = 1.0",
            "forcing_intensity = { times = [0.1, 0.0], values = [1.0, 2.0] }",
            "string.forcing_intensity.times[1]",
        ),
        (
            "forcing_intensity = 1.0",
            "forcing_intensity = { times = [0.0], value = [1.0] }",
            "string.forcing_intensity.value",
        ),
        (
            "sensor_width = 0.05",
            "sensor_width = 0.05\nnoise_intensity = { times = [0.0, 0.1], values = [1.0, -2.0] }",
            "string.noise_intensity.values[1]",
        ),
        ("sensor_width = 0.05", "sensor_width = 0.05\nnoise_intensity = \"high\"", "string.noise_intensity"),
    ];
    for (from, to, key) in cases {
        let err = config::parse("bad", "bad.toml", &text.patch(from, to)).err().expect("refused").to_string();
        eprintln!("{err}");
        assert!(err.contains(&format!("{key}: ")) && !err.contains('\n'), "{to}: {err}");
    }
}
