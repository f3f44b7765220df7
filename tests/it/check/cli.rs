//! `filterbench check` through the binary: exit 0 with a JUnit report that parses (quick-junit's
//! own reader) and has one test case per row of check.parquet; the negative controls (a Kalman
//! filter designed with its process covariance ×4 is not `consistent`; `better` with its filters
//! swapped) exit 1; `--results` evaluates the written folder to the same cells; `--min-detectable`
//! chooses the trials; bad input exits 2 with one line naming the key and writes nothing.

use std::path::Path;
use std::process::{Command, Output};

use polars::prelude::*;

use super::SMALL;
use crate::common::TempDir;
use crate::output_safety::refused;

const BIN: &str = env!("CARGO_BIN_EXE_filterbench");

const HOLDS: &str = r#"
[[expect]]
kind = "agrees_with_exact"
per = "both"

[[expect]]
kind = "consistent"
filters = ["kalman"]

[[expect]]
kind = "better"
a = "kalman"
b = "kalman_x4"
"#;

/// The negative controls: the ×4 filter is under-confident (it believes in 4 times the process
/// noise there is); the Kalman filter is optimal, so the ×4 one is not better than it.
const FAILS: &str = r#"
[[expect]]
kind = "consistent"
filters = ["kalman_x4"]

[[expect]]
kind = "better"
a = "kalman_x4"
b = "kalman"
"#;

fn write(dir: &Path, name: &str, expect: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, SMALL.replace("EXPECT", expect)).unwrap();
    p.display().to_string()
}

fn check(args: &[&str]) -> Output {
    Command::new(BIN).arg("check").args(args).output().unwrap()
}

fn cells(dir: &Path) -> DataFrame {
    ParquetReader::new(std::fs::File::open(dir.join("check.parquet")).unwrap()).finish().unwrap()
}

/// (test cases, failures) of a JUnit file, read back by quick-junit's deserializer.
fn junit(path: &Path) -> (usize, usize) {
    let report = quick_junit::Report::deserialize_from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    (report.tests, report.failures)
}

#[test]
fn holds_fails_junit_and_results() {
    let tmp = TempDir::new();
    let (out, xml) = (tmp.path().join("out"), tmp.path().join("report.xml"));
    let file = write(tmp.path(), "holds.toml", HOLDS);
    let o = check(&[&file, "--trials", "2000", "--out", out.to_str().unwrap(), "--junit", xml.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{stdout}{}", String::from_utf8_lossy(&o.stderr));
    let df = cells(&out);
    // sum + 21 steps for 2 filters, 21 NEES and 21 NIS steps, one paired cell
    assert_eq!(df.height(), 2 * 22 + 21 + 21 + 1);
    assert_eq!(junit(&xml), (df.height(), 0));
    assert!(stdout.contains("agrees_with_exact") && stdout.contains("holds"), "{stdout}");
    // The same folder read back: the same cells, nothing run.
    let again = tmp.path().join("again.xml");
    let o = check(&["--results", out.to_str().unwrap(), "--junit", again.to_str().unwrap(), "--quiet"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(std::fs::read_to_string(&xml).unwrap(), std::fs::read_to_string(&again).unwrap());

    let (out, xml) = (tmp.path().join("out_fails"), tmp.path().join("fails.xml"));
    let file = write(tmp.path(), "fails.toml", FAILS);
    let o = check(&[&file, "--trials", "2000", "--out", out.to_str().unwrap(), "--junit", xml.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{stdout}{}", String::from_utf8_lossy(&o.stderr));
    let df = cells(&out);
    let (tests, failures) = junit(&xml);
    assert_eq!(tests, df.height());
    let verdict = df.column("verdict").unwrap().str().unwrap().clone();
    let expectation = df.column("expectation").unwrap().u32().unwrap().clone();
    let failing =
        |e: u32| (0..df.height()).filter(|&i| expectation.get(i) == Some(e) && verdict.get(i) == Some("fails")).count();
    assert!(failing(0) > 0, "the ×4 filter is not consistent at some step: {stdout}");
    // Both of its beliefs are wrong: its error covariance (NEES) and its innovation covariance (NIS).
    let what = df.column("test").unwrap().str().unwrap().clone();
    for w in ["NEES", "NIS"] {
        let n = (0..df.height())
            .filter(|&i| expectation.get(i) == Some(0) && verdict.get(i) == Some("fails"))
            .filter(|&i| what.get(i).is_some_and(|s| s.starts_with(w)))
            .count();
        assert!(n > 0, "the ×4 filter fails {w} at some step: {stdout}");
    }
    assert_eq!(failing(1), 1, "swapped `better` fails: {stdout}");
    assert_eq!(failures, failing(0) + failing(1));
}

#[test]
fn min_detectable_chooses_the_trials() {
    let tmp = TempDir::new();
    let out = tmp.path().join("out");
    let file = write(tmp.path(), "md.toml", "[[expect]]\nkind = \"agrees_with_exact\"\n");
    let o = check(&[&file, "--min-detectable", "0.02", "--out", out.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{stdout}{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("min_detectable 0.02"), "{stdout}");
    let df = cells(&out);
    let rel = df.column("detectable_relative").unwrap().f64().unwrap().clone();
    // The pilot's 400 trials estimate σ to about √((κ − 1)/(4n)) ≈ 7 % for a kurtosis κ ≈ 9; 1.3
    // leaves 4 such standard errors.
    for (i, r) in rel.iter().enumerate() {
        let r = r.unwrap();
        assert!(r <= 0.02 * 1.3 && r >= 0.02 / 1.3, "cell {i}: detectable {r} for a requested 0.02");
    }
    let o = check(&[&file, "--min-detectable", "1e-5", "--max-trials", "1000000", "--out", out.to_str().unwrap()]);
    refused(&o, &["--min-detectable", "trials", "--max-trials"]);
}

#[test]
fn bad_input_exits_2_naming_the_key() {
    let tmp = TempDir::new();
    let lin = "[[filters]]\nname = \"lin\"\nfamily = \"linear\"\ngain = [[0.5], [0.1]]\nform = \"predictor\"\n";
    let cases: &[(&str, &[&str], &[&str])] = &[
        ("[[expect]]\nkind = \"nope\"\n", &[], &["expect[0].kind", "nope"]),
        ("[[expect]]\nkind = \"agrees_with_exact\"\nfoo = 1\n", &[], &["expect[0].foo"]),
        ("[[expect]]\nkind = \"agrees_with_exact\"\nper = \"weekly\"\n", &[], &["expect[0].per"]),
        ("[[expect]]\nkind = \"consistent\"\nfilters = [\"ghost\"]\n", &[], &["expect[0].filters", "ghost"]),
        ("[[expect]]\nkind = \"consistent\"\nscenarios = [\"ghost\"]\n", &[], &["expect[0].scenarios", "ghost"]),
        ("[[expect]]\nkind = \"better\"\na = \"ghost\"\nb = \"kalman\"\n", &[], &["expect[0].a", "ghost"]),
        (
            "[[expect]]\nkind = \"better\"\na = \"kalman\"\nb = \"kalman_x4\"\nmargin = 1\nmargin_relative = 0.1\n",
            &[],
            &["expect[0].margin_relative"],
        ),
        ("[[expect]]\nkind = \"agrees_with_exact\"\n", &["--alpha", "1.5"], &["--alpha"]),
        ("[[expect]]\nkind = \"agrees_with_exact\"\n[check]\nalpha = 0\n", &[], &["check.alpha"]),
        ("", &[], &["expect", "no [[expect]]"]),
        // applies to no cell: found after the run, and nothing is written
        (&format!("{lin}[[expect]]\nkind = \"consistent\"\nfilters = [\"lin\"]\n"), &[], &["expect[0].filters", "lin"]),
    ];
    for (i, (expect, args, needles)) in cases.iter().enumerate() {
        let file = write(tmp.path(), &format!("bad{i}.toml"), expect);
        let out = tmp.path().join(format!("out{i}"));
        let mut all = vec![file.as_str(), "--trials", "50", "--out", out.to_str().unwrap(), "--quiet"];
        all.extend_from_slice(args);
        refused(&check(&all), needles);
        assert!(!out.exists(), "case {i}: nothing written");
    }
    // `experiment` refuses a bad entry at load too.
    let file = write(tmp.path(), "bad_experiment.toml", "[[expect]]\nkind = \"nope\"\n");
    let o = Command::new(BIN)
        .args(["experiment", &file, "--trials", "5", "--quiet", "--out"])
        .arg(tmp.path().join("x"))
        .output()
        .unwrap();
    refused(&o, &["expect[0].kind"]);
}
