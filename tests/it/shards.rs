//! Shards and merge (issue 19): `experiment --shard I/N` on every I, then `merge` in a shuffled
//! order, gives the tables of one run bit for bit (timing columns aside, per-trial rows included),
//! for N ∈ {1, 2, 3, 7}; and every shard that does not belong is refused with one line, exit 2.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use polars::prelude::*;

use crate::common::{Patch, TempDir};

const BIN: &str = env!("CARGO_BIN_EXE_filterbench");
/// Columns that measure time, not results.
const TIMING: &[&str] = &["design_seconds", "mc_seconds"];

fn run(args: &[&str]) -> Output {
    Command::new(BIN).args(args).current_dir(env!("CARGO_MANIFEST_DIR")).output().unwrap()
}

fn ok(o: Output) -> Output {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Every column of two tables equal, floats compared as bits (NaN included).
fn same_table(a: &DataFrame, b: &DataFrame, what: &str) {
    assert_eq!(a.get_column_names(), b.get_column_names(), "{what}: columns");
    assert_eq!(a.height(), b.height(), "{what}: rows");
    for name in a.get_column_names() {
        if TIMING.contains(&name.as_str()) {
            continue;
        }
        let (x, y) = (a.column(name).unwrap(), b.column(name).unwrap());
        assert_eq!(x.dtype(), y.dtype(), "{what}.{name}: type");
        if x.dtype() == &DataType::Float64 {
            let bits = |c: &Column| c.f64().unwrap().iter().map(|v| v.map(f64::to_bits)).collect::<Vec<_>>();
            assert_eq!(bits(x), bits(y), "{what}.{name}: bits");
        } else {
            assert!(x.as_materialized_series().equals_missing(y.as_materialized_series()), "{what}.{name}: values");
        }
    }
}

/// The result folders `a` and `b` hold the same tables, bit for bit but for timings.
pub fn same_results(a: &Path, b: &Path) {
    let tables = |d: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".parquet"))
            .collect();
        v.sort();
        v
    };
    let names = tables(a);
    assert_eq!(names, tables(b), "the same tables");
    assert!(names.len() >= 5, "tables: {names:?}");
    let read = |p: PathBuf| ParquetReader::new(std::fs::File::open(p).unwrap()).finish().unwrap();
    for n in &names {
        same_table(&read(a.join(n)), &read(b.join(n)), n);
    }
}

/// Runs `experiment` with `args` as N shards into `dir/N-I`, merges them (argument order rotated
/// and reversed) into `dir/merged-N` and returns that folder.
fn sharded(dir: &Path, experiment: &str, args: &[&str], n: usize) -> PathBuf {
    let mut shards: Vec<PathBuf> = (0..n).map(|i| dir.join(format!("{n}-{i}"))).collect();
    for (i, d) in shards.iter().enumerate() {
        let shard = format!("{i}/{n}");
        let mut a = vec!["experiment", experiment, "--quiet", "--shard", &shard, "--out", s(d)];
        a.extend(args);
        ok(run(&a));
    }
    shards.rotate_left(n / 2);
    shards.reverse();
    let merged = dir.join(format!("merged-{n}"));
    let mut a = vec!["merge", "--quiet", "--out", s(&merged)];
    a.extend(shards.iter().map(|p| s(p)));
    ok(run(&a));
    merged
}

fn merged_equals_one_run(experiment: &str, trials: &str) {
    let tmp = TempDir::new();
    let args = ["--trials", trials, "--per-trial", "--threads", "2"];
    let one = tmp.path().join("one");
    let mut a = vec!["experiment", experiment, "--quiet", "--out", s(&one)];
    a.extend(args);
    ok(run(&a));
    for n in [1, 2, 3, 7] {
        same_results(&one, &sharded(tmp.path(), experiment, &args, n));
    }
    let summary = ParquetReader::new(std::fs::File::open(one.join("summary.parquet")).unwrap()).finish().unwrap();
    let trials_rows = ParquetReader::new(std::fs::File::open(one.join("trials.parquet")).unwrap()).finish().unwrap();
    assert!(summary.column("median").is_ok() && summary.column("p95").is_ok());
    assert_eq!(trials_rows.height(), summary.height() * trials.parse::<usize>().unwrap());
}

#[test]
fn merged_kalman_baseline_is_one_run_bit_for_bit() {
    // 500 trials: 8 blocks (the last partial), so 7 shards of one or two blocks each.
    merged_equals_one_run("kalman_baseline", "500");
}

#[test]
fn merged_aniso_dropout_variant_is_one_run_bit_for_bit() {
    // aniso_dropout's p = 0.95 variant (dropouts, coloured and worst-case inputs, mode-dependent
    // filters), horizon 50 for speed; 450 trials = 8 blocks.
    let text = crate::common::text("aniso_dropout").patch("horizon = 200", "horizon = 50");
    let text = text[..text.find("[[variants]]").unwrap()].to_string()
        + "[[variants]]\nname = \"p=0.95\"\nplant = { arrival = 0.95 }\n";
    let tmp = TempDir::new();
    let file = tmp.path().join("aniso_dropout.toml");
    std::fs::write(&file, text).unwrap();
    merged_equals_one_run(s(&file), "450");
}

/// A merge that must be refused: exit 2, one line containing every needle, no output folder.
fn refused(shards: &[&Path], out: &Path, needles: &[&str]) {
    let mut a = vec!["merge", "--quiet", "--out", s(out)];
    a.extend(shards.iter().map(|p| s(p)));
    let o = run(&a);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "exit 2: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    for n in needles {
        assert!(err.contains(n), "mentions {n:?}: {err}");
    }
    assert!(!out.exists(), "nothing written");
}

#[test]
fn merge_refuses_shards_that_do_not_belong() {
    let tmp = TempDir::new();
    let t = tmp.path();
    let shard = |name: &str, spec: &str, extra: &[&str]| {
        let d = t.join(name);
        let mut a = vec!["experiment", "kalman_baseline", "--quiet", "--shard", spec, "--out", s(&d)];
        // 200 trials (4 blocks) unless the shard is to differ in its count.
        a.extend(if extra.contains(&"--trials") { extra.to_vec() } else { [&["--trials", "200"], extra].concat() });
        ok(run(&a));
        d
    };
    let (a0, a1, a2) = (shard("a0", "0/3", &[]), shard("a1", "1/3", &[]), shard("a2", "2/3", &[]));
    let out = t.join("merged");
    let other_seed = shard("seed", "1/3", &["--seed", "5"]);
    refused(&[&a0, &other_seed, &a2], &out, &["seed", "shard", s(&other_seed)]);
    let other_trials = shard("trials", "1/3", &["--trials", "300"]);
    refused(&[&a0, &other_trials, &a2], &out, &["trial count", s(&other_trials)]);
    let other_n = shard("n", "1/4", &[]);
    refused(&[&a0, &other_n, &a2], &out, &["shard count", s(&other_n)]);
    // Another experiment file under the same name.
    let file = t.join("kalman_baseline.toml");
    std::fs::write(&file, crate::common::text("kalman_baseline").patch("horizon = 50", "horizon = 40")).unwrap();
    let d = t.join("exp");
    ok(run(&["experiment", s(&file), "--quiet", "--trials", "200", "--shard", "1/3", "--out", s(&d)]));
    refused(&[&a0, &d, &a2], &out, &["experiment", s(&d)]);
    refused(&[&a0, &a2], &out, &["1/3", "missing"]);
    refused(&[&a0, &a1, &a1, &a2], &out, &["repeats shard 1/3", s(&a1)]);
    refused(&[&a0, &a1, &t.join("nowhere")], &out, &["nowhere", "not a partial result"]);
    // A partial written by another version, or whose designs differ from this machine's.
    let edit = |from_dir: &Path, name: &str, from: &str, to: &str| {
        let d = t.join(name);
        std::fs::create_dir_all(&d).unwrap();
        for f in std::fs::read_dir(from_dir).unwrap().flatten() {
            std::fs::copy(f.path(), d.join(f.file_name())).unwrap();
        }
        let meta = std::fs::read_to_string(d.join("partial.json")).unwrap();
        std::fs::write(d.join("partial.json"), meta.patch(from, to)).unwrap();
        d
    };
    let old = edit(&a1, "version", "\"filterbench_version\": \"", "\"filterbench_version\": \"0.0.1-");
    refused(&[&a0, &old, &a2], &out, &["filterbench 0.0.1-", s(&old)]);
    let meta = std::fs::read_to_string(a0.join("partial.json")).unwrap();
    let fp = meta.split("\"fingerprints\": [\n    \"").nth(1).unwrap()[..64].to_string();
    let forged: String = fp.chars().rev().collect();
    let f1 = edit(&a1, "f1", &fp, &forged);
    refused(&[&a0, &f1, &a2], &out, &["design fingerprint", s(&f1)]);
    // All shards agree, but not with the designs made again here.
    let (f0, f2) = (edit(&a0, "f0", &fp, &forged), edit(&a2, "f2", &fp, &forged));
    refused(&[&f0, &f1, &f2], &out, &["fingerprint", &forged]);
    // All shards agree, but their trial count is not what their file and overrides build.
    let (from, to) = ("\"overrides\": {\n    \"trials\": 200", "\"overrides\": {\n    \"trials\": 300");
    let o: Vec<PathBuf> =
        [&a0, &a1, &a2].iter().enumerate().map(|(i, d)| edit(d, &format!("o{i}"), from, to)).collect();
    refused(&[&o[0], &o[1], &o[2]], &out, &["not its experiment file's with its overrides", s(&o[0])]);
    let o = run(&["merge", "--quiet", "--out", s(&a1), s(&a0), s(&a1), s(&a2)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!((o.status.code(), err.trim_end().lines().count()), (Some(2), 1), "{err}");
    assert!(err.contains("being merged") && a1.join("partial.json").is_file(), "the shard kept: {err}");
    // A shard index that is not one.
    for spec in ["3/3", "1/0", "x/2", "2"] {
        let o = run(&["experiment", "kalman_baseline", "--quiet", "--shard", spec, "--out", s(&t.join("bad"))]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!((o.status.code(), err.trim_end().lines().count()), (Some(2), 1), "{spec}: {err}");
        assert!(err.contains("--shard") && !t.join("bad").exists(), "{spec}: {err}");
    }
    // Every real shard together merges.
    ok(run(&["merge", "--quiet", "--out", s(&out), s(&a2), s(&a0), s(&a1)]));
}

/// For tools/slurm/selftest.sh: `FB_ONE=DIR FB_MERGED=DIR cargo test --release -- --ignored
/// shards::slurm_result_equals_one_run` compares the Slurm run's merged folder with a one-machine run.
#[test]
#[ignore = "run by tools/slurm/selftest.sh with FB_ONE and FB_MERGED"]
fn slurm_result_equals_one_run() {
    let dir = |k: &str| PathBuf::from(std::env::var(k).unwrap_or_else(|_| panic!("{k} is not set")));
    same_results(&dir("FB_ONE"), &dir("FB_MERGED"));
}

/// The scale measurement of issue 19 (docs/partial-results.md): `FB_SCALE_DIR=D FB_SCALE_SHARDS=N
/// FB_SCALE_TRIALS=T cargo test --release -- --ignored shards::generate_aniso_dropout_shards` writes
/// shards 0..N-1 of aniso_dropout with T trials into D/shard-I, through the code `--shard I/N` runs
/// (the filters designed once, not N times), for `filterbench merge` to be timed on them.
#[test]
#[ignore = "a measurement: run by hand with FB_SCALE_DIR, FB_SCALE_SHARDS and FB_SCALE_TRIALS"]
fn generate_aniso_dropout_shards() {
    let var = |k: &str| std::env::var(k).unwrap_or_else(|_| panic!("{k} is not set"));
    let (dir, n, trials) = (PathBuf::from(var("FB_SCALE_DIR")), var("FB_SCALE_SHARDS"), var("FB_SCALE_TRIALS"));
    let (n, trials): (u64, usize) = (n.parse().unwrap(), trials.parse().unwrap());
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/aniso_dropout.toml");
    let overrides = filterbench::config::Overrides { trials: Some(trials), ..Default::default() };
    let exps = filterbench::config::load_variants(&path, &overrides).unwrap();
    let which: Vec<u64> = (0..n).collect();
    filterbench::pipeline::shards::run_shards(&exps, n, &which, &overrides, |i| {
        let d = dir.join(format!("shard-{i}"));
        std::fs::create_dir_all(&d).unwrap();
        d
    })
    .unwrap();
}
