//! Steps whose gains are the same bits share one allocation (docs/architecture.md, "Memory on a
//! long horizon"): a settled Kalman filter stores its steady state once, a change to one step
//! changes that step alone, and `map_gains` gives the bits a step-by-step change gives.

use std::sync::Arc;

use filterbench::families::kalman::kalman;
use filterbench::filter::realization::{Gains, Realization};
use filterbench::model::plant::Pattern;

use crate::common;

/// Every entry of a step's gains, as bits (shapes included).
fn bits(gs: &[Gains]) -> Vec<u64> {
    gs.iter()
        .flat_map(|g| [&g.af, &g.bf, &g.cf, &g.df, &g.gf])
        .flat_map(|m| [m.nrows() as u64, m.ncols() as u64].into_iter().chain(m.iter().map(|x| x.to_bits())))
        .collect()
}

/// The long_horizon predictor at its nominal covariances (N = 100 000).
fn settled() -> Realization {
    let exp = common::load("long_horizon", 2);
    kalman(&exp.plant, &exp.nominal, Pattern::Prediction)
}

#[test]
fn a_settled_kalman_filter_shares_exactly_its_repeated_steps() {
    let r = settled();
    for (k, w) in r.gains.windows(2).enumerate() {
        let same = bits(&w[0]) == bits(&w[1]);
        assert_eq!(Arc::ptr_eq(&w[0], &w[1]), same, "steps {k} and {}: shared iff the same bits", k + 1);
    }
    // The Riccati recursion reaches its fixed point in double precision after its transient (161
    // steps measured): every later step is the same allocation, so the gains cost a pointer per step.
    let distinct = 1 + r.gains.windows(2).filter(|w| !Arc::ptr_eq(&w[0], &w[1])).count();
    assert!(distinct * 100 <= r.gains.len(), "{distinct} distinct steps of {}", r.gains.len());
}

#[test]
fn changing_a_shared_step_changes_that_step_alone() {
    let r = settled();
    let k = r.gains.len() / 2;
    assert!(Arc::ptr_eq(&r.gains[k - 1], &r.gains[k]) && Arc::ptr_eq(&r.gains[k], &r.gains[k + 1]));
    let mut c = r.clone();
    c.gains_mut(k)[0].bf[(0, 0)] += 1.0;
    assert_ne!(bits(&c.gains[k]), bits(&r.gains[k]));
    for j in [0, k - 1, k + 1, r.gains.len() - 1] {
        assert_eq!(bits(&c.gains[j]), bits(&r.gains[j]), "step {j} unchanged");
    }
}

#[test]
fn map_gains_is_the_step_by_step_change_and_keeps_the_sharing() {
    let r = settled();
    let mut m = r.clone();
    m.map_gains(|g| {
        g.bf = 2.0 * &g.bf;
        g.cf = &g.cf * 0.5;
    });
    for k in 0..r.gains.len() {
        let mut want = r.gains[k].to_vec();
        for g in &mut want {
            g.bf = 2.0 * &g.bf;
            g.cf = &g.cf * 0.5;
        }
        assert_eq!(bits(&m.gains[k]), bits(&want), "step {k}");
    }
    let shared = |x: &Realization| x.gains.windows(2).map(|w| Arc::ptr_eq(&w[0], &w[1])).collect::<Vec<_>>();
    assert_eq!(shared(&m), shared(&r));
}
