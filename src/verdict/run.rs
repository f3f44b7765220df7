//! The steps of `filterbench check` below the command line: the experiments of an existing result
//! folder (from its manifest), the check's rates, and the evaluation of a folder's tables, the one
//! code path whether the experiment was just run or ran earlier (docs/checks.md).

use std::path::Path;

use super::evaluate::{self, Check, Rates};
use super::tables::Tables;
use crate::config::{self, CheckSettings, Experiment, Overrides};
use crate::error::{Error, Result};

/// The default family-wise false-alarm rate of a check.
pub const DEFAULT_ALPHA: f64 = 1e-3;
/// The default miss rate the power is stated at.
pub const DEFAULT_BETA: f64 = 0.05;

/// The rates from the command line, else the file's `[check]`, else the defaults; each checked.
pub fn rates(alpha: Option<f64>, beta: Option<f64>, file: &CheckSettings) -> Result<Rates> {
    if let Some(a) = alpha {
        config::check_probability("--alpha", a)?;
    }
    if let Some(b) = beta {
        config::check_probability("--beta", b)?;
    }
    Ok(Rates { alpha: alpha.or(file.alpha).unwrap_or(DEFAULT_ALPHA), beta: beta.or(file.beta).unwrap_or(DEFAULT_BETA) })
}

/// The experiments (one per variant) a result folder was run from: its manifest's experiment file
/// text with the seed and trial count the run used.
pub fn experiments_of(dir: &Path) -> Result<Vec<Experiment>> {
    let path = dir.join("manifest.json");
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    let shown = path.display().to_string();
    let doc: serde_json::Value = serde_json::from_str(&text).map_err(|e| Error::invalid(&shown, e.to_string()))?;
    let field =
        |k: &str| doc.get(k).ok_or_else(|| Error::invalid(&shown, format!("no `{k}`: not a filterbench result")));
    let name = field("experiment")?.as_str().ok_or_else(|| Error::invalid(&shown, "`experiment` is not a string"))?;
    let file = field("experiment_file")?
        .as_str()
        .ok_or_else(|| Error::invalid(&shown, "`experiment_file` is not a string"))?;
    let seed = field("seed")?.as_u64();
    let trials = field("trials")?.as_u64().map(|t| t as usize);
    let overrides = Overrides { trials, seed, per_trial: false };
    config::variants_of(name, &format!("{shown} (experiment_file)"), file, &overrides, None)
}

/// Every expectation of `exps` evaluated on the tables of the result folder `dir` (`baseline`: the
/// folder `--baseline` names, for `matches_baseline`).
pub fn evaluate_folder(dir: &Path, exps: &[Experiment], rates: Rates, baseline: Option<&Path>) -> Result<Check> {
    let exp = &exps[0];
    let configured = evaluate::configure(exp)?;
    if configured.is_empty() {
        return Err(Error::invalid(
            "expect",
            format!("experiment `{}` has no [[expect]] entries: nothing to check", exp.name),
        ));
    }
    let tables = Tables::read(dir)?;
    let tests = evaluate::tests(&configured, &exp.expectations, exps, &tables, baseline)?;
    Ok(evaluate::evaluate(&configured, tests, rates))
}
