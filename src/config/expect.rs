//! `[[expect]]` entries and the `[check]` table of an experiment file: what `filterbench check`
//! tests (docs/checks.md). This layer reads the keys every kind shares (`kind`, `scenarios`,
//! `filters`) and checks that the names exist; each kind's own parameters are kept as written and
//! read by the kind itself (`verdict::kinds`), which refuses unknown keys when the file is loaded.

use serde::Deserialize;

use super::experiment::{CheckSettings, Expectation};
use crate::error::{Error, Result};

/// `[[expect]]` as written.
#[derive(Deserialize)]
pub(super) struct ExpectFile {
    kind: String,
    scenarios: Option<Vec<String>>,
    filters: Option<Vec<String>>,
    #[serde(flatten)]
    params: toml::Table,
}

/// `[check]` as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CheckFile {
    alpha: Option<f64>,
    beta: Option<f64>,
    min_detectable: Option<f64>,
    max_trials: Option<usize>,
}

/// A probability strictly between 0 and 1 (a test level or a miss rate).
pub fn check_probability(key: &str, v: f64) -> Result<()> {
    if !(v > 0.0 && v < 1.0) {
        return Err(Error::invalid(key, format!("must be strictly between 0 and 1, got {v}")));
    }
    Ok(())
}

/// A relative discrepancy to detect: positive and finite.
pub fn check_min_detectable(key: &str, v: f64) -> Result<()> {
    if !(v > 0.0 && v.is_finite()) {
        return Err(Error::invalid(key, format!("must be a positive relative size such as 0.01, got {v}")));
    }
    Ok(())
}

pub(super) fn settings(c: Option<CheckFile>) -> Result<CheckSettings> {
    let Some(c) = c else { return Ok(CheckSettings::default()) };
    if let Some(a) = c.alpha {
        check_probability("check.alpha", a)?;
    }
    if let Some(b) = c.beta {
        check_probability("check.beta", b)?;
    }
    if let Some(d) = c.min_detectable {
        check_min_detectable("check.min_detectable", d)?;
    }
    if let Some(t) = c.max_trials {
        super::experiment::check_max_trials("check.max_trials", t)?;
    }
    Ok(CheckSettings { alpha: c.alpha, beta: c.beta, min_detectable: c.min_detectable, max_trials: c.max_trials })
}

/// Checks the names every entry gives against the experiment's scenarios and filters.
pub(super) fn expectations(raw: Vec<ExpectFile>, known_s: &[&str], known_f: &[&str]) -> Result<Vec<Expectation>> {
    raw.into_iter()
        .enumerate()
        .map(|(i, e)| {
            let key = |k: &str| format!("expect[{i}].{k}");
            if e.kind.is_empty() {
                return Err(Error::invalid(key("kind"), "is empty"));
            }
            names(&key("scenarios"), e.scenarios.as_deref(), known_s, "scenario")?;
            names(&key("filters"), e.filters.as_deref(), known_f, "filter")?;
            Ok(Expectation { kind: e.kind, scenarios: e.scenarios, filters: e.filters, params: e.params })
        })
        .collect()
}

fn names(key: &str, given: Option<&[String]>, known: &[&str], what: &str) -> Result<()> {
    let Some(given) = given else { return Ok(()) };
    if given.is_empty() {
        return Err(Error::invalid(key, format!("is empty: leave it out to mean every {what}")));
    }
    for (j, n) in given.iter().enumerate() {
        if !known.contains(&n.as_str()) {
            return Err(Error::invalid(key, format!("no {what} named `{n}` in this experiment")));
        }
        if given[..j].contains(n) {
            return Err(Error::invalid(key, format!("`{n}` is named twice")));
        }
    }
    Ok(())
}
