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
    for c in [
        "experiment",
        "scenario",
        "filter",
        "family",
        "params",
        "n_trials",
        "empirical_mean",
        "ci_low",
        "ci_high",
        "exact",
        "guaranteed",
        "guarantee_kind",
        "worst_case",
        "violations",
        "design_seconds",
        "mc_seconds",
    ] {
        assert!(summary.column(c).is_ok(), "summary.parquet has column {c}");
    }
    assert_eq!(summary.height(), 5 * 2);
    let steps = read(&out.join("steps.parquet"));
    for c in ["scenario", "filter", "step", "mse_mean", "mse_ci_low", "mse_ci_high", "exact_mse", "bound"] {
        assert!(steps.column(c).is_ok(), "steps.parquet has column {c}");
    }
    assert_eq!(steps.height(), 5 * 2 * 51);
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
    assert_eq!(summary.height(), 3 * 8, "3 variants × 1 scenario × (2 bases × 2 n × 2 α)");
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
