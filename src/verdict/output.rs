//! What `check` writes: the console table (one row per expectation, the failing cells below),
//! check.parquet (one row per cell, docs/output-columns.md) and the JUnit XML report (one test
//! case per cell), each file written beside its place and renamed onto it when complete.

use crate::report::console::num;
use std::path::Path;

use comfy_table::{CellAlignment, ContentArrangement, Table, presets};
use polars::prelude::*;

use super::evaluate::{Cell, Check, Verdict};
use super::kind::Method;
use crate::error::{Error, Result};

pub use crate::report::output::CHECK_FILE;

/// Where a cell is: `variant / scenario / filter [/ step k]`.
pub fn place(c: &Cell) -> String {
    let t = &c.test;
    let mut s = t.variant.as_ref().map(|v| format!("{v} / ")).unwrap_or_default();
    s += &format!("{} / {}", t.scenario, t.filter);
    if let Some(k) = t.step {
        s += &format!(" / step {k}");
    }
    s
}

/// The statistic of a cell: `z = …` for a z-test, `p = …` for a χ² test.
fn statistic(c: &Cell) -> String {
    match (&c.test.method, c.z, c.p) {
        (Method::Z(_), Some(z), _) => format!("z = {z:.2}"),
        (Method::Chi2 { .. }, _, Some(p)) => format!("p = {p:.2e}"),
        _ => "—".into(),
    }
}

/// One line on a cell: what was compared, its statistic and Holm's threshold.
pub fn describe(c: &Cell) -> String {
    let t = &c.test;
    let head = format!("{}: {} {} vs {}", t.what, place(c), num(t.observed), num(t.reference));
    match (&t.method, c.p, c.holm_threshold) {
        (Method::NotApplicable(why), _, _) => format!("{head}: not applicable: {why}"),
        (Method::Certain { .. }, _, _) => format!("{head} (no sampling error)"),
        (Method::Z(_), Some(p), Some(h)) => format!("{head}: {}, p = {p:.3e} vs Holm threshold {h:.3e}", statistic(c)),
        (_, Some(p), Some(h)) => format!("{head}: χ² p = {p:.3e} vs Holm threshold {h:.3e}"),
        _ => head,
    }
}

/// The failing cells listed per expectation below the table (all are in check.parquet).
const SHOWN: usize = 10;

/// The console table: one row per expectation with its worst cell (the smallest p, or a failing
/// count), its power (the largest detectable discrepancy over its cells, relative where every cell
/// has a scale) and verdict; the failing cells and the reasons for untested ones below.
pub fn table(check: &Check) -> String {
    let mut t = Table::new();
    t.load_preset(presets::NOTHING).set_content_arrangement(ContentArrangement::Disabled).set_header(vec![
        "expect",
        "kind",
        "cells",
        "worst observed",
        "reference",
        "z or p",
        "power (1−β)",
        "verdict",
    ]);
    let mut notes = String::new();
    for (i, kind) in check.kinds.iter().enumerate() {
        let cells: Vec<&Cell> = check.cells.iter().filter(|c| c.expectation == i).collect();
        let na = cells.iter().filter(|c| c.verdict == Verdict::NotApplicable).count();
        let worst =
            cells.iter().filter(|c| c.verdict == Verdict::Fails && c.p.is_none()).copied().next().or_else(|| {
                cells
                    .iter()
                    .filter(|c| c.p.is_some())
                    .min_by(|a, b| a.p.unwrap_or(1.0).total_cmp(&b.p.unwrap_or(1.0)))
                    .copied()
            });
        let worst = worst.or_else(|| cells.iter().find(|c| c.verdict != Verdict::NotApplicable).copied());
        let tested: Vec<&&Cell> = cells.iter().filter(|c| c.detectable.is_some()).collect();
        let power = if tested.is_empty() {
            "—".to_string()
        } else if tested.iter().all(|c| c.detectable_relative.is_some()) {
            let d = tested.iter().filter_map(|c| c.detectable_relative).fold(0.0, f64::max);
            format!("{} %", num(100.0 * d))
        } else {
            format!("±{}", num(tested.iter().filter_map(|c| c.detectable).fold(0.0, f64::max)))
        };
        let count = if na > 0 { format!("{} ({na} n/a)", cells.len()) } else { cells.len().to_string() };
        t.add_row(vec![
            format!("[{i}]"),
            kind.to_string(),
            count,
            worst.map_or("—".into(), |c| num(c.test.observed)),
            worst.map_or("—".into(), |c| num(c.test.reference)),
            worst.map_or("—".into(), statistic),
            power,
            check.verdict(i).name().to_string(),
        ]);
        let failing: Vec<&&Cell> = cells.iter().filter(|c| c.verdict == Verdict::Fails).collect();
        for c in failing.iter().take(SHOWN) {
            notes += &format!("  expect[{i}] {kind} fails: {}\n", describe(c));
        }
        if failing.len() > SHOWN {
            notes += &format!("  expect[{i}] {kind}: {} more failing cells in {CHECK_FILE}\n", failing.len() - SHOWN);
        }
        let mut reasons: Vec<&str> = cells
            .iter()
            .filter_map(|c| match &c.test.method {
                Method::NotApplicable(why) => Some(why.as_str()),
                _ => None,
            })
            .collect();
        reasons.dedup();
        for r in reasons {
            notes += &format!("  expect[{i}] {kind}: not applicable in some cells: {r}\n");
        }
    }
    for (i, c) in t.column_iter_mut().enumerate() {
        c.set_cell_alignment(if i < 2 { CellAlignment::Left } else { CellAlignment::Right });
    }
    let mut out: String = t.lines().map(|l| format!(" {}\n", l.trim_end())).collect();
    out += &format!(
        "  α = {} over {} tested cells (Holm); power: the smallest discrepancy detected with probability {} at level α/m = {:.2e}\n",
        check.rates.alpha,
        check.tested,
        1.0 - check.rates.beta,
        check.level()
    );
    out + &notes
}

/// Writes `bytes` to `path` through a temporary file beside it, renamed onto it when complete.
fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("check");
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    let done = write(&tmp).and_then(|_| std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e)));
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done
}

/// check.parquet: one row per cell (docs/output-columns.md).
pub fn write_parquet(check: &Check, experiment: &str, path: &Path) -> Result<()> {
    let cells = &check.cells;
    let f = |g: &dyn Fn(&Cell) -> Option<f64>| cells.iter().map(g).collect::<Vec<_>>();
    let s = |g: &dyn Fn(&Cell) -> Option<String>| cells.iter().map(g).collect::<Vec<_>>();
    let method = |c: &Cell| {
        Some(match &c.test.method {
            Method::Z(sided) => format!("z {}", sided.name()),
            Method::Chi2 { dof } => format!("chi2({dof})"),
            Method::Certain { .. } => "certain".into(),
            Method::NotApplicable(_) => "not applicable".into(),
        })
    };
    let col = |name: &str, v: Series| v.with_name(name.into()).into_column();
    let mut df = DataFrame::new_infer_height(vec![
        col("experiment", Series::new("".into(), vec![experiment; cells.len()])),
        col("variant", Series::new("".into(), s(&|c| c.test.variant.clone()))),
        col("expectation", Series::new("".into(), cells.iter().map(|c| c.expectation as u32).collect::<Vec<_>>())),
        col("kind", Series::new("".into(), cells.iter().map(|c| c.kind).collect::<Vec<_>>())),
        col("scenario", Series::new("".into(), s(&|c| Some(c.test.scenario.clone())))),
        col("filter", Series::new("".into(), s(&|c| Some(c.test.filter.clone())))),
        col("step", Series::new("".into(), cells.iter().map(|c| c.test.step).collect::<Vec<_>>())),
        col("test", Series::new("".into(), cells.iter().map(|c| c.test.what.as_ref()).collect::<Vec<_>>())),
        col("method", Series::new("".into(), s(&method))),
        col("observed", Series::new("".into(), f(&|c| Some(c.test.observed)))),
        col("reference", Series::new("".into(), f(&|c| Some(c.test.reference)))),
        col("std_error", Series::new("".into(), f(&|c| c.test.std_error))),
        col("z", Series::new("".into(), f(&|c| c.z))),
        col("p", Series::new("".into(), f(&|c| c.p))),
        col("holm_threshold", Series::new("".into(), f(&|c| c.holm_threshold))),
        col("detectable", Series::new("".into(), f(&|c| c.detectable))),
        col("detectable_relative", Series::new("".into(), f(&|c| c.detectable_relative))),
        col("verdict", Series::new("".into(), cells.iter().map(|c| c.verdict.name()).collect::<Vec<_>>())),
        col(
            "reason",
            Series::new(
                "".into(),
                s(&|c| match &c.test.method {
                    Method::NotApplicable(why) => Some(why.clone()),
                    _ => None,
                }),
            ),
        ),
    ])
    .map_err(|e| Error::output(CHECK_FILE, e))?;
    write_atomically(path, |tmp| {
        let file = std::fs::File::create(tmp).map_err(|e| Error::io(tmp, e))?;
        ParquetWriter::new(file).finish(&mut df).map_err(|e| Error::output(CHECK_FILE, e))?;
        Ok(())
    })
}

/// The JUnit XML report: one test suite per expectation, one test case per cell (a failure with
/// its statistic, a skipped case with the reason it is not applicable).
pub fn junit(check: &Check, experiment: &str) -> Result<String> {
    use quick_junit::{NonSuccessKind, Report, TestCase, TestCaseStatus, TestSuite};
    let mut report = Report::new(format!("filterbench check {experiment}"));
    for (i, kind) in check.kinds.iter().enumerate() {
        let mut suite = TestSuite::new(format!("expect[{i}] {kind}"));
        suite.add_property(("alpha", check.rates.alpha.to_string().as_str()));
        suite.add_property(("beta", check.rates.beta.to_string().as_str()));
        suite.add_property(("tested_cells", check.tested.to_string().as_str()));
        for c in check.cells.iter().filter(|c| c.expectation == i) {
            let mut status = match c.verdict {
                Verdict::Holds => TestCaseStatus::success(),
                Verdict::Fails => TestCaseStatus::non_success(NonSuccessKind::Failure),
                Verdict::NotApplicable => TestCaseStatus::skipped(),
            };
            if c.verdict != Verdict::Holds {
                status.set_message(describe(c));
            }
            let mut case = TestCase::new(place(c), status);
            case.set_classname(format!("filterbench.{experiment}.expect[{i}].{kind}"));
            suite.add_test_case(case);
        }
        report.add_test_suite(suite);
    }
    report.to_string().map_err(|e| Error::output("JUnit report", e))
}

/// Writes the JUnit report to `path`.
pub fn write_junit(check: &Check, experiment: &str, path: &Path) -> Result<()> {
    let xml = junit(check, experiment)?;
    write_atomically(path, |tmp| std::fs::write(tmp, xml).map_err(|e| Error::io(tmp, e)))
}
