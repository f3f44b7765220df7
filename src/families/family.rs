//! What a family is to the rest of the program: the [`Family`] trait with what it supports, its
//! footprint and its analysis of the finished run, the [`Configured`] filter an experiment carries,
//! and what several families share (the design point, a design that promises its exact error).

use std::fmt::Debug;
use std::sync::Arc;

use serde::de::DeserializeOwned;

use crate::error::{Error, Result};
use crate::filter::design::{Design, DesignInput, Guarantee, GuaranteeKind, Record};
use crate::filter::realization::Realization;
use crate::model::choice::CovChoiceFile;
use crate::model::plant::{Covariances, Measurement, Pattern, Plant};
use crate::model::string::StringModel;
use crate::numerics::linalg::Mat;

/// A filter family: a design procedure with its name, its typed parameters and what it promises
/// (argmin's `Solver` in spirit: what a solver needs is a trait bound; linfa's `ParamGuard`: the
/// parameters are checked when they are built, before any design). Everything the rest of the
/// program knows of a family comes through this trait: no family name is compared outside
/// `families/`.
pub trait Family: 'static {
    /// The name experiment files use: `family = "kalman"`.
    const NAME: &'static str;
    /// The `[filters.params]` table, read with `deny_unknown_fields` when the file is loaded.
    type Params: DeserializeOwned + Debug + Send + Sync;
    /// What the family designs for with these parameters; [`Supports::check`] refuses the rest when
    /// the file is loaded, with one message format for every family.
    fn supports(params: &Self::Params) -> Supports;
    /// The parameters' values, checked when the file is loaded: `Err((key under filters.NAME, cause))`.
    fn check(_params: &Self::Params) -> std::result::Result<(), (&'static str, String)> {
        Ok(())
    }
    /// What the designed filter will hold in memory, for the run's budget ([`Footprint`]).
    fn footprint(_params: &Self::Params, plant: PlantSize) -> Footprint {
        Footprint { state: plant.nx, gain_sets: 1, dense_horizon: false }
    }
    /// Designs the filter.
    fn design(input: &DesignInput, params: &Self::Params) -> Result<Design>;
    /// An analysis of the finished run that concerns this family's filters together (seed 004's
    /// α rule), computed by the pipeline after the Monte Carlo; None when it has nothing to add.
    fn after_run(_run: &RunView, _mine: &[usize]) -> Result<Option<Finding>> {
        Ok(None)
    }
}

/// The plant's sizes that a [`Footprint`] depends on.
#[derive(Clone, Copy, Debug)]
pub struct PlantSize {
    pub nx: usize,
    /// Markov modes (0 for a plant that does not switch).
    pub modes: usize,
}

/// What a designed filter holds, for the memory budget estimated before anything is designed.
#[derive(Clone, Copy, Debug)]
pub struct Footprint {
    /// The filter's state size.
    pub state: usize,
    /// Sets of gains per step (one per mode and one more for a mode-indexed filter).
    pub gain_sets: usize,
    /// Whether its design builds dense matrices over the whole horizon (inputs × inputs).
    pub dense_horizon: bool,
}

/// What a family designs for: the plant's features it can take. A feature the plant has and the
/// family lacks is refused by [`Supports::check`] when the file is loaded.
#[derive(Clone, Copy, Debug)]
pub struct Supports {
    /// The information patterns it designs for.
    pub patterns: &'static [Pattern],
    /// Measurement dropouts (`plant.arrival`).
    pub dropouts: bool,
    /// Markov modes (`[modes]`).
    pub markov_modes: bool,
    /// Multiplicative noise on the matrices (`plant.multiplicative`).
    pub multiplicative: bool,
    /// Matrices that change with the step.
    pub time_varying: bool,
    /// A disturbance block whose weights change with the step (its design surrogate then changes
    /// with the step, seed 000 eq (39)).
    pub varying_weights: bool,
    /// Whether it needs the string plant of seed 004 (`[string]`).
    pub needs_string: bool,
    /// The parameter that narrows what it designs for (`structure = "static"`), named in a refusal.
    pub narrowed_by: Option<(&'static str, &'static str)>,
}

/// Both patterns.
pub const ANY_PATTERN: &[Pattern] = &[Pattern::Filtering, Pattern::Prediction];
/// Prediction only: ẑ\[k] from y\[0..k−1].
pub const PREDICTION: &[Pattern] = &[Pattern::Prediction];
/// Filtering only: ẑ\[k] from y\[0..k].
pub const FILTERING: &[Pattern] = &[Pattern::Filtering];

impl Supports {
    /// Every plant an experiment file can describe.
    pub const ALL: Supports = Supports {
        patterns: ANY_PATTERN,
        dropouts: true,
        markov_modes: true,
        multiplicative: true,
        time_varying: true,
        varying_weights: false,
        needs_string: false,
        narrowed_by: None,
    };

    /// Refuses the first feature of the plant that `family` lacks, for the filter `input` designs:
    /// one message format for all families ("the F family does not design for X: how to fix it").
    pub fn check(&self, family: &str, input: &DesignInput) -> Result<()> {
        let (plant, pattern) = (input.plant, input.pattern);
        let with = self.narrowed_by.map_or(String::new(), |(k, v)| format!(" with {k} = \"{v}\""));
        let lacks = |what: &str, fix: &str| {
            Err(Error::design(input.name, format!("the {family} family{with} does not design for {what}: {fix}")))
        };
        if self.needs_string && input.string.is_none() {
            return lacks("a plant without a string (seed 004)", "describe the plant with [string]");
        }
        if !self.patterns.contains(&pattern) {
            let other = if pattern == Pattern::Filtering { "prediction" } else { "filtering" };
            let now = if pattern == Pattern::Filtering { "filtering" } else { "prediction" };
            return lacks(&format!("the {now} pattern"), &format!("set pattern = \"{other}\""));
        }
        match plant.measurement {
            Measurement::Dropout { .. } if !self.dropouts => {
                return lacks("measurement dropouts", "remove plant.arrival");
            }
            Measurement::Markov(_) if !self.markov_modes => return lacks("Markov modes", "remove [modes]"),
            _ => {}
        }
        if !plant.factors.is_empty() && !self.multiplicative {
            return lacks("multiplicative noise on the matrices", "remove plant.multiplicative");
        }
        if plant.time_varying() && !self.time_varying {
            return lacks(
                "matrices that change with the step",
                "give constant matrices, or parameters under which it takes them (docs/families.md, \"What each family designs for\")",
            );
        }
        if input.nominal.varies() && !self.varying_weights {
            return lacks(
                "a disturbance with time-varying weights (its surrogate, seed 000 eq (39), changes with the step)",
                "use constant weights, or the kalman or minimax family",
            );
        }
        Ok(())
    }
}

/// What a family's [`Family::after_run`] sees of the finished run.
pub struct RunView<'a> {
    pub plant: &'a Plant,
    pub nominal: &'a Covariances,
    pub string: Option<&'a StringModel>,
    /// Every filter's name, family and design, in file order.
    pub filters: Vec<(&'a str, &'static str, &'a Design)>,
    /// Per scenario (in file order), its name and every filter's exact summed error.
    pub exact: Vec<(&'a str, Vec<f64>)>,
    /// Per scenario (in file order), every filter's Monte Carlo mean of the summed error with the
    /// ends of its 95 % interval: (mean, low, high).
    pub monte_carlo: Vec<Vec<(f64, f64, f64)>>,
    /// One record y\[0..N] of the truth at the nominal covariances (column k = y\[k]), from a random
    /// stream no trial uses: the data a user would have to tune a filter on.
    pub pilot_record: &'a dyn Fn() -> Mat,
}

/// A family's analysis of a finished run: a typed record the reports format (the manifest lists it
/// as JSON; the report that knows the type reads it back with [`Finding::get`]).
#[derive(Clone, Debug)]
pub struct Finding {
    pub family: &'static str,
    pub record: Arc<dyn Record>,
}

impl Finding {
    /// The record as `T`, if it is one.
    pub fn get<T: 'static>(&self) -> Option<&T> {
        self.record.as_any().downcast_ref()
    }
}

/// A family with its parameters read: what an experiment's filter carries until it is designed.
pub trait Configured: Debug + Send + Sync {
    fn family(&self) -> &'static str;
    fn supports(&self) -> Supports;
    fn footprint(&self, plant: PlantSize) -> Footprint;
    fn design(&self, input: &DesignInput) -> Result<Design>;
    fn after_run(&self, run: &RunView, mine: &[usize]) -> Result<Option<Finding>>;
}

/// The figure of a family whose design Riccati recursion predicts its error (intermittent,
/// Markov-jump with finite-horizon gains).
#[derive(Debug, serde::Serialize)]
pub struct Predicted {
    /// The summed error the design's Riccati recursion predicts.
    pub riccati_summed_error: f64,
}

impl Record for Predicted {}

/// The covariance a family designs at, `filters.NAME.design`: any choice but those that name
/// another filter (`worst_for`, `design_of`), which `who` refuses (a filter designed at its own
/// covariance cannot wait for another's design).
pub(super) fn own_design_point(input: &DesignInput, choice: &CovChoiceFile, who: &str) -> Result<Covariances> {
    let key = input.key("design");
    if matches!(choice, CovChoiceFile::WorstFor { .. } | CovChoiceFile::DesignOf { .. }) {
        return Err(Error::invalid(key, format!("{who} cannot be designed at another filter's covariance")));
    }
    input.design_point(&key, choice, input.has_sets())
}

/// A filter designed at `cov` that promises its exact error there (`exact_at_design`).
pub fn exact_at_design(
    plant: &crate::model::plant::Plant,
    realization: Realization,
    cov: Covariances,
    diagnostics: serde_json::Map<String, serde_json::Value>,
) -> Design {
    let at = crate::analysis::exact::error(plant, &realization, &cov);
    Design {
        guarantee: Some(Guarantee { kind: GuaranteeKind::ExactAtDesign, total: at.total, per_step: at.per_step }),
        design_covariance: Some(cov),
        ..Design::new(realization, diagnostics)
    }
}
