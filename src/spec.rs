//! Experiment files: the TOML schema, its parsing (every error names the offending key) and its
//! validation into a resolved [`Experiment`]. Every key is documented in the README.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use crate::disturbance::{Disturbance, DisturbanceChoice};
use crate::error::{Error, Result};
use crate::kind::{self, Kinds, Strict};
use crate::linalg::{Mat, Vector, check_psd, from_rows};
use crate::noise::{CovChoice, Shape};
use crate::plant::{Covariances, Plant};
use crate::uncertainty::{CovSet, SetShape};

type Rows = Vec<Vec<f64>>;

/// Information pattern (SPEC §0): filtering lets ẑ[k] use y[k]; prediction uses y[0..k-1] only.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Pattern {
    Filtering,
    Prediction,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ExperimentFile {
    description: String,
    seed: u64,
    trials: usize,
    pattern: Pattern,
    #[serde(default = "default_samples")]
    sample_trajectories: usize,
    /// Total anisotropy a at which every filter's exact a-anisotropic norm is reported (seed 003).
    anisotropy: Option<f64>,
    /// The plant's matrices, or none when `string` generates them.
    plant: Option<PlantFile>,
    /// The vibrating string of seed 004 (generates the plant and the nominal covariances).
    string: Option<crate::string::StringFile>,
    modes: Option<ModesFile>,
    #[serde(default)]
    nominal: BTreeMap<String, Rows>,
    #[serde(default)]
    sets: BTreeMap<String, Strict<SetFile>>,
    #[serde(default)]
    disturbances: BTreeMap<String, DisturbanceFile>,
    scenarios: Vec<ScenarioFile>,
    #[serde(default)]
    filters: Vec<FilterFile>,
    /// Families of filters over a grid of parameter values, expanded into `filters`.
    #[serde(default)]
    filter_sweeps: Vec<SweepFile>,
    /// Patches of this file, each run as its own variant (read by [`load_variants`]).
    #[serde(default)]
    #[allow(dead_code)]
    variants: Vec<toml::Table>,
}

fn default_samples() -> usize {
    3
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlantFile {
    horizon: usize,
    A: Rows,
    B: Rows,
    C: Rows,
    D: Rows,
    Cz: Option<Rows>,
    Dz: Option<Rows>,
    x0_mean: Option<Vec<f64>>,
    noise_blocks: Vec<String>,
    #[serde(default)]
    first_measurement: usize,
    #[serde(default)]
    sum_from: usize,
    C_steps: Option<Vec<Rows>>,
    known_input: Option<Strict<KnownInputFile>>,
    /// Probability p that a measurement arrives (seed 003: y = λ C x + D w, λ ~ Bernoulli(p)).
    arrival: Option<f64>,
}

/// Markov-switching matrices (seed 001): the chain and each mode's overrides of the plant's A, B,
/// C, D (a matrix not given is the plant's).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ModesFile {
    /// Π[s][k] = P(θ[n+1] = k | θ[n] = s).
    transition: Rows,
    /// p(0); default the stationary distribution.
    initial: Option<Vec<f64>>,
    mode: Vec<ModeFile>,
}

#[allow(non_snake_case)]
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ModeFile {
    name: String,
    A: Option<Rows>,
    B: Option<Rows>,
    C: Option<Rows>,
    D: Option<Rows>,
}

#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum KnownInputFile {
    /// r[k] given row by row, one row per step k = 0..N-1.
    Values { values: Rows },
    /// r_i[k] = amplitude_i · sin(frequency · k + phase).
    Sine {
        amplitude: Vec<f64>,
        frequency: f64,
        #[serde(default)]
        phase: f64,
    },
}

#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum SetFile {
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
enum HalfWidth {
    Scalar(f64),
    Matrix(Rows),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ScenarioFile {
    name: String,
    #[serde(default)]
    covariance: CovChoiceFile,
    #[serde(default, deserialize_with = "kind::strict")]
    shape: Shape,
    #[serde(default, deserialize_with = "kind::strict")]
    disturbance: DisturbanceChoice<String>,
    #[serde(default, deserialize_with = "kind::strict")]
    input: Input<String>,
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

/// How a scenario's inputs are drawn: block by block and white in time (the default), or jointly
/// over the horizon as ξ = col(x0 − E x0, w[0..N−1]) (seed 002's setting; w[N] = 0). `F` refers to
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
    /// ξ ~ (0, Σ) with Σ a random full covariance (fixed by the seed), E[ξᵀK⁻¹ξ] = dim.
    RandomCovariance { seed: u64 },
    /// The worst input on the ellipsoid for the named filter (the top eigenvector of ΨKΨᵀ).
    EllipsoidWorstFor { filter: F },
    /// Gaussian W = col(w[0..N]) coloured in time (AR(1) per component, the nominal covariance per
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
    fn map_filter<G>(self, f: impl FnOnce(F) -> Result<G>) -> Result<Input<G>> {
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

/// An energy-bounded deterministic disturbance block (seed 000 eq (36)).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DisturbanceFile {
    weight: Rows,
    energy: f64,
}

/// A covariance choice as written in a file (`{ kind = …, … }` or a bare kind name); see [`CovChoice`].
#[derive(Deserialize, Default)]
#[serde(try_from = "toml::Value")]
pub(crate) enum CovChoiceFile {
    #[default]
    Nominal,
    Given {
        blocks: BTreeMap<String, Rows>,
    },
    Vertex {
        seed: u64,
    },
    Interior {
        seed: u64,
    },
    WorstFor {
        filter: String,
    },
    DesignOf {
        filter: String,
    },
    ElementwiseMax,
}

/// The kinds of covariance choice and their keys; `given` names its blocks as keys beside `kind`.
const COV_KINDS: &[(&str, &[&str])] = &[
    ("nominal", &[]),
    ("given", &[]),
    ("vertex", &["seed"]),
    ("interior", &["seed"]),
    ("elementwise_max", &[]),
    ("worst_for", &["filter"]),
    ("design_of", &["filter"]),
];

impl TryFrom<toml::Value> for CovChoiceFile {
    type Error = String;
    fn try_from(v: toml::Value) -> std::result::Result<Self, String> {
        let mut t = kind::check_table("covariance", COV_KINDS, &["given"], v)?;
        let kind = t.remove("kind").and_then(|k| k.as_str().map(str::to_string)).unwrap_or_default();
        fn field<T: serde::de::DeserializeOwned>(
            t: &mut toml::Table,
            kind: &str,
            key: &str,
        ) -> std::result::Result<T, String> {
            let v = t.remove(key).ok_or_else(|| format!("missing field `{key}` for covariance kind `{kind}`"))?;
            T::deserialize(v).map_err(|e| format!("`{key}`: {}", e.message().trim()))
        }
        Ok(match kind.as_str() {
            "nominal" => CovChoiceFile::Nominal,
            "given" => CovChoiceFile::Given {
                blocks: std::mem::take(&mut t)
                    .into_iter()
                    .map(|(k, v)| {
                        let rows = Rows::deserialize(v).map_err(|e| format!("`{k}`: {}", e.message().trim()))?;
                        Ok((k, rows))
                    })
                    .collect::<std::result::Result<_, String>>()?,
            },
            "vertex" => CovChoiceFile::Vertex { seed: field(&mut t, &kind, "seed")? },
            "interior" => CovChoiceFile::Interior { seed: field(&mut t, &kind, "seed")? },
            "elementwise_max" => CovChoiceFile::ElementwiseMax,
            "worst_for" => CovChoiceFile::WorstFor { filter: field(&mut t, &kind, "filter")? },
            _ => CovChoiceFile::DesignOf { filter: field(&mut t, &kind, "filter")? },
        })
    }
}

/// `{ name = "template {key}", family, sweep = { key = [values…] }, …fixed parameters }`: one filter
/// per combination of the swept values (the last key varies fastest), named by the template.
#[derive(Deserialize)]
struct SweepFile {
    name: String,
    family: String,
    sweep: toml::Table,
    #[serde(flatten)]
    params: toml::Table,
}

impl SweepFile {
    fn expand(&self, i: usize) -> Result<Vec<FilterFile>> {
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
struct FilterFile {
    name: String,
    family: String,
    #[serde(flatten)]
    params: toml::Table,
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

/// A filter entry: its name, its family, and the family's own parameters (parsed by the family).
#[derive(Clone, Debug)]
pub struct FilterSpec {
    pub name: String,
    pub family: String,
    pub params: toml::Table,
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
    /// The total anisotropy a at which every filter's a-anisotropic norm is reported, if any.
    pub anisotropy: Option<f64>,
    pub plant: Plant,
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
    pub string: Option<crate::string::StringModel>,
}

impl Experiment {
    pub fn has_sets(&self) -> bool {
        self.sets.iter().any(Option::is_some)
    }
    /// The covariances noise is drawn with: deterministic disturbance blocks have none (their
    /// entry in `cov` is the design surrogate energy · W⁻¹).
    pub fn sampling(&self, cov: &Covariances) -> Covariances {
        let mut out = cov.clone();
        for (b, d) in out.blocks.iter_mut().zip(&self.disturbances) {
            if d.is_some() {
                b.fill(0.0);
            }
        }
        out
    }
    pub fn has_disturbances(&self) -> bool {
        self.disturbances.iter().any(Option::is_some)
    }
    pub fn filter_index(&self, name: &str) -> Option<usize> {
        self.filters.iter().position(|f| f.name == name)
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

/// The one rule for `sample_trajectories`: at most one per trial, so a value above the trial count
/// (from the file, or after `--trials` lowered it) keeps every trial's trajectory.
pub fn sample_count(sample_trajectories: usize, trials: usize) -> usize {
    sample_trajectories.min(trials)
}

/// What can be checked of the scenarios without designing a filter, so a bad scenario fails in
/// seconds and not after every design: the coloured input's anisotropy against white noise's.
fn check_scenarios_before_design(plant: &Plant, nominal: &Covariances, scenarios: &[Scenario]) -> Result<()> {
    for (i, s) in scenarios.iter().enumerate() {
        if let Input::Coloured { anisotropy } = &s.input {
            let w = nominal.w();
            let white = plant.steps() as f64 * crate::anisotropy::gaussian_anisotropy(&w);
            let key = format!("scenarios.{}.input.anisotropy (scenarios[{i}])", s.name);
            if !white.is_finite() {
                return Err(Error::invalid(
                    key,
                    "the nominal noise covariance is singular: its anisotropy is infinite",
                ));
            }
            if *anisotropy < white - 1e-12 {
                return Err(Error::invalid(
                    key,
                    format!(
                        "white noise with the nominal covariance already has anisotropy {white:.6}; a coloured input cannot have less (got {anisotropy})"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Reads and validates an experiment file. `name` is the experiment's name (the file stem).
pub fn load(path: &Path) -> Result<Experiment> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("experiment").to_string();
    parse(&name, &path.display().to_string(), &text)
}

/// Reads an experiment file and returns one experiment per `[[variants]]` entry: the file with the
/// entry's keys merged in (tables key by key, anything else replaced), named by its `name`. A file
/// without variants gives itself. The base file must be valid on its own.
pub fn load_variants(path: &Path) -> Result<Vec<Experiment>> {
    let base = load(path)?;
    let file = path.display().to_string();
    let mut doc: toml::Table =
        toml::from_str(&base.source).map_err(|e| Error::Parse { file: file.clone(), message: e.to_string() })?;
    let Some(variants) = doc.remove("variants") else { return Ok(vec![base]) };
    let variants = variants.as_array().cloned().unwrap_or_default();
    let mut out = Vec::with_capacity(variants.len());
    let mut seen = std::collections::BTreeSet::new();
    for (i, v) in variants.into_iter().enumerate() {
        let key = format!("variants[{i}]");
        let mut patch = match v {
            toml::Value::Table(t) => t,
            _ => return Err(Error::invalid(key, "each variant is a table")),
        };
        let name = match patch.remove("name") {
            Some(toml::Value::String(n)) => n,
            _ => return Err(Error::invalid(format!("{key}.name"), "each variant needs a `name` (a string)")),
        };
        check_name(&format!("{key}.name"), &name)?;
        if !seen.insert(name.clone()) {
            return Err(Error::invalid(format!("{key}.name"), format!("variant name `{name}` is repeated")));
        }
        let mut merged = doc.clone();
        merge(&mut merged, patch);
        let raw: ExperimentFile =
            serde_path_to_error::deserialize(toml::Value::Table(merged)).map_err(|e| Error::Parse {
                file: file.clone(),
                message: format!("variant `{name}`: key `{}`: {}", e.path(), e.inner().message().trim()),
            })?;
        let mut exp = resolve_file(&base.name, raw, &base.source)
            .map_err(|e| Error::Parse { file: file.clone(), message: format!("variant `{name}`: {e}") })?;
        exp.variant = Some(name);
        out.push(exp);
    }
    if out.is_empty() {
        return Err(Error::invalid("variants", "the list of variants is empty"));
    }
    Ok(out)
}

/// Merges `patch` into `doc`: tables key by key, any other value replaced.
fn merge(doc: &mut toml::Table, patch: toml::Table) {
    for (k, v) in patch {
        match (doc.get_mut(&k), v) {
            (Some(toml::Value::Table(d)), toml::Value::Table(p)) => merge(d, p),
            (_, v) => {
                doc.insert(k, v);
            }
        }
    }
}

/// Parses experiment text; `file` is only used in messages.
pub fn parse(name: &str, file: &str, text: &str) -> Result<Experiment> {
    check_name("experiment name", name)?;
    let raw: ExperimentFile = deserialize(file, text)?;
    resolve_file(name, raw, text)
}

/// Resolves a file, generating the plant and the nominal covariances first when it describes a
/// string (seed 004) instead of giving matrices.
fn resolve_file(name: &str, mut raw: ExperimentFile, text: &str) -> Result<Experiment> {
    let Some(sf) = raw.string.take() else {
        if raw.plant.is_none() {
            return Err(Error::invalid("plant", "missing: give [plant] or [string]"));
        }
        return resolve(name, raw, text);
    };
    if raw.plant.is_some() || !raw.nominal.is_empty() || raw.modes.is_some() {
        return Err(Error::invalid(
            "string",
            "[string] generates the plant and its covariances: remove [plant], [nominal] and [modes]",
        ));
    }
    let model = crate::string::StringModel::from_file(&sf)?;
    let (plant, cov) = model.plant(sf.duration);
    let rows = |m: &Mat| -> Rows { (0..m.nrows()).map(|i| m.row(i).iter().copied().collect()).collect() };
    raw.plant = Some(PlantFile {
        horizon: plant.horizon,
        A: rows(&plant.a),
        B: rows(&plant.b),
        C: rows(&plant.c),
        D: rows(&plant.d),
        Cz: Some(rows(&plant.cz)),
        Dz: Some(rows(&plant.dz)),
        x0_mean: None,
        noise_blocks: plant.noise_blocks.iter().map(|(n, _)| n.clone()).collect(),
        first_measurement: 0,
        sum_from: 0,
        C_steps: None,
        known_input: None,
        arrival: None,
    });
    for (n, m) in plant.block_names().iter().zip(&cov.blocks) {
        raw.nominal.insert(n.to_string(), rows(m));
    }
    let mut exp = resolve(name, raw, text)?;
    exp.string = Some(model);
    Ok(exp)
}

fn deserialize<T: serde::de::DeserializeOwned>(file: &str, text: &str) -> Result<T> {
    let line_of = |span: Option<std::ops::Range<usize>>| {
        span.map(|s| format!(" (line {})", text[..s.start.min(text.len())].lines().count().max(1))).unwrap_or_default()
    };
    let de = toml::Deserializer::parse(text).map_err(|e| Error::Parse {
        file: file.to_string(),
        message: format!("TOML syntax: {}{}", e.message().trim(), line_of(e.span())),
    })?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.inner();
        let key = if path == "." { String::new() } else { format!("key `{path}`: ") };
        Error::Parse {
            file: file.to_string(),
            message: format!("{key}{}{}", inner.message().trim(), line_of(inner.span())),
        }
    })
}

/// Parses one family's parameter table with the family's own schema (unknown keys are errors).
pub fn family_params<T: serde::de::DeserializeOwned>(filter: &FilterSpec) -> Result<T> {
    let v = toml::Value::Table(filter.params.clone());
    serde_path_to_error::deserialize(v).map_err(|e| {
        let path = e.path().to_string();
        let key =
            if path == "." { format!("filters.{}", filter.name) } else { format!("filters.{}.{path}", filter.name) };
        Error::invalid(key, e.inner().message().trim().to_string())
    })
}

/// Resolves a covariance given block by block (missing blocks fall back to `nominal`). `key`
/// prefixes the error messages.
pub(crate) fn given_covariances(
    key: &str,
    plant: &Plant,
    nominal: &Covariances,
    blocks: &BTreeMap<String, Rows>,
) -> Result<Covariances> {
    let names = plant.block_names();
    let mut out = nominal.clone();
    for (bname, rows) in blocks {
        let i = names.iter().position(|n| n == bname).ok_or_else(|| {
            Error::invalid(format!("{key}.{bname}"), format!("unknown covariance block (known: {})", names.join(", ")))
        })?;
        let d = nominal.blocks[i].nrows();
        let m = from_rows(&format!("{key}.{bname}"), rows, Some((d, d)))?;
        check_psd(&format!("{key}.{bname}"), &m)?;
        out.blocks[i] = m;
    }
    Ok(out)
}

fn resolve(name: &str, mut f: ExperimentFile, text: &str) -> Result<Experiment> {
    let p = f.plant.as_ref().expect("resolve_file checked the plant");
    if p.horizon == 0 {
        return Err(Error::invalid("plant.horizon", "the horizon N must be at least 1"));
    }
    check_trials("trials", f.trials)?;
    let a = from_rows("plant.A", &p.A, None)?;
    let n = a.nrows();
    if n == 0 || !a.is_square() {
        return Err(Error::invalid(
            "plant.A",
            format!("must be square and non-empty, found {}×{}", a.nrows(), a.ncols()),
        ));
    }
    let b = from_rows("plant.B", &p.B, None)?;
    if b.nrows() != n {
        return Err(Error::invalid("plant.B", format!("expected {n} rows (the state dimension), found {}", b.nrows())));
    }
    let nw = b.ncols();
    let c = from_rows("plant.C", &p.C, None)?;
    if c.ncols() != n {
        return Err(Error::invalid(
            "plant.C",
            format!("expected {n} columns (the state dimension), found {}", c.ncols()),
        ));
    }
    let ny = c.nrows();
    let d = from_rows("plant.D", &p.D, Some((ny, nw)))?;
    let cz = match &p.Cz {
        Some(r) => from_rows("plant.Cz", r, None)?,
        None => Mat::identity(n, n),
    };
    if cz.ncols() != n {
        return Err(Error::invalid(
            "plant.Cz",
            format!("expected {n} columns (the state dimension), found {}", cz.ncols()),
        ));
    }
    let nz = cz.nrows();
    let dz = match &p.Dz {
        Some(r) => from_rows("plant.Dz", r, Some((nz, nw)))?,
        None => Mat::zeros(nz, nw),
    };
    let x0_mean = match &p.x0_mean {
        Some(v) if v.len() != n => {
            return Err(Error::invalid("plant.x0_mean", format!("expected {n} entries, found {}", v.len())));
        }
        Some(v) => Vector::from_column_slice(v),
        None => Vector::zeros(n),
    };
    if p.sum_from > p.horizon {
        return Err(Error::invalid("plant.sum_from", "must not exceed the horizon"));
    }
    if p.first_measurement > p.horizon {
        return Err(Error::invalid("plant.first_measurement", "must not exceed the horizon"));
    }
    let known_input = match &p.known_input {
        None => Vec::new(),
        Some(Strict(KnownInputFile::Values { values })) => {
            let m = from_rows("plant.known_input.values", values, Some((p.horizon, n)))?;
            (0..p.horizon).map(|k| m.row(k).transpose()).collect()
        }
        Some(Strict(KnownInputFile::Sine { amplitude, frequency, phase })) => {
            if amplitude.len() != n {
                return Err(Error::invalid(
                    "plant.known_input.amplitude",
                    format!("expected {n} entries, found {}", amplitude.len()),
                ));
            }
            (0..p.horizon)
                .map(|k| Vector::from_iterator(n, amplitude.iter().map(|a| a * (frequency * k as f64 + phase).sin())))
                .collect()
        }
    };

    // Covariance blocks: x0 first, then the noise blocks in the order `plant.noise_blocks` gives.
    let mut seen = std::collections::BTreeSet::new();
    for (i, bn) in p.noise_blocks.iter().enumerate() {
        check_name(&format!("plant.noise_blocks[{i}]"), bn)?;
        if bn == "x0" || !seen.insert(bn.as_str()) {
            return Err(Error::invalid("plant.noise_blocks", format!("block name `{bn}` is reserved or repeated")));
        }
    }
    for key in f.nominal.keys() {
        if key != "x0" && !seen.contains(key.as_str()) {
            return Err(Error::invalid(
                format!("nominal.{key}"),
                "not a covariance block: expected `x0` or one of plant.noise_blocks",
            ));
        }
    }
    for key in f.disturbances.keys() {
        if !seen.contains(key.as_str()) {
            return Err(Error::invalid(
                format!("disturbances.{key}"),
                "not a noise block: expected one of plant.noise_blocks",
            ));
        }
        if f.nominal.contains_key(key) {
            return Err(Error::invalid(
                format!("nominal.{key}"),
                "a disturbance block has no covariance (it is deterministic, bounded in energy by [disturbances]): remove it",
            ));
        }
    }
    let mut blocks = Vec::new();
    let mut dims = Vec::new();
    let mut disturbances = vec![None];
    for bn in std::iter::once("x0").chain(p.noise_blocks.iter().map(String::as_str)) {
        if let Some(df) = f.disturbances.get(bn) {
            let key = format!("disturbances.{bn}");
            let w = from_rows(&format!("{key}.weight"), &df.weight, None)?;
            check_psd(&format!("{key}.weight"), &w)?;
            if w.is_empty() || nalgebra::Cholesky::new(w.clone()).is_none() || crate::linalg::min_eigenvalue(&w) <= 0.0
            {
                return Err(Error::invalid(format!("{key}.weight"), "the weight must be positive definite"));
            }
            if !(df.energy >= 0.0 && df.energy.is_finite()) {
                return Err(Error::invalid(format!("{key}.energy"), "the energy bound must be finite and ≥ 0"));
            }
            let d = Disturbance { weight: w, energy: df.energy };
            dims.push((bn.to_string(), d.weight.nrows()));
            blocks.push(d.surrogate_covariance());
            disturbances.push(Some(d));
            continue;
        }
        if bn != "x0" {
            disturbances.push(None);
        }
        let key = format!("nominal.{bn}");
        let rows = f.nominal.get(bn).ok_or_else(|| Error::invalid(&key, "missing covariance"))?;
        let m = from_rows(&key, rows, None)?;
        if bn == "x0" && m.shape() != (n, n) {
            return Err(Error::invalid(key, format!("expected a {n}×{n} matrix, found {}×{}", m.nrows(), m.ncols())));
        }
        check_psd(&key, &m)?;
        if bn != "x0" {
            dims.push((bn.to_string(), m.nrows()));
        }
        blocks.push(m);
    }
    let total: usize = dims.iter().map(|(_, d)| d).sum();
    if total != nw {
        return Err(Error::invalid(
            "nominal",
            format!("the noise blocks have {total} components in all but plant.B has {nw} columns"),
        ));
    }
    let mut plant = Plant::new(p.horizon, a, b, c, d, cz, dz, x0_mean, p.first_measurement, known_input, dims);
    plant.sum_from = p.sum_from;
    if let Some(steps) = &p.C_steps {
        if steps.len() != p.horizon + 1 {
            return Err(Error::invalid(
                "plant.C_steps",
                format!("expected one matrix per step k = 0..N ({}), found {}", p.horizon + 1, steps.len()),
            ));
        }
        plant.c_steps = steps
            .iter()
            .enumerate()
            .map(|(k, r)| from_rows(&format!("plant.C_steps[{k}]"), r, Some((ny, n))))
            .collect::<Result<_>>()?;
    }
    if let Some(pa) = p.arrival {
        if !(pa > 0.0 && pa <= 1.0) {
            return Err(Error::invalid("plant.arrival", format!("a probability in (0, 1] is needed, got {pa}")));
        }
        if !p.C_steps.as_ref().is_none_or(Vec::is_empty) {
            return Err(Error::invalid("plant.arrival", "dropouts with a time-varying C (C_steps) are not supported"));
        }
        plant.set_arrival(pa);
    }
    if let Some(mf) = &f.modes {
        if plant.arrival.is_some() {
            return Err(Error::invalid("modes", "a plant has either dropouts (plant.arrival) or [modes], not both"));
        }
        if !plant.c_steps.is_empty() {
            return Err(Error::invalid("modes", "Markov modes with a time-varying C (C_steps) are not supported"));
        }
        plant.modes = Some(resolve_modes(mf, &plant)?);
    }
    let nominal = Covariances { blocks };

    let names: Vec<String> = plant.block_names().iter().map(|s| s.to_string()).collect();
    let mut sets: Vec<Option<CovSet>> = vec![None; names.len()];
    for (bn, Strict(s)) in &f.sets {
        let key = format!("sets.{bn}");
        if f.disturbances.contains_key(bn) {
            return Err(Error::invalid(key, "a disturbance block has an energy bound, not a covariance set"));
        }
        let i = names
            .iter()
            .position(|n| n == bn)
            .ok_or_else(|| Error::invalid(&key, format!("unknown covariance block (known: {})", names.join(", "))))?;
        let nom = &nominal.blocks[i];
        let d = nom.nrows();
        let matrix = |name: &str, r: &Rows| from_rows(&format!("{key}.{name}"), r, Some((d, d)));
        let center = |c: &Option<Rows>| c.as_ref().map_or(Ok(nom.clone()), |r| matrix("center", r));
        let (shape, psd) = match s {
            SetFile::Box { half_width, center: c, psd } => {
                let half_width = match half_width {
                    HalfWidth::Scalar(v) => Mat::from_element(d, d, *v),
                    HalfWidth::Matrix(r) => matrix("half_width", r)?,
                };
                (SetShape::Box { center: center(c)?, half_width }, *psd)
            }
            SetFile::Ball { radius, center: c, psd } => (SetShape::Ball { center: center(c)?, radius: *radius }, *psd),
            SetFile::Loewner { lower, upper, psd } => {
                (SetShape::Loewner { lower: matrix("lower", lower)?, upper: matrix("upper", upper)? }, *psd)
            }
        };
        sets[i] = Some(CovSet::new(&key, shape, psd, nom)?);
    }

    let mut filters_in = std::mem::take(&mut f.filters);
    for (i, sw) in f.filter_sweeps.iter().enumerate() {
        filters_in.extend(sw.expand(i)?);
    }
    f.filters = filters_in;
    if f.filters.is_empty() {
        return Err(Error::invalid("filters", "the experiment names no filter"));
    }
    let mut fnames = std::collections::BTreeSet::new();
    for (i, fl) in f.filters.iter().enumerate() {
        check_name(&format!("filters[{i}].name"), &fl.name)?;
        if !fnames.insert(fl.name.as_str()) {
            return Err(Error::invalid(format!("filters[{i}].name"), format!("filter name `{}` is repeated", fl.name)));
        }
        if !crate::families::registry::is_family(&fl.family) {
            return Err(Error::invalid(
                format!("filters.{}.family", fl.name),
                format!("unknown family `{}` (known: {})", fl.family, crate::families::registry::FAMILIES.join(", ")),
            ));
        }
    }
    let filters: Vec<FilterSpec> =
        f.filters.into_iter().map(|fl| FilterSpec { name: fl.name, family: fl.family, params: fl.params }).collect();

    if f.scenarios.is_empty() {
        return Err(Error::invalid("scenarios", "the experiment names no scenario"));
    }
    let has_sets = sets.iter().any(Option::is_some);
    let mut scenarios = Vec::new();
    let mut snames = std::collections::BTreeSet::new();
    for (i, s) in f.scenarios.into_iter().enumerate() {
        check_name(&format!("scenarios[{i}].name"), &s.name)?;
        if !snames.insert(s.name.clone()) {
            return Err(Error::invalid(
                format!("scenarios[{i}].name"),
                format!("scenario name `{}` is repeated", s.name),
            ));
        }
        let key = format!("scenarios.{}.covariance", s.name);
        let covariance = CovChoice::resolve(&key, &s.covariance, &plant, &nominal, has_sets, &filters)?;
        s.shape.validate(&format!("scenarios.{}.shape", s.name))?;
        let filters = &filters;
        let index_of = |key: String| {
            move |name: String| {
                filters.iter().position(|x| x.name == name).ok_or_else(|| {
                    Error::invalid(format!("{key}.filter"), format!("no filter named `{name}` in this experiment"))
                })
            }
        };
        let dkey = format!("scenarios.{}.disturbance", s.name);
        if s.disturbance != DisturbanceChoice::None && !disturbances.iter().any(Option::is_some) {
            return Err(Error::invalid(dkey, "the plant has no [disturbances] block"));
        }
        let disturbance = s.disturbance.map_filter(index_of(dkey))?;
        let ikey = format!("scenarios.{}.input", s.name);
        if s.input != Input::Independent
            && (!matches!(covariance, CovChoice::Nominal) || disturbance != DisturbanceChoice::None)
        {
            return Err(Error::invalid(ikey, "a joint input replaces `covariance` and `disturbance`: remove them"));
        }
        if let Input::Coloured { anisotropy: a } | Input::AnisotropicWorstFor { anisotropy: a, .. } = &s.input {
            if !(*a >= 0.0 && a.is_finite()) {
                return Err(Error::invalid(format!("{ikey}.anisotropy"), format!("must be finite and ≥ 0, got {a}")));
            }
        }
        let input = s.input.map_filter(index_of(ikey))?;
        scenarios.push(Scenario { name: s.name, covariance, shape: s.shape, disturbance, input });
    }
    if let Some(a) = f.anisotropy {
        if !(a >= 0.0 && a.is_finite()) {
            return Err(Error::invalid("anisotropy", format!("must be finite and ≥ 0, got {a}")));
        }
    }
    check_scenarios_before_design(&plant, &nominal, &scenarios)?;

    Ok(Experiment {
        name: name.to_string(),
        variant: None,
        description: f.description,
        seed: f.seed,
        trials: f.trials,
        pattern: f.pattern,
        sample_trajectories: sample_count(f.sample_trajectories, f.trials),
        anisotropy: f.anisotropy,
        plant,
        nominal,
        sets,
        disturbances,
        scenarios,
        filters,
        source: text.to_string(),
        string: None,
    })
}

/// Validates a Markov chain and its modes: Π square with one row per mode, non-negative, rows
/// summing to 1; p(0) likewise (default: the stationary distribution, which must then exist).
fn resolve_modes(mf: &ModesFile, plant: &Plant) -> Result<crate::plant::Modes> {
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
    let pick = |key: &str, given: &Option<Rows>, base: &Mat, shape: (usize, usize)| -> Result<Mat> {
        given.as_ref().map_or(Ok(base.clone()), |r| from_rows(key, r, Some(shape)))
    };
    let mut modes = crate::plant::Modes {
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

/// The one-line description of an experiment file, for `filterbench list` (None if unreadable).
pub fn describe(path: &Path) -> Option<String> {
    #[derive(Deserialize)]
    struct Head {
        description: String,
    }
    let text = std::fs::read_to_string(path).ok()?;
    toml::from_str::<Head>(&text).ok().map(|h| h.description)
}
