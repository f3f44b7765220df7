//! Every expectation of a file evaluated on one result's tables: the cells of every kind, one
//! Holm family over every tested cell at the check's α (so a correct filter fails the whole check
//! with probability at most α), each cell's power, and the verdicts (docs/checks.md).

use super::kind::{Configured, Context, Method, Selection, Test};
use super::stats::{self, Sided};
use super::tables::Tables;
use crate::config::{Expectation, Experiment};
use crate::error::{Error, Result};

/// The check's error rates: α the family-wise false-alarm rate, β the miss rate the power is
/// stated at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rates {
    pub alpha: f64,
    pub beta: f64,
}

/// A cell's or an expectation's verdict.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Holds,
    Fails,
    NotApplicable,
}

impl Verdict {
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Holds => "holds",
            Verdict::Fails => "fails",
            Verdict::NotApplicable => "not applicable",
        }
    }
}

/// One tested cell with its statistics.
#[derive(Clone, Debug)]
pub struct Cell {
    /// The index of its `[[expect]]` entry.
    pub expectation: usize,
    pub kind: &'static str,
    pub test: Test,
    /// z = (observed − reference)/std_error (z-tests only).
    pub z: Option<f64>,
    pub p: Option<f64>,
    /// Holm's threshold for this cell's p-value, α/(m − rank).
    pub holm_threshold: Option<f64>,
    /// The smallest true discrepancy detected with probability 1 − β at the Bonferroni level α/m
    /// (absolute; for NEES the factor c − 1 of the covariance).
    pub detectable: Option<f64>,
    /// `detectable` over |scale| (the exact value, the bound), where there is one.
    pub detectable_relative: Option<f64>,
    pub verdict: Verdict,
}

/// The check of one result: every cell, in expectation order.
#[derive(Clone, Debug)]
pub struct Check {
    pub rates: Rates,
    /// Each expectation's kind, in file order.
    pub kinds: Vec<&'static str>,
    pub cells: Vec<Cell>,
    /// The cells in Holm's family (z and χ² tests).
    pub tested: usize,
}

impl Check {
    /// An expectation's verdict: it fails when a cell fails, is not applicable when no cell is.
    pub fn verdict(&self, expectation: usize) -> Verdict {
        let mut v = self.cells.iter().filter(|c| c.expectation == expectation).map(|c| c.verdict);
        let all: Vec<Verdict> = v.by_ref().collect();
        if all.contains(&Verdict::Fails) {
            Verdict::Fails
        } else if all.iter().all(|v| *v == Verdict::NotApplicable) {
            Verdict::NotApplicable
        } else {
            Verdict::Holds
        }
    }
    /// Whether any expectation fails.
    pub fn fails(&self) -> bool {
        self.cells.iter().any(|c| c.verdict == Verdict::Fails)
    }
    /// The Bonferroni level α/m every cell's power is stated at.
    pub fn level(&self) -> f64 {
        self.rates.alpha / self.tested.max(1) as f64
    }
}

/// Every `[[expect]]` entry of `exp` with its kind's parameters read: what `experiment` and
/// `check` refuse at load, one line naming `expect[i].KEY`.
pub fn configure(exp: &Experiment) -> Result<Vec<Box<dyn Configured>>> {
    exp.expectations.iter().enumerate().map(|(i, e)| super::kinds::configure(i, e, exp)).collect()
}

/// The tests of every expectation on `tables`, refusing an expectation that applies to none of
/// its named filters or scenarios (or to no cell at all) with its key.
pub fn tests(
    configured: &[Box<dyn Configured>],
    expectations: &[Expectation],
    exps: &[Experiment],
    tables: &Tables,
    baseline: Option<&std::path::Path>,
) -> Result<Vec<(usize, &'static str, Test)>> {
    let mut out = Vec::new();
    for (i, (k, e)) in configured.iter().zip(expectations).enumerate() {
        let cx = Context { exps, tables, sel: Selection::of(e), baseline };
        let tests = k.tests(&cx)?;
        let why = |what: &str| format!("kind `{}` applies to no {what} of this result", k.kind());
        for (key, names, of) in [
            ("filters", e.filters.as_deref(), &|t: &Test| t.filter.clone() as String),
            ("scenarios", e.scenarios.as_deref(), &|t: &Test| t.scenario.clone()),
        ] as [(&str, Option<&[String]>, &dyn Fn(&Test) -> String); 2]
        {
            for n in names.unwrap_or_default() {
                if !tests.iter().any(|t| of(t) == *n) {
                    let what = &key[..key.len() - 1];
                    return Err(Error::invalid(format!("expect[{i}].{key}"), format!("{} `{n}`", why(what))));
                }
            }
        }
        if tests.is_empty() {
            return Err(Error::invalid(format!("expect[{i}].kind"), why("cell (scenario, filter)")));
        }
        out.extend(tests.into_iter().map(|t| (i, k.kind(), t)));
    }
    Ok(out)
}

/// Evaluates the tests: p-values, one Holm family at `rates.alpha`, the power at the Bonferroni
/// level, the verdicts.
pub fn evaluate(configured: &[Box<dyn Configured>], tests: Vec<(usize, &'static str, Test)>, rates: Rates) -> Check {
    let (z, p): (Vec<Option<f64>>, Vec<Option<f64>>) = tests
        .iter()
        .map(|(_, _, t)| match t.method {
            Method::Z(sided) => {
                let z = (t.observed - t.reference) / t.std_error.unwrap_or(f64::NAN);
                (Some(z), Some(stats::normal_p(z, sided)))
            }
            Method::Chi2 { dof } => (None, Some(stats::chi2_p(dof * t.observed, dof, Sided::TwoSided))),
            _ => (None, None),
        })
        .unzip();
    let family: Vec<usize> = (0..tests.len()).filter(|i| p[*i].is_some()).collect();
    let holm = stats::holm(&family.iter().map(|i| p[*i].unwrap_or(f64::NAN)).collect::<Vec<_>>(), rates.alpha);
    let level = rates.alpha / family.len().max(1) as f64;
    let mut cells: Vec<Cell> = tests
        .into_iter()
        .enumerate()
        .map(|(i, (expectation, kind, test))| {
            let detectable = match test.method {
                Method::Z(sided) => test.std_error.map(|se| stats::detectable(se, level, rates.beta, sided)),
                Method::Chi2 { dof } => Some(stats::chi2_detectable(dof, level, rates.beta)),
                _ => None,
            };
            let scale = test.scale.filter(|s| *s != 0.0 && s.is_finite());
            let detectable_relative = detectable.zip(scale).map(|(d, s)| d / s.abs());
            let verdict = match test.method {
                Method::Certain { holds: true } => Verdict::Holds,
                Method::Certain { holds: false } => Verdict::Fails,
                Method::NotApplicable(_) => Verdict::NotApplicable,
                _ => Verdict::Holds,
            };
            Cell {
                expectation,
                kind,
                test,
                z: z[i],
                p: p[i],
                holm_threshold: None,
                detectable,
                detectable_relative,
                verdict,
            }
        })
        .collect();
    for (j, &i) in family.iter().enumerate() {
        cells[i].holm_threshold = Some(holm.threshold[j]);
        if holm.rejected[j] {
            cells[i].verdict = Verdict::Fails;
        }
    }
    Check { rates, kinds: configured.iter().map(|k| k.kind()).collect(), cells, tested: family.len() }
}

/// The trials that make every tested cell with a scale detect a relative discrepancy `delta` with
/// probability 1 − β at the Bonferroni level of this check's family: the largest
/// n = ⌈((z_crit + z_{1−β})·σ/(δ·|scale|))²⌉ over the cells, σ = std_error·√trials the per-trial
/// standard deviation estimated by this (pilot) check, `trials` its trial count. A χ² cell is
/// planned by the normal approximation of its mean NEES. None when no cell has a scale.
pub fn trials_for(check: &Check, trials: usize, delta: f64) -> Option<f64> {
    let level = check.level();
    check
        .cells
        .iter()
        .filter_map(|c| {
            let sided = match c.test.method {
                Method::Z(s) => s,
                Method::Chi2 { .. } => Sided::TwoSided,
                _ => return None,
            };
            let scale = c.test.scale.filter(|s| *s != 0.0 && s.is_finite())?;
            let sigma = c.test.std_error? * (trials as f64).sqrt();
            Some(stats::trials_for(sigma, delta * scale.abs(), level, check.rates.beta, sided))
        })
        .reduce(f64::max)
}
