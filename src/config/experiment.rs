//! What the experiment file resolves to: the [`Experiment`] with its scenarios and filters, the
//! command line's [`Overrides`], and the rules a name or a trial count follows.

use serde::Deserialize;

use crate::error::{Error, Result};
use crate::model::choice::CovChoice;
use crate::model::disturbance::{Disturbance, DisturbanceChoice};
use crate::model::plant::{Covariances, Pattern, Plant};
use crate::model::shape::Shape;
use crate::model::uncertainty::CovSet;

/// How a scenario's inputs are drawn: block by block and white in time (the default), or jointly
/// over the horizon as ξ = col(x0 − E x0, w\[0..N−1]) (seed 002's setting; w\[N] = 0). `F` refers to
/// a filter: its name as written in the file, its index once resolved.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Input<F> {
    #[default]
    Independent,
    /// Uniform on the surface of the ellipsoid ξᵀK⁻¹ξ = 1, K = blockdiag(nominal x0, nominal w, …).
    EllipsoidSurface,
    /// Uniform inside that ellipsoid.
    EllipsoidInterior,
    /// ξ ~ (0, Σ) with Σ a random full covariance (fixed by the seed), E\[ξᵀK⁻¹ξ] = dim.
    RandomCovariance { seed: u64 },
    /// The worst input on the ellipsoid for the named filter (the top eigenvector of ΨKΨᵀ).
    EllipsoidWorstFor { filter: F },
    /// Gaussian W = col(w\[0..N]) coloured in time (AR(1) per component, the nominal covariance per
    /// step) with total anisotropy exactly `anisotropy` (seed 003; a over lw = mw(N+1)).
    Coloured { anisotropy: f64 },
    /// The named filter's worst Gaussian input at total anisotropy `anisotropy`: Σ(q) = (I − qΛ)⁻¹,
    /// scaled to the power of white nominal noise.
    AnisotropicWorstFor { filter: F, anisotropy: f64 },
}

/// A resolved [`Input`].
pub type InputChoice = Input<usize>;

impl<F> Input<F> {
    /// The same choice with its filter reference mapped (name → index).
    pub(crate) fn map_filter<G>(self, f: impl FnOnce(F) -> Result<G>) -> Result<Input<G>> {
        Ok(match self {
            Input::Independent => Input::Independent,
            Input::EllipsoidSurface => Input::EllipsoidSurface,
            Input::EllipsoidInterior => Input::EllipsoidInterior,
            Input::RandomCovariance { seed } => Input::RandomCovariance { seed },
            Input::EllipsoidWorstFor { filter } => Input::EllipsoidWorstFor { filter: f(filter)? },
            Input::Coloured { anisotropy } => Input::Coloured { anisotropy },
            Input::AnisotropicWorstFor { filter, anisotropy } => {
                Input::AnisotropicWorstFor { filter: f(filter)?, anisotropy }
            }
        })
    }
}

/// A scenario: which covariance the noise has and which distribution shape it is drawn with.
#[derive(Clone, Debug)]
pub struct Scenario {
    pub name: String,
    pub covariance: CovChoice,
    pub shape: Shape,
    pub disturbance: DisturbanceChoice,
    pub input: InputChoice,
}

/// A filter entry: its name, its family, the parameter table as written (for the manifest and
/// the sweeps), and the family with those parameters read ([`crate::families::Family::Params`]).
#[derive(Clone, Debug)]
pub struct FilterSpec {
    pub name: String,
    pub family: String,
    pub params: toml::Table,
    pub configured: std::sync::Arc<dyn crate::families::Configured>,
}

impl FilterSpec {
    /// Reads the family's parameters (an unknown family or a bad key is refused with its name).
    pub fn new(name: String, family: String, params: toml::Table) -> Result<Self> {
        let configured = crate::families::configure(&name, &family, &params)?;
        Ok(FilterSpec { name, family, params, configured })
    }
}

/// The index of the filter named `name` among `filters`.
pub(crate) fn filter_index(filters: &[FilterSpec], name: &str) -> Option<usize> {
    filters.iter().position(|f| f.name == name)
}

/// A validated experiment, ready to design and run.
#[derive(Clone, Debug)]
pub struct Experiment {
    pub name: String,
    /// The variant's name when the file has `[[variants]]` (e.g. one dropout probability each).
    pub variant: Option<String>,
    pub description: String,
    pub seed: u64,
    pub trials: usize,
    pub pattern: Pattern,
    pub sample_trajectories: usize,
    /// Keep every trial's summed error J (`--per-trial`): `trials.parquet` and the summary's
    /// median and 95th percentile.
    pub per_trial: bool,
    /// The total anisotropy a at which every filter's a-anisotropic norm is reported, if any.
    pub anisotropy: Option<f64>,
    pub plant: Plant,
    /// The nominal covariances noise is drawn with: a deterministic disturbance block has none
    /// (zero); the designs see its surrogate instead (`Experiment::design_nominal`).
    pub nominal: Covariances,
    /// The uncertainty set of each covariance block (index as in `Covariances::blocks`), if any.
    pub sets: Vec<Option<CovSet>>,
    /// The energy bound of each block that is a deterministic disturbance (index as in `sets`).
    pub disturbances: Vec<Option<Disturbance>>,
    pub scenarios: Vec<Scenario>,
    pub filters: Vec<FilterSpec>,
    /// The file text, kept for the manifest.
    pub source: String,
    /// The string model when the file describes one (seed 004).
    pub string: Option<crate::model::string::StringModel>,
    /// The array files the experiment file references, in the order read (docs/experiment-files.md,
    /// "Matrices from files").
    pub inputs: Vec<super::FileInput>,
    /// The `[[expect]]` entries `filterbench check` tests, in file order (docs/checks.md).
    pub expectations: Vec<Expectation>,
    /// The `[check]` table's defaults.
    pub check: CheckSettings,
}

impl Experiment {
    /// The covariances noise is drawn with when a scenario names `cov`: deterministic disturbance
    /// blocks have none (a filter's design covariance carries their surrogate there).
    pub(crate) fn sampling(&self, cov: &Covariances) -> Covariances {
        let mut out = cov.clone();
        for (b, d) in out.blocks.iter_mut().zip(&self.disturbances) {
            if d.is_some() {
                b.fill(0.0);
            }
        }
        out.varying.clear();
        out
    }
    /// The nominal covariances the designs use: each disturbance block replaced by the white-noise
    /// surrogate s · W_k⁻¹ of seed 000 eqs (38)–(39), step by step when its weights vary.
    pub(crate) fn design_nominal(&self) -> Covariances {
        let mut out = self.nominal.clone();
        for (i, (b, d)) in out.blocks.iter_mut().zip(&self.disturbances).enumerate() {
            if let Some(d) = d {
                *b = d.surrogate_covariance();
                if let Some(steps) = d.surrogate_steps() {
                    out.varying.push((i, steps));
                }
            }
        }
        out
    }
    pub fn filter_index(&self, name: &str) -> Option<usize> {
        filter_index(&self.filters, name)
    }

    /// What filter `i`'s family designs from.
    pub(crate) fn design_input(&self, i: usize) -> crate::filter::design::DesignInput<'_> {
        crate::filter::design::DesignInput {
            name: &self.filters[i].name,
            plant: &self.plant,
            pattern: self.pattern,
            nominal: self.design_nominal(),
            sets: &self.sets,
            string: self.string.as_ref(),
        }
    }
}

/// Refuses a user-given name that would corrupt the terminal or a file name: control characters
/// (an ESC sequence printed in a message can clear the screen).
pub fn check_name(key: &str, name: &str) -> Result<()> {
    if let Some(c) = name.chars().find(|c| c.is_control()) {
        return Err(Error::invalid(
            key,
            format!("contains the control character U+{:04X}: names must be printable", c as u32),
        ));
    }
    Ok(())
}

/// The most trials a run may have: every count (trials × scenarios on the progress bar, the trial
/// index of the random streams) then fits in 64 bits, and a count is exact in an f64 (< 2⁵³).
pub const MAX_TRIALS: usize = 1_000_000_000_000;

/// The one rule for a trial count, from the file (`trials`) or the command line (`--trials`).
pub fn check_trials(key: &str, trials: usize) -> Result<()> {
    if trials < 2 {
        return Err(Error::invalid(key, "at least 2 trials are needed for a confidence interval"));
    }
    if trials > MAX_TRIALS {
        return Err(Error::invalid(key, format!("{trials} trials is more than the limit of {MAX_TRIALS} (10¹²)")));
    }
    Ok(())
}

/// A cap on the trials `min_detectable` may choose.
pub fn check_max_trials(key: &str, v: usize) -> Result<()> {
    if !(2..=MAX_TRIALS).contains(&v) {
        return Err(Error::invalid(key, format!("must be between 2 and {MAX_TRIALS}, got {v}")));
    }
    Ok(())
}

/// One `[[expect]]` entry: its kind, the scenarios and filters it names (None: every one the kind
/// applies to) and the kind's own parameters, read by the kind.
#[derive(Clone, Debug, PartialEq)]
pub struct Expectation {
    pub kind: String,
    pub scenarios: Option<Vec<String>>,
    pub filters: Option<Vec<String>>,
    pub params: toml::Table,
}

/// The `[check]` table: defaults for `check`'s `--alpha`, `--beta`, `--min-detectable` and
/// `--max-trials` (the command line wins).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CheckSettings {
    pub alpha: Option<f64>,
    pub beta: Option<f64>,
    pub min_detectable: Option<f64>,
    pub max_trials: Option<usize>,
}

/// The one rule for `sample_trajectories`: at most one per trial, so a value above the trial count
/// (the file's, or `--trials`) keeps every trial's trajectory.
pub fn sample_count(sample_trajectories: usize, trials: usize) -> usize {
    sample_trajectories.min(trials)
}

/// What the command line sets instead of the file: `--trials`, `--seed` and `--per-trial`. The
/// loader takes them ([`load_variants`](super::load_variants)) and validates them with the file, so the command line
/// builds the experiment it runs and no [`Experiment`] changes after validation. A shard records
/// them so that `merge` builds the same experiments again.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Overrides {
    pub trials: Option<usize>,
    pub seed: Option<u64>,
    pub per_trial: bool,
}
