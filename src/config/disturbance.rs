//! `[disturbances.BLOCK]`: a deterministic disturbance's weights and energy bounds (seed 000
//! eqs (33)–(36)), checked and resolved.

use super::schema::{DisturbanceFile, Rows};
use crate::error::{Error, Result};
use crate::model::disturbance::Disturbance;
use crate::numerics::linalg::{Mat, check_psd, from_rows};

/// One `[disturbances.BLOCK]` table: its weights (one repeated, or one per step, all positive
/// definite and of one size) and its bounds (at least one of `energy` and `step_energy`).
pub(super) fn resolve(key: &str, df: &DisturbanceFile, steps: usize) -> Result<Disturbance> {
    let weight = |k: &str, rows: &Rows, size: Option<usize>| -> Result<Mat> {
        let w = from_rows(k, rows, size.map(|m| (m, m)))?;
        check_psd(k, &w)?;
        if w.is_empty()
            || nalgebra::Cholesky::new(w.clone()).is_none()
            || crate::numerics::linalg::min_eigenvalue(&w) <= 0.0
        {
            return Err(Error::invalid(k, "the weight must be positive definite"));
        }
        Ok(w)
    };
    let weights = match (&df.weight, &df.weights) {
        (Some(rows), None) => vec![weight(&format!("{key}.weight"), rows, None)?; steps],
        (None, Some(list)) => {
            if list.len() != steps {
                return Err(Error::invalid(
                    format!("{key}.weights"),
                    format!("needs one matrix per step k = 0..N ({steps}), got {}", list.len()),
                ));
            }
            let first = weight(&format!("{key}.weights[0]"), &list[0], None)?;
            let m = first.nrows();
            let mut out = vec![first];
            for (k, rows) in list.iter().enumerate().skip(1) {
                out.push(weight(&format!("{key}.weights[{k}]"), rows, Some(m))?);
            }
            out
        }
        _ => return Err(Error::invalid(key, "give exactly one of `weight` (constant) and `weights` (one per step)")),
    };
    let bound_ok = |r: f64| r >= 0.0 && r.is_finite();
    if let Some(r) = df.energy.filter(|r| !bound_ok(*r)) {
        return Err(Error::invalid(
            format!("{key}.energy"),
            format!("the energy bound must be finite and ≥ 0, got {r}"),
        ));
    }
    if let Some(r) = &df.step_energy {
        if r.len() != steps {
            return Err(Error::invalid(
                format!("{key}.step_energy"),
                format!("needs one bound per step k = 0..N ({steps}), got {}", r.len()),
            ));
        }
        if let Some(k) = r.iter().position(|r| !bound_ok(*r)) {
            return Err(Error::invalid(format!("{key}.step_energy[{k}]"), "a per-step bound must be finite and ≥ 0"));
        }
    }
    if df.energy.is_none() && df.step_energy.is_none() {
        return Err(Error::invalid(key, "needs `energy` (summed bound), `step_energy` (per-step bounds) or both"));
    }
    Ok(Disturbance { weights, energy: df.energy.unwrap_or(f64::INFINITY), step_energy: df.step_energy.clone() })
}
