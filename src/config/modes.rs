//! `[modes]`: the Markov chain of seed 001 and each mode's matrices, validated.

use super::experiment::check_name;
use super::schema::{ModesFile, Rows};
use crate::error::{Error, Result};
use crate::model::plant::{Modes, Plant, Steps};
use crate::numerics::linalg::from_rows;

/// Validates a Markov chain and its modes (a matrix a mode does not give is the plant's): Π square with one row per mode, non-negative, rows
/// summing to 1; p(0) likewise (default: the stationary distribution, which must then exist).
pub(super) fn resolve_modes(mf: &ModesFile, plant: &Plant) -> Result<Modes> {
    let q = mf.mode.len();
    if q == 0 {
        return Err(Error::invalid("modes.mode", "list at least one mode"));
    }
    let mut names = std::collections::BTreeSet::new();
    for (i, m) in mf.mode.iter().enumerate() {
        check_name(&format!("modes.mode[{i}].name"), &m.name)?;
        if !names.insert(m.name.as_str()) {
            return Err(Error::invalid(format!("modes.mode[{i}].name"), format!("mode name `{}` is repeated", m.name)));
        }
    }
    let pi = from_rows("modes.transition", &mf.transition, Some((q, q)))?;
    let stochastic = |key: &str, row: &[f64]| -> Result<()> {
        if row.iter().any(|v| !(*v >= 0.0 && v.is_finite())) {
            return Err(Error::invalid(key, format!("probabilities must be finite and ≥ 0, got {row:?}")));
        }
        let sum: f64 = row.iter().sum();
        if (sum - 1.0).abs() > 1e-9 {
            return Err(Error::invalid(key, format!("probabilities must sum to 1, these sum to {sum}")));
        }
        Ok(())
    };
    for s in 0..q {
        let row: Vec<f64> = pi.row(s).iter().copied().collect();
        stochastic(&format!("modes.transition row {} ({})", s + 1, mf.mode[s].name), &row)?;
    }
    let (n, nw, ny) = (plant.nx(), plant.nw(), plant.ny());
    // A matrix the mode does not give is the plant's, per step when the plant's varies.
    let pick = |key: &str, given: &Option<Rows>, base: &Steps, shape: (usize, usize)| -> Result<Steps> {
        given.as_ref().map_or(Ok(base.clone()), |r| from_rows(key, r, Some(shape)).map(Steps::constant))
    };
    let mut modes = Modes {
        names: mf.mode.iter().map(|m| m.name.clone()).collect(),
        transition: pi,
        initial: Vec::new(),
        a: Vec::new(),
        b: Vec::new(),
        c: Vec::new(),
        d: Vec::new(),
    };
    for m in &mf.mode {
        let key = |x: &str| format!("modes.{}.{x}", m.name);
        modes.a.push(pick(&key("A"), &m.A, &plant.a, (n, n))?);
        modes.b.push(pick(&key("B"), &m.B, &plant.b, (n, nw))?);
        modes.c.push(pick(&key("C"), &m.C, &plant.c, (ny, n))?);
        modes.d.push(pick(&key("D"), &m.D, &plant.d, (ny, nw))?);
    }
    modes.initial = match &mf.initial {
        Some(p0) => {
            if p0.len() != q {
                return Err(Error::invalid("modes.initial", format!("expected {q} probabilities, found {}", p0.len())));
            }
            stochastic("modes.initial", p0)?;
            p0.clone()
        }
        None => modes.stationary().ok_or_else(|| {
            Error::invalid("modes.initial", "the chain has no unique stationary distribution: give p(0) explicitly")
        })?,
    };
    Ok(modes)
}
