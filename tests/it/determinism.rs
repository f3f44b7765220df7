//! Results are bit-identical for any number of threads: every accumulator of the lane engine (per
//! step, NEES, totals, paired differences, the per-trial checks' maximum ratio and violations) and
//! every sample trajectory, on plants that exercise each feature of the trial loop; and the engine
//! draws trial i exactly what the per-trial draw of (seed, scenario, i) gives, whichever block and
//! lane it lands in.
use crate::common::Patch;

use filterbench::pipeline;

use crate::common;

fn run_with(threads: usize, exp: &filterbench::config::Experiment) -> pipeline::RunOutcome {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(|| pipeline::run(exp, false).unwrap())
}

#[test]
fn one_and_two_threads_give_identical_bits() {
    // 16,700 trials: more than one wave of 256 blocks of 64 trials, and a partial last block.
    identical(&common::baseline(16_700));
}

#[test]
fn identical_bits_with_dropouts_and_anisotropic_inputs() {
    // Mode sequences, and worst-case covariances from faer eigendecompositions large enough
    // (lw = 453) for faer to split its work by threads if it were allowed to.
    let text = crate::aniso_dropout::dropout_shapes_text("prediction")
        .patch("horizon = 20", "horizon = 150")
        .patch("anisotropy = 12.0", "anisotropy = 80.0");
    let mut exp = filterbench::config::parse("dropout_shapes", "t.toml", &text).unwrap();
    exp.trials = 700;
    identical(&exp);
}

#[test]
fn identical_bits_with_per_trial_checks_joint_inputs_and_error_coordinates() {
    // hinf_tradeoff: per-trial H∞/H2 checks, ellipsoid and worst-case joint inputs, filters run in
    // error coordinates; 1000 trials = 15 full lane blocks and a partial one.
    identical(&common::load("hinf_tradeoff", 1000));
}

#[test]
fn identical_bits_with_multiplicative_noise_and_dropouts() {
    use crate::time_varying::{parse, plant_text};
    let factors = "arrival = 0.85\n[[plant.multiplicative]]\nname = \"gust\"\nshape = \"uniform\"\n\
                   A = [[0.1, 0.05], [0.0, 0.15]]\nC = [[0.3, 0.0]]\n";
    let kalman = "[[filters]]\nname = \"kalman\"\nfamily = \"kalman\"\n";
    let scenarios = "[[scenarios]]\nname = \"laplace\"\nshape = \"laplace\"\n";
    let mut exp = parse(&plant_text("prediction", 30, false, factors, kalman, scenarios));
    exp.trials = 333;
    identical(&exp);
}

#[test]
fn variants_side_by_side_give_each_variants_bits_alone() {
    // `experiment` runs a file's variants side by side (`pipeline::run_variants`); each must be the
    // bits of that variant run alone on one thread: aniso_dropout's three dropout rates, N = 40.
    let tmp = common::TempDir::new();
    let path = tmp.path().join("aniso_dropout.toml");
    std::fs::write(&path, common::text("aniso_dropout").patch("horizon = 200", "horizon = 40")).unwrap();
    let overrides = filterbench::config::Overrides { trials: Some(300), ..Default::default() };
    let exps = filterbench::config::load_variants(&path, &overrides).unwrap();
    assert_eq!(exps.len(), 3);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let together = pool.install(|| pipeline::run_variants(&exps, false)).unwrap();
    for (exp, b) in exps.iter().zip(&together) {
        let a = run_with(1, exp);
        let gains = |o: &pipeline::RunOutcome| -> Vec<u64> {
            o.filters.iter().flat_map(|f| f.anisotropic.map(|n| n.norm_sq.to_bits())).collect()
        };
        assert_eq!(gains(&a), gains(b), "{:?}: designs differ", exp.variant);
        for (x, y) in a.scenarios.iter().zip(&b.scenarios) {
            assert_eq!(bits(&x.mc), bits(&y.mc), "{:?} {}: statistics differ side by side", exp.variant, x.name);
            for (p, q) in x.exact.iter().zip(&y.exact) {
                assert_eq!(p.total.to_bits(), q.total.to_bits(), "{:?} {}: exact error", exp.variant, x.name);
            }
        }
    }
}

/// Every figure of the Monte Carlo statistics, as bits.
pub(crate) fn bits(mc: &filterbench::sim::montecarlo::McStats) -> Vec<u64> {
    let w = |w: &filterbench::sim::stats::Welford| [w.n, w.mean.to_bits(), w.variance().to_bits()];
    let mut out = Vec::new();
    for f in &mc.filters {
        out.extend(w(&f.total));
        out.extend(f.steps.iter().chain(f.nees.iter()).flat_map(|x| w(&x)));
        out.extend([f.max_ratio.to_bits(), f.violations]);
    }
    out.extend(mc.paired.iter().flat_map(w));
    out
}

fn identical(exp: &filterbench::config::Experiment) {
    let a = run_with(1, exp);
    let b = run_with(2, exp);
    assert_eq!(a.threads, 1);
    assert_eq!(b.threads, 2);
    for (x, y) in a.scenarios.iter().zip(&b.scenarios) {
        assert!(x.mc.filters[0].total.n == exp.trials as u64);
        assert_eq!(bits(&x.mc), bits(&y.mc), "scenario {}: statistics differ between 1 and 2 threads", x.name);
        assert_eq!(x.trajectories.len(), y.trajectories.len());
        for (t, u) in x.trajectories.iter().zip(&y.trajectories) {
            let b = |m: &filterbench::numerics::linalg::Mat| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(b(&t.z), b(&u.z));
            for (p, q) in t.zhat.iter().zip(&u.zhat) {
                assert_eq!(b(p), b(q));
            }
            assert_eq!(t.modes, u.modes);
        }
        for (p, q) in x.exact.iter().zip(&y.exact) {
            assert_eq!(p.total.to_bits(), q.total.to_bits(), "scenario {}: exact error", x.name);
        }
    }
}

#[test]
fn a_trial_draws_the_same_in_any_lane() {
    // Trial 70 is lane 6 of block 1 in the engine and lane 0 when drawn alone; a plant with modes
    // and a multiplicative factor draws all three streams.
    use crate::time_varying::{parse, plant_text};
    use filterbench::sim::noise::NoiseSampler;
    let factors = "arrival = 0.6\n[[plant.multiplicative]]\nname = \"gust\"\nA = [[0.1, 0.05], [0.0, 0.15]]\n";
    let kalman = "[[filters]]\nname = \"kalman\"\nfamily = \"kalman\"\n";
    let exp = parse(&plant_text("prediction", 12, false, factors, kalman, "[[scenarios]]\nname = \"n\"\n"));
    let sampler = NoiseSampler::new(&exp.plant, &exp.nominal, &exp.scenarios[0].shape);
    let mut one = sampler.workspace();
    sampler.draw_trial(exp.seed, 2, 70, &mut one);
    let mut block = sampler.lanes();
    sampler.start(exp.seed, 2, 64, 64, &mut block);
    for (i, r) in block.x0.iter().enumerate() {
        assert_eq!(r[6].to_bits(), one.x0[i].to_bits());
    }
    let mut seen = std::collections::BTreeSet::new();
    for k in 0..exp.plant.steps() {
        sampler.step(k, &mut block);
        for (i, r) in block.w.iter().enumerate() {
            assert_eq!(r[6].to_bits(), one.w[(i, k)].to_bits(), "w[{k}]");
        }
        assert_eq!(block.modes[6] as usize, one.modes[k]);
        seen.insert(one.modes[k]);
        assert_eq!(block.zeta[0][6].to_bits(), one.zeta[(0, k)].to_bits());
    }
    assert_eq!(seen.len(), 2, "both modes occur, so the mode stream is exercised");
}

#[test]
fn a_trial_gives_the_same_bits_whoever_shares_its_block() {
    // Trials 64.. fill block 1 alone at 65, 66 and 70 trials and share it with the others at 128,
    // so their lanes' modes agree at other steps. The mode-dependent predictor's gains differ per mode
    // (dropouts) and it sees two measurements, so its products sum several terms that depend on
    // the lane's mode: each lane must still take its own mode's sum, the one a block of lanes all
    // in that mode computes.
    let text = r#"description = "lanes"
seed = 7
trials = 100
pattern = "prediction"

[plant]
horizon = 60
noise_blocks = ["w"]
A = [[0.9, 0.3], [-0.2, 0.8]]
B = [[1.0, 0.0, 0.0, 0.0], [0.3, 1.0, 0.0, 0.0]]
C = [[1.0, 0.0], [0.5, 1.0]]
D = [[0.0, 0.0, 0.7, 0.0], [0.0, 0.0, 0.2, 0.6]]
Cz = [[1.0, 0.0], [0.0, 1.0]]
arrival = 0.6

[nominal]
x0 = [[1.0, 0.0], [0.0, 1.0]]
w = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]

[[filters]]
name = "sees_dropouts"
family = "markov_jump"

[[scenarios]]
name = "white"
"#;
    let exp = filterbench::config::parse("lanes", "t.toml", text).unwrap();
    let run = |trials| {
        let mut e = exp.clone();
        e.trials = trials;
        e.per_trial = true;
        run_with(1, &e)
    };
    let long = run(128);
    for short in [65, 66, 70] {
        let (p, q) = (&run(short).scenarios[0].per_trial[0], &long.scenarios[0].per_trial[0]);
        assert_eq!((p.len(), q.len()), (short as usize, 128));
        for (t, (x, y)) in p.iter().zip(q).enumerate() {
            assert_eq!(x.to_bits(), y.to_bits(), "trial {t} of {short}");
        }
    }
}
