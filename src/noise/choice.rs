//! Which covariance a scenario's noise has (SPEC §7): the nominal one, a given matrix, a vertex or
//! an interior point of the uncertainty set, or the worst case for one named filter.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::error::{Error, Result};
use crate::linalg::check_psd;
use crate::plant::{Covariances, Plant};
use crate::spec::FilterSpec;
use crate::spec::{CovChoiceFile, Experiment, given_covariances};

#[derive(Clone, Debug)]
pub enum CovChoice {
    Nominal,
    Given(Covariances),
    /// A random extreme point of every block's set (blocks without a set stay nominal); the
    /// seed makes the choice reproducible.
    Vertex {
        seed: u64,
    },
    /// A uniformly random point of every block's set.
    Interior {
        seed: u64,
    },
    /// The maximizer of the named filter's (affine) error over the set.
    WorstFor {
        filter: usize,
    },
}

impl CovChoice {
    pub(crate) fn resolve(
        key: &str,
        f: &CovChoiceFile,
        plant: &Plant,
        nominal: &Covariances,
        has_sets: bool,
        filters: &[FilterSpec],
    ) -> Result<Self> {
        Ok(match f {
            CovChoiceFile::Nominal => CovChoice::Nominal,
            CovChoiceFile::Given { blocks } => {
                CovChoice::Given(given_covariances(key, plant, nominal, blocks)?)
            }
            CovChoiceFile::Vertex { seed } | CovChoiceFile::Interior { seed } if !has_sets => {
                let _ = seed;
                return Err(Error::invalid(
                    key,
                    "a vertex or interior point needs an uncertainty set: add [sets.BLOCK]",
                ));
            }
            CovChoiceFile::Vertex { seed } => CovChoice::Vertex { seed: *seed },
            CovChoiceFile::Interior { seed } => CovChoice::Interior { seed: *seed },
            CovChoiceFile::WorstFor { filter } => {
                if !has_sets {
                    return Err(Error::invalid(
                        key,
                        "a worst case needs an uncertainty set: add [sets.BLOCK]",
                    ));
                }
                let i = filters
                    .iter()
                    .position(|x| &x.name == filter)
                    .ok_or_else(|| {
                        Error::invalid(
                            format!("{key}.filter"),
                            format!("no filter named `{filter}` in this experiment"),
                        )
                    })?;
                CovChoice::WorstFor { filter: i }
            }
        })
    }

    pub fn label(&self, exp: &Experiment) -> String {
        match self {
            CovChoice::Nominal => "nominal".into(),
            CovChoice::Given(_) => "given".into(),
            CovChoice::Vertex { seed } => format!("vertex(seed={seed})"),
            CovChoice::Interior { seed } => format!("interior(seed={seed})"),
            CovChoice::WorstFor { filter } => format!("worst_for({})", exp.filters[*filter].name),
        }
    }

    /// The concrete covariances. `worst` gives, for a filter index, the maximizer of its error over
    /// the set (only asked for `WorstFor`). A point that is not PSD (a box corner can fail to be)
    /// cannot be sampled and is refused with the block and its smallest eigenvalue.
    pub fn covariances(
        &self,
        key: &str,
        exp: &Experiment,
        worst: &dyn Fn(usize) -> Result<Covariances>,
    ) -> Result<Covariances> {
        let cov = match self {
            CovChoice::Nominal => exp.nominal.clone(),
            CovChoice::Given(c) => c.clone(),
            CovChoice::Vertex { seed } | CovChoice::Interior { seed } => {
                let mut rng = ChaCha8Rng::seed_from_u64(*seed);
                let mut out = exp.nominal.clone();
                for (i, set) in exp.sets.iter().enumerate() {
                    if let Some(set) = set {
                        out.blocks[i] = if matches!(self, CovChoice::Vertex { .. }) {
                            set.random_vertex(&mut rng)
                        } else {
                            set.random_interior(&mut rng)
                        };
                    }
                }
                out
            }
            CovChoice::WorstFor { filter } => worst(*filter)?,
        };
        for (name, m) in exp.plant.block_names().iter().zip(&cov.blocks) {
            check_psd(&format!("{key} ({}: block {name})", self.label(exp)), m)?;
        }
        Ok(cov)
    }
}
