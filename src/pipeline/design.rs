//! Stage 1: design every filter and the figures that depend on the filter alone: its worst case over
//! the experiment's uncertainty (seed 000, seed 001's disturbances), its a-anisotropic norm (seed
//! 003), its claimed error and NEES weights, its generalized H2 norm (seed 002).

use std::time::Instant;

use rayon::prelude::*;

use crate::analysis::exact::{self, WorstCase};
use crate::analysis::nees::{self, Normalized};
use crate::config::Experiment;
use crate::error::{Error, Result};
use crate::filter::design::Design;
use crate::filter::realization::Realization;
use crate::model::plant::{Measurement, Plant};
use crate::numerics::linalg::Mat;

/// A designed filter with its cost and its worst case over the experiment's uncertainty sets.
pub struct DesignedFilter {
    pub design: Design,
    pub seconds: f64,
    pub worst: Option<WorstCase>,
    /// The exact a-anisotropic norm² and its limits, at the experiment's `anisotropy` level (seed 003).
    pub anisotropic: Option<AnisotropicFigures>,
    /// Λ's eigendecomposition, kept where a scenario draws this filter's worst anisotropic input
    /// and the figures above took it (the dense route), so that the scenario does not redo it.
    pub gram_eigen: Option<crate::analysis::anisotropy::GramEigen>,
    /// The summed error with zero noise (x0's mean and the known input alone).
    pub deterministic_error: f64,
    /// What the filter believes its error is, if it has a design covariance P (see [`Claimed`]).
    pub claimed: Option<Claimed>,
    /// Its NEES weights per step, P_z\[k]⁺ / rank, and ranks, where it claims a covariance
    /// ([`crate::analysis::nees`]).
    pub nees: Option<Normalized>,
    /// Its NIS weights S\[k]⁺ / rank and ranks, where it has an innovation and a design covariance
    /// to claim S at ([`crate::analysis::nees::innovation_system`]).
    pub nis: Option<Normalized>,
    /// Its generalized H2 norm² under the nominal weights ([`crate::analysis::hinf::generalized_h2_norm_sq`]);
    /// None on a switching plant or when the stacked operator would be too large.
    pub generalized_h2_sq: Option<f64>,
}

/// Inputs (x0 and w over the horizon) beyond which the generalized H2 norm is not computed: its
/// stacked operator grows with their number squared (galerkin_string would need 50 000 of them).
const GENERALIZED_H2_MAX_INPUTS: usize = 4000;

fn generalized_h2(exp: &Experiment, real: &Realization) -> Result<Option<f64>> {
    let p = &exp.plant;
    if p.random_matrices() || p.nx() + p.horizon * p.nw() > GENERALIZED_H2_MAX_INPUTS {
        return Ok(None);
    }
    crate::analysis::hinf::generalized_h2_norm_sq(p, real, &exp.nominal).map(Some)
}

/// A filter's own belief about its error: the error at its design covariance, Σ_k tr(Cz P\[k] Czᵀ)
/// with P its design Riccati solution (Kalman, intermittent, Markov-jump: at `design`; minimax: at
/// K̂). It is not a promise: under another covariance the filter does not know it is wrong, and
/// `exact / claimed` (the consistency) says by how much.
#[derive(Clone, Debug)]
pub struct Claimed {
    pub total: f64,
    /// Shared with every scenario's [`super::Promise`] that states it (one copy per filter).
    pub per_step: std::sync::Arc<[f64]>,
}

impl Claimed {
    fn of(plant: &Plant, design: &Design) -> Option<Claimed> {
        let total =
            |per_step: &[f64]| per_step.iter().enumerate().filter(|(k, _)| plant.counts(*k)).map(|(_, v)| v).sum();
        // A filter that states its error covariance (the `linear` family's `claimed`) believes tr of it.
        if let Some(moments) = &design.claimed_error {
            let per_step: Vec<f64> = moments.iter().map(Mat::trace).collect();
            return Some(Claimed { total: total(&per_step), per_step: per_step.into() });
        }
        // Every guarantee kind is stated at the filter's design covariance (Kalman: its P; minimax: K̂).
        let g = design.guarantee.as_ref()?;
        // A family that guarantees only the sum (minimax, seed 000 eq (22)) still claims its error at
        // its design covariance step by step.
        let per_step = if g.per_step.is_empty() {
            exact::error(plant, &design.realization, design.design_covariance.as_ref()?).per_step
        } else {
            g.per_step.clone()
        };
        Some(Claimed { total: total(&per_step), per_step: per_step.into() })
    }
}

/// Designs every filter of `exp` (in parallel; each timed on its own). When several designs fail, the
/// error reported is the first in file order, not whichever thread failed first, so the message is
/// the same on every run and every thread count.
pub fn design_all(exp: &Experiment) -> Result<Vec<DesignedFilter>> {
    let designed: Vec<Result<DesignedFilter>> = exp
        .filters
        .par_iter()
        .enumerate()
        .map(|(i, f)| {
            let t = Instant::now();
            let design = crate::families::design(f.configured.as_ref(), &exp.design_input(i))?;
            let seconds = t.elapsed().as_secs_f64();
            let worst = worst_case(exp, &design.realization)
                .map_err(|e| Error::design(&f.name, format!("worst case over the set: {e}")))?;
            let (anisotropic, gram_eigen) = match exp.anisotropy {
                Some(a) => {
                    let (figures, eigen) = anisotropic_figures(exp, &design.realization, a)?;
                    let drawn = exp.scenarios.iter().any(
                        |s| matches!(s.input, crate::config::InputChoice::AnisotropicWorstFor { filter, .. } if filter == i),
                    );
                    (Some(figures), eigen.filter(|_| drawn))
                }
                None => (None, None),
            };
            let deterministic_error = exact::deterministic_error(&exp.plant, &design.realization);
            let claimed = Claimed::of(&exp.plant, &design);
            let claimed_moments = match (&claimed, &design.design_covariance) {
                (Some(_), _) if design.claimed_error.is_some() => design.claimed_error.clone(),
                (Some(_), Some(cov)) => {
                    let at_design = |pairs: &[(&Plant, &Realization)]| {
                        exact::errors(pairs, cov).into_iter().map(|e| e.trusted(&f.name)).collect()
                    };
                    Some(nees::error_moments(&exp.plant, &design.realization, &at_design)?)
                }
                _ => None,
            };
            let nees = claimed_moments.as_deref().map(Normalized::of);
            // A claimed S that double precision cannot resolve is no claim: no NIS then.
            let nis = match (&design.design_covariance, nees::innovation_system(&exp.plant, &design.realization)) {
                (Some(cov), Some((p, r))) => {
                    let at_design = |pairs: &[(&Plant, &Realization)]| {
                        exact::errors(pairs, cov).into_iter().map(|e| e.trusted(&f.name)).collect()
                    };
                    nees::error_moments(&p, &r, &at_design).ok().map(|m| Normalized::of(&m))
                }
                _ => None,
            };
            let generalized_h2_sq = generalized_h2(exp, &design.realization)?;
            Ok(DesignedFilter {
                design,
                seconds,
                worst,
                anisotropic,
                gram_eigen,
                deterministic_error,
                claimed,
                nees,
                nis,
                generalized_h2_sq,
            })
        })
        .collect();
    designed.into_iter().collect()
}

/// A filter's exact |||F|||²_a at the experiment's level a and its limits ‖F‖₂²/lw (a = 0) and
/// ‖F‖∞² (a → ∞), from the eigenvalues of one Λ = E\[𝓕ᵀ𝓕] or by Lemma 1 (seed 003 §2).
#[derive(Clone, Copy, Debug)]
pub struct AnisotropicFigures {
    pub norm_sq: f64,
    pub h2_sq: f64,
    pub hinf_sq: f64,
}

/// Above this many inputs lw = mw(N + 1) the a-anisotropic figures come from seed 003's Lemma 1
/// (a Riccati recursion, O(N n³)) instead of the eigenvalues of the lw × lw matrix Λ (O(lw³) time,
/// O(lw²) memory: 1 s at lw = 1600, 29 s at 4000); the two agree to 1e-13 (tests/it/lemma1.rs).
/// Markov plants (outside seed 003) keep the dense route.
const DENSE_NORM_MAX_INPUTS: usize = 1500;

/// A filter's a-anisotropic norm, its H2 limit ‖F‖₂²/lw (a = 0) and its H∞ limit λmax(Λ) (a = ∞),
/// squared (seed 003 §2), with Λ's eigendecomposition where they come from it (the dense route).
fn anisotropic_figures(
    exp: &Experiment,
    real: &Realization,
    a: f64,
) -> Result<(AnisotropicFigures, Option<crate::analysis::anisotropy::GramEigen>)> {
    let p = &exp.plant;
    if p.nw() * p.steps() > DENSE_NORM_MAX_INPUTS && !matches!(p.measurement, Measurement::Markov(_)) {
        let lemma = crate::analysis::lemma1::Lemma1::new(p, real)?;
        let sq = |a: f64| lemma.norm(a).map(|n| n.value.powi(2));
        return Ok((AnisotropicFigures { norm_sq: sq(a)?, h2_sq: sq(0.0)?, hinf_sq: sq(f64::INFINITY)? }, None));
    }
    let eigen = crate::analysis::anisotropy::gram_eigen(p, real)?;
    let mu: Vec<f64> = eigen.values.iter().map(|m| m.max(0.0)).collect();
    let norm = crate::analysis::anisotropy::anisotropic_norm_from_eigenvalues(&mu, a)?;
    let figures = AnisotropicFigures {
        norm_sq: norm.value.powi(2),
        h2_sq: mu.iter().sum::<f64>() / mu.len() as f64,
        hinf_sq: mu.iter().cloned().fold(0.0, f64::max),
    };
    Ok((figures, Some(eigen)))
}

/// A filter's exact worst case over the experiment's uncertainty: covariances over their sets
/// (disturbance blocks carry no covariance) and deterministic disturbances over their energy bounds
/// ([`crate::analysis::disturbance::worst`]), evaluated exactly at the joint maximizer found. With
/// disturbances, also the certified bound on the joint maximum: E J = J(K) + (what the sequence
/// adds), the two parts maximized independently (J(K) is affine in K and does not involve the
/// sequence; seed 000 §5), so the sets' exact maximum plus the certified increase bounds it. None
/// if the experiment has neither sets nor disturbances.
pub fn worst_case(exp: &Experiment, real: &Realization) -> Result<Option<WorstCase>> {
    let center = exp.nominal.clone();
    let sets = exact::worst_case(&exp.plant, real, &center, &exp.sets)?;
    let dist = crate::analysis::disturbance::worst(&exp.plant, real, &exp.disturbances)?;
    if sets.is_none() && dist.is_none() {
        return Ok(None);
    }
    let mut wc = match sets {
        Some(wc) => wc,
        None => {
            let at = exact::error(&exp.plant, real, &center);
            if let Some(cause) = at.unresolved() {
                return Err(Error::invalid("exact error at the nominal covariances", cause));
            }
            WorstCase {
                total: at.total,
                argmax: center,
                psd: true,
                disturbance: None,
                disturbance_bound: None,
                certified: None,
            }
        }
    };
    wc.certified = dist.as_ref().map(|w| (wc.total + w.increase) * (1.0 + 2.0 * f64::EPSILON));
    wc.disturbance_bound = dist.as_ref().map(|w| (w.value, w.upper));
    wc.disturbance = dist.map(|w| w.sequence);
    let at = exact::error_with_mean(&exp.plant, real, &wc.argmax, wc.disturbance.as_ref());
    if let Some(cause) = at.unresolved() {
        return Err(Error::invalid("exact error at the maximizer", cause));
    }
    wc.total = at.total;
    Ok(Some(wc))
}
