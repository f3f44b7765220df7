//! NEES, the consistency of a filter with its own claimed covariance (issue 14 §3): exact from the
//! moments, empirical from Monte Carlo with its interval.

use filterbench::pipeline;

/// At its design covariance a Kalman filter is consistent: the exact NEES is 1 at every step where
/// it claims an error (a deterministic identity, to rounding), and the claimed moments' trace is
/// the claimed per-step error. Monte Carlo agrees with the exact NEES within 4.5 standard errors
/// at every step (4 in the average): the per-step tolerance of the other per-step tests.
#[test]
fn kalman_is_consistent_at_its_design_covariance_and_monte_carlo_agrees() {
    let exp = crate::common::baseline(6000);
    let out = pipeline::run(&exp, false).unwrap();
    let k = exp.filter_index("kalman_nominal").unwrap();
    let nominal = out.scenarios.iter().find(|s| s.name == "nominal_gaussian").unwrap();
    let exact = nominal.filters[k].nees_exact.as_ref().expect("a Kalman filter has NEES");
    let mut counted = 0;
    for (step, v) in exact.iter().enumerate() {
        if let Some(v) = v {
            assert!((v - 1.0).abs() < 1e-9, "step {step}: exact NEES {v} at the design covariance");
            counted += 1;
        }
    }
    assert!(counted >= exact.len() - 1, "NEES is defined where the filter claims an error");
    for sc in &out.scenarios {
        for (f, ex) in sc.filters.iter().map(|o| &o.nees_exact).enumerate() {
            let Some(ex) = ex else { continue };
            let mc = &sc.mc.filters[f].nees;
            let mut zs = Vec::new();
            for (step, v) in ex.iter().enumerate() {
                let (Some(v), w) = (v, &mc[step]) else { continue };
                let z = (w.mean - v) / w.std_error();
                assert!(
                    z.abs() < 4.5,
                    "{} / {}: step {step}: NEES {} ± {} vs exact {v}",
                    sc.name,
                    f,
                    w.mean,
                    w.std_error()
                );
                zs.push(z);
            }
            assert!(!zs.is_empty());
        }
    }
}

/// A Kalman filter designed at the wrong covariance believes itself better than it is in this
/// plant: its exact NEES averages well above 1 (claimed 10.3 against an exact 46.9 summed), and
/// the exact error-moment recursion by polarization agrees with the claim's trace.
#[test]
fn a_misspecified_kalman_filter_is_overconfident() {
    let exp = crate::common::baseline(200);
    let out = pipeline::run(&exp, false).unwrap();
    let k = exp.filter_index("kalman_wrong").unwrap();
    let nominal = out.scenarios.iter().find(|s| s.name == "nominal_gaussian").unwrap();
    let exact = nominal.filters[k].nees_exact.as_ref().unwrap();
    let vals: Vec<f64> = exact.iter().flatten().copied().collect();
    let avg = vals.iter().sum::<f64>() / vals.len() as f64;
    assert!(avg > 2.0, "over-confident: average NEES {avg}");
    let d = &out.filters[k];
    let cov = d.design.design_covariance.as_ref().unwrap();
    let at = |p: &filterbench::model::plant::Plant, r: &filterbench::filter::realization::Realization| {
        Ok(filterbench::analysis::exact::error(p, r, cov))
    };
    let m = filterbench::analysis::nees::error_moments(&exp.plant, &d.design.realization, &at).unwrap();
    for (step, (mk, c)) in m.iter().zip(&d.claimed.as_ref().unwrap().per_step).enumerate() {
        assert!((mk.trace() - c).abs() <= 1e-9 * c.abs().max(1.0), "step {step}: tr {} vs claimed {c}", mk.trace());
    }
}
