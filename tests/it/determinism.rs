//! Results are bit-identical for any number of threads.
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

fn identical(exp: &filterbench::config::Experiment) {
    let a = run_with(1, exp);
    let b = run_with(2, exp);
    assert_eq!(a.threads, 1);
    assert_eq!(b.threads, 2);
    for (x, y) in a.scenarios.iter().zip(&b.scenarios) {
        assert!(x.mc == y.mc, "scenario {}: statistics differ between 1 and 2 threads", x.name);
        for (f, (p, q)) in x.mc.filters.iter().zip(&y.mc.filters).enumerate() {
            assert_eq!(p.total.mean.to_bits(), q.total.mean.to_bits(), "filter {f}");
            assert_eq!(p.total.variance().to_bits(), q.total.variance().to_bits(), "filter {f}");
        }
        for (t, u) in x.trajectories.iter().zip(&y.trajectories) {
            assert_eq!(t.z, u.z);
        }
        for (p, q) in x.exact.iter().zip(&y.exact) {
            assert_eq!(p.total.to_bits(), q.total.to_bits(), "scenario {}: exact error", x.name);
        }
    }
}
