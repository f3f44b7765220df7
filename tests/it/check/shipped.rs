//! The shipped experiments' own expectations (docs/checks.md), checked at reduced trial counts:
//! `filterbench check` exits 0 on kalman_baseline (MC agrees with exact, summed and per step; the
//! Kalman filter consistent at its design covariance under three noise shapes, by NEES and NIS), minimax_example2
//! (the minimax guarantee) and hinf_tradeoff (no trial above an H∞-λ or H2 filter's bound), and
//! aniso_dropout's p = 0.95 variant, in-process (its SDPs are the slow part), keeps every
//! anisotropic γ². A correct implementation fails each at most with probability α = 1e-3 (fixed
//! seeds: the outcome is reproducible).

use std::process::Command;

use polars::prelude::*;

use filterbench::verdict::evaluate::{Rates, Verdict};
use filterbench::verdict::run::{DEFAULT_ALPHA, DEFAULT_BETA};

use crate::common::TempDir;

const BIN: &str = env!("CARGO_BIN_EXE_filterbench");

/// `(kind, test)` pairs of check.parquet's rows.
fn kinds(dir: &std::path::Path) -> Vec<(String, String)> {
    let df = ParquetReader::new(std::fs::File::open(dir.join("check.parquet")).unwrap()).finish().unwrap();
    let (k, t) = (df.column("kind").unwrap().str().unwrap().clone(), df.column("test").unwrap().str().unwrap().clone());
    (0..df.height()).map(|i| (k.get(i).unwrap().to_string(), t.get(i).unwrap().to_string())).collect()
}

#[test]
fn shipped_expectations_hold() {
    let tmp = TempDir::new();
    for (name, must) in [
        (
            "kalman_baseline",
            &[("agrees_with_exact", "step mean vs exact"), ("consistent", "NEES"), ("consistent", "NIS")][..],
        ),
        ("minimax_example2", &[("agrees_with_exact", "mean vs exact"), ("within_guarantee", "mean ≤ guaranteed")]),
        ("hinf_tradeoff", &[("agrees_with_exact", "mean vs exact"), ("within_guarantee", "per-trial violations")]),
    ] {
        let out = tmp.path().join(name);
        let o =
            Command::new(BIN).args(["check", name, "--trials", "2000", "--quiet", "--out"]).arg(&out).output().unwrap();
        assert_eq!(o.status.code(), Some(0), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        let rows = kinds(&out);
        for (k, t) in must {
            assert!(rows.iter().any(|(a, b)| a == k && b == t), "{name}: no `{t}` cell of {k}");
        }
    }
}

#[test]
fn aniso_dropout_keeps_its_guarantees() {
    let exp = crate::common::variant("aniso_dropout", "p=0.95", 500);
    let dir = TempDir::new();
    let check = super::run_and_check(&exp, dir.path(), Rates { alpha: DEFAULT_ALPHA, beta: DEFAULT_BETA });
    let bad: Vec<String> = check
        .cells
        .iter()
        .filter(|c| c.verdict == Verdict::Fails)
        .map(filterbench::verdict::output::describe)
        .collect();
    assert!(bad.is_empty(), "{bad:?}");
    let norms = check.cells.iter().filter(|c| c.test.what == "exact norm² ≤ γ²").count();
    let gains = check.cells.iter().filter(|c| c.test.what == "noise gain ≤ γ²").count();
    // the anisotropic and H∞-suboptimal designs (the H2 one's level 0 is below the file's a)
    assert_eq!(norms, 2);
    assert!(gains > 0);
}

/// Every shipped experiment carries its own expectations (at least `agrees_with_exact`, and
/// `within_guarantee` where a family promises something) and passes `filterbench check` at 1000
/// trials with the default α = 1e-3 (fixed seeds: reproducible; a correct implementation fails
/// each with probability at most α).
#[test]
fn every_shipped_experiment_passes_its_own_check() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.ok()?.path();
            (p.extension()? == "toml").then(|| p.file_stem()?.to_str().map(str::to_string))?
        })
        .collect();
    names.sort();
    let tmp = TempDir::new();
    for name in &names {
        let text = std::fs::read_to_string(dir.join(format!("{name}.toml"))).unwrap();
        assert!(text.contains("kind = \"agrees_with_exact\""), "{name} has no agrees_with_exact expectation");
        let promises =
            ["minimax", "hinf", "h2", "anisotropic"].iter().any(|f| text.contains(&format!("family = \"{f}\"")));
        assert_eq!(
            text.contains("kind = \"within_guarantee\""),
            promises,
            "{name}: within_guarantee where a family promises"
        );
        let out = tmp.path().join(name);
        let o =
            Command::new(BIN).args(["check", name, "--trials", "1000", "--quiet", "--out"]).arg(&out).output().unwrap();
        assert_eq!(o.status.code(), Some(0), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        assert!(kinds(&out).iter().any(|(k, _)| k == "agrees_with_exact"), "{name}: agrees_with_exact cells");
    }
}
