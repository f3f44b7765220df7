//! Monte Carlo agrees with the exact (Lyapunov) error, per step and in total, for Gaussian and
//! non-Gaussian noise of the same covariance.
//!
//! Tolerances: the summed error within 4σ (σ = the Monte Carlo standard error; with a few dozen
//! comparisons per test the chance that a correct engine fails one is below 0.3 %), each per-step
//! mean within 4.5σ (a few hundred comparisons, family-wise below 0.3 %). The seeds are fixed, so the
//! outcome is reproducible; the tolerances are what a correct engine passes with high probability
//! for any seed, not tuned to these seeds.

use filterbench::run;

use crate::common;

pub(crate) fn check(exp: &filterbench::spec::Experiment) {
    let out = run::run(exp, false).expect("runs");
    let mut worst_total: f64 = 0.0;
    let mut worst_step: f64 = 0.0;
    for sc in &out.scenarios {
        for (f, spec) in exp.filters.iter().enumerate() {
            let st = &sc.mc.filters[f];
            // A deterministic input (every trial the same) has no spread: then exact equality, up
            // to rounding, is required.
            let within = |d: f64, se: f64, exact: f64, tol: f64| {
                if se > 0.0 {
                    d / se
                } else if d.abs() <= 1e-9 * exact.abs().max(1.0) {
                    0.0
                } else {
                    tol * 10.0 + 1.0
                }
            };
            let z = within(st.total.mean - sc.exact[f].total, st.total.std_error(), sc.exact[f].total, 4.0);
            assert!(
                z.abs() <= 4.0,
                "{}/{}: empirical {} vs exact {} is {z:.2}σ away",
                sc.name,
                spec.name,
                st.total.mean,
                sc.exact[f].total
            );
            worst_total = worst_total.max(z.abs());
            for (k, w) in st.steps.iter().enumerate() {
                let zk = within(w.mean - sc.exact[f].per_step[k], w.std_error(), sc.exact[f].per_step[k], 4.5);
                assert!(
                    zk.abs() <= 4.5,
                    "{}/{} step {k}: {} vs exact {} is {zk:.2}σ away",
                    sc.name,
                    spec.name,
                    w.mean,
                    sc.exact[f].per_step[k]
                );
                worst_step = worst_step.max(zk.abs());
            }
        }
    }
    eprintln!("{}: largest |z| total {worst_total:.2}σ, per step {worst_step:.2}σ", exp.name);
}

#[test]
fn baseline_gaussian_laplace_student_vertex_worst() {
    check(&common::baseline(4000));
}

#[test]
fn every_shape_prediction_with_correlated_noise_and_known_input() {
    check(&common::shapes("prediction"));
}

#[test]
fn every_shape_filtering_with_correlated_noise_and_known_input() {
    check(&common::shapes("filtering"));
}
