//! Stage 2: each scenario's setup: the covariance it names (docs/math.md §7), its deterministic disturbance
//! (seed 000 §5), its joint input (seed 002, seed 003), which promises hold in it, and the noise
//! sampler built from all of these. Every command draws through [`setup`] (`super::each_scenario`).

use crate::config::{Experiment, InputChoice};
use crate::error::{Error, Result};
use crate::filter::design::Design;
use crate::model::choice::{CovChoice, check_point};
use crate::model::disturbance::{self, DisturbanceChoice};
use crate::model::plant::Covariances;
use crate::numerics::linalg::{Mat, Vector};
use crate::sim::noise::{JointInput, NoiseSampler, ShapeStep, Shaping};

use super::design::DesignedFilter;

/// A scenario made concrete: what its noise is drawn from, and what is promised about it.
pub struct Setup {
    /// Per filter: whether its guarantee is a promise in this scenario ([`guarantee_holds`]).
    pub holds: Vec<bool>,
    /// The covariances noise is drawn with (disturbance blocks zero: `Experiment::sampling`).
    pub covariances: Covariances,
    pub covariance_label: String,
    pub disturbance_label: String,
    /// The deterministic disturbance (column k added to w\[k]), if any.
    pub w_mean: Option<Mat>,
    pub joint: Option<JointInput>,
    /// The joint input's mean and covariance, which its exact error is computed from.
    pub joint_moments: Option<(Vector, Mat)>,
    pub sampler: NoiseSampler,
}

/// Scenario `index` of `exp` at its resolved covariance `cov` (from [`scenario_covariances`]).
pub fn setup(exp: &Experiment, filters: &[DesignedFilter], index: usize, cov: &Covariances) -> Result<Setup> {
    let s = &exp.scenarios[index];
    let joint_given = s.input != InputChoice::Independent;
    let holds = filters.iter().map(|f| guarantee_holds(exp, &f.design, cov, joint_given)).collect();
    let covariances = exp.sampling(cov);
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
    let (joint, shaping) = joint_input(exp, filters, &s.input)?;
    let sampler = NoiseSampler::new(&exp.plant, &covariances, &s.shape)
        .with_mean(w_mean.clone())
        .with_joint(joint.clone())
        .with_shaping(shaping);
    let covariance_label = match &s.input {
        InputChoice::Coloured { anisotropy } => format!("coloured(a={anisotropy})"),
        InputChoice::AnisotropicWorstFor { filter, anisotropy } => {
            format!("anisotropic_worst_for({}, a={anisotropy})", exp.filters[*filter].name)
        }
        _ => joint
            .as_ref()
            .map_or_else(|| s.covariance.label(|i| exp.filters[i].name.as_str()), |j| j.label().to_string()),
    };
    let joint_moments = joint.as_ref().map(JointInput::moments);
    Ok(Setup { holds, covariances, covariance_label, disturbance_label, w_mean, joint, joint_moments, sampler })
}

/// The covariances a scenario's choice names (docs/math.md §7); `worst_for` and `design_of` read the
/// designed filters.
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

/// Resolves the concrete covariance of every scenario (a worst case needs the designed filter), all
/// before any Monte Carlo runs, so a bad choice is refused before the run spends its time.
pub fn scenario_covariances(exp: &Experiment, filters: &[DesignedFilter]) -> Result<Vec<Covariances>> {
    exp.scenarios
        .iter()
        .map(|s| covariance_of(&s.covariance, &format!("scenarios.{}.covariance", s.name), exp, filters))
        .collect()
}

/// Whether a filter's `guarantee` is a promise in a scenario: the minimax bound holds for every
/// covariance of its sets (any shape, any disturbance within its energy bound), so where the
/// scenario's covariance lies in every set and its inputs are independent; `exact_at_design` is
/// the filter's belief ([`Claimed`](super::design::Claimed)), never a promise. With disturbances the
/// bound printed is the filter's certified worst case over the sets and the sequences (any number of blocks;
/// [`super::outcome::FilterOutcome`]), so it holds wherever the covariance lies in the sets.
pub fn guarantee_holds(exp: &Experiment, design: &Design, cov: &Covariances, joint: bool) -> bool {
    let Some(g) = &design.guarantee else { return false };
    g.kind.bounds_the_sets()
        && !joint
        && exp
            .sets
            .iter()
            .zip(&cov.blocks)
            .zip(&exp.disturbances)
            .all(|((set, m), dist)| dist.is_some() || set.as_ref().is_none_or(|s| s.contains(m)))
}

/// The joint input of a scenario, if it has one, with the ellipsoid weighted by the nominal
/// covariances K = blockdiag(x0, w, …, w) (seed 002), and the recursion that draws it where there is
/// one (`sim::noise::Shaping`: seed 003's coloured and worst inputs).
fn joint_input(
    exp: &Experiment,
    filters: &[DesignedFilter],
    input: &InputChoice,
) -> Result<(Option<JointInput>, Option<Shaping>)> {
    let k = || crate::analysis::hinf::input_weight(&exp.plant, &exp.nominal);
    let joint = match input {
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
            let (_, xi) = crate::analysis::hinf::norm(&exp.plant, &d.realization, &exp.nominal, &s)?;
            Some(JointInput::Fixed { xi })
        }
        InputChoice::Coloured { anisotropy } => {
            let w = exp.nominal.w();
            let (sigma, rho) = crate::analysis::anisotropy::coloured_covariance(&w, exp.plant.steps(), *anisotropy)?;
            let joint = anisotropic_input(exp, &sigma);
            let x0_half = crate::numerics::linalg::psd_factor(exp.nominal.x0());
            let shaping =
                nalgebra::Cholesky::new(w.clone()).map(|c| Shaping::ar1(x0_half, &c.l(), rho, exp.plant.steps()));
            return Ok(with_shaping(joint, shaping));
        }
        InputChoice::AnisotropicWorstFor { filter, anisotropy } => {
            let real = &filters[*filter].design.realization;
            let (norm, sigma) = match &filters[*filter].gram_eigen {
                Some(eigen) => crate::analysis::anisotropy::worst_from_eigen(eigen, *anisotropy)?,
                None => crate::analysis::anisotropy::realization_norm(&exp.plant, real, *anisotropy)?,
            };
            // Σ(q) has tr Σ = lw; give it the power of white nominal noise.
            let w = exp.nominal.w();
            let joint = anisotropic_input(exp, &(sigma * (w.trace() / w.nrows() as f64)));
            let shaping = crate::analysis::lemma1::Lemma1::new(&exp.plant, real)
                .ok()
                .and_then(|l| l.shaping(norm.q))
                .map(|steps| {
                    let steps = steps.into_iter().map(|[a, b, c, d]| ShapeStep { a, b, c, d }).collect();
                    Shaping::new(crate::numerics::linalg::psd_factor(exp.nominal.x0()), steps)
                });
            return Ok(with_shaping(joint, shaping));
        }
    };
    Ok((joint, None))
}

/// The joint input and its recursion, kept only where the recursion's factor is the input's
/// ([`Shaping::matching`]).
fn with_shaping(joint: JointInput, shaping: Option<Shaping>) -> (Option<JointInput>, Option<Shaping>) {
    let shaping = match &joint {
        JointInput::Correlated { factor } => shaping.and_then(|s| s.matching(factor)),
        _ => None,
    };
    (Some(joint), shaping)
}

/// J = col(x0 − E x0, w\[0..N]) with x0 at its nominal covariance and W = col(w\[0..N]) ~ (0, Σ).
fn anisotropic_input(exp: &Experiment, sigma: &Mat) -> JointInput {
    let factor = crate::numerics::linalg::block_diag(&[
        &crate::numerics::linalg::psd_factor(exp.nominal.x0()),
        &crate::numerics::linalg::psd_factor(sigma),
    ]);
    JointInput::Correlated { factor }
}
