//! The clarabel helper against closed forms.

use filterbench::numerics::linalg::Mat;
use filterbench::numerics::solve::sdp::{SymConstraints, max_linear};

#[test]
fn box_and_ball_without_psd_match_their_closed_forms() {
    let g = Mat::from_row_slice(3, 3, &[1.0, -0.5, 0.2, -0.5, -2.0, 0.3, 0.2, 0.3, 0.7]);
    let c = Mat::from_row_slice(3, 3, &[1.0, 0.1, 0.0, 0.1, 2.0, 0.2, 0.0, 0.2, 1.5]);
    let h = Mat::from_element(3, 3, 0.1);
    let bx = max_linear(&g, 3, &SymConstraints { bounds: Some((&c - &h, &c + &h)), ..Default::default() }).unwrap();
    let closed = filterbench::numerics::linalg::frob_dot(&g, &c) + g.abs().sum() * 0.1;
    assert!((bx.value - closed).abs() < 1e-7 * closed.abs(), "box {} vs {closed}", bx.value);
    let ball = max_linear(&g, 3, &SymConstraints { ball: Some((c.clone(), 0.3)), ..Default::default() }).unwrap();
    let closed = filterbench::numerics::linalg::frob_dot(&g, &c) + 0.3 * g.norm();
    assert!((ball.value - closed).abs() < 1e-7 * closed.abs(), "ball {} vs {closed}", ball.value);
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
    assert!((r.value - 5f64.sqrt()).abs() < 1e-7, "{}", r.value);
    // An empty set is refused with clarabel's status.
    let e = max_linear(
        &g,
        2,
        &SymConstraints { lower: Some(Mat::identity(2, 2)), upper: Some(Mat::zeros(2, 2)), ..Default::default() },
    );
    assert!(e.unwrap_err().contains("Infeasible"));
}
