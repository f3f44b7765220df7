//! `within_guarantee`: a family's promise kept (docs/families.md). Where it promises a bound per
//! trial (the `violations` column), no trial may break it: a count, decided with certainty. Where
//! it promises a bound on the mean (`guaranteed`), the Monte Carlo mean must not be above it:
//! one-sided z = (mean − guaranteed)/std_error, which a filter exactly at its bound passes with
//! probability 1 − level. Seed 003's anisotropic filters promise a gain, γ² (`guaranteed_gain`), for
//! inputs within their anisotropy level (`guarantee_applies`): the mean gain of the noise,
//! (mean − deterministic_error)/input_power, is tested the same way, and the exact norm² at the file's
//! `anisotropy` level, where that is within the guarantee's, must not exceed the certified γ² (both certified numbers, docs/families.md "What is certified, and how").

use serde::Deserialize;

use crate::verdict::kind::{Context, Kind, Method, Test, z_test};
use crate::verdict::stats::Sided;

pub struct WithinGuarantee;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {}

impl Kind for WithinGuarantee {
    const NAME: &'static str = "within_guarantee";
    type Params = Params;

    fn tests(_p: &Params, cx: &Context) -> crate::Result<Vec<Test>> {
        let mut out = Vec::new();
        let mut designs_seen = std::collections::BTreeSet::new();
        for r in cx.tables.summary.iter().filter(|r| cx.sel.both(&r.scenario, &r.filter)) {
            let row = (&r.variant, r.scenario.as_str(), r.filter.as_str(), None);
            let certain = |what: &'static str, observed: f64, reference: f64, holds: bool| Test {
                variant: r.variant.clone(),
                scenario: r.scenario.clone(),
                filter: r.filter.clone(),
                step: None,
                what: what.into(),
                observed,
                reference,
                std_error: None,
                scale: None,
                method: Method::Certain { holds },
            };
            if let Some(v) = r.violations {
                out.push(certain("per-trial violations", v as f64, 0.0, v == 0));
            }
            let heavy = || cx.heavy_tails(r.variant.as_deref(), &r.scenario);
            if let Some(g) = r.guaranteed {
                out.push(z_test(row, "mean ≤ guaranteed", r.mean, g, r.std_error, Some(g), Sided::Upper, heavy()));
            }
            let (Some(gamma), Some(true)) = (r.guaranteed_gain, r.guarantee_applies) else { continue };
            if let (Some(power), Some(det)) = (r.input_power, r.deterministic_error) {
                if power > 0.0 {
                    let (gain, se) = ((r.mean - det) / power, r.std_error / power);
                    out.push(z_test(row, "noise gain ≤ γ²", gain, gamma, se, Some(gamma), Sided::Upper, heavy()));
                }
            }
            // The norm is reported at the file's level a; it is bounded by γ² when a is within the
            // level the guarantee holds for (the a-anisotropic norm grows with a).
            let file_level = cx.experiment(r.variant.as_deref()).and_then(|e| e.anisotropy);
            let within = matches!((file_level, r.guarantee_anisotropy), (Some(a), Some(g)) if a <= g);
            if let (Some(norm), true) = (r.anisotropic_norm_sq, within) {
                if designs_seen.insert((r.variant.clone(), r.filter.clone())) {
                    let mut t = certain("exact norm² ≤ γ²", norm, gamma, norm <= gamma);
                    t.scenario = "(design)".into();
                    out.push(t);
                }
            }
        }
        Ok(out)
    }
}
