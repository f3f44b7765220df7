//! `better`: filter `a`'s summed error is below filter `b`'s by at least a margin, absolute
//! (`margin`) or relative to b's exact error (`margin_relative`), in the named scenarios. A paired
//! test on the same draws (paired.parquet's mean of J_a − J_b and its standard error, far smaller
//! than the two means' own): the expectation E\[J_a − J_b] ≤ −margin fails when
//! z = (mean_diff + margin)/std_error is significantly positive (one-sided).

use serde::Deserialize;

use crate::config::{Expectation, Experiment};
use crate::verdict::kind::{Context, Kind, Test, z_test};
use crate::verdict::stats::Sided;

pub struct Better;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    a: String,
    b: String,
    margin: Option<f64>,
    margin_relative: Option<f64>,
}

impl Kind for Better {
    const NAME: &'static str = "better";
    type Params = Params;

    fn check(p: &Params, e: &Expectation, exp: &Experiment) -> Result<(), (String, String)> {
        let bad = |k: &str, c: String| Err((k.to_string(), c));
        if e.filters.is_some() {
            return bad("filters", "`better` names its two filters with `a` and `b`, not `filters`".into());
        }
        for (k, name) in [("a", &p.a), ("b", &p.b)] {
            if exp.filter_index(name).is_none() {
                return bad(k, format!("no filter named `{name}` in this experiment"));
            }
        }
        if p.a == p.b {
            return bad("b", format!("is `a` again (`{}`): name two different filters", p.a));
        }
        match (p.margin, p.margin_relative) {
            (Some(_), Some(_)) => bad("margin_relative", "give `margin` or `margin_relative`, not both".into()),
            (Some(m), _) if !(m >= 0.0 && m.is_finite()) => bad("margin", format!("must be finite and ≥ 0, got {m}")),
            (_, Some(m)) if !(0.0..1.0).contains(&m) => {
                bad("margin_relative", format!("must be in [0, 1) (a fraction of b's exact error), got {m}"))
            }
            _ => Ok(()),
        }
    }

    fn tests(p: &Params, cx: &Context) -> crate::Result<Vec<Test>> {
        let mut out = Vec::new();
        for r in cx.tables.paired.iter().filter(|r| cx.sel.scenario(&r.scenario)) {
            let sign = if (r.filter_a.as_str(), r.filter_b.as_str()) == (p.a.as_str(), p.b.as_str()) {
                1.0
            } else if (r.filter_a.as_str(), r.filter_b.as_str()) == (p.b.as_str(), p.a.as_str()) {
                -1.0
            } else {
                continue;
            };
            let v = r.variant.as_deref();
            let exact_b = cx
                .tables
                .summary
                .iter()
                .find(|s| s.variant.as_deref() == v && s.scenario == r.scenario && s.filter == p.b)
                .and_then(|s| s.exact);
            let (margin, na) = match (p.margin, p.margin_relative, exact_b) {
                (Some(m), _, _) => (m, None),
                (None, Some(f), Some(e)) => (f * e, None),
                (None, Some(_), None) => (0.0, Some(format!("`{}` has no exact error to take the margin from", p.b))),
                (None, None, _) => (0.0, None),
            };
            let na = na.or_else(|| cx.heavy_tails(v, &r.scenario));
            let label = format!("{} vs {}", p.a, p.b);
            let row = (&r.variant, r.scenario.as_str(), label.as_str(), None);
            let d = sign * r.mean_diff;
            out.push(z_test(row, "J_a − J_b ≤ −margin", d, 0.0 - margin, r.std_error, exact_b, Sided::Upper, na));
        }
        Ok(out)
    }
}
