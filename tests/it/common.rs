//! Shared fixtures.

use filterbench::config::{self, Experiment};

/// `str::replace` for fixtures: panics when the pattern is absent, so a reformatted experiment file
/// cannot silently turn a test into a test of another case.
pub trait Patch {
    fn patch(&self, from: &str, to: &str) -> String;
}

impl Patch for str {
    fn patch(&self, from: &str, to: &str) -> String {
        assert!(self.contains(from), "fixture pattern not found: {from:?}");
        self.replace(from, to)
    }
}

/// The text of the shipped experiment file `name`.
pub fn text(name: &str) -> String {
    std::fs::read_to_string(format!("{}/experiments/{name}.toml", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// The shipped experiment `name` with `trials` trials.
pub fn load(name: &str, trials: usize) -> Experiment {
    let path = format!("{}/experiments/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    let mut e = config::load(std::path::Path::new(&path)).unwrap_or_else(|err| panic!("{name} parses: {err}"));
    e.trials = trials;
    e
}

/// The shipped experiment's variant `variant`.
pub fn variant(name: &str, variant: &str, trials: usize) -> Experiment {
    let path = format!("{}/experiments/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    let mut e = config::load_variants(std::path::Path::new(&path), &Default::default())
        .expect("parses")
        .into_iter()
        .find(|e| e.variant.as_deref() == Some(variant))
        .expect("variant exists");
    e.trials = trials;
    e
}

/// `galerkin_string` made small: 32 truth modes, N = 100, n ∈ {2, 4}, α ∈ {1e-1, 1e-8}, 3000 trials.
pub fn small_string() -> String {
    text("galerkin_string")
        .patch("truth_modes = 128", "truth_modes = 32")
        .patch("duration = 1.0", "duration = 0.25")
        .patch("n = [2, 4, 8, 16], alpha = [1e-1, 1e-4, 1e-8, 1e-12]", "n = [2, 4], alpha = [1e-1, 1e-8]")
        .patch("trials = 300", "trials = 3000")
}

/// The shipped `kalman_baseline` experiment with `trials` trials.
pub fn baseline(trials: usize) -> Experiment {
    load("kalman_baseline", trials)
}

/// A small plant that exercises what kalman_baseline does not: prediction, noise shared between
/// the state and the measurement (B and D use the same components of w), a nonzero x0 mean, a
/// known input, Dz ≠ 0, and every distribution shape.
pub const SHAPES_TOML: &str = r#"
description = "test plant with correlated noise, known input and every shape"
seed = 7
trials = 6000
pattern = "PATTERN"
sample_trajectories = 1

[plant]
horizon = 20
noise_blocks = ["w"]
A = [[0.9, 0.5], [-0.3, 0.7]]
B = [[1.0, 0.0, 0.2], [0.3, 0.8, 0.0]]
C = [[1.0, 0.5]]
D = [[0.2, 0.0, 0.7]]
Cz = [[1.0, 0.0], [0.0, 1.0], [1.0, -1.0]]
Dz = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.1, 0.0, 0.0]]
x0_mean = [1.0, -2.0]
known_input = { kind = "sine", amplitude = [0.0, 0.5], frequency = 0.3 }

[nominal]
x0 = [[2.0, 0.3], [0.3, 1.0]]
w = [[1.0, 0.2, 0.0], [0.2, 0.5, 0.1], [0.0, 0.1, 0.8]]

[[filters]]
name = "kalman"
family = "kalman"

[[filters]]
name = "kalman_other"
family = "kalman"
design = { kind = "given", w = [[0.3, 0.0, 0.0], [0.0, 0.3, 0.0], [0.0, 0.0, 2.0]] }

[[scenarios]]
name = "gaussian"

[[scenarios]]
name = "uniform"
shape = { kind = "uniform" }

[[scenarios]]
name = "laplace"
shape = { kind = "laplace" }

[[scenarios]]
name = "student_t"
shape = { kind = "student_t", nu = 6 }

[[scenarios]]
name = "rademacher"
shape = { kind = "rademacher" }

[[scenarios]]
name = "mixture"
shape = { kind = "mixture", weight = 0.1, ratio = 4.0 }
"#;

pub fn shapes(pattern: &str) -> Experiment {
    config::parse("shapes", "shapes.toml", &SHAPES_TOML.patch("PATTERN", pattern)).expect("test plant parses")
}

/// A fresh folder under the system temp dir, removed on drop. (No dev-dependency for this: a
/// dev-dependency changes the features cargo resolves, so `cargo run` after `cargo test` would
/// rebuild half the dependency tree.)
pub struct TempDir(std::path::PathBuf);

impl TempDir {
    pub fn new() -> Self {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static N: AtomicUsize = AtomicUsize::new(0);
        let p = std::env::temp_dir().join(format!(
            "filterbench-test-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(&p).unwrap();
        TempDir(p)
    }
    pub fn path(&self) -> &std::path::Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A matrix as a TOML array, every entry in Rust's shortest round-trip form (`{:?}`), so it reads
/// back as the same f64.
pub fn toml_mat(m: &filterbench::numerics::linalg::Mat) -> String {
    let rows: Vec<String> = (0..m.nrows())
        .map(|i| format!("[{}]", (0..m.ncols()).map(|j| format!("{:?}", m[(i, j)])).collect::<Vec<_>>().join(", ")))
        .collect();
    format!("[{}]", rows.join(", "))
}
