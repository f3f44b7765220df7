//! `consistent`: the filter's claimed error covariance matches its error, by NEES step by step
//! (docs/output-columns.md, `nees_mean`), never pooled over time (the errors of one trial are
//! correlated across steps, so a time average has a far wider spread than its steps suggest); and,
//! where the filter has an innovation ν = y − C x̂ (its state estimates x), its claimed innovation
//! covariance S\[k] likewise by NIS (`nis_mean`), each step a cell of its own.
//!
//! With Gaussian errors of exactly the claimed covariance P_z\[k] of rank r, e\[k]ᵀ P_z⁺ e\[k] is
//! χ²(r), and over n independent trials n·r·NEES\[k] is χ²(n·r): tested two-sided at each step. Where
//! the error is not Gaussian (another noise shape, dropouts, modes, multiplicative noise, a
//! deterministic disturbance), E\[NEES\[k]] = 1 still holds for any error of that second moment, and
//! the mean of n i.i.d. trials is tested by the central limit theorem, z = (NEES − 1)/std_error;
//! that needs the error's fourth moment, absent for Student-t noise with ν ≤ 4 (then: not
//! applicable). A filter is consistent at its design covariance only: name the scenarios where the
//! noise has it.

use serde::Deserialize;

use crate::verdict::kind::{Context, Kind, Method, Test, z_test};
use crate::verdict::stats::Sided;

pub struct Consistent;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {}

impl Kind for Consistent {
    const NAME: &'static str = "consistent";
    type Params = Params;

    fn tests(_p: &Params, cx: &Context) -> crate::Result<Vec<Test>> {
        let mut out = Vec::new();
        let rows = cx.tables.steps.iter().filter(|r| cx.sel.both(&r.scenario, &r.filter));
        for (r, what, sq) in rows.flat_map(|r| [(r, "NEES", &r.nees), (r, "NIS", &r.nis)]) {
            let (Some(mean), Some(se)) = (sq.mean, sq.std_error) else { continue };
            let v = r.variant.as_deref();
            let n = cx
                .tables
                .summary
                .iter()
                .find(|s| s.variant.as_deref() == v && s.scenario == r.scenario && s.filter == r.filter)
                .map(|s| s.n_trials)
                .unwrap_or(0);
            let row = (&r.variant, r.scenario.as_str(), r.filter.as_str(), Some(r.step));
            let mut t = z_test(row, what, mean, 1.0, se, Some(1.0), Sided::TwoSided, cx.heavy_tails(v, &r.scenario));
            if let (Method::Z(_), None, Some(rank)) = (&t.method, cx.non_gaussian(v, &r.scenario), sq.rank) {
                if rank > 0 && n > 0 {
                    t.method = Method::Chi2 { dof: n as f64 * rank as f64 };
                }
            }
            out.push(t);
        }
        Ok(out)
    }
}
