//! `experiment` writes the whole output contract, and the tables have the named columns.

use std::process::Command;

use polars::prelude::*;

const BIN: &str = env!("CARGO_BIN_EXE_filterbench");

fn read(path: &std::path::Path) -> DataFrame {
    ParquetReader::new(std::fs::File::open(path).unwrap()).finish().unwrap()
}

#[test]
fn kalman_baseline_writes_the_output_contract() {
    let tmp = crate::common::TempDir::new();
    let out = tmp.path().join("kb");
    let o = Command::new(BIN)
        .args(["experiment", "kalman_baseline", "--trials", "500", "--threads", "2", "--out", out.to_str().unwrap()])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("kalman_nominal") && stdout.contains("exact"), "console table: {stdout}");
    for f in ["summary.parquet", "steps.parquet", "gains.parquet", "paired.parquet", "manifest.json", "recording.rrd"] {
        let p = out.join(f);
        assert!(p.is_file() && std::fs::metadata(&p).unwrap().len() > 0, "{f} written");
    }
    let summary = read(&out.join("summary.parquet"));
    assert_eq!(summary.height(), 5 * 2);
    assert_eq!(names(&summary), SUMMARY_COLUMNS, "summary.parquet's columns, in the documented order");
    summary_values_are_sane(&summary, 500);
    let steps = read(&out.join("steps.parquet"));
    assert_eq!(names(&steps), STEPS_COLUMNS, "steps.parquet's columns");
    assert_eq!(steps.height(), 5 * 2 * 51);
    let (m, lo, hi) = (f64s(&steps, "mse_mean"), f64s(&steps, "mse_ci_low"), f64s(&steps, "mse_ci_high"));
    for i in 0..steps.height() {
        let (m, lo, hi) = (m[i].unwrap(), lo[i].unwrap(), hi[i].unwrap());
        assert!(lo <= m && m <= hi && m >= 0.0, "steps row {i}: {lo} ≤ {m} ≤ {hi}");
    }
    assert!(f64s(&steps, "bound").iter().all(Option::is_none), "a Kalman filter guarantees no per-step bound");
    assert!(f64s(&steps, "claimed").iter().all(Option::is_some), "every filter here claims its error");
    let gains = read(&out.join("gains.parquet"));
    for c in ["filter", "step", "mode", "matrix", "row", "col", "value"] {
        assert!(gains.column(c).is_ok(), "gains.parquet has column {c}");
    }
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["trials"], 500);
    assert_eq!(manifest["threads"], 2);
    let rrd = std::fs::read(out.join("recording.rrd")).unwrap();
    assert!(rrd.starts_with(b"RRF2"), "an .rrd file starts with Rerun's magic bytes");
}

/// Every column of summary.parquet, in order: a new or renamed column must be documented here and
/// in the README.
const SUMMARY_COLUMNS: [&str; 48] = [
    "experiment",
    "variant",
    "scenario",
    "covariance",
    "shape",
    "disturbance",
    "filter",
    "family",
    "params",
    "n_trials",
    "empirical_mean",
    "std_error",
    "ci_low",
    "ci_high",
    "exact",
    "exact_terminal",
    "guaranteed",
    "guarantee_kind",
    "claimed",
    "consistency",
    "nees_exact",
    "nees_empirical",
    "nis_exact",
    "nis_empirical",
    "generalized_h2_norm_sq",
    "worst_case",
    "worst_case_psd",
    "violations",
    "ratio_bound",
    "max_ratio",
    "input_power",
    "input_anisotropy",
    "gain_empirical",
    "gain_ci_low",
    "gain_ci_high",
    "gain_exact",
    "deterministic_error",
    "gain_exact_noise",
    "anisotropic_norm_sq",
    "h2_norm_sq",
    "hinf_norm_sq",
    "guaranteed_gain",
    "design_gain",
    "guarantee_anisotropy",
    "theorem1_gain",
    "guarantee_applies",
    "design_seconds",
    "mc_seconds",
];

const STEPS_COLUMNS: [&str; 24] = [
    "experiment",
    "variant",
    "scenario",
    "filter",
    "step",
    "mse_mean",
    "mse_ci_low",
    "mse_ci_high",
    "mse_std_error",
    "exact_mse",
    "bound",
    "claimed",
    "nees_exact",
    "nees_mean",
    "nees_ci_low",
    "nees_ci_high",
    "nees_std_error",
    "nees_rank",
    "nis_exact",
    "nis_mean",
    "nis_ci_low",
    "nis_ci_high",
    "nis_std_error",
    "nis_rank",
];

fn names(df: &DataFrame) -> Vec<String> {
    df.get_column_names().iter().map(|s| s.to_string()).collect()
}

pub(crate) fn f64s(df: &DataFrame, c: &str) -> Vec<Option<f64>> {
    let s = df
        .column(c)
        .unwrap_or_else(|_| panic!("column {c}"))
        .as_materialized_series()
        .cast(&DataType::Float64)
        .unwrap();
    let ca = s.f64().unwrap();
    (0..ca.len()).map(|i| ca.get(i)).collect()
}

/// kalman_baseline's summary, value by value: the interval around the mean, the trial count, the
/// exact value present, and nulls exactly where the README says (no guarantee, no per-trial bound,
/// no anisotropy level) and values where it promises them (the worst case over the sets).
fn summary_values_are_sane(summary: &DataFrame, trials: u64) {
    let (mean, lo, hi, se) = (
        f64s(summary, "empirical_mean"),
        f64s(summary, "ci_low"),
        f64s(summary, "ci_high"),
        f64s(summary, "std_error"),
    );
    let n = f64s(summary, "n_trials");
    for i in 0..summary.height() {
        let (m, l, h, s) = (mean[i].unwrap(), lo[i].unwrap(), hi[i].unwrap(), se[i].unwrap());
        assert!(l < m && m < h && s > 0.0, "row {i}: {l} < {m} < {h}, se {s}");
        assert!(
            ((h - l) / (2.0 * 1.959_963_984_540_054) - s).abs() <= 1e-9 * s,
            "row {i}: the 95 % interval is ±1.96 se"
        );
        assert_eq!(n[i], Some(trials as f64), "row {i}: n_trials");
    }
    for c in [
        "exact",
        "exact_terminal",
        "claimed",
        "consistency",
        "nees_exact",
        "nees_empirical",
        "nis_exact",
        "nis_empirical",
        "generalized_h2_norm_sq",
        "worst_case",
        "input_power",
    ] {
        assert!(f64s(summary, c).iter().all(Option::is_some), "{c} is given in every row of kalman_baseline");
    }
    for c in ["guaranteed", "violations", "ratio_bound", "max_ratio", "anisotropic_norm_sq", "guaranteed_gain"] {
        assert!(
            f64s(summary, c).iter().all(Option::is_none),
            "{c} is null for Kalman filters without anisotropy level"
        );
    }
    let (exact, claimed, consistency) =
        (f64s(summary, "exact"), f64s(summary, "claimed"), f64s(summary, "consistency"));
    for i in 0..summary.height() {
        let r = exact[i].unwrap() / claimed[i].unwrap();
        assert!((consistency[i].unwrap() - r).abs() <= 1e-12 * r, "row {i}: consistency = exact / claimed");
    }
}

#[test]
fn variants_share_one_set_of_tables_and_one_recording() {
    let tmp = crate::common::TempDir::new();
    let out = tmp.path().join("mj");
    let o = Command::new(BIN)
        .args(["experiment", "markov_jump", "--trials", "200", "--quiet", "--out", out.to_str().unwrap()])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = read(&out.join("summary.parquet"));
    let col = summary.column("variant").unwrap().str().unwrap().clone();
    let mut variants: Vec<String> = (0..col.len()).map(|i| col.get(i).unwrap().to_string()).collect();
    variants.sort();
    variants.dedup();
    assert_eq!(variants, ["fast_chain", "slow_chain"]);
    assert_eq!(summary.height(), 2 * 4 * 4, "2 variants × 4 scenarios × 4 filters");
    // Mode-indexed gains carry their mode; the mode-averaged Kalman filter's have none.
    let gains = read(&out.join("gains.parquet"));
    let modes = gains.column("mode").unwrap().u32().unwrap().clone();
    let modes: Vec<Option<u32>> = (0..modes.len()).map(|i| modes.get(i)).collect();
    assert!(modes.contains(&Some(2)), "three modes' gains");
    assert!(modes.contains(&None), "gains of a filter that does not switch");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["variants"].as_array().unwrap().len(), 2);
    let loss = manifest["variants"][0]["filters"][2]["diagnostics"]["loss_percent"].as_f64().unwrap();
    assert!(loss > 0.0, "the common gain loses against mode-dependent gains");
}

#[test]
fn galerkin_sweep_labels_its_rows_and_omits_zero_gains() {
    let tmp = crate::common::TempDir::new();
    let file = tmp.path().join("string.toml");
    std::fs::write(&file, crate::common::small_string()).unwrap();
    let out = tmp.path().join("gs");
    let o = Command::new(BIN)
        .args(["experiment", file.to_str().unwrap(), "--trials", "50", "--quiet", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = read(&out.join("summary.parquet"));
    assert_eq!(summary.height(), 4 * 8, "4 variants × 1 scenario × (2 bases × 2 n × 2 α)");
    // `params` holds each swept filter's parameters as JSON, so the surface can be pivoted.
    let (filters, params) =
        (summary.column("filter").unwrap().str().unwrap(), summary.column("params").unwrap().str().unwrap());
    for i in 0..summary.height() {
        let p: serde_json::Value = serde_json::from_str(params.get(i).unwrap()).unwrap();
        let (head, alpha) = filters.get(i).unwrap().split_once("_alpha").unwrap();
        assert_eq!(head, format!("{}_n{}", p["basis"].as_str().unwrap(), p["n"]));
        assert_eq!(alpha.parse::<f64>().unwrap(), p["alpha"].as_f64().unwrap(), "the name and the parameters agree");
    }
    let gains = read(&out.join("gains.parquet"));
    let values = gains.column("value").unwrap().f64().unwrap();
    assert!((0..values.len()).all(|i| values.get(i) != Some(0.0)), "exact zeros are left out");
    assert!(std::fs::metadata(out.join("recording.rrd")).unwrap().len() > 0);
}
