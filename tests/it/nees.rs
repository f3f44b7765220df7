//! NEES, the consistency of a filter with its own claimed covariance (issue 14 §3), and NIS, that of
//! its innovation (issue 27): exact from the moments, empirical from Monte Carlo with its interval.

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
    agrees_step_by_step(&out);
}

/// Monte Carlo agrees with the exact NEES and NIS of every filter that has them, in every scenario,
/// within 4.5 standard errors at every step (the per-step tolerance of the other per-step tests).
fn agrees_step_by_step(out: &pipeline::RunOutcome) {
    for sc in &out.scenarios {
        for (f, o) in sc.filters.iter().enumerate() {
            let st = &sc.mc.filters[f];
            for (what, ex, mc) in [("NEES", &o.nees_exact, &st.nees), ("NIS", &o.nis_exact, &st.nis)] {
                let Some(ex) = ex else { continue };
                let mut steps = 0;
                for (step, v) in ex.iter().enumerate() {
                    let (Some(v), w) = (v, mc.at(step)) else { continue };
                    let z = (w.mean - v) / w.std_error();
                    assert!(
                        z.abs() < 4.5,
                        "{} / {f}: step {step}: {what} {} ± {} vs exact {v}",
                        sc.name,
                        w.mean,
                        w.std_error()
                    );
                    steps += 1;
                }
                assert!(steps > 0, "{} / {f}: {what} at no step", sc.name);
            }
        }
    }
}

/// The innovation ν = y − C x̂⁻ of the Kalman filter (seed 002 (5.6)–(5.7)): at its design
/// covariance its claimed S\[k] is C P⁻\[k] Cᵀ + D W Dᵀ, P⁻ the Riccati prediction covariance
/// recomputed here independently (no measurement at step 0 in this plant), so the exact NIS is 1
/// at every measured step. The misdesigned filter's exact NIS differs from 1; Monte Carlo agrees
/// with both (`agrees_step_by_step`, run above on 6000 trials). Tolerance: S is a sum of products of
/// O(1) matrices over ≤ 20 steps of a contracting recursion; 1e-9 relative leaves 10⁶ rounding units.
#[test]
fn kalman_innovations_have_the_riccati_covariance() {
    use filterbench::numerics::linalg::Mat;
    let exp = crate::common::baseline(200);
    let out = pipeline::run(&exp, false).unwrap();
    let p = &exp.plant;
    let k = exp.filter_index("kalman_nominal").unwrap();
    let nis = out.filters[k].nis.as_ref().expect("a Kalman filter has an innovation");
    let w = exp.nominal.w();
    let (a, b) = (p.a_at(0).clone(), p.b_at(0).clone());
    let mut pm: Mat = exp.nominal.x0().clone();
    for step in 0..p.steps() {
        let (c, d) = (p.c_at(step).into_owned(), p.d_at(step).into_owned());
        let s = &c * &pm * c.transpose() + &d * &w * d.transpose();
        match &nis.weights[step] {
            None => assert!(s.amax() == 0.0, "step {step}: no NIS only where there is no measurement"),
            Some(wt) => {
                // weights = S⁺ / rank: S · weights · rank is the identity for a full-rank S.
                let id = &s * &**wt * nis.ranks[step] as f64;
                let err = (id - Mat::identity(s.nrows(), s.nrows())).amax();
                assert!(err < 1e-9, "step {step}: claimed S differs from C P⁻ Cᵀ + D W Dᵀ by {err}");
            }
        }
        if step == p.horizon {
            break;
        }
        let cross = &a * &pm * c.transpose() + &b * &w * d.transpose();
        let gain = match s.clone().try_inverse() {
            Some(si) if s.amax() > 0.0 => &cross * si,
            _ => Mat::zeros(p.nx(), p.ny()),
        };
        pm = &a * &pm * a.transpose() + &b * &w * b.transpose() - &gain * cross.transpose();
    }
    let nominal = out.scenarios.iter().find(|s| s.name == "nominal_gaussian").unwrap();
    for v in nominal.filters[k].nis_exact.as_ref().unwrap().iter().flatten() {
        assert!((v - 1.0).abs() < 1e-9, "exact NIS {v} at the design covariance");
    }
    let wrong = exp.filter_index("kalman_wrong").unwrap();
    let avg = nominal.filters[wrong].nis_average.exact.unwrap();
    assert!((avg - 1.0).abs() > 0.1, "the misdesigned filter's innovations are not as claimed: NIS {avg}");
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
    let vals: Vec<f64> = exact.iter().flatten().collect();
    let avg = vals.iter().sum::<f64>() / vals.len() as f64;
    assert!(avg > 2.0, "over-confident: average NEES {avg}");
    let d = &out.filters[k];
    let cov = d.design.design_covariance.as_ref().unwrap();
    let at = |pairs: &[(&filterbench::model::plant::Plant, &filterbench::filter::realization::Realization)]| {
        Ok(filterbench::analysis::exact::errors(pairs, cov))
    };
    let m = filterbench::analysis::nees::error_moments(&exp.plant, &d.design.realization, &at).unwrap();
    for (step, (mk, c)) in m.iter().zip(d.claimed.as_ref().unwrap().per_step.iter()).enumerate() {
        assert!((mk.trace() - c).abs() <= 1e-9 * c.abs().max(1.0), "step {step}: tr {} vs claimed {c}", mk.trace());
    }
}

/// The projections of the error that the NEES moments read share one state recursion
/// (`exact::errors_joint`, `exact::errors`): every moment is the same bits as with each projection
/// run alone, under a correlated joint input with dropouts and a known input (filtering, so Df ≠ 0)
/// and under white noise. Deterministic: compared exactly.
#[test]
fn error_moments_from_one_recursion_equal_each_projection_alone() {
    use filterbench::analysis::{exact, nees};
    use filterbench::filter::realization::Realization;
    use filterbench::model::plant::Plant;
    use filterbench::numerics::linalg::{Mat, Vector};
    use filterbench::sim::noise::JointInput;

    let exp = crate::aniso_dropout::dropout_shapes("filtering");
    assert!(exp.plant.nz() >= 2, "the test needs cross moments");
    let real = filterbench::families::kalman::kalman(&exp.plant, &exp.nominal, filterbench::config::Pattern::Filtering);
    let d = exp.plant.nx() + exp.plant.steps() * exp.plant.nw();
    let JointInput::Correlated { factor } = JointInput::random_covariance(&Mat::identity(d, d), 5) else {
        unreachable!()
    };
    let (mean, cov) = (Vector::from_fn(d, |i, _| 0.1 * (i % 3) as f64), &factor * factor.transpose());
    let together = |pairs: &[(&Plant, &Realization)]| exact::errors_joint(pairs, &mean, &cov);
    let alone = |pairs: &[(&Plant, &Realization)]| {
        pairs.iter().map(|(p, r)| exact::error_joint(p, r, &mean, &cov)).collect::<Result<Vec<_>, _>>()
    };
    let (a, b) = (
        nees::error_moments(&exp.plant, &real, &together).unwrap(),
        nees::error_moments(&exp.plant, &real, &alone).unwrap(),
    );
    assert!(a.iter().any(|m| m[(0, 1)] != 0.0), "the joint input correlates the outputs");
    assert_eq!(a, b, "joint input: one recursion against each projection alone");
    let together = |pairs: &[(&Plant, &Realization)]| Ok(exact::errors(pairs, &exp.nominal));
    let alone =
        |pairs: &[(&Plant, &Realization)]| Ok(pairs.iter().map(|(p, r)| exact::error(p, r, &exp.nominal)).collect());
    let (a, b) = (
        nees::error_moments(&exp.plant, &real, &together).unwrap(),
        nees::error_moments(&exp.plant, &real, &alone).unwrap(),
    );
    assert_eq!(a, b, "white noise: one recursion against each projection alone");
}
