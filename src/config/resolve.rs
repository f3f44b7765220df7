//! From the file as written to a validated [`Experiment`]: every dimension, name and reference
//! checked, each error naming its key.

use std::collections::BTreeMap;

use super::experiment::{
    Experiment, FilterSpec, Input, Overrides, Scenario, check_name, check_trials, filter_index, sample_count,
};
use super::plant::{plant, plant_matrices};
use super::schema::*;
use crate::analysis::anisotropy::gaussian_anisotropy;
use crate::error::{Error, Result};
use crate::model::choice::CovChoice;
use crate::model::disturbance::{Disturbance, DisturbanceChoice};
use crate::model::kind::Strict;
use crate::model::plant::{Covariances, Plant};
use crate::model::uncertainty::{CovSet, SetShape};
use crate::numerics::linalg::{Mat, check_psd, from_rows};

/// What can be checked of the scenarios without designing a filter, so a bad scenario fails in
/// seconds and not after every design: the coloured input's anisotropy against white noise's.
fn check_scenarios_before_design(plant: &Plant, nominal: &Covariances, scenarios: &[Scenario]) -> Result<()> {
    for (i, s) in scenarios.iter().enumerate() {
        if let Input::Coloured { anisotropy } = &s.input {
            let w = nominal.w();
            let white = plant.steps() as f64 * gaussian_anisotropy(&w);
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

/// Resolves a file, then refuses a filter whose family does not design for the plant
/// ([`crate::families::Supports::check`]), before anything is designed.
pub(super) fn resolve_file(name: &str, raw: ExperimentFile, text: &str, overrides: &Overrides) -> Result<Experiment> {
    let exp = resolve_plant(name, raw, text, overrides)?;
    for (i, f) in exp.filters.iter().enumerate() {
        f.configured.supports().check(f.configured.family(), &exp.design_input(i))?;
    }
    Ok(exp)
}

/// Resolves a file, generating the plant and the nominal covariances first when it describes a
/// string (seed 004) instead of giving matrices. The command line's `overrides` replace the file's
/// values once the file itself is valid.
fn resolve_plant(name: &str, mut raw: ExperimentFile, text: &str, overrides: &Overrides) -> Result<Experiment> {
    let Some(sf) = raw.string.take() else {
        if raw.plant.is_none() {
            return Err(Error::invalid("plant", "missing: give [plant] or [string]"));
        }
        return resolve(name, raw, text, overrides);
    };
    if raw.plant.is_some() || !raw.nominal.is_empty() || raw.modes.is_some() {
        return Err(Error::invalid(
            "string",
            "[string] generates the plant and its covariances: remove [plant], [nominal] and [modes]",
        ));
    }
    let model = crate::model::string::StringModel::from_file(&sf)?;
    let (plant, cov) = model.plant(sf.duration);
    let rows = |m: &Mat| -> Rows { (0..m.nrows()).map(|i| m.row(i).iter().copied().collect()).collect() };
    raw.plant = Some(PlantFile {
        horizon: plant.horizon,
        A: rows(plant.a_at(0)),
        B: rows(plant.b_at(0)),
        C: rows(plant.c.at(0)),
        D: rows(plant.d.at(0)),
        Cz: Some(rows(plant.cz_at(0))),
        Dz: Some(rows(plant.dz_at(0))),
        x0_mean: None,
        noise_blocks: plant.noise_blocks.iter().map(|(n, _)| n.clone()).collect(),
        first_measurement: 0,
        sum_from: 0,
        C_steps: None,
        A_steps: None,
        B_steps: None,
        D_steps: None,
        Cz_steps: None,
        Dz_steps: None,
        known_input: None,
        arrival: None,
        multiplicative: Vec::new(),
    });
    for (n, m) in plant.block_names().iter().zip(&cov.blocks) {
        raw.nominal.insert(n.to_string(), rows(m));
    }
    let mut exp = resolve(name, raw, text, overrides)?;
    // Time-varying intensities enter through B[k], D[k] (model::string): carried over as they are,
    // not through `B_steps`/`D_steps` rows (a full matrix per step for a large truth).
    if plant.b.varies() || plant.d.varies() {
        exp.plant.b = plant.b;
        exp.plant.d = plant.d;
    }
    exp.string = Some(model);
    Ok(exp)
}

pub(super) fn deserialize<T: serde::de::DeserializeOwned>(file: &str, text: &str) -> Result<T> {
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

fn resolve(name: &str, mut f: ExperimentFile, text: &str, overrides: &Overrides) -> Result<Experiment> {
    let p = f.plant.as_ref().expect("resolve_file checked the plant");
    if p.horizon == 0 {
        return Err(Error::invalid("plant.horizon", "the horizon N must be at least 1"));
    }
    check_trials("trials", f.trials)?;
    let m = plant_matrices(p)?;
    let (blocks, dims, disturbances) = covariance_blocks(p, &f.nominal, &f.disturbances, m.a.nrows(), m.b.ncols())?;
    let plant = plant(p, m, dims, f.modes.as_ref())?;
    let nominal = Covariances::new(blocks);
    let sets = sets(&f.sets, &f.disturbances, &plant, &nominal)?;
    let filters = filters(&mut f)?;
    let scenarios = scenarios(std::mem::take(&mut f.scenarios), &plant, &nominal, &sets, &disturbances, &filters)?;
    if let Some(a) = f.anisotropy {
        if !(a >= 0.0 && a.is_finite()) {
            return Err(Error::invalid("anisotropy", format!("must be finite and ≥ 0, got {a}")));
        }
    }
    check_scenarios_before_design(&plant, &nominal, &scenarios)?;
    let (known_s, known_f): (Vec<&str>, Vec<&str>) =
        (scenarios.iter().map(|s| s.name.as_str()).collect(), filters.iter().map(|f| f.name.as_str()).collect());
    let expectations = super::expect::expectations(std::mem::take(&mut f.expect), &known_s, &known_f)?;
    let check = super::expect::settings(f.check.take())?;
    // The command line's values, checked by the same rule as the file's but named by their flag.
    let trials = match overrides.trials {
        Some(t) => check_trials("--trials", t).map(|_| t)?,
        None => f.trials,
    };

    Ok(Experiment {
        name: name.to_string(),
        variant: None,
        description: f.description,
        seed: overrides.seed.unwrap_or(f.seed),
        trials,
        pattern: f.pattern,
        sample_trajectories: sample_count(f.sample_trajectories, trials),
        per_trial: overrides.per_trial,
        anisotropy: f.anisotropy,
        plant,
        nominal,
        sets,
        disturbances,
        scenarios,
        filters,
        source: text.to_string(),
        string: None,
        inputs: Vec::new(),
        expectations,
        check,
    })
}

/// The covariance blocks, x0 first and then the noise blocks in the order `plant.noise_blocks`
/// gives: each nominal covariance, zero for a disturbance block (it is not noise; its energy bound
/// is in the third list, and the designs see its surrogate through
/// [`Experiment::design_nominal`]). Returns the noise blocks' dimensions.
#[allow(clippy::type_complexity)]
fn covariance_blocks(
    p: &PlantFile,
    nominal: &BTreeMap<String, Rows>,
    disturbances_file: &BTreeMap<String, DisturbanceFile>,
    n: usize,
    nw: usize,
) -> Result<(Vec<Mat>, Vec<(String, usize)>, Vec<Option<Disturbance>>)> {
    let mut seen = std::collections::BTreeSet::new();
    for (i, bn) in p.noise_blocks.iter().enumerate() {
        check_name(&format!("plant.noise_blocks[{i}]"), bn)?;
        if bn == "x0" || !seen.insert(bn.as_str()) {
            return Err(Error::invalid("plant.noise_blocks", format!("block name `{bn}` is reserved or repeated")));
        }
    }
    for key in nominal.keys() {
        if key != "x0" && !seen.contains(key.as_str()) {
            return Err(Error::invalid(
                format!("nominal.{key}"),
                "not a covariance block: expected `x0` or one of plant.noise_blocks",
            ));
        }
    }
    for key in disturbances_file.keys() {
        if !seen.contains(key.as_str()) {
            return Err(Error::invalid(
                format!("disturbances.{key}"),
                "not a noise block: expected one of plant.noise_blocks",
            ));
        }
        if nominal.contains_key(key) {
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
        if let Some(df) = disturbances_file.get(bn) {
            let d = super::disturbance::resolve(&format!("disturbances.{bn}"), df, p.horizon + 1)?;
            let m = d.weights[0].nrows();
            dims.push((bn.to_string(), m));
            blocks.push(Mat::zeros(m, m));
            disturbances.push(Some(d));
            continue;
        }
        if bn != "x0" {
            disturbances.push(None);
        }
        let key = format!("nominal.{bn}");
        let rows = nominal.get(bn).ok_or_else(|| Error::invalid(&key, "missing covariance"))?;
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
    Ok((blocks, dims, disturbances))
}

/// Each `[sets.BLOCK]`: the uncertainty set of that covariance block (docs/math.md §2).
fn sets(
    files: &BTreeMap<String, Strict<SetFile>>,
    disturbances: &BTreeMap<String, DisturbanceFile>,
    plant: &Plant,
    nominal: &Covariances,
) -> Result<Vec<Option<CovSet>>> {
    let mut sets: Vec<Option<CovSet>> = vec![None; plant.block_names().len()];
    for (bn, Strict(s)) in files {
        let key = format!("sets.{bn}");
        if disturbances.contains_key(bn) {
            return Err(Error::invalid(key, "a disturbance block has an energy bound, not a covariance set"));
        }
        let i = plant.block_index(&key, bn)?;
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

    Ok(sets)
}

/// The filters, sweeps expanded, names checked, each family's parameters read.
fn filters(f: &mut ExperimentFile) -> Result<Vec<FilterSpec>> {
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
    }
    std::mem::take(&mut f.filters).into_iter().map(|fl| FilterSpec::new(fl.name, fl.family, fl.params)).collect()
}

/// The scenarios: names, the covariance choice, shape, disturbance and input, every filter they
/// name resolved to its index.
fn scenarios(
    files: Vec<ScenarioFile>,
    plant: &Plant,
    nominal: &Covariances,
    sets: &[Option<CovSet>],
    disturbances: &[Option<Disturbance>],
    filters: &[FilterSpec],
) -> Result<Vec<Scenario>> {
    if files.is_empty() {
        return Err(Error::invalid("scenarios", "the experiment names no scenario"));
    }
    let has_sets = sets.iter().any(Option::is_some);
    let mut scenarios = Vec::new();
    let mut snames = std::collections::BTreeSet::new();
    for (i, s) in files.into_iter().enumerate() {
        check_name(&format!("scenarios[{i}].name"), &s.name)?;
        if !snames.insert(s.name.clone()) {
            return Err(Error::invalid(
                format!("scenarios[{i}].name"),
                format!("scenario name `{}` is repeated", s.name),
            ));
        }
        let key = format!("scenarios.{}.covariance", s.name);
        let covariance =
            CovChoice::resolve(&key, &s.covariance, plant, nominal, has_sets, |n| filter_index(filters, n))?;
        s.shape.validate(&format!("scenarios.{}.shape", s.name))?;
        let index_of =
            |key: String| move |name: String| filter_index(filters, &name).ok_or_else(|| Error::no_filter(&key, &name));
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
    Ok(scenarios)
}
