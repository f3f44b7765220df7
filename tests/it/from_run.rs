//! The `linear` family's third form and its per-mode matrices: a minimax filter taken from an
//! earlier run's gains.parquet (`from_run`) and seed 001's mode-indexed Markov-jump predictor,
//! given back through `from_run` and as per-mode gains, reproduce the designed filters bit for bit;
//! a run from another plant, a missing filter, variant or folder are refused in one line.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::bad_input::check_failure;
use crate::common::{Patch, TempDir, toml_mat};
use filterbench::config::{self, Experiment, Overrides};
use filterbench::pipeline::RunOutcome;

/// Runs the shipped experiment `name` with `trials` into `out` through the command line.
fn run_shipped(name: &str, trials: usize, out: &Path) {
    let o = Command::new(env!("CARGO_BIN_EXE_filterbench"))
        .args(["experiment", name, "--trials", &trials.to_string(), "--quiet", "--out"])
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Writes `text` as `name.toml` into `dir` and loads its variants, relative references from `dir`.
fn load_in(dir: &Path, name: &str, text: &str) -> std::result::Result<Vec<Experiment>, String> {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    config::load_variants(&path, &Overrides::default()).map_err(|e| e.to_string())
}

/// Asserts `copy` has bit for bit the exact error (every step and the sum) and the Monte Carlo
/// mean of `original` in every scenario: the same realization run on the same draws.
fn bit_for_bit(exp: &Experiment, out: &RunOutcome, original: &str, copy: &str) {
    let (a, b) = (exp.filter_index(original).unwrap(), exp.filter_index(copy).unwrap());
    for sc in &out.scenarios {
        let (ea, eb) = (&sc.exact[a], &sc.exact[b]);
        assert_eq!(ea.total.to_bits(), eb.total.to_bits(), "{copy} exact in {}: {} vs {}", sc.name, eb.total, ea.total);
        assert!(
            ea.per_step.iter().zip(&eb.per_step).all(|(x, y)| x.to_bits() == y.to_bits()),
            "{copy} per step in {}",
            sc.name
        );
        let (ma, mb) = (sc.mc.filters[a].total.mean, sc.mc.filters[b].total.mean);
        assert_eq!(ma.to_bits(), mb.to_bits(), "{copy} Monte Carlo mean in {}: {mb} vs {ma}", sc.name);
    }
    assert!(!out.scenarios.is_empty());
}

const MINIMAX_TRIALS: &str = "trials = 20000";

fn with_filter(text: &str, before: &str, filter: &str) -> String {
    text.patch(before, &format!("{filter}\n{before}"))
}

#[test]
fn a_minimax_filter_from_an_earlier_run_is_the_same_filter() {
    let tmp = TempDir::new();
    run_shipped("minimax_example3", 200, &tmp.path().join("run"));
    let text = with_filter(
        &crate::common::text("minimax_example3").patch(MINIMAX_TRIALS, "trials = 1000"),
        "[[filters]]\nname = \"kalman_elementwise_max\"",
        "[[filters]]\nname = \"old_minimax\"\nfamily = \"linear\"\nfrom_run = \"run\"\nfilter = \"minimax\"\n",
    );
    let exp = load_in(tmp.path(), "again", &text).expect("loads").remove(0);
    let out = filterbench::pipeline::run(&exp, false).expect("runs");
    bit_for_bit(&exp, &out, "minimax", "old_minimax");
    // The worst case over the sets is the same number too: the analyses see one realization.
    let (a, b) = (exp.filter_index("minimax").unwrap(), exp.filter_index("old_minimax").unwrap());
    let worst = |i: usize| out.filters[i].worst.as_ref().map(|w| w.total.to_bits());
    assert_eq!(worst(a), worst(b));
    assert!(worst(a).is_some());
    // Nothing is promised for the copy: the guarantee is the minimax family's.
    assert!(out.filters[a].design.guarantee.is_some() && out.filters[b].design.guarantee.is_none());
    // The manifest of the new run names the two files read, with their digests.
    let files: Vec<_> = exp.inputs.iter().filter(|i| i.key == "filters.old_minimax.from_run").collect();
    assert_eq!(files.len(), 2, "{:?}", exp.inputs);
    assert!(files.iter().all(|f| f.sha256.len() == 64));
}

/// markov_jump with `trials` trials and its slow_chain variant only.
fn markov(trials: usize) -> String {
    let t = crate::common::text("markov_jump").patch("trials = 20000", &format!("trials = {trials}"));
    let i = t.find("[[variants]]").unwrap();
    t[..i].to_string()
}

#[test]
fn a_mode_indexed_markov_jump_filter_is_given_back_bit_for_bit() {
    let tmp = TempDir::new();
    run_shipped("markov_jump", 100, &tmp.path().join("run"));
    // Its per-mode gains K_θ[k], read from the design: the gain form with one table per mode.
    let designed = {
        let exp = load_in(tmp.path(), "designed", &markov(10)).unwrap().remove(0);
        let f = exp.filter_index("mode_dependent").unwrap();
        filterbench::pipeline::design_all(&exp).unwrap().swap_remove(f).design.realization
    };
    assert!(designed.gains[0].len() == 3, "mode-indexed, 3 modes");
    let modes: Vec<String> = (0..3)
        .map(|m| {
            let ks: Vec<String> = designed.gains.iter().map(|g| toml_mat(&g[m].bf)).collect();
            format!("{{ gain = [{}] }}", ks.join(", "))
        })
        .collect();
    let extra = format!(
        "[[filters]]\nname = \"from_run\"\nfamily = \"linear\"\nfrom_run = \"run\"\nfilter = \"mode_dependent\"\nvariant = \"slow_chain\"\n\n\
         [[filters]]\nname = \"per_mode_gains\"\nfamily = \"linear\"\nform = \"predictor\"\nmodes = [{}]\n",
        modes.join(",\n  ")
    );
    let text = with_filter(&markov(600), "[[filters]]\nname = \"mode_dependent_steady\"", &extra);
    let exp = load_in(tmp.path(), "again", &text).expect("loads").remove(0);
    let out = filterbench::pipeline::run(&exp, false).expect("runs");
    bit_for_bit(&exp, &out, "mode_dependent", "from_run");
    bit_for_bit(&exp, &out, "mode_dependent", "per_mode_gains");
    // The common gain on each mode's model: one gain, an empty table per mode.
    let common = {
        let exp = load_in(tmp.path(), "designed", &markov(10)).unwrap().remove(0);
        let f = exp.filter_index("common_gain").unwrap();
        filterbench::pipeline::design_all(&exp).unwrap().swap_remove(f).design.realization
    };
    let ks: Vec<String> = common.gains.iter().map(|g| toml_mat(&g[0].bf)).collect();
    let extra = format!(
        "[[filters]]\nname = \"common_copy\"\nfamily = \"linear\"\nform = \"predictor\"\ngain = [{}]\nmodes = [{{}}, {{}}, {{}}]\n",
        ks.join(", ")
    );
    let text = with_filter(&markov(600), "[[filters]]\nname = \"kalman_mode_averaged\"", &extra);
    let exp = load_in(tmp.path(), "common", &text).expect("loads").remove(0);
    let out = filterbench::pipeline::run(&exp, false).expect("runs");
    bit_for_bit(&exp, &out, "common_gain", "common_copy");
}

/// Runs the experiment `text` (written into `dir`) through the command line and checks the
/// bad-input contract with `needles`.
fn refused(dir: &Path, text: &str, needles: &[&str]) {
    let path = dir.join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let out: PathBuf = dir.join("bad_out");
    let o = Command::new(env!("CARGO_BIN_EXE_filterbench"))
        .args(["experiment", path.to_str().unwrap(), "--trials", "2", "--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    check_failure(&o, needles);
    assert!(!out.exists(), "nothing written");
}

#[test]
fn bad_runs_are_refused_in_one_line() {
    let tmp = TempDir::new();
    let dir = tmp.path();
    run_shipped("minimax_example3", 20, &dir.join("run"));
    run_shipped("markov_jump", 20, &dir.join("markov"));
    let base = crate::common::text("minimax_example3");
    let at = "[[filters]]\nname = \"kalman_elementwise_max\"";
    let mine =
        |keys: &str| with_filter(&base, at, &format!("[[filters]]\nname = \"old\"\nfamily = \"linear\"\n{keys}\n"));
    refused(
        dir,
        &mine("from_run = \"nowhere\"\nfilter = \"minimax\""),
        &["filters.old.from_run", "nowhere", "is not a folder"],
    );
    std::fs::create_dir(dir.join("empty")).unwrap();
    refused(
        dir,
        &mine("from_run = \"empty\"\nfilter = \"minimax\""),
        &["filters.old.from_run", "manifest.json", "not a result folder"],
    );
    refused(
        dir,
        &mine("from_run = \"run\"\nfilter = \"nope\""),
        &[
            "filters.old.filter",
            "run `run` has no filter `nope` (it has: kalman_nominal, minimax, kalman_elementwise_max)",
        ],
    );
    refused(dir, &mine("from_run = \"run\""), &["filters.old.filter", "missing"]);
    refused(
        dir,
        &mine("from_run = \"run\"\nfilter = \"minimax\"\nvariant = \"x\""),
        &["filters.old.from_run", "has no variants"],
    );
    refused(
        dir,
        &mine("from_run = \"run\"\nfilter = \"minimax\"\nAf = [[1.0]]"),
        &["filters.old.Af", "from_run gives the filter's whole realization"],
    );
    refused(
        dir,
        &mine("from_run = \"markov\"\nfilter = \"common_gain\""),
        &["filters.old.from_run", "has variants (slow_chain, fast_chain)"],
    );
    refused(
        dir,
        &mine("from_run = \"markov\"\nfilter = \"common_gain\"\nvariant = \"slow\""),
        &["filters.old.from_run", "has no variant `slow`"],
    );
    // Another plant: other sizes, then the same sizes with one entry of A changed.
    refused(
        dir,
        &mine("from_run = \"markov\"\nfilter = \"common_gain\"\nvariant = \"slow_chain\""),
        &["filters.old.from_run", "designed for another plant: its plant has 2 states, this one 3"],
    );
    let other_a = mine("from_run = \"run\"\nfilter = \"minimax\"").patch("[0.8, 0.2, -0.2]", "[0.8, 0.2, -0.21]");
    refused(dir, &other_a, &["filters.old.from_run", "`run`", "plant's matrices (A, B, C, D, Cz, Dz) differ"]);
    // A folder whose manifest predates the plant record, and one without its gains.
    std::fs::create_dir(dir.join("old")).unwrap();
    let manifest = std::fs::read_to_string(dir.join("run/manifest.json")).unwrap();
    let mut m: serde_json::Value = serde_json::from_str(&manifest).unwrap();
    m.as_object_mut().unwrap().remove("plant");
    std::fs::write(dir.join("old/manifest.json"), m.to_string()).unwrap();
    refused(
        dir,
        &mine("from_run = \"old\"\nfilter = \"minimax\""),
        &["filters.old.from_run", "no `plant` record", "run it again"],
    );
    std::fs::write(dir.join("old/manifest.json"), &manifest).unwrap();
    refused(dir, &mine("from_run = \"old\"\nfilter = \"minimax\""), &["filters.old.from_run", "gains.parquet"]);
}

#[test]
fn per_mode_matrices_are_refused_where_they_do_not_fit() {
    let tmp = TempDir::new();
    let dir = tmp.path();
    let mark = |keys: &str| {
        with_filter(
            &markov(10),
            "[[filters]]\nname = \"kalman_mode_averaged\"",
            &format!("[[filters]]\nname = \"mine\"\nfamily = \"linear\"\n{keys}\n"),
        )
    };
    refused(
        dir,
        &mark("form = \"predictor\"\ngain = [[0.5], [0.1]]"),
        &["filters.mine.gain", "one model per mode", "modes = ["],
    );
    refused(
        dir,
        &mark("form = \"predictor\"\ngain = [[0.5], [0.1]]\nmodes = [{}, {}]"),
        &["filters.mine.modes", "has 2 tables, the plant has 3 modes (left, right, sensor_failed)"],
    );
    refused(
        dir,
        &mark("form = \"predictor\"\nmodes = [{}, {}, { gain = [[0.5], [0.1]] }]"),
        &["filters.mine.gain", "missing"],
    );
    refused(
        dir,
        &mark("form = \"predictor\"\ngain = [[0.5], [0.1]]\nmodes = [{}, {}, { Af = [[1.0]] }]"),
        &["filters.mine.Af", "belongs to the realization form"],
    );
    refused(
        dir,
        &mark("Af = [[0.5, 0], [0, 0.5]]\nBf = [[1], [0]]\nCf = [[1, 0], [0, 1]]\nmodes = [{}, { Af = [[0.5]] }, {}]"),
        &["filters.mine.modes[1].Af", "is 1×1, mode 0's is 2×2"],
    );
    let base = crate::common::text("kalman_baseline");
    let plain = base.clone()
        + "\n[[filters]]\nname = \"mine\"\nfamily = \"linear\"\nform = \"predictor\"\ngain = [[0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]]\nmodes = [{}, {}]\n";
    refused(dir, &plain, &["filters.mine.modes", "need a switching plant"]);
}
