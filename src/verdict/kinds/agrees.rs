//! `agrees_with_exact`: the Monte Carlo mean agrees with the exact value (the moment recursion of
//! docs/math.md), summed and/or per step. Two-sided z = (mean − exact)/std_error; the central
//! limit theorem for the mean of i.i.d. trials, which needs the squared error's variance finite.

use serde::Deserialize;

use crate::verdict::kind::{Context, Kind, Test, z_test};
use crate::verdict::stats::Sided;

pub struct AgreesWithExact;

/// Which means are compared.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Per {
    /// The summed error J (summary.parquet).
    #[default]
    Sum,
    /// Every step's mean-square error (steps.parquet).
    Step,
    Both,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    #[serde(default)]
    per: Per,
}

impl Kind for AgreesWithExact {
    const NAME: &'static str = "agrees_with_exact";
    type Params = Params;

    fn tests(p: &Params, cx: &Context) -> crate::Result<Vec<Test>> {
        let mut out = Vec::new();
        if p.per != Per::Step {
            for r in cx.tables.summary.iter().filter(|r| cx.sel.both(&r.scenario, &r.filter)) {
                let Some(exact) = r.exact else { continue };
                let heavy = cx.heavy_tails(r.variant.as_deref(), &r.scenario);
                let row = (&r.variant, r.scenario.as_str(), r.filter.as_str(), None);
                out.push(z_test(row, "mean vs exact", r.mean, exact, r.std_error, Some(exact), Sided::TwoSided, heavy));
            }
        }
        if p.per != Per::Sum {
            for r in cx.tables.steps.iter().filter(|r| cx.sel.both(&r.scenario, &r.filter)) {
                let Some(exact) = r.exact else { continue };
                let heavy = cx.heavy_tails(r.variant.as_deref(), &r.scenario);
                let row = (&r.variant, r.scenario.as_str(), r.filter.as_str(), Some(r.step));
                let (m, se) = (r.mse_mean, r.mse_std_error);
                out.push(z_test(row, "step mean vs exact", m, exact, se, Some(exact), Sided::TwoSided, heavy));
            }
        }
        Ok(out)
    }
}
