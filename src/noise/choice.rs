//! Which covariance a scenario's noise has (SPEC §7): the nominal one, a given matrix, a vertex, an
//! interior point or the elementwise maximum of the uncertainty set, the worst case for one named
//! filter, or the covariance a named filter was designed at (for a minimax filter, K̂).

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::error::{Error, Result};
use crate::linalg::check_psd;
use crate::plant::{Covariances, Plant};
use crate::run::DesignedFilter;
use crate::spec::{CovChoiceFile, Experiment, FilterSpec, given_covariances};
use crate::uncertainty::SetShape;

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
    /// center + half-width of every box (other blocks nominal): the "largest" covariance by
    /// entries, a common but wrong guess at the worst case.
    ElementwiseMax,
    /// The maximizer of the named filter's (affine) error over the set.
    WorstFor {
        filter: usize,
    },
    /// The covariance the named filter was designed at.
    DesignOf {
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
        let needs_set = matches!(
            f,
            CovChoiceFile::Vertex { .. }
                | CovChoiceFile::Interior { .. }
                | CovChoiceFile::ElementwiseMax
                | CovChoiceFile::WorstFor { .. }
        );
        if needs_set && !has_sets {
            return Err(Error::invalid(key, "this covariance choice needs an uncertainty set: add [sets.BLOCK]"));
        }
        let filter_index = |name: &str| {
            filters.iter().position(|x| x.name == name).ok_or_else(|| {
                Error::invalid(format!("{key}.filter"), format!("no filter named `{name}` in this experiment"))
            })
        };
        Ok(match f {
            CovChoiceFile::Nominal => CovChoice::Nominal,
            CovChoiceFile::Given { blocks } => CovChoice::Given(given_covariances(key, plant, nominal, blocks)?),
            CovChoiceFile::Vertex { seed } => CovChoice::Vertex { seed: *seed },
            CovChoiceFile::Interior { seed } => CovChoice::Interior { seed: *seed },
            CovChoiceFile::ElementwiseMax => CovChoice::ElementwiseMax,
            CovChoiceFile::WorstFor { filter } => CovChoice::WorstFor { filter: filter_index(filter)? },
            CovChoiceFile::DesignOf { filter } => CovChoice::DesignOf { filter: filter_index(filter)? },
        })
    }

    pub fn label(&self, exp: &Experiment) -> String {
        match self {
            CovChoice::Nominal => "nominal".into(),
            CovChoice::Given(_) => "given".into(),
            CovChoice::Vertex { seed } => format!("vertex(seed={seed})"),
            CovChoice::Interior { seed } => format!("interior(seed={seed})"),
            CovChoice::ElementwiseMax => "elementwise_max".into(),
            CovChoice::WorstFor { filter } => format!("worst_for({})", exp.filters[*filter].name),
            CovChoice::DesignOf { filter } => format!("design_of({})", exp.filters[*filter].name),
        }
    }

    /// The concrete covariances. `designed` holds the designed filters when they exist (needed by
    /// `worst_for` and `design_of`). A point that is not PSD (a box corner can fail to be) cannot be
    /// sampled and is refused with the block and its smallest eigenvalue.
    pub fn covariances(&self, key: &str, exp: &Experiment, designed: Option<&[DesignedFilter]>) -> Result<Covariances> {
        let designed_filter = |i: usize| {
            designed.map(|d| &d[i]).ok_or_else(|| Error::invalid(key, "refers to a filter, which is not allowed here"))
        };
        let cov = match self {
            CovChoice::Nominal => exp.nominal.clone(),
            CovChoice::Given(c) => c.clone(),
            CovChoice::Vertex { seed } | CovChoice::Interior { seed } => {
                let mut rng = ChaCha8Rng::seed_from_u64(*seed);
                let mut out = exp.nominal.clone();
                for (i, set) in exp.sets.iter().enumerate() {
                    if let Some(set) = set {
                        out.blocks[i] = if matches!(self, CovChoice::Vertex { .. }) {
                            set.random_vertex(&mut rng)?
                        } else {
                            set.random_interior(&mut rng)?
                        };
                    }
                }
                out
            }
            CovChoice::ElementwiseMax => {
                let mut out = exp.nominal.clone();
                for (i, set) in exp.sets.iter().enumerate() {
                    if let Some(SetShape::Box { center, half_width }) = set.as_ref().map(|s| &s.shape) {
                        out.blocks[i] = center + half_width;
                    }
                }
                out
            }
            CovChoice::WorstFor { filter } => designed_filter(*filter)?
                .worst
                .as_ref()
                .map(|w| w.argmax.clone())
                .ok_or_else(|| Error::invalid(key, "no uncertainty set"))?,
            CovChoice::DesignOf { filter } => designed_filter(*filter)?
                .design
                .design_covariance
                .clone()
                .ok_or_else(|| Error::invalid(key, "that filter was not designed at a covariance"))?,
        };
        for (name, m) in exp.plant.block_names().iter().zip(&cov.blocks) {
            check_psd(&format!("{key} ({}: block {name})", self.label(exp)), m)?;
        }
        Ok(cov)
    }
}
