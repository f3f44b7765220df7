//! The noise-free output z̄ of seed 003's Figs. 3–4, the reference the recording's sample trials
//! draw: E z[k] under zero-mean noise, from the known input and x(0)'s mean, on a plain plant, with
//! dropouts, with multiplicative factors on A and Cz, and with Markov modes that switch A.
//!
//! Tolerance: at every step and component the mean of z over 4000 recorded trials (the pipeline's
//! own sample trajectories) lies within 4σ of z̄, σ the sample standard deviation over √4000
//! (63 comparisons per plant, 252 in all: family-wise about 1.6 % for independent comparisons; the
//! seeds are fixed, so the outcome is deterministic).
use crate::common::{Patch, SHAPES_TOML};

use filterbench::config::{self, Experiment};

const TRIALS: usize = 4000;

fn parse(name: &str, text: &str) -> Experiment {
    let mut e = config::parse(name, &format!("{name}.toml"), text).expect("test plant parses");
    e.trials = TRIALS;
    e.sample_trajectories = TRIALS;
    // The Gaussian scenario: z̄ is the mean for any zero-mean shape, one is enough.
    e.scenarios.truncate(1);
    e
}

fn check(name: &str, exp: &Experiment) {
    let out = filterbench::pipeline::run(exp, false).expect("runs");
    let sc = &out.scenarios[0];
    let zbar = sc.noise_free.as_ref().expect("a plant with a known input has a noise-free output");
    assert_eq!(sc.trajectories.len(), TRIALS);
    assert_eq!((zbar.nrows(), zbar.ncols()), (exp.plant.nz(), exp.plant.steps()));
    let n = TRIALS as f64;
    let mut worst = 0.0f64;
    for k in 0..exp.plant.steps() {
        for i in 0..exp.plant.nz() {
            let v: Vec<f64> = sc.trajectories.iter().map(|t| t.z[(i, k)]).collect();
            let mean = v.iter().sum::<f64>() / n;
            let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
            let (d, se) = (mean - zbar[(i, k)], sd / n.sqrt());
            worst = worst.max(d.abs() / se);
            assert!(
                d.abs() <= 4.0 * se,
                "{name}: z{}[{k}]: mean {mean} vs noise-free {} ({:.2}σ)",
                i + 1,
                zbar[(i, k)],
                d / se
            );
        }
    }
    eprintln!("{name}: largest |mean − z̄| = {worst:.2}σ over {} steps × {} components", zbar.ncols(), zbar.nrows());
    // The reference moves: a check against a flat zero would pass for nothing.
    assert!(zbar.amax() > 0.5, "{name}: the known input and x(0)'s mean drive z̄ ({})", zbar.amax());
}

#[test]
fn noise_free_output_is_the_mean_of_z() {
    let plain = SHAPES_TOML.patch("PATTERN", "prediction");
    check("plain", &parse("plain", &plain));
    let dropouts = plain.patch("known_input = {", "arrival = 0.7\nknown_input = {");
    check("dropouts", &parse("dropouts", &dropouts));
    let factors = plain.patch(
        "\n[nominal]",
        "\n[[plant.multiplicative]]\nname = \"gust\"\nA = [[0.3, 0.1], [0.0, 0.2]]\n\
         Cz = [[0.5, 0.0], [0.0, 0.5], [0.2, 0.2]]\n\n[nominal]",
    );
    let exp = parse("factors", &factors);
    assert_eq!(exp.plant.factors.len(), 1);
    check("factors", &exp);
    let markov = plain.clone()
        + "\n[modes]\ntransition = [[0.8, 0.2], [0.3, 0.7]]\ninitial = [1.0, 0.0]\n\
           [[modes.mode]]\nname = \"slow\"\n\n[[modes.mode]]\nname = \"turn\"\nA = [[0.5, -0.6], [0.6, 0.5]]\n";
    let exp = parse("markov", &markov);
    assert_eq!(exp.plant.n_modes(), 2);
    check("markov", &exp);
}

#[test]
fn no_known_input_no_noise_free_output() {
    let mut exp = crate::common::baseline(40);
    exp.scenarios.truncate(1);
    assert!(exp.plant.known_input.is_empty());
    let out = filterbench::pipeline::run(&exp, false).expect("runs");
    assert!(out.scenarios.iter().all(|s| s.noise_free.is_none()));
}
