//! Seed 004: the regularized Galerkin filter for the string with degenerate measurement noise.
//!
//! Exact errors are compared as time averages (summed error / (N + 1)), so that different steps are
//! comparable. Tolerances: stated at each assertion; Monte Carlo within 4σ in total and 4.5σ per
//! step (as in `exact_vs_mc`).

use filterbench::analysis::exact;
use filterbench::config::{self, Experiment, FilterSpec};

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
