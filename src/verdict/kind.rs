//! What a kind of expectation is (`Kind`), the cells it tests (`Test`) and what the kinds share:
//! the selection of scenarios and filters, and the assumptions a test rests on (a finite fourth
//! moment for the central limit theorem, Gaussian errors for the χ² of NEES; docs/checks.md).

use serde::de::DeserializeOwned;

use super::stats::Sided;
use super::tables::Tables;
use crate::config::{Expectation, Experiment, Scenario};
use crate::model::disturbance::DisturbanceChoice;
use crate::model::plant::Measurement;
use crate::model::shape::Shape;

/// How one cell is decided.
#[derive(Clone, Debug, PartialEq)]
pub enum Method {
    /// z = (observed − reference)/std_error against a standard normal (the central limit theorem
    /// for a mean of i.i.d. trials), in the direction given; in Holm's family.
    Z(Sided),
    /// dof · observed is χ²(dof) when the expectation holds, tested two-sided (reference 1); in
    /// Holm's family.
    Chi2 { dof: f64 },
    /// A comparison with no sampling error (a per-trial violation count, an exact value against a
    /// certified bound): it fails with certainty or not at all, so it is not in Holm's family.
    Certain { holds: bool },
    /// The test's assumptions do not hold here; the reason is reported and nothing is tested.
    NotApplicable(String),
}

/// One cell of an expectation: one (variant, scenario, filter[, step]) and what is tested there.
#[derive(Clone, Debug, PartialEq)]
pub struct Test {
    pub variant: Option<String>,
    pub scenario: String,
    /// The filter, or `A vs B` for a comparison of two.
    pub filter: String,
    /// The step, None for a summed error.
    pub step: Option<u32>,
    /// What is compared, e.g. `mean vs exact`, `violations`, `NEES`.
    pub what: std::borrow::Cow<'static, str>,
    pub observed: f64,
    pub reference: f64,
    /// The standard error of `observed` (None for a `Certain` cell).
    pub std_error: Option<f64>,
    /// The scale a discrepancy is stated relative to (the exact value, the bound), None: absolute.
    pub scale: Option<f64>,
    pub method: Method,
}

/// The scenarios and filters an expectation names (None: every one the kind applies to).
#[derive(Clone, Copy, Debug)]
pub struct Selection<'a> {
    pub scenarios: Option<&'a [String]>,
    pub filters: Option<&'a [String]>,
}

impl<'a> Selection<'a> {
    pub fn of(e: &'a Expectation) -> Self {
        Selection { scenarios: e.scenarios.as_deref(), filters: e.filters.as_deref() }
    }
    pub fn scenario(&self, name: &str) -> bool {
        self.scenarios.is_none_or(|s| s.iter().any(|x| x == name))
    }
    pub fn filter(&self, name: &str) -> bool {
        self.filters.is_none_or(|s| s.iter().any(|x| x == name))
    }
    pub fn both(&self, scenario: &str, filter: &str) -> bool {
        self.scenario(scenario) && self.filter(filter)
    }
}

/// What a kind sees: the experiment (one per variant), the tables, its selection.
pub struct Context<'a> {
    pub exps: &'a [Experiment],
    pub tables: &'a Tables,
    pub sel: Selection<'a>,
    /// The baseline folder `--baseline` names, for `matches_baseline`.
    pub baseline: Option<&'a std::path::Path>,
}

impl Context<'_> {
    /// The experiment of a table row's variant.
    pub fn experiment(&self, variant: Option<&str>) -> Option<&Experiment> {
        self.exps.iter().find(|e| e.variant.as_deref() == variant)
    }
    /// The scenario of a table row.
    pub fn scenario(&self, variant: Option<&str>, name: &str) -> Option<(&Experiment, &Scenario)> {
        let e = self.experiment(variant)?;
        Some((e, e.scenarios.iter().find(|s| s.name == name)?))
    }
    /// Why a mean of this scenario's trials may have no finite variance, so the central limit
    /// theorem gives no z-test (docs/checks.md, "Heavy tails"): the error is quadratic in the noise,
    /// so it needs the noise's fourth moment; Student-t has it only for ν > 4. None when it holds.
    pub fn heavy_tails(&self, variant: Option<&str>, scenario: &str) -> Option<String> {
        let (e, s) = self.scenario(variant, scenario)?;
        let shapes = std::iter::once(("noise", &s.shape)).chain(e.plant.factors.iter().map(|f| ("factor", &f.shape)));
        for (what, shape) in shapes {
            if let Shape::StudentT { nu } = *shape {
                if nu <= 4.0 {
                    return Some(format!(
                        "Student-t {what} with ν = {nu} ≤ 4 has no finite fourth moment, so the squared error has no finite variance and no central limit theorem applies"
                    ));
                }
            }
        }
        None
    }
    /// Why the output error of this scenario may not be Gaussian, so that N·r·NEES is not χ²(N·r)
    /// (docs/checks.md, `consistent`). None when the plant is linear with Gaussian inputs.
    pub fn non_gaussian(&self, variant: Option<&str>, scenario: &str) -> Option<String> {
        use crate::config::Input;
        let (e, s) = self.scenario(variant, scenario)?;
        let why = if s.shape != Shape::Gaussian {
            "the noise is not Gaussian"
        } else if !matches!(s.disturbance, DisturbanceChoice::None) {
            "a deterministic disturbance gives the error a mean"
        } else if !matches!(s.input, Input::Independent | Input::Coloured { .. } | Input::AnisotropicWorstFor { .. }) {
            "the input is not Gaussian"
        } else if !matches!(e.plant.measurement, Measurement::Always) {
            "dropouts or switching modes make the error a mixture"
        } else if !e.plant.factors.is_empty() {
            "multiplicative noise makes the error non-Gaussian"
        } else {
            return None;
        };
        Some(why.to_string())
    }
}

/// A kind of expectation: its name in `[[expect]]`'s `kind`, its parameters (the entry's other
/// keys, refused when unknown) and its cells. Adding a kind is one file in `verdict/kinds/` with a
/// type implementing this and one line in `kinds!` (`verdict/kinds/mod.rs`).
pub trait Kind: 'static {
    const NAME: &'static str;
    type Params: DeserializeOwned + std::fmt::Debug + Send + Sync;
    /// The parameters' values against the experiment, when the file is loaded: `Err((key, cause))`
    /// becomes `expect[i].key: cause`.
    fn check(_p: &Self::Params, _e: &Expectation, _exp: &Experiment) -> Result<(), (String, String)> {
        Ok(())
    }
    /// The cells the expectation tests in these tables (the cells that apply to it; a named cell
    /// whose assumptions fail is a `NotApplicable` test). An error (a file a kind reads itself, such
    /// as a baseline folder, that cannot be read) names its key and refuses the check, exit 2.
    fn tests(p: &Self::Params, cx: &Context) -> crate::Result<Vec<Test>>;
}

/// A z-test cell, or `NotApplicable` when there is no spread to test against (every trial equal).
#[allow(clippy::too_many_arguments)]
pub fn z_test(
    row: (&Option<String>, &str, &str, Option<u32>),
    what: impl Into<std::borrow::Cow<'static, str>>,
    observed: f64,
    reference: f64,
    std_error: f64,
    scale: Option<f64>,
    sided: Sided,
    not_applicable: Option<String>,
) -> Test {
    let method = match not_applicable {
        Some(why) => Method::NotApplicable(why),
        None if !(std_error > 0.0 && std_error.is_finite()) => {
            Method::NotApplicable(format!("no sampling spread to test against (std_error {std_error})"))
        }
        None => Method::Z(sided),
    };
    Test {
        variant: row.0.clone(),
        scenario: row.1.to_string(),
        filter: row.2.to_string(),
        step: row.3,
        what: what.into(),
        observed,
        reference,
        std_error: Some(std_error),
        scale,
        method,
    }
}

/// A kind with its parameters read: what the registry hands on.
pub trait Configured: Send + Sync + std::fmt::Debug {
    fn kind(&self) -> &'static str;
    fn tests(&self, cx: &Context) -> crate::Result<Vec<Test>>;
}

struct With<K: Kind>(K::Params);

impl<K: Kind> std::fmt::Debug for With<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {:?}", K::NAME, self.0)
    }
}

impl<K: Kind> Configured for With<K> {
    fn kind(&self) -> &'static str {
        K::NAME
    }
    fn tests(&self, cx: &Context) -> crate::Result<Vec<Test>> {
        K::tests(&self.0, cx)
    }
}

/// Reads entry `i`'s parameters for kind `K` (serde, unknown keys refused) and checks them.
pub fn build<K: Kind>(i: usize, e: &Expectation, exp: &Experiment) -> crate::Result<Box<dyn Configured>> {
    use crate::Error;
    let p: K::Params = serde_path_to_error::deserialize(toml::Value::Table(e.params.clone())).map_err(|err| {
        let path = err.path().to_string();
        let message = err.inner().to_string();
        // serde names an unknown key in its message, at the path of the table that holds it.
        let unknown = message.strip_prefix("unknown field `").and_then(|m| m.split('`').next());
        let key = match (path.as_str(), unknown) {
            (".", Some(k)) => format!("expect[{i}].{k}"),
            (".", None) => format!("expect[{i}]"),
            (p, _) => format!("expect[{i}].{p}"),
        };
        Error::invalid(key, format!("{} (kind `{}`)", message.trim(), K::NAME))
    })?;
    K::check(&p, e, exp).map_err(|(key, cause)| Error::invalid(format!("expect[{i}].{key}"), cause))?;
    Ok(Box::new(With::<K>(p)))
}
