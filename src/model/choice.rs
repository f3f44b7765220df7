//! Which covariance a scenario's noise has, or a filter is designed at (docs/math.md §7): the nominal one,
//! a given matrix, a vertex, an interior point or the elementwise maximum of the uncertainty set —
//! the points this layer can compute — or the worst case for, or the design point of, a named
//! filter, which the pipeline resolves once the filters are designed.

use std::collections::BTreeMap;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;

use crate::error::{Error, Result};
use crate::model::kind;
use crate::model::plant::{Covariances, Plant};
use crate::model::uncertainty::{CovSet, SetShape};
use crate::numerics::linalg::{check_psd, from_rows};

type Rows = Vec<Vec<f64>>;

/// A covariance choice as written in a file (`{ kind = …, … }` or a bare kind name); see [`CovChoice`].
#[derive(Clone, Debug, Deserialize, Default)]
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

/// Resolves a covariance given block by block (missing blocks fall back to `nominal`). `key`
/// prefixes the error messages.
pub(crate) fn given_covariances(
    key: &str,
    plant: &Plant,
    nominal: &Covariances,
    blocks: &BTreeMap<String, Rows>,
) -> Result<Covariances> {
    let mut out = nominal.clone();
    for (bname, rows) in blocks {
        let i = plant.block_index(&format!("{key}.{bname}"), bname)?;
        let d = nominal.blocks[i].nrows();
        let m = from_rows(&format!("{key}.{bname}"), rows, Some((d, d)))?;
        check_psd(&format!("{key}.{bname}"), &m)?;
        out.blocks[i] = m;
        // A given block is constant, whatever step-by-step surrogate the nominal carried there.
        out.varying.retain(|(b, _)| *b != i);
    }
    Ok(out)
}

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
    /// The file's choice with its filter names resolved by `filter_index`.
    pub(crate) fn resolve(
        key: &str,
        f: &CovChoiceFile,
        plant: &Plant,
        nominal: &Covariances,
        has_sets: bool,
        filter_index: impl Fn(&str) -> Option<usize>,
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
        let index = |name: &str| filter_index(name).ok_or_else(|| Error::no_filter(key, name));
        Ok(match f {
            CovChoiceFile::Nominal => CovChoice::Nominal,
            CovChoiceFile::Given { blocks } => CovChoice::Given(given_covariances(key, plant, nominal, blocks)?),
            CovChoiceFile::Vertex { seed } => CovChoice::Vertex { seed: *seed },
            CovChoiceFile::Interior { seed } => CovChoice::Interior { seed: *seed },
            CovChoiceFile::ElementwiseMax => CovChoice::ElementwiseMax,
            CovChoiceFile::WorstFor { filter } => CovChoice::WorstFor { filter: index(filter)? },
            CovChoiceFile::DesignOf { filter } => CovChoice::DesignOf { filter: index(filter)? },
        })
    }

    /// The choice as the tables name it; `filter` names a filter by its index.
    pub fn label<'a>(&self, filter: impl Fn(usize) -> &'a str) -> String {
        match self {
            CovChoice::Nominal => "nominal".into(),
            CovChoice::Given(_) => "given".into(),
            CovChoice::Vertex { seed } => format!("vertex(seed={seed})"),
            CovChoice::Interior { seed } => format!("interior(seed={seed})"),
            CovChoice::ElementwiseMax => "elementwise_max".into(),
            CovChoice::WorstFor { filter: i } => format!("worst_for({})", filter(*i)),
            CovChoice::DesignOf { filter: i } => format!("design_of({})", filter(*i)),
        }
    }

    /// The point of the nominal covariances and sets this choice names, or None when it names a
    /// filter (`worst_for`, `design_of`: known only once the filters are designed).
    pub fn point(&self, nominal: &Covariances, sets: &[Option<CovSet>]) -> Result<Option<Covariances>> {
        Ok(Some(match self {
            CovChoice::Nominal => nominal.clone(),
            CovChoice::Given(c) => c.clone(),
            CovChoice::Vertex { seed } | CovChoice::Interior { seed } => {
                let mut rng = ChaCha8Rng::seed_from_u64(*seed);
                let mut out = nominal.clone();
                for (i, set) in sets.iter().enumerate() {
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
                let mut out = nominal.clone();
                for (i, set) in sets.iter().enumerate() {
                    if let Some(SetShape::Box { center, half_width }) = set.as_ref().map(|s| &s.shape) {
                        out.blocks[i] = center + half_width;
                    }
                }
                out
            }
            CovChoice::WorstFor { .. } | CovChoice::DesignOf { .. } => return Ok(None),
        }))
    }
}

/// A point that is not PSD (a box corner can fail to be) cannot be sampled: refused with the block
/// and its smallest eigenvalue. `what` labels the choice in the message.
pub(crate) fn check_point(key: &str, what: &str, plant: &Plant, cov: &Covariances) -> Result<()> {
    for (name, m) in plant.block_names().iter().zip(&cov.blocks) {
        check_psd(&format!("{key} ({what}: block {name})"), m)?;
    }
    Ok(())
}
