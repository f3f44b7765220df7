//! Seed 001: Markov-jump plants and the mode-dependent, steady-state and common-gain predictors.
use crate::common::Patch;

use filterbench::config::{self, Experiment};
use filterbench::families::markov_jump;
use filterbench::numerics::linalg::Mat;

use crate::common;

#[test]
fn common_gain_gradient_matches_finite_differences() {
    for v in ["slow_chain", "fast_chain"] {
        let exp = common::variant("markov_jump", v, 100);
        let modes = exp.plant.modes().unwrap();
        let modes = &*modes;
        let w = exp.nominal.w();
        let prob = modes.stationary().unwrap();
        let st = markov_jump::steady(&exp.plant, modes, &w).unwrap();
        let k0 = st.k.iter().zip(&prob).fold(Mat::zeros(2, 1), |a, (k, p)| a + *p * k);
        let (_, g) = markov_jump::cost_and_gradient(&exp.plant, modes, &prob, &k0, &w).unwrap();
        for i in 0..2 {
            let h = 1e-6;
            let mut kp = k0.clone();
            kp[(i, 0)] += h;
            let mut km = k0.clone();
            km[(i, 0)] -= h;
            let jp = markov_jump::cost_and_gradient(&exp.plant, modes, &prob, &kp, &w).unwrap().0;
            let jm = markov_jump::cost_and_gradient(&exp.plant, modes, &prob, &km, &w).unwrap().0;
            let fd = (jp - jm) / (2.0 * h);
            eprintln!("{v}: ∂J/∂K[{i}] adjoint {} vs finite difference {fd}", g[(i, 0)]);
            assert!((fd - g[(i, 0)]).abs() <= 1e-6 * g.amax().max(1e-3), "{v}: gradient entry {i}");
        }
        let c = markov_jump::common(&exp.plant, modes, &w).unwrap();
        let (_, g) = markov_jump::cost_and_gradient(&exp.plant, modes, &prob, &c.k, &w).unwrap();
        assert!(g.amax() <= 1e-7, "{v}: gradient at the optimum {}", g.amax());
        assert!(c.cost >= c.mode_dependent_cost, "one gain cannot beat one per mode");
    }
}

/// Per-mode Monte Carlo: Σ_k |e[k]|² 1{θ[k] = j} for every trial, with the engine's sampler and the
/// realization's own output/advance (so the mode sequence and the noise are exactly the engine's).
fn per_mode_mc(
    exp: &Experiment,
    real: &filterbench::filter::realization::Realization,
    trials: u64,
) -> Vec<filterbench::sim::stats::Welford> {
    use filterbench::numerics::linalg::Vector;
    use filterbench::sim::noise::NoiseSampler;
    let p = &exp.plant;
    let sampler = NoiseSampler::new(p, &exp.nominal, &exp.scenarios[0].shape);
    let mut draw = sampler.workspace();
    let q = p.n_modes();
    let mut acc = vec![filterbench::sim::stats::Welford::default(); q];
    let (mut y, mut z, mut zhat) = (Vector::zeros(p.ny()), Vector::zeros(p.nz()), Vector::zeros(p.nz()));
    for t in 0..trials {
        sampler.draw_trial(exp.seed, 0, t, &mut draw);
        let mut x = draw.x0.clone();
        let mut s = real.s0.clone();
        let mut sums = vec![0.0; q];
        for k in 0..p.steps() {
            let th = draw.modes[k];
            let wk = draw.w.column(k);
            y.gemv(1.0, &*p.c_of(k, th), &x, 0.0);
            y.gemv(1.0, &*p.d_of(k, th), &wk, 1.0);
            z.gemv(1.0, p.cz.at(0), &x, 0.0);
            z.gemv(1.0, p.dz.at(0), &wk, 1.0);
            real.output(k, th, &s, &y, &mut zhat);
            if p.counts(k) {
                sums[th] += (&z - &zhat).norm_squared();
            }
            if k < p.horizon {
                let mut sn = s.clone();
                real.advance(k, th, &s, &y, p.r_at(k), &mut sn);
                s = sn;
                x = p.a_of(k, th) * &x + p.b_of(k, th) * wk;
                if let Some(r) = p.r_at(k) {
                    x += r;
                }
            }
        }
        for (a, v) in acc.iter_mut().zip(&sums) {
            a.push(*v);
        }
    }
    acc
}

/// Tolerance: each per-mode sum within 4σ of its exact value (σ its Monte Carlo standard error;
/// 4 filters × 3 modes × 2 variants = 24 comparisons, family-wise about 0.15 %).
#[test]
fn exact_per_mode_moments_agree_with_monte_carlo() {
    for v in ["slow_chain", "fast_chain"] {
        let exp = common::variant("markov_jump", v, 100);
        let out = filterbench::pipeline::design_all(&exp).unwrap();
        for (f, d) in out.iter().enumerate() {
            let real = &d.design.realization;
            let exact = filterbench::analysis::exact::error(&exp.plant, real, &exp.nominal);
            let mc = per_mode_mc(&exp, real, 6000);
            for (j, w) in mc.iter().enumerate() {
                let z = (w.mean - exact.per_mode[j]) / w.std_error();
                eprintln!(
                    "{v}/{}/mode {j}: MC {:.4} vs exact {:.4} ({z:.2}σ)",
                    exp.filters[f].name, w.mean, exact.per_mode[j]
                );
                assert!(z.abs() <= 4.0, "{v}/{} mode {j}: {z:.2}σ", exp.filters[f].name);
            }
            let sum: f64 = exact.per_mode.iter().sum();
            assert!((sum - exact.total).abs() <= 1e-9 * exact.total);
        }
    }
}

#[test]
fn one_mode_is_the_kalman_predictor() {
    let text = crate::common::SHAPES_TOML.patch("PATTERN", "prediction")
        + "\n[modes]\ntransition = [[1.0]]\n[[modes.mode]]\nname = \"only\"\n";
    let exp = config::parse("one_mode", "one_mode.toml", &text).unwrap();
    let (mj, predicted) = markov_jump::finite(&exp.plant, &exp.nominal);
    let kf =
        filterbench::families::kalman::kalman(&exp.plant, &exp.nominal, filterbench::model::plant::Pattern::Prediction);
    for k in 0..exp.plant.steps() {
        let (a, b) = (mj.gains(k, 0), kf.step(k));
        // Equal up to the order of floating-point operations.
        assert!((&a.bf - &b.bf).amax() <= 1e-12 * b.bf.amax().max(1.0), "step {k}: K");
        assert!((&a.af - &b.af).amax() <= 1e-12 * b.af.amax().max(1.0), "step {k}: A − KC");
    }
    let exact = filterbench::analysis::exact::error(&exp.plant, &mj, &exp.nominal).total;
    assert!((exact - predicted).abs() <= 1e-9 * exact);
}

#[test]
fn mode_dependent_beats_common_gain_beats_mode_averaged_kalman() {
    for v in ["slow_chain", "fast_chain"] {
        let exp = common::variant("markov_jump", v, 100);
        let out = filterbench::pipeline::design_all(&exp).unwrap();
        let exact = |name: &str| {
            let i = exp.filter_index(name).unwrap();
            filterbench::analysis::exact::error(&exp.plant, &out[i].design.realization, &exp.nominal).total
        };
        let (md, st, cg, ka) = (
            exact("mode_dependent"),
            exact("mode_dependent_steady"),
            exact("common_gain"),
            exact("kalman_mode_averaged"),
        );
        eprintln!("{v}: mode-dependent {md:.4}, steady {st:.4}, common gain {cg:.4}, mode-averaged Kalman {ka:.4}");
        assert!(md <= st && md <= cg && cg <= ka, "{v}: the ordering fails");
        // The finite-horizon gains are those of the coupled Riccati recursion: its prediction is exact.
        let d = &out[exp.filter_index("mode_dependent").unwrap()].design;
        let predicted = d.figures.get::<filterbench::families::Predicted>().unwrap().riccati_summed_error;
        assert!((predicted - md).abs() <= 1e-9 * md);
    }
}

#[test]
fn steady_gains_need_an_ergodic_chain() {
    let text = crate::common::text("markov_jump").patch(
        "transition = [[0.9, 0.08, 0.02], [0.08, 0.9, 0.02], [0.1, 0.1, 0.8]]",
        "transition = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\ninitial = [0.5, 0.3, 0.2]",
    );
    let exp = config::parse("reducible", "reducible.toml", &text).unwrap();
    let err = filterbench::pipeline::design_all(&exp).err().expect("steady gains refused").to_string();
    assert!(err.contains("not ergodic"), "{err}");
}
