//! `matches_baseline` through the binary: a run of the same file at another seed matches its stored
//! baseline (exact and design values identical, Monte Carlo means within noise: exit 0); a baseline
//! whose exact values are 2 % higher fails, naming those cells (exit 1); without a baseline folder
//! the check is refused (exit 2).

use std::process::Command;

use super::SMALL;
use crate::common::TempDir;
use crate::compare::{copy, read, write};

const BIN: &str = env!("CARGO_BIN_EXE_filterbench");

const EXPECT: &str = "[[expect]]\nkind = \"matches_baseline\"\n";

#[test]
fn a_run_matches_its_baseline_and_a_shifted_one_fails() {
    let tmp = TempDir::new();
    let dir = tmp.path();
    let file = dir.join("small.toml");
    std::fs::write(&file, SMALL.replace("EXPECT", EXPECT)).unwrap();
    let f = file.to_str().unwrap();
    let base = dir.join("base");
    let o = Command::new(BIN).args(["experiment", f, "--seed", "1", "--quiet", "--out"]).arg(&base).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let check = |baseline: &std::path::Path, out: &str| {
        Command::new(BIN)
            .args(["check", f, "--seed", "2", "--out"])
            .arg(dir.join(out))
            .arg("--baseline")
            .arg(baseline)
            .output()
            .unwrap()
    };
    let o = check(&base, "again");
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{text}{}", String::from_utf8_lossy(&o.stderr));
    assert!(text.contains("matches_baseline"), "{text}");
    // The cells: one per compared value, the Monte Carlo ones tested by z in Holm's family.
    let cells = read(&dir.join("again/check.parquet"));
    let method = cells.column("method").unwrap().str().unwrap();
    assert!(method.iter().any(|m| m.is_some_and(|m| m.starts_with("z "))), "Monte Carlo means tested by z");
    assert!(method.iter().any(|m| m == Some("certain")), "exact values compared certainly");

    // The negative control: every exact value of the baseline 2 % higher.
    let shifted = dir.join("shifted");
    copy(&base, &shifted);
    let mut df = read(&shifted.join("summary.parquet"));
    let exact = df.column("exact").unwrap().f64().unwrap() * 1.02;
    df.with_column(polars::prelude::IntoSeries::into_series(exact).into()).unwrap();
    write(&shifted.join("summary.parquet"), &mut df);
    let o = check(&shifted, "against_shifted");
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{text}");
    let cells = read(&dir.join("against_shifted/check.parquet"));
    let failing: Vec<String> = cells
        .column("verdict")
        .unwrap()
        .str()
        .unwrap()
        .iter()
        .zip(cells.column("test").unwrap().str().unwrap().iter())
        .filter(|(v, _)| *v == Some("fails"))
        .map(|(_, t)| t.unwrap_or_default().to_string())
        .collect();
    assert_eq!(failing.len(), df.height(), "one failing cell per summary row: {failing:?}");
    assert!(failing.iter().all(|t| t.starts_with("summary.exact vs baseline")), "{failing:?}");

    // No baseline folder: refused, nothing written.
    let o = Command::new(BIN).args(["check", f, "--quiet", "--out"]).arg(dir.join("none")).output().unwrap();
    crate::bad_input::check_failure(&o, &["--baseline", "matches_baseline expectation needs the baseline folder"]);
    assert!(!dir.join("none").exists());
}
