//! The minimax family (seed 000): Example 3's printed numbers, the saddle point, an independent
//! maximization of the dual functional, and the guarantee under Monte Carlo.

use filterbench::config::{self, Experiment};
use filterbench::families::minimax::{dual_gradient, dual_solve, dual_value};
use filterbench::model::plant::Covariances;
use filterbench::model::uncertainty::SetShape;
use filterbench::numerics::linalg::{Mat, frob_dot, min_eigenvalue};
use filterbench::pipeline;

fn load(name: &str, trials: usize) -> Experiment {
    crate::common::load(name, trials)
}

fn corner(exp: &Experiment, k: &Covariances) -> Covariances {
    let g = dual_gradient(&exp.plant, exp.pattern, k);
    let mut out = k.clone();
    for (i, s) in exp.sets.iter().enumerate() {
        if let Some(s) = s {
            out.blocks[i] = s.argmax_linear(&g[i]).unwrap();
        }
    }
    out
}

/// Seed 000 Example 3 (N = 3, criterion over n = 1..N, printed as I/N). "To the printed precision"
/// is taken as one unit of the last printed digit: 0.4377, 0.6725 and 0.6742 within 1e-4, Sw(2,3)
/// within 1e-3 of 0.016. The step τ is the one number the seed's own (inexact) line search decides:
/// the exact maximizer is 0.5762 and the printed 0.578 is checked to be optimal to 1e-6 relative in
/// I, which is all a value on that flat segment can be.
#[test]
fn example3_reproduces_the_printed_numbers() {
    let exp = load("minimax_example3", 10);
    let (pl, pat) = (&exp.plant, exp.pattern);
    let n = pl.horizon as f64;
    let sol = dual_solve(pl, pat, &exp.sets, exp.nominal.clone(), 1e-12, 100).unwrap();
    let t = &sol.trace;
    let i0 = t[0].objective / n;
    assert!((i0 - 0.4377).abs() <= 1e-4, "I/N at the nominal covariances: {i0}");
    assert_eq!(t[0].step, 1.0, "the first step goes all the way to the first corner");
    let i1 = t[1].objective / n;
    assert!((i1 - 0.6725).abs() <= 1e-4, "I/N after the first LP step: {i1}");
    let k1 = corner(&exp, &exp.nominal);
    assert!((dual_value(pl, pat, &k1) / n - i1).abs() < 1e-12);
    let k2 = corner(&exp, &k1);
    let i2 = dual_value(pl, pat, &k2) / n;
    assert!((i2 - 0.6742).abs() <= 1e-4, "I/N at the second corner: {i2}");
    let tau = t[1].step;
    let along = |tau: f64| Covariances::new(k1.blocks.iter().zip(&k2.blocks).map(|(a, b)| a + (b - a) * tau).collect());
    let best = dual_value(pl, pat, &along(tau));
    let printed = dual_value(pl, pat, &along(0.578));
    assert!(
        best >= printed && (best - printed) <= 1e-6 * best,
        "τ = {tau}: I = {best}, at the printed 0.578: {printed}"
    );
    assert!((tau - 0.578).abs() < 0.003, "τ = {tau}");
    let sw23 = sol.k_hat.blocks[2][(1, 2)];
    assert!((sw23 - 0.016).abs() <= 1e-3, "final Sw(2,3) = {sw23}");
    assert!(sol.converged && t.len() == 3 && t[2].gap <= 1e-12 * t[2].objective, "stops with δ = 0 at s = 2: {t:?}");
    eprintln!(
        "Example 3: I/N {i0:.6} → {i1:.6}, corner {i2:.6}, τ {tau:.4}, Sw(2,3) {sw23:.4}, I(K̂)/N {:.6}",
        sol.value / n
    );
    fig1_line_searches(&sol, n, i0, i1, i2);
}

/// Fig. 1 (the kept line searches): search 0 runs from the nominal 0.4377 to the first corner
/// 0.6725, search 1 (the printed figure) from 0.6725 to the second corner 0.6742 through its
/// maximum at the step taken; every sampled curve is concave (second differences on the uniform
/// grid ≤ 1e-12 relative) and peaks at the step taken.
fn fig1_line_searches(sol: &filterbench::families::minimax::DualSolution, n: f64, i0: f64, i1: f64, i2: f64) {
    let ls = &sol.line_searches;
    assert_eq!(ls.iter().map(|l| l.iteration).collect::<Vec<_>>(), vec![0, 1], "the two line searches taken");
    for (l, (start, end)) in ls.iter().zip([(i0, i1), (i1, i2)]) {
        let v = &l.value;
        assert!((v[0] - start).abs() <= 1e-12 * start && (v.last().unwrap() - end).abs() <= 1e-12 * end, "{l:?}");
        let at_step = l.tau.iter().position(|t| *t == sol.trace[l.iteration].step).unwrap();
        let next = sol.trace[l.iteration + 1].objective / n;
        assert!((v[at_step] - next).abs() <= 1e-12 * next, "I/N at the step {} vs the next iterate {next}", v[at_step]);
        assert!(v.iter().all(|x| *x <= v[at_step] * (1.0 + 1e-12)), "the step taken is the sampled maximum");
        let grid: Vec<f64> = l.tau.iter().zip(v).filter(|(t, _)| (*t * 40.0).fract() == 0.0).map(|(_, v)| *v).collect();
        assert_eq!(grid.len(), 41);
        for w in grid.windows(3) {
            assert!(w[0] + w[2] - 2.0 * w[1] <= 1e-12 * w[1], "I/N is concave along the segment: {w:?}");
        }
    }
    eprintln!(
        "Fig. 1: I/N from {:.4} up to {:.6} at τ = {:.4}, {:.4} at τ = 1",
        i1,
        sol.value / n,
        sol.trace[1].step,
        i2
    );
}

/// At K̂ the exact worst case of the minimax filter over the set equals I(K̂) (to the final gap),
/// and no other filter of the experiment has a smaller worst case.
#[test]
fn saddle_point_and_smallest_worst_case() {
    for name in ["minimax_example3", "minimax_example2", "minimax_example4", "minimax_box"] {
        let exp = load(name, 10);
        let filters = pipeline::design_all(&exp).unwrap();
        let m = exp.filter_index("minimax").unwrap();
        let d = &filters[m].design;
        let k_hat = d.design_covariance.as_ref().unwrap();
        let i_hat = dual_value(&exp.plant, exp.pattern, k_hat);
        let worst = filters[m].worst.as_ref().unwrap().total;
        let gap = d.figures.get::<filterbench::families::minimax::MinimaxFigures>().unwrap().final_gap;
        assert!(worst >= i_hat - 1e-9 * i_hat, "{name}: worst {worst} < I(K̂) {i_hat}");
        assert!(
            worst - i_hat <= gap + 1e-9 * i_hat,
            "{name}: worst {worst} exceeds I(K̂) {i_hat} by more than the gap {gap}"
        );
        for (f, other) in filters.iter().enumerate() {
            let w = other.worst.as_ref().unwrap().total;
            assert!(
                w >= worst - 1e-9 * worst,
                "{name}: filter {} has worst case {w} < minimax {worst}",
                exp.filters[f].name
            );
        }
        eprintln!("{name}: I(K̂) = {i_hat:.6}, worst case of F̂ = {worst:.6}, gap {gap:.2e}");
    }
}

/// Projected gradient ascent on the concave I over the box (clipping; the iterates stay PD here, which
/// is checked) reaches the value Algorithm 1 finds, to 1e-6 relative.
#[test]
fn agrees_with_projected_gradient_ascent() {
    let exp = load("minimax_example3", 10);
    let (pl, pat) = (&exp.plant, exp.pattern);
    let sol = dual_solve(pl, pat, &exp.sets, exp.nominal.clone(), 1e-12, 100).unwrap();
    let mut k = exp.nominal.clone();
    let clip = |i: usize, m: &Mat| match &exp.sets[i].as_ref().unwrap().shape {
        SetShape::Box { center, half_width } => Mat::from_fn(m.nrows(), m.ncols(), |r, c| {
            m[(r, c)].clamp(center[(r, c)] - half_width[(r, c)], center[(r, c)] + half_width[(r, c)])
        }),
        _ => unreachable!("Example 3 has boxes"),
    };
    for _ in 0..4000 {
        let g = dual_gradient(pl, pat, &k);
        // Block 0 (x0) has no set; the noise blocks step along the gradient and are clipped.
        for (i, (b, gi)) in k.blocks.iter_mut().zip(&g).enumerate().skip(1) {
            *b = clip(i, &(&*b + gi * 0.05));
        }
    }
    for b in &k.blocks {
        assert!(min_eigenvalue(b) > 0.0);
    }
    let pga = dual_value(pl, pat, &k);
    assert!((pga - sol.value).abs() <= 1e-6 * sol.value, "projected gradient {pga} vs Algorithm 1 {}", sol.value);
    // And I is maximal: the gap at the projected-gradient point is (nearly) zero as well.
    let g = dual_gradient(pl, pat, &k);
    let gap: f64 = (1..3)
        .map(|i| frob_dot(&g[i], &(exp.sets[i].as_ref().unwrap().argmax_linear(&g[i]).unwrap() - &k.blocks[i])))
        .sum();
    assert!(gap <= 1e-6 * pga, "gap at the projected-gradient point {gap}");
}

/// Monte Carlo: for every scenario of minimax_box and minimax_example3 (each covariance lies in the
/// set, Gaussian or not), the minimax filter's mean error does not exceed its guarantee by more than
/// 4 standard errors; at K̂ with Gaussian noise it matches I(K̂) within 4 standard errors.
#[test]
fn guarantee_holds_under_monte_carlo() {
    for name in ["minimax_box", "minimax_example3"] {
        let exp = load(name, 4000);
        let out = pipeline::run(&exp, false).unwrap();
        let m = exp.filter_index("minimax").unwrap();
        let bound = out.filters[m].design.guarantee.as_ref().unwrap().total;
        for sc in &out.scenarios {
            let st = &sc.mc.filters[m].total;
            let z = (st.mean - bound) / st.std_error();
            assert!(z <= 4.0, "{name}/{}: empirical {} above the guarantee {bound} by {z:.2}σ", sc.name, st.mean);
            if sc.name == "at_k_hat" {
                let i_hat = dual_value(&exp.plant, exp.pattern, &sc.covariances);
                let z = (st.mean - i_hat) / st.std_error();
                assert!(z.abs() <= 4.0, "{name}: at K̂ empirical {} vs I(K̂) {i_hat} ({z:.2}σ)", st.mean);
            }
        }
        // The exact error never exceeds the guarantee either (each scenario's covariance is in the set).
        for sc in &out.scenarios {
            assert!(
                sc.exact[m].total <= bound * (1.0 + 1e-9),
                "{name}/{}: exact {} > {bound}",
                sc.name,
                sc.exact[m].total
            );
        }
    }
}

/// Theorem 1.2a: when every set is a Loewner interval, K̂ is the upper end, found without
/// iterating; the clarabel oracle over the interval then confirms a zero gap at it.
#[test]
fn largest_element_of_loewner_intervals() {
    let text = crate::common::text("minimax_example3");
    let sets_start = text.find("[sets.process]").unwrap();
    let sets_end = text.find("[[filters]]").unwrap();
    let loewner = "[sets.process]\nkind = \"loewner\"\nlower = [[0.8, -0.4, 0.2], [-0.4, 0.6, 0.1], [0.2, 0.1, 0.5]]\nupper = [[1.1, -0.4, 0.2], [-0.4, 0.9, 0.1], [0.2, 0.1, 0.8]]\n\n[sets.measurement]\nkind = \"loewner\"\nlower = [[0.4, 0, 0], [0, 0.7, 0], [0, 0, 0.05]]\nupper = [[0.7, 0.1, 0], [0.1, 0.9, 0], [0, 0, 0.2]]\n\n";
    let t = format!("{}{}{}", &text[..sets_start], loewner, &text[sets_end..]);
    let exp = config::parse("loewner", "loewner.toml", &t).unwrap();
    let sol = dual_solve(&exp.plant, exp.pattern, &exp.sets, exp.nominal.clone(), 1e-12, 100).unwrap();
    assert!(sol.largest_element && sol.trace.len() == 1);
    let upper = |i: usize| match &exp.sets[i].as_ref().unwrap().shape {
        SetShape::Loewner { upper, .. } => upper.clone(),
        _ => unreachable!(),
    };
    assert_eq!(sol.k_hat.blocks[1], upper(1));
    assert_eq!(sol.k_hat.blocks[2], upper(2));
    let g = dual_gradient(&exp.plant, exp.pattern, &sol.k_hat);
    let gap: f64 = (1..3)
        .map(|i| frob_dot(&g[i], &(exp.sets[i].as_ref().unwrap().argmax_linear(&g[i]).unwrap() - &sol.k_hat.blocks[i])))
        .sum();
    assert!(gap.abs() <= 1e-7 * sol.value, "gap at the largest element {gap}");
}

/// The scalar recursion of seed 000's Examples 1 and 5: P̄n = a² P̂n−1 + r_u(n) + b² D⁰ε,
/// k̂n = P̄n c / (c² P̄n + r_v + d² D⁰w), P̂n = (1 − k̂n c) P̄n for n = 1..N; returns (k̂n, P̂n).
/// r_u(n) is the surrogate variance of u_n (eq (39): r_u W_n⁻¹, step-dependent with time-varying
/// weights).
#[allow(clippy::too_many_arguments)]
fn scalar_minimax(
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    de: f64,
    dw: f64,
    ru: impl Fn(usize) -> f64,
    rv: f64,
    p0: f64,
    n: usize,
) -> Vec<(f64, f64)> {
    let mut p = p0;
    (1..=n)
        .map(|n| {
            let pbar = a * a * p + ru(n) + b * b * de;
            let k = pbar * c / (c * c * pbar + rv + d * d * dw);
            p = (1.0 - k * c) * pbar;
            (k, p)
        })
        .collect()
}

/// Examples 1 and 5 in closed form (1e-9): K̂ is the upper bounds of the variances (the sets'
/// largest element), the minimax gains are the scalar recursion's k̂n at every step, and the
/// guarantee is Σ P̂n (with the disturbances as white noise of variance r_u, r_v in Example 5).
#[test]
fn examples_1_and_5_in_closed_form() {
    for (name, ru, rv, p0) in [("minimax_example1", 0.0, 0.0, 1.0), ("minimax_example5", 0.4, 0.3, 0.0)] {
        let exp = load(name, 10);
        let filters = pipeline::design_all(&exp).unwrap();
        let m = exp.filter_index("minimax").unwrap();
        let d = &filters[m].design;
        let (closed, bound) = assert_scalar_closed_form(&exp, d, |_| ru, rv, p0);
        eprintln!("{name}: Σ P̂n = {bound:.10}, k̂N = {:.10}", closed.last().unwrap().0);
    }
}

/// A scalar minimax design (the variances bounded by 0.5 and 1) against [`scalar_minimax`] to 1e-9:
/// K̂ the upper bounds, every gain, and the guarantee Σ P̂n. Returns (k̂n, P̂n) and Σ P̂n.
fn assert_scalar_closed_form(
    exp: &Experiment,
    d: &filterbench::filter::design::Design,
    ru: impl Fn(usize) -> f64,
    rv: f64,
    p0: f64,
) -> (Vec<(f64, f64)>, f64) {
    let name = &exp.name;
    let k_hat = d.design_covariance.as_ref().unwrap();
    let (de, dw) = (k_hat.blocks[1][(0, 0)], k_hat.blocks[2][(0, 0)]);
    assert!((de - 0.5).abs() < 1e-12 && (dw - 1.0).abs() < 1e-12, "{name}: K̂ = ({de}, {dw}), the upper bounds");
    let pl = &exp.plant;
    let (a, b, c, dd) = (pl.a.at(0)[(0, 0)], pl.b.at(0)[(0, 0)], pl.c.at(0)[(0, 0)], pl.d.at(0)[(0, 1)]);
    let closed = scalar_minimax(a, b, c, dd, 0.5, 1.0, ru, rv, p0, pl.horizon);
    for (n, (k, _)) in closed.iter().enumerate() {
        let ours = d.realization.gains(n + 1, 0).df[(0, 0)];
        assert!((ours - k).abs() <= 1e-9 * k.abs(), "{name}: k̂{} = {ours} vs closed form {k}", n + 1);
    }
    let bound: f64 = closed.iter().map(|(_, p)| p).sum();
    let g = d.guarantee.as_ref().unwrap().total;
    assert!((g - bound).abs() <= 1e-9 * bound, "{name}: guarantee {g} vs Σ P̂n = {bound}");
    (closed, bound)
}

/// Example 2's worst covariance (N = 16, the horizon at which the iteration converges to the
/// printed values): Ŝ_w is the printed matrix (the box's corner, exactly), and Ŝ_ε matches the
/// printed entries to the three printed decimals where it reproduces — (1,1), (2,2), (2,3), (3,3) —
/// while (1,2) and (1,3) print .012 and .009 against our converged .011 and .007 (the seed's own
/// iteration stops earlier), checked to 0.0025.
#[test]
fn example2_worst_covariance_to_the_printed_digits() {
    let exp = load("minimax_example2", 10);
    let filters = pipeline::design_all(&exp).unwrap();
    let m = exp.filter_index("minimax").unwrap();
    let k = filters[m].design.design_covariance.as_ref().unwrap();
    let names = exp.plant.block_names();
    let sw = &k.blocks[names.iter().position(|n| *n == "measurement").unwrap()];
    let se = &k.blocks[names.iter().position(|n| *n == "process").unwrap()];
    let printed_w = [[1.0, -0.3, 0.3], [-0.3, 0.8, 0.0], [0.3, 0.0, 0.7]];
    for i in 0..3 {
        for j in 0..3 {
            assert!((sw[(i, j)] - printed_w[i][j]).abs() < 1e-9, "Ŝ_w({},{}) = {}", i + 1, j + 1, sw[(i, j)]);
        }
    }
    for ((i, j), printed, tol) in [
        ((0, 0), 0.597, 5e-4),
        ((1, 1), 0.715, 5e-4),
        ((1, 2), 0.001, 5e-4),
        ((2, 2), 0.601, 5e-4),
        ((0, 1), 0.012, 2.5e-3),
        ((0, 2), 0.009, 2.5e-3),
    ] {
        assert!(
            (se[(i, j)] - printed).abs() <= tol,
            "Ŝ_ε({},{}) = {:.4} vs printed {printed}",
            i + 1,
            j + 1,
            se[(i, j)]
        );
    }
}

/// Theorem 1.2b's condition is checked and reported: R_z(K̂) ≻ 0 at every shipped example whose set
/// has no largest element, and R_z is singular (reported 0) when no noise at all reaches the
/// measurements.
#[test]
fn theorem_1_2b_condition_is_checked() {
    use filterbench::families::minimax::observation_covariance_min_eigenvalue;
    for name in ["minimax_example2", "minimax_example3", "minimax_box", "minimax_example1"] {
        let exp = load(name, 10);
        let filters = pipeline::design_all(&exp).unwrap();
        let d = &filters[exp.filter_index("minimax").unwrap()].design.figures;
        let d = d.get::<filterbench::families::minimax::MinimaxFigures>().unwrap();
        let (which, rz) = (d.theorem_1_2, d.rz_min_eigenvalue);
        if name == "minimax_example1" {
            assert!(which.starts_with("a:"), "{name}: {which}");
        } else {
            assert!(which.starts_with("b:") && rz > 0.0, "{name}: {which}, λmin(R_z)/λmax = {rz}");
        }
        let zero = Covariances::new(exp.nominal.blocks.iter().map(|b| b * 0.0).collect());
        assert_eq!(observation_covariance_min_eigenvalue(&exp.plant, &zero).unwrap(), 0.0, "{name}: no noise, R_z = 0");
    }
}

/// Section 5 with time-varying weights and per-step bounds (experiments/minimax_time_varying.toml),
/// in closed form (1e-9): the surrogate variance of u_n = w_u[n − 1] is s / W_(n−1) with
/// s = min(r, Σ r_k), K̂ is the variances' upper bounds, the gains are the scalar recursion's and
/// the guarantee is Σ P̂n.
#[test]
fn time_varying_weights_in_closed_form() {
    let exp = load("minimax_time_varying", 10);
    let u = exp.disturbances.iter().flatten().next().unwrap();
    let s = u.energy.min(u.step_energy.as_ref().unwrap().iter().sum());
    assert!(u.varies() && (u.surrogate_scale() - s).abs() == 0.0);
    let filters = pipeline::design_all(&exp).unwrap();
    let d = &filters[exp.filter_index("minimax").unwrap()].design;
    let (closed, bound) = assert_scalar_closed_form(&exp, d, |n| s / u.weights[n - 1][(0, 0)], 0.0, 0.0);
    eprintln!(
        "minimax_time_varying: s = {s}, Σ P̂n = {bound:.10}, k̂1 = {:.10}, k̂N = {:.10}",
        closed[0].0,
        closed.last().unwrap().0
    );
}
