//! `matches_baseline`: the run against a stored result folder of the same experiment (`--baseline
//! DIR`, or `baseline = "DIR"` in the entry), through `filterbench compare`'s cells
//! (docs/regression-tests.md): every design and exact value (summary, steps, paired, the designed
//! gains, the design trace) equal within a relative tolerance, a certain test; every Monte Carlo
//! mean by the two-sample z with the combined standard error √(se_old² + se_new²), two-sided, in
//! the check's Holm family. Both runs' means rest on the central limit theorem, as in
//! `agrees_with_exact`; with common draws (the same seed and trials) the test is conservative.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::config::{Expectation, Experiment};
use crate::error::Error;
use crate::verdict::compare::{self, Cell, CompareOptions, Kind as CellKind, Status, Value};
use crate::verdict::kind::{Context, Kind, Method, Test, z_test};
use crate::verdict::stats::Sided;

pub struct MatchesBaseline;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// The baseline folder (relative to the working directory); `--baseline` overrides it.
    baseline: Option<String>,
    /// The relative tolerance of the deterministic values (default: `compare`'s, the solvers'
    /// stated accuracy).
    rel_tol: Option<f64>,
}

impl Kind for MatchesBaseline {
    const NAME: &'static str = "matches_baseline";
    type Params = Params;

    fn check(p: &Params, _: &Expectation, _: &Experiment) -> Result<(), (String, String)> {
        match p.rel_tol {
            Some(t) if !(t >= 0.0 && t.is_finite()) => {
                Err(("rel_tol".into(), format!("must be finite and ≥ 0, got {t}")))
            }
            _ => Ok(()),
        }
    }

    fn tests(p: &Params, cx: &Context) -> crate::Result<Vec<Test>> {
        let dir: PathBuf = match (cx.baseline, &p.baseline) {
            (Some(d), _) => d.to_path_buf(),
            (None, Some(d)) => PathBuf::from(d),
            (None, None) => {
                return Err(Error::invalid(
                    "--baseline",
                    "a matches_baseline expectation needs the baseline folder: give --baseline DIR or baseline = \"DIR\"",
                ));
            }
        };
        let opts = CompareOptions {
            rel_tol: p.rel_tol.unwrap_or(compare::DEFAULT_REL_TOL),
            keep_identical: true,
            independent_draws: true,
            ..Default::default()
        };
        let c = compare::compare_folders(&dir, &cx.tables.dir, &opts)?;
        Ok(c.cells.iter().filter(|cell| selected(cx, cell)).filter_map(|cell| test(cx, &dir, cell)).collect())
    }
}

/// Whether the expectation's scenarios and filters name the cell (a cell without a scenario, a
/// gain or a design-trace entry, is named by its filter).
fn selected(cx: &Context, c: &Cell) -> bool {
    c.scenario.as_deref().is_none_or(|s| cx.sel.scenario(s)) && c.filter.as_deref().is_none_or(|f| cx.sel.filter(f))
}

/// The cell as a test: a Monte Carlo mean by z, anything else compared certainly (held unless the
/// comparison found it changed); a sampled figure without a test of its own is left out.
fn test(cx: &Context, dir: &Path, c: &Cell) -> Option<Test> {
    let what = format!(
        "{}.{}{} vs baseline",
        c.table,
        c.column,
        c.entry.as_ref().map(|e| format!(" {e}")).unwrap_or_default()
    );
    let filter = match (&c.filter, &c.filter_b) {
        (Some(a), Some(b)) => format!("{a} vs {b}"),
        (Some(a), None) => a.clone(),
        _ => String::new(),
    };
    let scenario = c.scenario.clone().unwrap_or_default();
    let num = |v: &Value| v.num().unwrap_or(f64::NAN);
    match c.kind {
        CellKind::Sampled => None,
        CellKind::MonteCarlo => {
            let heavy = cx.heavy_tails(c.variant.as_deref(), &scenario);
            let se = c.std_error.unwrap_or(f64::NAN);
            let row = (&c.variant, scenario.as_str(), filter.as_str(), c.step);
            let (old, new) = (num(&c.old), num(&c.new));
            Some(z_test(row, what, new, old, se, Some(old.abs()), Sided::TwoSided, heavy))
        }
        _ => {
            let holds = c.status != Status::Changed;
            let note = (!holds).then(|| format!(" (baseline {}: {} → {})", dir.display(), c.old, c.new));
            Some(Test {
                variant: c.variant.clone(),
                scenario,
                filter,
                step: c.step,
                what: (what + &note.unwrap_or_default()).into(),
                observed: num(&c.new),
                reference: num(&c.old),
                std_error: None,
                scale: None,
                method: Method::Certain { holds },
            })
        }
    }
}
