//! `filterbench check` (docs/checks.md): the statistics core, the designed error rates measured
//! over many seeds, the negative controls, the command with its JUnit report and exit codes, and
//! the shipped experiments' own expectations.

mod baseline;
mod calibration;
mod cli;
mod shipped;
mod stats;

use filterbench::config::{self, Experiment};
use filterbench::verdict::evaluate::{Check, Rates};
use filterbench::{pipeline, report, verdict};

/// A 2-state plant, N = 20, a Kalman predictor at the nominal covariance and one designed with
/// its process covariance ×4 (0.3 → 1.2), one Gaussian scenario; `EXPECT` is replaced by the
/// entries under test.
pub const SMALL: &str = r#"
description = "check: a small plant"
seed = 1
trials = 400
pattern = "prediction"
sample_trajectories = 1

[plant]
horizon = 20
noise_blocks = ["w"]
A = [[0.9, 0.2], [-0.1, 0.8]]
B = [[1.0, 0.0], [0.0, 0.0]]
C = [[1.0, 0.0]]
D = [[0.0, 0.5]]

[nominal]
x0 = [[1.0, 0.0], [0.0, 1.0]]
w = [[0.3, 0.0], [0.0, 0.25]]

[[filters]]
name = "kalman"
family = "kalman"

[[filters]]
name = "kalman_x4"
family = "kalman"
design = { kind = "given", w = [[1.2, 0.0], [0.0, 0.25]] }

[[scenarios]]
name = "gaussian"

EXPECT
"#;

/// SMALL with these `[[expect]]` entries, `trials` trials and seed `seed`.
pub fn small(expect: &str, trials: usize, seed: u64) -> Experiment {
    let mut e = config::parse("small", "small.toml", &SMALL.replace("EXPECT", expect)).unwrap();
    (e.trials, e.seed) = (trials, seed);
    e
}

/// Runs `exp` in-process, writes its tables into `dir` and checks them at `rates` (what `check`
/// does, without the recording).
pub fn run_and_check(exp: &Experiment, dir: &std::path::Path, rates: Rates) -> Check {
    let out = pipeline::run(exp, false).unwrap();
    report::parquet::write_tables(&[(exp, &out)], dir).unwrap();
    verdict::run::evaluate_folder(dir, std::slice::from_ref(exp), rates, None).unwrap()
}
