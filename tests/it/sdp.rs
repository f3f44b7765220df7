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
