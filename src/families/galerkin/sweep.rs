//! The Galerkin family's analysis of a finished run (seed 004): m(z), the least error any filter
//! can reach (a `kalman` filter on the string is the Kalman filter of the exact truth, Theorem 3's
//! optimum), with the gap of the best Galerkin filter to it; and, per (basis, n) swept over at least
//! three α > 0, the α the discrepancy principle ([`super::alpha`]) chooses from one record, against
//! the sweep's best α.

use super::alpha::{AlphaChoice, Pilot, choose_alpha};
use super::projection::{Basis, GalerkinPoint};
use crate::error::Result;
use crate::families::family::{Family, RunView};
use crate::filter::design::Record;

/// Fewer α than this on a (basis, n) and the rule has no grid to choose on.
const MIN_GRID: usize = 3;

/// What the analysis found.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Sweep {
    /// Per scenario (file order): m(z) per Kalman filter of the truth.
    pub optimum: Vec<Optimum>,
    /// Per (basis, n) with a grid of α, in basis then n order.
    pub alpha_rule: Vec<AlphaRule>,
}

impl Record for Sweep {}

/// m(z) in one scenario: a Kalman filter of the exact truth and the best Galerkin filter's gap to it.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Optimum {
    pub scenario: String,
    pub filter: String,
    /// Its exact error, time-averaged (Σ_k, / steps).
    pub error: f64,
    /// (best Galerkin − m(z)) / m(z).
    pub best_galerkin_gap: f64,
}

/// The discrepancy principle on one (basis, n).
#[derive(Clone, Debug, serde::Serialize)]
pub struct AlphaRule {
    pub basis: String,
    pub n: usize,
    /// The rule's choice; None when it chose none, and then `refused` says why.
    pub choice: Option<AlphaChoice>,
    pub refused: Option<String>,
    /// Per scenario: the sweep's least exact error on this (basis, n), time-averaged, and its α.
    pub best: Vec<(f64, f64)>,
}

/// The run's [`Sweep`], over the Galerkin filters `mine`; None without a string or filters.
pub fn analyze(run: &RunView, mine: &[usize]) -> Result<Option<Sweep>> {
    let Some(model) = run.string else { return Ok(None) };
    let points: Vec<(usize, &GalerkinPoint)> =
        mine.iter().filter_map(|&f| Some((f, run.filters[f].2.figures.get::<GalerkinPoint>()?))).collect();
    if points.is_empty() {
        return Ok(None);
    }
    let steps = run.plant.steps() as f64;
    let kalman = run.filters.iter().enumerate().filter(|(_, f)| f.1 == crate::families::kalman::Kalman::NAME);
    let mut optimum = Vec::new();
    for (scenario, exact) in &run.exact {
        let best = points.iter().map(|(f, _)| exact[*f] / steps).fold(f64::INFINITY, f64::min);
        for (f, (name, _, _)) in kalman.clone() {
            let error = exact[f] / steps;
            optimum.push(Optimum {
                scenario: scenario.to_string(),
                filter: name.to_string(),
                error,
                best_galerkin_gap: (best - error) / error,
            });
        }
    }
    let y = (run.pilot_record)();
    let pilot = Pilot { model, plant: run.plant, nominal: run.nominal, y: &y };
    let mut alpha_rule = Vec::new();
    let mut bases: Vec<&str> = points.iter().map(|(_, p)| p.basis.as_str()).collect();
    bases.sort();
    bases.dedup();
    for basis in bases {
        let kind = if basis == Basis::Hat.name() { Basis::Hat } else { Basis::Eigen };
        let mut ns: Vec<usize> = points.iter().filter(|(_, p)| p.basis == basis).map(|(_, p)| p.n).collect();
        ns.sort();
        ns.dedup();
        for n in ns {
            let group: Vec<&(usize, &GalerkinPoint)> =
                points.iter().filter(|(_, p)| p.basis == basis && p.n == n && p.alpha > 0.0).collect();
            if group.len() < MIN_GRID {
                continue;
            }
            let mut grid: Vec<f64> = group.iter().map(|(_, p)| p.alpha).collect();
            grid.sort_by(|a, b| b.total_cmp(a));
            grid.dedup();
            let best = run
                .exact
                .iter()
                .map(|(_, exact)| {
                    let (f, p) = group.iter().min_by(|a, b| exact[a.0].total_cmp(&exact[b.0])).expect("a grid");
                    (exact[*f] / steps, p.alpha)
                })
                .collect();
            let (choice, refused) = match choose_alpha(&pilot, kind, n, &grid) {
                Ok(c) => (Some(c), None),
                Err(e) => (None, Some(e.to_string())),
            };
            alpha_rule.push(AlphaRule { basis: basis.to_string(), n, choice, refused, best });
        }
    }
    Ok(Some(Sweep { optimum, alpha_rule }))
}
