//! Layer 5, the filter families. Each is one file with a type implementing [`Family`]: its name in
//! experiment files, its typed parameters (read strictly when the file is loaded) and its design
//! procedure, which turns a [`DesignInput`] into a [`Design`]. Adding a family is that file and
//! one line in the `families!` list below.

use std::fmt::Debug;
use std::sync::Arc;

use serde::de::DeserializeOwned;

use crate::error::{Error, Result};
use crate::filter::design::{Design, DesignInput, Guarantee, GuaranteeKind};
use crate::filter::realization::Realization;
use crate::model::choice::CovChoiceFile;
use crate::model::plant::Covariances;

/// A filter family: a design procedure with its name and typed parameters (argmin's `Solver` in
/// spirit: the name, the parameters, the one method).
pub trait Family: 'static {
    /// The name experiment files use: `family = "kalman"`.
    const NAME: &'static str;
    /// The `[filters.params]` table, read with `deny_unknown_fields` when the file is loaded.
    type Params: DeserializeOwned + Debug + Send + Sync;
    /// Designs the filter.
    fn design(input: &DesignInput, params: &Self::Params) -> Result<Design>;
}

/// A family with its parameters read: what an experiment's filter carries until it is designed.
pub trait Configured: Debug + Send + Sync {
    fn family(&self) -> &'static str;
    fn design(&self, input: &DesignInput) -> Result<Design>;
}

struct WithParams<F: Family>(F::Params);

impl<F: Family> Debug for WithParams<F> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {:?}", F::NAME, self.0)
    }
}

impl<F: Family> Configured for WithParams<F> {
    fn family(&self) -> &'static str {
        F::NAME
    }
    fn design(&self, input: &DesignInput) -> Result<Design> {
        F::design(input, &self.0)
    }
}

/// One registered family: its name and how to read its parameters.
pub struct Entry {
    pub name: &'static str,
    read: fn(&str, &toml::Table) -> Result<Arc<dyn Configured>>,
}

const fn entry<F: Family>() -> Entry {
    Entry { name: F::NAME, read: read::<F> }
}

/// Reads filter `filter`'s parameter table as `F::Params`; errors name the key
/// (`filters.NAME.key`).
fn read<F: Family>(filter: &str, params: &toml::Table) -> Result<Arc<dyn Configured>> {
    let p: F::Params = serde_path_to_error::deserialize(toml::Value::Table(params.clone())).map_err(|e| {
        let path = e.path().to_string();
        let key = if path == "." { format!("filters.{filter}") } else { format!("filters.{filter}.{path}") };
        Error::invalid(key, e.inner().message().trim().to_string())
    })?;
    Ok(Arc::new(WithParams::<F>(p)))
}

/// Declares each family's module and lists its type in [`FAMILIES`].
macro_rules! families {
    ($($module:ident :: $family:ident),* $(,)?) => {
        $(pub mod $module;)*
        /// Every family an experiment file may name.
        pub const FAMILIES: &[Entry] = &[$(entry::<$module::$family>()),*];
    };
}

/// The design form of the SDP (4.7) that the `hinf` family's `method = "sdp"` uses.
pub mod hinf_sdp;

families! {
    kalman::Kalman,
    minimax::Minimax,
    hinf_lambda::HinfLambda,
    h2::H2,
    anisotropic::Anisotropic,
    intermittent::Intermittent,
    markov_jump::MarkovJump,
    galerkin::Galerkin,
}

/// Reads a filter's family and parameters: the unknown family or the bad parameter is named.
pub fn configure(filter: &str, family: &str, params: &toml::Table) -> Result<Arc<dyn Configured>> {
    let known = || FAMILIES.iter().map(|e| e.name).collect::<Vec<_>>().join(", ");
    let e = FAMILIES.iter().find(|e| e.name == family).ok_or_else(|| {
        Error::invalid(format!("filters.{filter}.family"), format!("unknown family `{family}` (known: {})", known()))
    })?;
    (e.read)(filter, params)
}

/// Designs one filter and checks its realization against the plant and pattern.
pub fn design(configured: &dyn Configured, input: &DesignInput) -> Result<Design> {
    if input.nominal.varies() && !matches!(configured.family(), "kalman" | "minimax") {
        return Err(Error::design(
            input.name,
            format!(
                "the {} family designs with one covariance per block, but the surrogate of a disturbance with \
                 time-varying weights (seed 000 eq (39)) changes with the step: only kalman and minimax take it",
                configured.family()
            ),
        ));
    }
    let d = configured.design(input)?;
    d.realization.check(input.name, input.plant, input.pattern)?;
    Ok(d)
}

/// The covariance a family designs at, `filters.NAME.design`: any choice but those that name
/// another filter (`worst_for`, `design_of`), which `who` refuses (a filter designed at its own
/// covariance cannot wait for another's design).
fn own_design_point(input: &DesignInput, choice: &CovChoiceFile, who: &str) -> Result<Covariances> {
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
