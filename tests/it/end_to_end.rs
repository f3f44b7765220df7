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
