//! Layer 5, the filter families. Each is one file with a type implementing [`Family`]: its name in
//! experiment files, its typed parameters (read strictly when the file is loaded) and its design
//! procedure, which turns a [`DesignInput`] into a [`Design`]. Adding a family is that file and
//! one line in the `families!` list below.

mod family;

use std::fmt::Debug;
use std::sync::{Arc, RwLock};

use crate::error::{Error, Result};
use crate::filter::design::{Design, DesignInput};
pub use family::{
    ANY_PATTERN, Configured, FILTERING, Family, Finding, Footprint, PREDICTION, PlantSize, Predicted, RunView,
    Supports, exact_at_design,
};

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
    fn supports(&self) -> Supports {
        F::supports(&self.0)
    }
    fn footprint(&self, plant: PlantSize) -> Footprint {
        F::footprint(&self.0, plant)
    }
    fn design(&self, input: &DesignInput) -> Result<Design> {
        F::design(input, &self.0)
    }
    fn after_run(&self, run: &RunView, mine: &[usize]) -> Result<Option<Finding>> {
        F::after_run(run, mine)
    }
}

/// One registered family: its name and how to read its parameters.
#[derive(Clone, Copy)]
pub struct Entry {
    pub name: &'static str,
    read: fn(&str, &toml::Table) -> Result<Arc<dyn Configured>>,
}

const fn entry<F: Family>() -> Entry {
    Entry { name: F::NAME, read: read::<F> }
}

/// Reads filter `filter`'s parameter table as `F::Params` and checks its values ([`Family::check`]);
/// errors name the key (`filters.NAME.key`).
fn read<F: Family>(filter: &str, params: &toml::Table) -> Result<Arc<dyn Configured>> {
    let p: F::Params = serde_path_to_error::deserialize(toml::Value::Table(params.clone())).map_err(|e| {
        let path = e.path().to_string();
        let key = if path == "." { format!("filters.{filter}") } else { format!("filters.{filter}.{path}") };
        Error::invalid(key, e.inner().message().trim().to_string())
    })?;
    F::check(&p).map_err(|(key, cause)| Error::invalid(format!("filters.{filter}.{key}"), cause))?;
    Ok(Arc::new(WithParams::<F>(p)))
}

/// Families added at run time ([`register`]): a user's own, or a test's.
static REGISTERED: RwLock<Vec<Entry>> = RwLock::new(Vec::new());

/// Makes family `F`, defined outside this crate, one an experiment file may name: the one line a
/// program that embeds filterbench (or a test) writes to add a family. Registering twice is harmless.
pub fn register<F: Family>() {
    let mut r = REGISTERED.write().unwrap_or_else(|e| e.into_inner());
    if !r.iter().any(|e| e.name == F::NAME) {
        r.push(entry::<F>());
    }
}

/// Every family an experiment file may name: the built-in ones (`FAMILIES`) and the registered.
pub fn known() -> Vec<Entry> {
    let r = REGISTERED.read().unwrap_or_else(|e| e.into_inner());
    FAMILIES.iter().copied().chain(r.iter().copied()).collect()
}

/// Declares each family's module and lists its type in [`FAMILIES`].
macro_rules! families {
    ($($module:ident :: $family:ident),* $(,)?) => {
        $(pub mod $module;)*
        /// Every family an experiment file may name.
        pub(crate) const FAMILIES: &[Entry] = &[$(entry::<$module::$family>()),*];
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
    linear::Linear,
}

/// Reads a filter's family and parameters: the unknown family or the bad parameter is named.
pub(crate) fn configure(filter: &str, family: &str, params: &toml::Table) -> Result<Arc<dyn Configured>> {
    let all = known();
    let e = all.iter().find(|e| e.name == family).ok_or_else(|| {
        let names = all.iter().map(|e| e.name).collect::<Vec<_>>().join(", ");
        Error::invalid(format!("filters.{filter}.family"), format!("unknown family `{family}` (known: {names})"))
    })?;
    (e.read)(filter, params)
}

/// Designs one filter and checks its realization against the plant and pattern. What the family
/// supports was checked when the file was loaded; it is checked again here, since a design input
/// can be built without a file.
pub fn design(configured: &dyn Configured, input: &DesignInput) -> Result<Design> {
    configured.supports().check(configured.family(), input)?;
    let d = configured.design(input)?;
    d.realization.check(input.name, input.plant, input.pattern)?;
    Ok(d)
}
