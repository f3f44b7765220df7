//! Runs one experiment end to end: design every filter, resolve every scenario's covariance, compute
//! the exact and worst-case errors, run the Monte Carlo, and hand everything to the reports.

pub mod bench;
pub mod budget;

use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;

use crate::analysis::exact::{self, ExactError, WorstCase};
use crate::config::{Experiment, InputChoice};
use crate::error::{Error, Result};
use crate::filter::design::Design;
use crate::filter::realization::Realization;
use crate::model::choice::{CovChoice, check_point};
use crate::model::disturbance::{self, DisturbanceChoice};
use crate::model::plant::{Covariances, Plant};
use crate::model::shape::Shape;
use crate::numerics::linalg::Mat;
use crate::sim::montecarlo::{self, McStats, Trajectory};
use crate::sim::noise::{JointInput, NoiseSampler};

/// A designed filter with its cost and its worst case over the experiment's uncertainty sets.
pub struct DesignedFilter {
    pub design: Design,
    pub seconds: f64,
    pub worst: Option<WorstCase>,
    /// The exact a-anisotropic norm² and its limits, at the experiment's `anisotropy` level (seed 003).
    pub anisotropic: Option<AnisotropicFigures>,
    /// The summed error with zero noise (x0's mean and the known input alone).
    pub deterministic_error: f64,
    /// What the filter believes its error is, if it has a design covariance P (see [`Claimed`]).
    pub claimed: Option<Claimed>,
    /// Its NEES weight per step, P_z[k]⁺ / rank, where it claims a covariance ([`crate::analysis::nees`]).
    pub nees_weights: Option<Vec<Option<Mat>>>,
    /// Its generalized H2 norm² under the nominal weights ([`crate::analysis::hinf::generalized_h2_norm_sq`]);
    /// None on a switching plant or when the stacked operator would be too large.
    pub generalized_h2_sq: Option<f64>,
}

/// Inputs (x0 and w over the horizon) beyond which the generalized H2 norm is not computed: its
/// stacked operator grows with their number squared (galerkin_string would need 50 000 of them).
const GENERALIZED_H2_MAX_INPUTS: usize = 4000;

fn generalized_h2(exp: &Experiment, real: &Realization) -> Result<Option<f64>> {
    let p = &exp.plant;
    if p.modes.is_some() || p.nx() + p.horizon * p.nw() > GENERALIZED_H2_MAX_INPUTS {
        return Ok(None);
    }
    crate::analysis::hinf::generalized_h2_norm_sq(p, real, &exp.sampling(&exp.nominal)).map(Some)
}

/// A filter's own belief about its error: the error at its design covariance, Σ_k tr(Cz P[k] Czᵀ)
/// with P its design Riccati solution (Kalman, intermittent, Markov-jump: at `design`; minimax: at
/// K̂). It is not a promise: under another covariance the filter does not know it is wrong, and
/// `exact / claimed` (the consistency) says by how much.
#[derive(Clone, Debug)]
pub struct Claimed {
    pub total: f64,
    pub per_step: Vec<f64>,
}

impl Claimed {
    fn of(plant: &crate::model::plant::Plant, design: &Design) -> Option<Claimed> {
        let g = design.guarantee.as_ref().filter(|g| g.kind.at_design_covariance())?;
        let total = g.per_step.iter().enumerate().filter(|(k, _)| plant.counts(*k)).map(|(_, v)| v).sum();
        Some(Claimed { total, per_step: g.per_step.clone() })
    }
}

/// Whether a filter's `guarantee` is a promise in a scenario: the minimax bound holds for every
/// covariance of its sets (any shape, any disturbance within its energy bound), so where the
/// scenario's covariance lies in every set and its inputs are independent; `exact_at_design` is
/// the filter's belief ([`Claimed`]), never a promise. With two or more disturbance blocks seed
/// 000's Theorem 3 drops the cross terms between them, so its bound is not proven and is no promise
/// either.
pub fn guarantee_holds(exp: &Experiment, design: &Design, cov: &Covariances, joint: bool) -> bool {
    let Some(g) = &design.guarantee else { return false };
    g.kind.bounds_the_sets()
        && !joint
        && exp.disturbances.iter().filter(|d| d.is_some()).count() <= 1
        && exp
            .sets
            .iter()
            .zip(&cov.blocks)
            .zip(&exp.disturbances)
            .all(|((set, m), dist)| dist.is_some() || set.as_ref().map_or(true, |s| s.contains(m)))
}

/// One scenario's results.
pub struct ScenarioOutcome {
    pub name: String,
    pub covariance_label: String,
    pub shape_label: String,
    /// The covariances noise was drawn with (disturbance blocks zero).
    pub covariances: Covariances,
    pub disturbance_label: String,
    /// The deterministic disturbance (column k added to w[k]), if any.
    pub disturbance: Option<Mat>,
    pub exact: Vec<ExactError>,
    /// E|W|² of W = col(w[0..N]) (noise and any deterministic disturbance).
    pub input_power: f64,
    /// The anisotropy of a Gaussian W with the scenario's covariance (None when W is degenerate).
    pub input_anisotropy: Option<f64>,
    pub mc: McStats,
    pub mc_seconds: f64,
    pub trajectories: Vec<Trajectory>,
    /// Per filter: its guaranteed summed error where the promise holds in this scenario
    /// ([`guarantee_holds`]), else None.
    pub guaranteed: Vec<Option<f64>>,
    /// Per filter with a claimed covariance: the exact NEES per step (None at a step where it
    /// claims no error).
    pub nees_exact: Vec<Option<Vec<Option<f64>>>>,
}

pub struct RunOutcome {
    pub filters: Vec<DesignedFilter>,
    pub scenarios: Vec<ScenarioOutcome>,
    pub threads: usize,
    pub design_seconds: f64,
    pub total_seconds: f64,
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
            let anisotropic = match exp.anisotropy {
                Some(a) => Some(anisotropic_figures(exp, &design.realization, a)?),
                None => None,
            };
            let deterministic_error = exact::deterministic_error(&exp.plant, &design.realization);
            let claimed = Claimed::of(&exp.plant, &design);
            let nees_weights = match (&claimed, &design.design_covariance) {
                (Some(_), Some(cov)) => {
                    let at_design = |p: &Plant, r: &Realization| exact::error(p, r, cov).trusted(&f.name);
                    Some(crate::analysis::nees::weights(&crate::analysis::nees::error_moments(
                        &exp.plant,
                        &design.realization,
                        &at_design,
                    )?))
                }
                _ => None,
            };
            let generalized_h2_sq = generalized_h2(exp, &design.realization)?;
            Ok(DesignedFilter {
                design,
                seconds,
                worst,
                anisotropic,
                deterministic_error,
                claimed,
                nees_weights,
                generalized_h2_sq,
            })
        })
        .collect();
    designed.into_iter().collect()
}

/// A filter's exact |||F|||²_a at the experiment's level a and its limits ‖F‖₂²/lw (a = 0) and
/// ‖F‖∞² (a → ∞), all from the eigenvalues of one Λ = E[𝓕ᵀ𝓕] (seed 003 §2).
#[derive(Clone, Copy, Debug)]
pub struct AnisotropicFigures {
    pub norm_sq: f64,
    pub h2_sq: f64,
    pub hinf_sq: f64,
}

fn anisotropic_figures(exp: &Experiment, real: &Realization, a: f64) -> Result<AnisotropicFigures> {
    let (mu, _) = crate::numerics::linalg::sym_eigen(&crate::analysis::anisotropy::error_gram(&exp.plant, real)?)?;
    let mu: Vec<f64> = mu.into_iter().map(|m| m.max(0.0)).collect();
    let norm = crate::analysis::anisotropy::anisotropic_norm_from_eigenvalues(&mu, a)?;
    Ok(AnisotropicFigures {
        norm_sq: norm.value.powi(2),
        h2_sq: mu.iter().sum::<f64>() / mu.len() as f64,
        hinf_sq: mu.iter().cloned().fold(0.0, f64::max),
    })
}

/// A filter's exact worst case over the experiment's uncertainty: covariances over their sets
/// (disturbance blocks carry no covariance) and deterministic disturbances over their energy bounds
/// ([`crate::analysis::disturbance::worst`]), evaluated exactly at the joint maximizer. None if the experiment has
/// neither sets nor disturbances.
pub fn worst_case(exp: &Experiment, real: &Realization) -> Result<Option<WorstCase>> {
    let center = exp.sampling(&exp.nominal);
    let sets = exact::worst_case(&exp.plant, real, &center, &exp.sets)?;
    let dist = crate::analysis::disturbance::worst(&exp.plant, real, &exp.disturbances)?;
    if sets.is_none() && dist.is_none() {
        return Ok(None);
    }
    let mut wc = sets.unwrap_or(WorstCase { total: 0.0, argmax: center, psd: true, disturbance: None });
    wc.disturbance = dist.map(|(_, wm)| wm);
    let at = exact::error_with_mean(&exp.plant, real, &wc.argmax, wc.disturbance.as_ref());
    if let Some(cause) = at.unresolved() {
        return Err(Error::invalid("exact error at the maximizer", cause));
    }
    wc.total = at.total;
    Ok(Some(wc))
}

/// The per-trial ratio checks of the filters that promise one (seed 002), weighted by the nominal
/// covariances of x0 and w (pseudo-inverses, so a singular block simply carries no weight).
pub fn ratio_check<'a>(exp: &Experiment, filters: &'a [DesignedFilter]) -> Option<montecarlo::RatioCheck<'a>> {
    let bounds: Vec<_> = filters.iter().map(|f| f.design.per_trial.as_ref()).collect();
    bounds.iter().any(Option::is_some).then(|| montecarlo::RatioCheck {
        x0_weight: crate::numerics::linalg::psd_pinv(exp.nominal.x0()),
        w_weight: crate::numerics::linalg::psd_pinv(&exp.nominal.w()),
        bounds,
    })
}

/// The joint input of a scenario, if it has one, with the ellipsoid weighted by the nominal
/// covariances K = blockdiag(x0, w, …, w) (seed 002).
fn joint_input(exp: &Experiment, filters: &[DesignedFilter], input: &InputChoice) -> Result<Option<JointInput>> {
    let k = || crate::analysis::hinf::input_weight(&exp.plant, &exp.sampling(&exp.nominal));
    Ok(match input {
        InputChoice::Independent => None,
        InputChoice::EllipsoidSurface => {
            Some(JointInput::Ellipsoid { k_half: crate::numerics::linalg::psd_factor(&k()), surface: true })
        }
        InputChoice::EllipsoidInterior => {
            Some(JointInput::Ellipsoid { k_half: crate::numerics::linalg::psd_factor(&k()), surface: false })
        }
        InputChoice::RandomCovariance { seed } => Some(JointInput::random_covariance(&k(), *seed)),
        InputChoice::EllipsoidWorstFor { filter } => {
            let d = &filters[*filter].design;
            let n = exp.plant.nx();
            let s = match &d.per_trial {
                Some(crate::filter::design::PerTrialBound::Ratio { terminal_weight, .. }) => terminal_weight.clone(),
                _ => Mat::zeros(n, n),
            };
            let (_, xi) = crate::analysis::hinf::norm(&exp.plant, &d.realization, &exp.sampling(&exp.nominal), &s)?;
            Some(JointInput::Fixed { xi })
        }
        InputChoice::Coloured { anisotropy } => {
            let (sigma, _) =
                crate::analysis::anisotropy::coloured_covariance(&exp.nominal.w(), exp.plant.steps(), *anisotropy)?;
            Some(anisotropic_input(exp, &sigma))
        }
        InputChoice::AnisotropicWorstFor { filter, anisotropy } => {
            let real = &filters[*filter].design.realization;
            let (_, sigma) = crate::analysis::anisotropy::realization_norm(&exp.plant, real, *anisotropy)?;
            // Σ(q) has tr Σ = lw; give it the power of white nominal noise.
            let w = exp.nominal.w();
            Some(anisotropic_input(exp, &(sigma * (w.trace() / w.nrows() as f64))))
        }
    })
}

/// J = col(x0 − E x0, w[0..N]) with x0 at its nominal covariance and W = col(w[0..N]) ~ (0, Σ).
fn anisotropic_input(exp: &Experiment, sigma: &Mat) -> JointInput {
    let factor = crate::numerics::linalg::block_diag(&[
        &crate::numerics::linalg::psd_factor(exp.nominal.x0()),
        &crate::numerics::linalg::psd_factor(sigma),
    ]);
    JointInput::Correlated { factor }
}

/// E|W|² and the Gaussian anisotropy of W = col(w[0..N]) for a scenario's input (SPEC §5).
///
/// The anisotropy is exact for W = L u with L square and u i.i.d. of the scenario's shape: the
/// Gaussian formula plus lw times the shape's negentropy h_G − h(u) (seed 003 §2 with
/// h(Lu) = Σ h(u_i) + ln|det L|; [`Shape::entropy`]); infinite for a discrete shape (W has no
/// density). Where W mixes the x0 components into it (a random full covariance) the
/// non-Gaussian value has no closed form and is left out; the ellipsoid inputs keep the Gaussian
/// value of their covariance.
fn input_statistics(
    exp: &Experiment,
    cov: &Covariances,
    shape: &Shape,
    w_mean: Option<&Mat>,
    joint: Option<&JointInput>,
) -> (f64, Option<f64>) {
    let p = &exp.plant;
    let steps = p.steps();
    // A(W) − A_Gaussian(W) for W = L u, lw components; None when it has no closed form here.
    let correction = |lw: usize| -> Option<f64> {
        match (shape, shape.entropy()) {
            (Shape::Gaussian, _) => Some(0.0),
            (_, Some(h)) => Some(lw as f64 * (Shape::Gaussian.entropy().expect("a density") - h)),
            (_, None) => Some(f64::INFINITY),
        }
    };
    match joint {
        None => {
            let w = cov.w();
            let power = steps as f64 * w.trace() + w_mean.map_or(0.0, |m| m.norm_squared());
            let a = steps as f64 * crate::analysis::anisotropy::gaussian_anisotropy(&w);
            let a = (a.is_finite() && w_mean.is_none()).then_some(a);
            (power, a.and_then(|a| Some(a + correction(steps * p.nw())?)))
        }
        Some(j) => {
            let (mean, c) = j.moments();
            let n = p.nx();
            let d = c.nrows() - n;
            let cw = c.view((n, n), (d, d)).into_owned();
            let power = cw.trace() + mean.rows(n, d).norm_squared();
            let full = d == steps * p.nw() && mean.rows(n, d).norm() == 0.0;
            let a = crate::analysis::anisotropy::gaussian_anisotropy(&cw);
            let a = (full && a.is_finite()).then_some(a);
            let a = match j {
                JointInput::Correlated { factor } if *shape != Shape::Gaussian => {
                    let square = factor.view((n, 0), (d, n)).amax() == 0.0;
                    a.and_then(|a| Some(a + correction(d).filter(|_| square)?))
                }
                _ => a,
            };
            (power, a)
        }
    }
}

/// Resolves the concrete covariance of every scenario (a worst case needs the designed filter).
/// The covariances a scenario's choice names; `worst_for` and `design_of` read the designed filters.
fn covariance_of(choice: &CovChoice, key: &str, exp: &Experiment, filters: &[DesignedFilter]) -> Result<Covariances> {
    let cov = match choice.point(&exp.nominal, &exp.sets)? {
        Some(c) => c,
        None => match choice {
            CovChoice::WorstFor { filter } => filters[*filter]
                .worst
                .as_ref()
                .map(|w| w.argmax.clone())
                .ok_or_else(|| Error::invalid(key, "no uncertainty set"))?,
            CovChoice::DesignOf { filter } => filters[*filter]
                .design
                .design_covariance
                .clone()
                .ok_or_else(|| Error::invalid(key, "that filter was not designed at a covariance"))?,
            _ => unreachable!("CovChoice::point names every choice but these two"),
        },
    };
    check_point(key, &choice.label(|i| exp.filters[i].name.as_str()), &exp.plant, &cov)?;
    Ok(cov)
}

pub fn scenario_covariances(exp: &Experiment, filters: &[DesignedFilter]) -> Result<Vec<Covariances>> {
    exp.scenarios
        .iter()
        .map(|s| covariance_of(&s.covariance, &format!("scenarios.{}.covariance", s.name), exp, filters))
        .collect()
}

/// A rate with three significant figures and a k/M/G suffix (91.3k, not 91,332.6321).
pub fn three_figures(x: f64) -> String {
    if !x.is_finite() {
        return "—".into();
    }
    let (v, suffix) = match x {
        _ if x >= 1e9 => (x / 1e9, "G"),
        _ if x >= 1e6 => (x / 1e6, "M"),
        _ if x >= 1e3 => (x / 1e3, "k"),
        _ => (x, ""),
    };
    let prec = if v >= 100.0 {
        0
    } else if v >= 10.0 {
        1
    } else {
        2
    };
    format!("{v:.prec$}{suffix}")
}

/// Runs the whole experiment on the current rayon pool.
pub fn run(exp: &Experiment, show_progress: bool) -> Result<RunOutcome> {
    let start = Instant::now();
    let filters = design_all(exp)?;
    let design_seconds = start.elapsed().as_secs_f64();
    let covs = scenario_covariances(exp, &filters)?;
    let reals: Vec<&crate::filter::realization::Realization> = filters.iter().map(|f| &f.design.realization).collect();
    let ratios = ratio_check(exp, &filters);
    let ops = montecarlo::PlantOps::new(&exp.plant);
    let nees_weights: Vec<_> = filters.iter().map(|f| f.nees_weights.clone()).collect();

    // One bar per scenario, counting the trials the user asked for (not trials × scenarios).
    let trials = exp.trials as u64;
    let bar = if show_progress {
        ProgressBar::new(trials)
    } else {
        ProgressBar::with_draw_target(Some(trials), ProgressDrawTarget::hidden())
    };
    bar.set_style(
        ProgressStyle::with_template("{msg} [{wide_bar}] {human_pos}/{human_len} trials, {rate}/s, eta {eta}")
            .expect("valid template")
            .with_key("rate", |st: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = w.write_str(&three_figures(st.per_sec()));
            })
            .progress_chars("=> "),
    );

    let mut scenarios = Vec::with_capacity(exp.scenarios.len());
    for (i, (s, cov)) in exp.scenarios.iter().zip(covs).enumerate() {
        bar.reset();
        bar.set_message(format!("scenario {}/{} {}", i + 1, exp.scenarios.len(), s.name));
        let joint_given = s.input != InputChoice::Independent;
        let guaranteed = filters
            .iter()
            .map(|f| match guarantee_holds(exp, &f.design, &cov, joint_given) {
                true => f.design.guarantee.as_ref().map(|g| g.total),
                false => None,
            })
            .collect();
        let cov = exp.sampling(&cov);
        let (disturbance_label, w_mean) = match &s.disturbance {
            DisturbanceChoice::None => ("none".to_string(), None),
            DisturbanceChoice::Random { seed } => {
                (format!("random(seed={seed})"), Some(disturbance::random(&exp.plant, &exp.disturbances, *seed)))
            }
            DisturbanceChoice::WorstFor { filter } => (
                format!("worst_for({})", exp.filters[*filter].name),
                filters[*filter].worst.as_ref().and_then(|w| w.disturbance.clone()),
            ),
        };
        let joint = joint_input(exp, &filters, &s.input)?;
        let sampler = NoiseSampler::new(&exp.plant, &cov, &s.shape).with_mean(w_mean.clone()).with_joint(joint.clone());
        let sc = montecarlo::Scenario {
            plant: &exp.plant,
            ops: &ops,
            filters: &reals,
            sampler: &sampler,
            seed: exp.seed,
            index: i,
            ratios: ratios.as_ref(),
            nees: &nees_weights,
            forms: &[],
        };
        // Exact first: a filter whose error double precision cannot resolve is refused before its
        // Monte Carlo runs, and one resolved only in error coordinates is simulated in them too.
        let moments = joint.as_ref().map(|j| j.moments());
        let exact_of = |p: &Plant, r: &Realization| match &moments {
            None => Ok(exact::error_with_mean(p, r, &cov, w_mean.as_ref())),
            Some((mean, jcov)) => exact::error_joint(p, r, mean, jcov),
        };
        let exact = reals.iter().map(|r| exact_of(&exp.plant, r)).collect::<Result<Vec<_>>>()?;
        let exact = exact.into_iter().zip(&exp.filters).map(|(e, f)| e.trusted(&f.name)).collect::<Result<Vec<_>>>()?;
        let forms: Vec<Option<exact::ErrorForm>> = exact
            .iter()
            .zip(&reals)
            .map(|(e, r)| {
                (e.coordinates == exact::Coordinates::Error).then(|| exact::error_form(&exp.plant, r).ok())?
            })
            .collect();
        let sc = montecarlo::Scenario { forms: &forms, ..sc };
        let t = Instant::now();
        let mc = montecarlo::run(&sc, exp.trials as u64, &|n| bar.inc(n));
        let mc_seconds = t.elapsed().as_secs_f64();
        let trajectories = montecarlo::trajectories(&sc, exp.sample_trajectories as u64);
        // NEES from the same exact recursions, each projected output checked like the error itself.
        let nees_exact = filters
            .iter()
            .zip(&exp.filters)
            .map(|(f, spec)| match &f.nees_weights {
                Some(w) => {
                    let trusted = |p: &Plant, r: &Realization| exact_of(p, r)?.trusted(&spec.name);
                    let m = crate::analysis::nees::error_moments(&exp.plant, &f.design.realization, &trusted)?;
                    Ok(Some(crate::analysis::nees::exact(w, &m)))
                }
                None => Ok(None),
            })
            .collect::<Result<Vec<_>>>()?;
        let covariance_label = match &s.input {
            InputChoice::Coloured { anisotropy } => format!("coloured(a={anisotropy})"),
            InputChoice::AnisotropicWorstFor { filter, anisotropy } => {
                format!("anisotropic_worst_for({}, a={anisotropy})", exp.filters[*filter].name)
            }
            _ => joint
                .as_ref()
                .map_or_else(|| s.covariance.label(|i| exp.filters[i].name.as_str()), |j| j.label().to_string()),
        };
        let (input_power, input_anisotropy) = input_statistics(exp, &cov, &s.shape, w_mean.as_ref(), joint.as_ref());
        scenarios.push(ScenarioOutcome {
            name: s.name.clone(),
            covariance_label,
            shape_label: s.shape.label(),
            covariances: cov,
            disturbance_label,
            disturbance: w_mean,
            exact,
            input_power,
            input_anisotropy,
            mc,
            mc_seconds,
            trajectories,
            guaranteed,
            nees_exact,
        });
    }
    bar.finish_and_clear();
    Ok(RunOutcome {
        filters,
        scenarios,
        threads: rayon::current_num_threads(),
        design_seconds,
        total_seconds: start.elapsed().as_secs_f64(),
    })
}
