//! The experiment file as written: the TOML schema that serde reads with `deny_unknown_fields`
//! (every key documented in docs/experiment-files.md), before [`super::resolve`] validates it.

use std::collections::BTreeMap;

use serde::Deserialize;

use super::experiment::Input;
use crate::error::{Error, Result};
use crate::model::choice::CovChoiceFile;
use crate::model::disturbance::DisturbanceChoice;
use crate::model::kind::{self, Kinds, Strict};
use crate::model::plant::Pattern;
use crate::model::shape::Shape;

pub(super) type Rows = Vec<Vec<f64>>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ExperimentFile {
    pub(super) description: String,
    pub(super) seed: u64,
    pub(super) trials: usize,
    pub(super) pattern: Pattern,
    #[serde(default = "default_samples")]
    pub(super) sample_trajectories: usize,
    /// Total anisotropy a at which every filter's exact a-anisotropic norm is reported (seed 003).
    pub(super) anisotropy: Option<f64>,
    /// The plant's matrices, or none when `string` generates them.
    pub(super) plant: Option<PlantFile>,
    /// The vibrating string of seed 004 (generates the plant and the nominal covariances).
    pub(super) string: Option<crate::model::string::StringFile>,
    pub(super) modes: Option<ModesFile>,
    #[serde(default)]
    pub(super) nominal: BTreeMap<String, Rows>,
    #[serde(default)]
    pub(super) sets: BTreeMap<String, Strict<SetFile>>,
    #[serde(default)]
    pub(super) disturbances: BTreeMap<String, DisturbanceFile>,
    pub(super) scenarios: Vec<ScenarioFile>,
    #[serde(default)]
    pub(super) filters: Vec<FilterFile>,
    /// Families of filters over a grid of parameter values, expanded into `filters`.
    #[serde(default)]
    pub(super) filter_sweeps: Vec<SweepFile>,
    /// What `filterbench check` tests (docs/checks.md).
    #[serde(default)]
    pub(super) expect: Vec<super::expect::ExpectFile>,
    /// `check`'s defaults.
    pub(super) check: Option<super::expect::CheckFile>,
    /// Patches of this file, each run as its own variant (read by [`load_variants`]).
    #[serde(default)]
    #[allow(dead_code)]
    pub(super) variants: Vec<toml::Table>,
}

pub(super) fn default_samples() -> usize {
    3
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PlantFile {
    pub(super) horizon: usize,
    pub(super) A: Rows,
    pub(super) B: Rows,
    pub(super) C: Rows,
    pub(super) D: Rows,
    pub(super) Cz: Option<Rows>,
    pub(super) Dz: Option<Rows>,
    pub(super) x0_mean: Option<Vec<f64>>,
    pub(super) noise_blocks: Vec<String>,
    #[serde(default)]
    pub(super) first_measurement: usize,
    #[serde(default)]
    pub(super) sum_from: usize,
    pub(super) C_steps: Option<Vec<Rows>>,
    /// Per-step lists k = 0..N replacing A, B, D, Cz, Dz (seed 003 (3.1): a time-varying plant).
    pub(super) A_steps: Option<Vec<Rows>>,
    pub(super) B_steps: Option<Vec<Rows>>,
    pub(super) D_steps: Option<Vec<Rows>>,
    pub(super) Cz_steps: Option<Vec<Rows>>,
    pub(super) Dz_steps: Option<Vec<Rows>>,
    pub(super) known_input: Option<Strict<KnownInputFile>>,
    /// Probability p that a measurement arrives (seed 003: y = λ C x + D w, λ ~ Bernoulli(p)).
    pub(super) arrival: Option<f64>,
    /// Multiplicative noise factors (seed 003 (3.1)).
    #[serde(default)]
    pub(super) multiplicative: Vec<FactorFile>,
}

/// `[[plant.multiplicative]]`: one factor ζ(k) and the matrices M(k) it multiplies, each constant
/// or per step (`A` or `A_steps`, …).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub(super) struct FactorFile {
    pub(super) name: String,
    #[serde(default, deserialize_with = "kind::strict")]
    pub(super) shape: Shape,
    pub(super) A: Option<Rows>,
    pub(super) B: Option<Rows>,
    pub(super) C: Option<Rows>,
    pub(super) D: Option<Rows>,
    pub(super) Cz: Option<Rows>,
    pub(super) Dz: Option<Rows>,
    pub(super) A_steps: Option<Vec<Rows>>,
    pub(super) B_steps: Option<Vec<Rows>>,
    pub(super) C_steps: Option<Vec<Rows>>,
    pub(super) D_steps: Option<Vec<Rows>>,
    pub(super) Cz_steps: Option<Vec<Rows>>,
    pub(super) Dz_steps: Option<Vec<Rows>>,
}

/// Markov-switching matrices (seed 001): the chain and each mode's overrides of the plant's A, B,
/// C, D (a matrix not given is the plant's).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ModesFile {
    /// Π\[s]\[k] = P(θ\[n+1] = k | θ\[n] = s).
    pub(super) transition: Rows,
    /// p(0); default the stationary distribution.
    pub(super) initial: Option<Vec<f64>>,
    pub(super) mode: Vec<ModeFile>,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ModeFile {
    pub(super) name: String,
    pub(super) A: Option<Rows>,
    pub(super) B: Option<Rows>,
    pub(super) C: Option<Rows>,
    pub(super) D: Option<Rows>,
}

#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub(super) enum KnownInputFile {
    /// r\[k] given row by row, one row per step k = 0..N-1.
    Values { values: Rows },
    /// r_i\[k] = amplitude_i · sin(frequency · k + phase).
    Sine {
        amplitude: Vec<f64>,
        frequency: f64,
        #[serde(default)]
        phase: f64,
    },
}

#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub(super) enum SetFile {
    Box {
        half_width: HalfWidth,
        center: Option<Rows>,
        #[serde(default)]
        psd: bool,
    },
    Ball {
        radius: f64,
        center: Option<Rows>,
        #[serde(default)]
        psd: bool,
    },
    Loewner {
        lower: Rows,
        upper: Rows,
        #[serde(default)]
        psd: bool,
    },
}

#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum HalfWidth {
    Scalar(f64),
    Matrix(Rows),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ScenarioFile {
    pub(super) name: String,
    #[serde(default)]
    pub(super) covariance: CovChoiceFile,
    #[serde(default, deserialize_with = "kind::strict")]
    pub(super) shape: Shape,
    #[serde(default, deserialize_with = "kind::strict")]
    pub(super) disturbance: DisturbanceChoice<String>,
    #[serde(default, deserialize_with = "kind::strict")]
    pub(super) input: Input<String>,
}

impl Kinds for KnownInputFile {
    const WHAT: &'static str = "known input";
    const KINDS: &'static [(&'static str, &'static [&'static str])] =
        &[("values", &["values"]), ("sine", &["amplitude", "frequency", "phase"])];
}

impl Kinds for SetFile {
    const WHAT: &'static str = "set";
    const KINDS: &'static [(&'static str, &'static [&'static str])] = &[
        ("box", &["half_width", "center", "psd"]),
        ("ball", &["radius", "center", "psd"]),
        ("loewner", &["lower", "upper", "psd"]),
    ];
}

impl Kinds for Shape {
    const WHAT: &'static str = "shape";
    const KINDS: &'static [(&'static str, &'static [&'static str])] = &[
        ("gaussian", &[]),
        ("uniform", &[]),
        ("laplace", &[]),
        ("student_t", &["nu"]),
        ("rademacher", &[]),
        ("mixture", &["weight", "ratio"]),
    ];
}

impl Kinds for DisturbanceChoice<String> {
    const WHAT: &'static str = "disturbance";
    const KINDS: &'static [(&'static str, &'static [&'static str])] =
        &[("none", &[]), ("random", &["seed"]), ("worst_for", &["filter"])];
}

impl Kinds for Input<String> {
    const WHAT: &'static str = "input";
    const KINDS: &'static [(&'static str, &'static [&'static str])] = &[
        ("independent", &[]),
        ("ellipsoid_surface", &[]),
        ("ellipsoid_interior", &[]),
        ("random_covariance", &["seed"]),
        ("ellipsoid_worst_for", &["filter"]),
        ("coloured", &["anisotropy"]),
        ("anisotropic_worst_for", &["filter", "anisotropy"]),
    ];
}

/// An energy-bounded deterministic disturbance block (seed 000 eq (36)): one `weight` or one of
/// `weights` per step k = 0..N, and the summed bound `energy`, per-step bounds `step_energy`, or both.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DisturbanceFile {
    #[serde(default)]
    pub(super) weight: Option<Rows>,
    #[serde(default)]
    pub(super) weights: Option<Vec<Rows>>,
    #[serde(default)]
    pub(super) energy: Option<f64>,
    #[serde(default)]
    pub(super) step_energy: Option<Vec<f64>>,
}

/// `{ name = "template {key}", family, sweep = { key = [values…] }, …fixed parameters }`: one filter
/// per combination of the swept values (the last key varies fastest), named by the template.
#[derive(Deserialize)]
pub(super) struct SweepFile {
    pub(super) name: String,
    pub(super) family: String,
    pub(super) sweep: toml::Table,
    #[serde(flatten)]
    pub(super) params: toml::Table,
}

impl SweepFile {
    pub(super) fn expand(&self, i: usize) -> Result<Vec<FilterFile>> {
        let mut combos: Vec<(String, toml::Table)> = vec![(self.name.clone(), self.params.clone())];
        for (k, values) in &self.sweep {
            let key = format!("filter_sweeps[{i}].sweep.{k}");
            let values = values
                .as_array()
                .filter(|v| !v.is_empty())
                .ok_or_else(|| Error::invalid(&key, "a non-empty list of values"))?;
            if self.params.contains_key(k) {
                return Err(Error::invalid(key, "is both swept and fixed"));
            }
            let placeholder = format!("{{{k}}}");
            if !self.name.contains(&placeholder) {
                return Err(Error::invalid(
                    format!("filter_sweeps[{i}].name"),
                    format!("must contain {placeholder} so the filters get distinct names"),
                ));
            }
            combos = combos
                .into_iter()
                .flat_map(|(name, params)| {
                    let placeholder = &placeholder;
                    values.iter().map(move |v| {
                        let shown = match v {
                            toml::Value::String(s) => s.clone(),
                            other => other.to_string(),
                        };
                        let mut p = params.clone();
                        p.insert(k.clone(), v.clone());
                        (name.replace(placeholder.as_str(), &shown), p)
                    })
                })
                .collect();
        }
        Ok(combos.into_iter().map(|(name, params)| FilterFile { name, family: self.family.clone(), params }).collect())
    }
}

#[derive(Deserialize)]
pub(super) struct FilterFile {
    pub(super) name: String,
    pub(super) family: String,
    #[serde(flatten)]
    pub(super) params: toml::Table,
}
