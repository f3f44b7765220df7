//! `filterbench compare OLD NEW` (issue 27, item 4; docs/regression-tests.md "Comparing two runs"):
//! two runs of minimax_example3 at 400 trials. The same seed gives every cell identical (exit 0);
//! seeds 11 and 12 give every deterministic cell identical and the Monte Carlo means within noise
//! (exit 0); a baseline whose `exact` is shifted by 2 %, or one Monte Carlo mean shifted by 10
//! combined standard errors, is changed beyond noise (exit 1, the cells named); another experiment
//! or a folder that is not a result is refused (exit 2, one line). And the two-sample test's
//! calibration: 400 independent seed pairs of a one-filter experiment, in process.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use filterbench::verdict::compare::{CompareOptions, Comparison, Kind, Status, compare_folders};
use polars::prelude::*;

use crate::bad_input::check_failure;
use crate::common::TempDir;

const BIN: &str = env!("CARGO_BIN_EXE_filterbench");

fn run(args: &[&str]) -> Output {
    Command::new(BIN).args(args).current_dir(env!("CARGO_MANIFEST_DIR")).output().unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// minimax_example3 (a minimax design by Algorithm 1, so gains and a design trace too) at 400 trials.
fn example3(dir: &Path, name: &str, seed: u64) -> PathBuf {
    let out = dir.join(name);
    let seed = seed.to_string();
    let o = run(&["experiment", "minimax_example3", "--trials", "400", "--seed", &seed, "--quiet", "--out", s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out
}

pub(crate) fn copy(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

pub(crate) fn read(path: &Path) -> DataFrame {
    ParquetReader::new(std::fs::File::open(path).unwrap()).finish().unwrap()
}

pub(crate) fn write(path: &Path, df: &mut DataFrame) {
    ParquetWriter::new(std::fs::File::create(path).unwrap()).finish(df).unwrap();
}

fn compare(old: &Path, new: &Path) -> Comparison {
    compare_folders(old, new, &CompareOptions::default()).unwrap()
}

fn status_of(c: &Comparison, kind: Kind) -> Vec<Status> {
    c.cells.iter().filter(|x| x.kind == kind).map(|x| x.status).collect()
}

#[test]
fn same_seed_identical_other_seed_within_noise() {
    let tmp = TempDir::new();
    let (a, b, c) = (example3(tmp.path(), "a", 11), example3(tmp.path(), "b", 11), example3(tmp.path(), "c", 12));

    let same = compare(&a, &b);
    assert!(same.common_draws);
    assert!(same.count(Status::Identical) > 0);
    for st in [Status::WithinNoise, Status::Changed, Status::NotTested] {
        assert_eq!(same.count(st), 0, "same seed: no cell {}", st.name());
    }
    let o = run(&["compare", s(&a), s(&b)]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stdout));

    // Seeds 11 and 12: every design and exact value identical; every Monte Carlo mean moved, none
    // beyond noise. A false alarm has probability ≤ α = 1e-3 (Holm), and this pair is fixed.
    let other = compare(&a, &c);
    assert!(!other.common_draws);
    assert!(other.tested_cells > 50, "{} Monte Carlo cells", other.tested_cells);
    for col in &other.columns {
        match col.kind {
            Some(Kind::Deterministic | Kind::Label) => {
                assert_eq!(col.identical, col.cells, "{}.{} identical", col.table, col.column)
            }
            Some(Kind::MonteCarlo) => {
                assert_eq!(col.changed, 0, "{}.{}: {:?}", col.table, col.column, col.max_abs_z);
                assert!(col.cells == 0 || col.within_noise > 0, "{}.{} moved", col.table, col.column);
            }
            Some(Kind::Presence) => panic!("{}.{}: in one folder only", col.table, col.column),
            _ => {}
        }
    }
    assert!(other.columns.iter().any(|c| c.table == "gains" && c.identical > 0));
    assert!(other.columns.iter().any(|c| c.table == "design_trace" && c.identical > 0));
    let o = run(&["compare", s(&a), s(&c)]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stdout));
    assert!(String::from_utf8_lossy(&o.stdout).contains("nothing changed beyond noise"));
}

#[test]
fn shifted_exact_and_shifted_mean_are_changes() {
    let tmp = TempDir::new();
    let (a, c) = (example3(tmp.path(), "a", 11), example3(tmp.path(), "c", 12));

    // A baseline whose exact values are 2 % higher: far beyond 1e-8 relative.
    let shifted = tmp.path().join("shifted");
    copy(&a, &shifted);
    let mut df = read(&shifted.join("summary.parquet"));
    let exact = df.column("exact").unwrap().f64().unwrap() * 1.02;
    df.with_column(exact.into_series().into()).unwrap();
    write(&shifted.join("summary.parquet"), &mut df);
    let cmp = compare(&shifted, &a);
    let changed: Vec<_> = cmp.changed_cells().collect();
    assert_eq!(changed.len(), df.height(), "one changed cell per summary row");
    for cell in &changed {
        assert_eq!((cell.table, cell.column.as_str()), ("summary", "exact"));
        let r = cell.rel_diff.unwrap();
        assert!((r - 0.02 / 1.02).abs() < 1e-12, "relative difference {r}");
    }
    let o = run(&["compare", s(&shifted), s(&a)]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}");
    assert!(out.contains("summary exact scenario=") && out.contains("CHANGED"), "{out}");

    // Moved by 1e-10 relative, below the default tolerance of 1e-8: within noise, exit 0.
    let nudged = tmp.path().join("nudged");
    copy(&a, &nudged);
    let mut df = read(&nudged.join("summary.parquet"));
    let exact = df.column("exact").unwrap().f64().unwrap() * (1.0 + 1e-10);
    df.with_column(exact.into_series().into()).unwrap();
    write(&nudged.join("summary.parquet"), &mut df);
    let cmp = compare(&a, &nudged);
    assert!(!cmp.changed());
    let col = cmp.columns.iter().find(|c| c.table == "summary" && c.column == "exact").unwrap();
    assert_eq!((col.within_noise, col.cells), (df.height(), df.height()));
    assert_eq!(cmp.count(Status::WithinNoise), df.height());
    assert_eq!(run(&["compare", s(&a), s(&nudged)]).status.code(), Some(0));

    // One Monte Carlo mean moved by 10 combined standard errors against a run on other draws.
    let moved = tmp.path().join("moved");
    copy(&c, &moved);
    let (sa, mut dm) = (read(&a.join("summary.parquet")), read(&moved.join("summary.parquet")));
    let se = |d: &DataFrame| d.column("std_error").unwrap().f64().unwrap().get(0).unwrap();
    let shift = 10.0 * (se(&sa).powi(2) + se(&dm).powi(2)).sqrt();
    let mean: Vec<f64> = dm.column("empirical_mean").unwrap().f64().unwrap().into_no_null_iter().collect();
    let mean: Vec<f64> = mean.iter().enumerate().map(|(i, m)| if i == 0 { m + shift } else { *m }).collect();
    dm.with_column(Column::new("empirical_mean".into(), mean)).unwrap();
    write(&moved.join("summary.parquet"), &mut dm);
    let cmp = compare(&a, &moved);
    let changed: Vec<_> = cmp.changed_cells().collect();
    assert_eq!(changed.len(), 1, "{changed:?}");
    let cell = changed[0];
    assert_eq!((cell.table, cell.column.as_str()), ("summary", "empirical_mean"));
    let scenario = sa.column("scenario").unwrap().str().unwrap().get(0).unwrap();
    assert_eq!(cell.scenario.as_deref(), Some(scenario));
    // z = 10 plus the two runs' own difference in combined standard errors (|z| < 3.3 for every
    // unshifted mean, see the test above).
    assert!(cell.z.unwrap() > 6.0, "z = {:?}", cell.z);
    assert!(status_of(&cmp, Kind::Deterministic).iter().all(|s| *s == Status::Identical));
    let json = tmp.path().join("cmp.json");
    let o = run(&["compare", s(&a), s(&moved), "--json", s(&json)]);
    assert_eq!(o.status.code(), Some(1), "{}", String::from_utf8_lossy(&o.stdout));
    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let cells = doc["cells"].as_array().unwrap();
    let hit: Vec<_> = cells.iter().filter(|c| c["status"] == "changed beyond noise").collect();
    assert_eq!(hit.len(), 1);
    assert_eq!(hit[0]["column"], "empirical_mean");
    assert_eq!(hit[0]["scenario"], scenario);
}

#[test]
fn other_experiments_and_non_results_are_refused() {
    let tmp = TempDir::new();
    let a = example3(tmp.path(), "a", 11);
    let kb = tmp.path().join("kb");
    let o = run(&["experiment", "kalman_baseline", "--trials", "128", "--quiet", "--out", s(&kb)]);
    assert!(o.status.success());
    let o = run(&["compare", s(&a), s(&kb)]);
    check_failure(&o, &["manifest.json", "not the same experiment", "`minimax_example3`", "`kalman_baseline`"]);

    // The same experiment name with a filter renamed in the manifest.
    let renamed = tmp.path().join("renamed");
    copy(&a, &renamed);
    let m = std::fs::read_to_string(renamed.join("manifest.json")).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&m).unwrap();
    let first = doc["filters"][0]["name"].as_str().unwrap().to_string();
    doc["filters"][0]["name"] = "someone_else".into();
    std::fs::write(renamed.join("manifest.json"), doc.to_string()).unwrap();
    let o = run(&["compare", s(&a), s(&renamed)]);
    check_failure(&o, &["filters differ", &format!("only in OLD: `{first}`"), "only in NEW: `someone_else`"]);

    let empty = tmp.path().join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    check_failure(&run(&["compare", s(&empty), s(&a)]), &["empty", "not a result folder", "manifest.json"]);
    check_failure(&run(&["compare", s(&a), "/no/such/folder"]), &["/no/such/folder", "no such folder"]);
    let file = a.join("summary.parquet");
    check_failure(&run(&["compare", s(&file), s(&a)]), &["summary.parquet", "it is a file"]);
    let shard = tmp.path().join("shard");
    let o =
        run(&["experiment", "minimax_example3", "--trials", "400", "--shard", "0/2", "--quiet", "--out", s(&shard)]);
    assert!(o.status.success());
    check_failure(&run(&["compare", s(&a), s(&shard)]), &["shard", "merge"]);
    check_failure(&run(&["compare", s(&a), s(&a), "--alpha", "1.5"]), &["--alpha"]);
    let broken = tmp.path().join("broken");
    copy(&a, &broken);
    std::fs::write(broken.join("steps.parquet"), b"not parquet").unwrap();
    check_failure(&run(&["compare", s(&a), s(&broken)]), &["steps.parquet", "not a readable table"]);
}

/// One Kalman filter on a scalar plant, N = 5: small enough for 800 runs in a few seconds.
const TINY: &str = r#"
description = "compare calibration: one Kalman filter, one scenario"
seed = 1
trials = 256
pattern = "filtering"
sample_trajectories = 0

[plant]
horizon = 5
first_measurement = 1
noise_blocks = ["process", "measurement"]
A = [[0.9]]
B = [[1.0, 0.0]]
C = [[1.0]]
D = [[0.0, 1.0]]

[nominal]
x0 = [[1.0]]
process = [[0.5]]
measurement = [[1.0]]

[[filters]]
name = "kalman"
family = "kalman"
design = { kind = "nominal" }

[[scenarios]]
name = "nominal"
covariance = { kind = "nominal" }
shape = { kind = "gaussian" }
"#;

/// The two-sample test's false-alarm rate, measured: 400 pairs of runs of the same filter on
/// independent draws (seeds 1000 … 1799, each used once, so the pairs are independent), 256 trials
/// each, compared in process at α = 0.1. Per cell (the summed error's mean, one per pair) the
/// rate of |z| > z₀.₉₅ must be 0.1 within 4σ of its binomial count, 40 ± 4·6 (σ = √(400·0.1·0.9)
/// = 6): this checks the combined standard error. Per comparison (Holm over the 18 Monte Carlo
/// cells: the sum, 6 per-step MSEs, 6 per-step NEES, 5 per-step NIS from the first measurement on)
/// it must be at most α, within the same 4σ.
#[test]
fn two_sample_false_alarm_rate_is_calibrated() {
    use filterbench::verdict::stats::{Sided, critical_z};
    use filterbench::{pipeline, report};
    let tmp = TempDir::new();
    let path = tmp.path().join("tiny.toml");
    std::fs::write(&path, TINY).unwrap();
    let base = filterbench::config::load(&path).unwrap();
    let opts = CompareOptions { alpha: 0.1, ..Default::default() };
    let z_crit = critical_z(0.1, Sided::TwoSided);
    let pairs = 400u64;
    let (mut cell_alarms, mut whole_alarms, mut tested) = (0u64, 0u64, 0);
    let start = std::time::Instant::now();
    for i in 0..pairs {
        let dirs: Vec<PathBuf> = (0..2)
            .map(|k| {
                let mut e = base.clone();
                e.seed = 1000 + 2 * i + k;
                let out = pipeline::run(&e, false).unwrap();
                let d = tmp.path().join(format!("{i}-{k}"));
                std::fs::create_dir_all(&d).unwrap();
                report::parquet::write_tables(&[(&e, &out)], &d).unwrap();
                report::manifest::write(&[(&e, &out)], &Default::default(), &d.join("manifest.json")).unwrap();
                d
            })
            .collect();
        let c = compare_folders(&dirs[0], &dirs[1], &opts).unwrap();
        assert!(!c.common_draws);
        tested = c.tested_cells;
        let sum = c.cells.iter().find(|x| x.table == "summary" && x.column == "empirical_mean").unwrap();
        cell_alarms += u64::from(sum.z.unwrap().abs() > z_crit);
        whole_alarms += u64::from(c.changed());
        for d in dirs {
            std::fs::remove_dir_all(d).unwrap();
        }
    }
    let n = pairs as f64;
    let sigma = (n * 0.1 * 0.9).sqrt();
    eprintln!(
        "compare calibration: {pairs} pairs in {:.1} s; per cell {cell_alarms}/{pairs} = {:.3} beyond z = {z_crit:.3}; \
         per comparison ({tested} cells, Holm at α = 0.1) {whole_alarms}/{pairs} = {:.3}",
        start.elapsed().as_secs_f64(),
        cell_alarms as f64 / n,
        whole_alarms as f64 / n
    );
    assert_eq!(tested, 18);
    assert!((cell_alarms as f64 - 0.1 * n).abs() <= 4.0 * sigma, "per-cell false alarms {cell_alarms} of {pairs}");
    assert!(whole_alarms as f64 <= 0.1 * n + 4.0 * sigma, "per-comparison false alarms {whole_alarms} of {pairs}");
}
