//! The clarabel helper against closed forms, each within the solver's stated accuracy
//! (`objective_error`, numerics::accuracy) and the closed form's rounding (1e-15 here); and the
//! certified upper bound of a linear maximum over a set ∩ PSD against points of the set.

use filterbench::numerics::accuracy;
use filterbench::numerics::linalg::Mat;
use filterbench::numerics::solve::sdp::{SymConstraints, max_linear};

#[test]
fn box_and_ball_without_psd_match_their_closed_forms() {
    let g = Mat::from_row_slice(3, 3, &[1.0, -0.5, 0.2, -0.5, -2.0, 0.3, 0.2, 0.3, 0.7]);
    let c = Mat::from_row_slice(3, 3, &[1.0, 0.1, 0.0, 0.1, 2.0, 0.2, 0.0, 0.2, 1.5]);
    let h = Mat::from_element(3, 3, 0.1);
    let bx = max_linear(&g, 3, &SymConstraints { bounds: Some((&c - &h, &c + &h)), ..Default::default() }).unwrap();
    let closed = filterbench::numerics::linalg::frob_dot(&g, &c) + g.abs().sum() * 0.1;
    assert!(accuracy::agree(bx.value, closed, bx.objective_error + 1e-15), "box {} vs {closed}", bx.value);
    // Without PSD the certified bound is the closed form itself, up to its rounding.
    // The closed forms round by at most n² ε times the magnitude of the products they sum, which
    // the bound adds (certified_upper); twice that here.
    let margin = 2.0 * 9.0 * f64::EPSILON * g.abs().component_mul(&(c.abs() + &h)).sum();
    assert!(bx.upper >= closed && bx.upper - closed <= margin, "box bound {} vs {closed}", bx.upper);
    let ball = max_linear(&g, 3, &SymConstraints { ball: Some((c.clone(), 0.3)), ..Default::default() }).unwrap();
    let closed = filterbench::numerics::linalg::frob_dot(&g, &c) + 0.3 * g.norm();
    assert!(accuracy::agree(ball.value, closed, ball.objective_error + 1e-15), "ball {} vs {closed}", ball.value);
    let margin = 2.0 * 9.0 * f64::EPSILON * (g.abs().component_mul(&c.abs()).sum() + 0.3 * g.norm());
    assert!(ball.upper >= closed && ball.upper - closed <= margin, "ball bound {} vs {closed}", ball.upper);
}

#[test]
fn loewner_interval_and_psd_constraint() {
    // max ⟨G, S⟩ over 0 ⪯ S ⪯ I is the sum of G's positive eigenvalues.
    let g = Mat::from_row_slice(2, 2, &[1.0, 2.0, 2.0, -1.0]);
    let r = max_linear(
        &g,
        2,
        &SymConstraints { lower: Some(Mat::zeros(2, 2)), upper: Some(Mat::identity(2, 2)), ..Default::default() },
    )
    .unwrap();
    assert!(accuracy::agree(r.value, 5f64.sqrt(), r.objective_error + 1e-15), "{} ±{:.1e}", r.value, r.objective_error);
    // The eigenvalue form adds n times its eigenvalue error bound (certified_upper): 2·2ε‖G‖_F.
    let margin = 2.0 * (4.0 * f64::EPSILON * g.norm() + 4.0 * f64::EPSILON * 5f64.sqrt());
    assert!(r.upper >= 5f64.sqrt() && r.upper - 5f64.sqrt() <= margin, "Loewner bound {}", r.upper);
    // An empty set is refused with clarabel's status.
    let e = max_linear(
        &g,
        2,
        &SymConstraints { lower: Some(Mat::identity(2, 2)), upper: Some(Mat::zeros(2, 2)), ..Default::default() },
    );
    assert!(e.unwrap_err().contains("Infeasible"));
}

/// A box whose sign-pattern corner is not PSD: the certified upper bound (weak duality with the
/// solver's multiplier) is above ⟨G, S⟩ at every PSD point of the box found by a search (corners and
/// random points, 20 000 of them, seed 7) and above the solver's value; and it is tight: within the
/// solver's objective error of its value, the first-order distance of a dual point from the optimum.
#[test]
fn box_and_psd_bound_is_certified_and_tight() {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Uniform};
    let u = Uniform::new(0.0, 1.0).unwrap();
    let g = Mat::from_row_slice(3, 3, &[1.0, 0.9, -0.8, 0.9, 0.5, 0.7, -0.8, 0.7, 0.3]);
    let c = Mat::from_row_slice(3, 3, &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
    let h = Mat::from_element(3, 3, 0.8);
    let cons = SymConstraints { bounds: Some((&c - &h, &c + &h)), psd: true, ..Default::default() };
    let r = max_linear(&g, 3, &cons).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut best = f64::NEG_INFINITY;
    for _ in 0..20_000 {
        let mut s = c.clone();
        for i in 0..3 {
            for j in i..3 {
                // Half the entries at a face of the box, half inside.
                let (a, b): (f64, f64) = (u.sample(&mut rng), u.sample(&mut rng));
                let t = if a < 0.5 {
                    2.0 * b - 1.0
                } else if b < 0.5 {
                    1.0
                } else {
                    -1.0
                };
                s[(i, j)] += 0.8 * t;
                s[(j, i)] = s[(i, j)];
            }
        }
        if filterbench::numerics::linalg::min_eigenvalue(&s) >= 0.0 {
            best = best.max(filterbench::numerics::linalg::frob_dot(&g, &s));
        }
    }
    eprintln!(
        "box ∩ PSD: solver {} (±{:.1e}), certified {}, best point found {best}",
        r.value, r.objective_error, r.upper
    );
    assert!(r.upper >= best && r.upper >= r.value, "bound {} vs search {best}, solver {}", r.upper, r.value);
    assert!(r.upper - r.value <= r.objective_error + 1e-12, "bound {} far above the solver's {}", r.upper, r.value);
}

/// clarabel's chordal decomposition (whose setup filterbench patches: vendor/clarabel/FILTERBENCH.md)
/// on a program with a known optimum: min Σ yᵢ subject to the tridiagonal T(y), diagonal y and
/// off-diagonals aᵢ, being PSD. Its dual maximizes −2 Σ aᵢ Zᵢ,ᵢ₊₁ over correlation matrices Z, and
/// on a path every choice of ±1 between neighbours is a rank-one correlation matrix, so the optimum
/// is 2 Σ |aᵢ|. The PSD cone sits between two other cones, so its rows start at an offset and every
/// variable also has rows outside it; clarabel splits it into cliques. With the decomposition on
/// and off, each solve's objective is the closed form within that solve's own accuracy: its gap
/// |primal − dual| plus its residual times the objective's scale.
#[test]
fn a_decomposed_psd_cone_gives_the_closed_form_optimum() {
    use clarabel::algebra::CscMatrix;
    use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
    let n = 40;
    let a: Vec<f64> = (0..n - 1).map(|i| ((i * 7 % 11) as f64 - 5.0) * 0.3 + 0.1).collect();
    let optimum = 2.0 * a.iter().map(|v| v.abs()).sum::<f64>();
    // clarabel's form: A x + s = b with s in the cones, so s = b − A x row by row.
    let (mut rows, mut cols, mut vals, mut b) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    // y ≥ 0 (never binding at the optimum: every yᵢ there is positive).
    for i in 0..n {
        rows.push(b.len());
        cols.push(i);
        vals.push(-1.0);
        b.push(0.0);
    }
    // svec T(y): the upper triangle column by column, off-diagonal entries scaled by √2.
    let start = b.len();
    for col in 0..n {
        for row in 0..=col {
            if row == col {
                rows.push(b.len());
                cols.push(col);
                vals.push(-1.0);
                b.push(0.0);
            } else if row + 1 == col {
                b.push(std::f64::consts::SQRT_2 * a[row]);
            } else {
                b.push(0.0);
            }
        }
    }
    assert_eq!(b.len() - start, n * (n + 1) / 2);
    // Σ y ≤ 10³.
    for i in 0..n {
        rows.push(b.len());
        cols.push(i);
        vals.push(1.0);
    }
    b.push(1e3);
    let cones =
        [SupportedConeT::NonnegativeConeT(n), SupportedConeT::PSDTriangleConeT(n), SupportedConeT::NonnegativeConeT(1)];
    let am = CscMatrix::new_from_triplets(b.len(), n, rows, cols, vals);
    let p = CscMatrix::zeros((n, n));
    let q = vec![1.0; n];
    for decompose in [true, false] {
        let settings =
            DefaultSettingsBuilder::default().verbose(false).chordal_decomposition_enable(decompose).build().unwrap();
        let mut solver = DefaultSolver::new(&p, &q, &am, &b, &cones, settings).unwrap();
        let psd_cones = solver.data.cones.iter().filter(|c| matches!(c, SupportedConeT::PSDTriangleConeT(_))).count();
        if decompose {
            assert!(psd_cones > 1, "the tridiagonal cone is split into cliques ({psd_cones} PSD cones)");
        } else {
            assert_eq!(psd_cones, 1);
        }
        solver.solve();
        let s = &solver.solution;
        assert_eq!(s.status, SolverStatus::Solved, "decomposition {decompose}");
        let accuracy = (s.obj_val - s.obj_val_dual).abs() + s.r_prim.max(s.r_dual) * (1.0 + optimum);
        assert!(
            (s.obj_val - optimum).abs() <= accuracy,
            "decomposition {decompose}: {} against 2 Σ|aᵢ| = {optimum} (accuracy {accuracy:.1e})",
            s.obj_val
        );
    }
}
