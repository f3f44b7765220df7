//! Deterministic disturbances bounded in energy (seed 000 §5): a noise block d of w that is not
//! random but an unknown sequence with Σ_k d[k]ᵀ W d[k] ≤ r (eq (36)). The minimax design treats it
//! as white noise with covariance r W⁻¹ (eqs (38)–(39)); this module draws such sequences for the
//! scenarios (random directions on the bound, or the worst case for a given filter) and computes a
//! filter's exact worst case over them.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use crate::model::plant::Plant;
use crate::numerics::linalg::Mat;

/// An energy bound Σ_k d[k]ᵀ W d[k] ≤ energy on one noise block.
#[derive(Clone, Debug)]
pub struct Disturbance {
    pub weight: Mat,
    pub energy: f64,
}

impl Disturbance {
    /// The white-noise covariance the minimax design uses for it: energy · W⁻¹ (seed 000 eq (39)).
    pub fn surrogate_covariance(&self) -> Mat {
        self.weight.clone().try_inverse().expect("weight checked positive definite") * self.energy
    }
}

/// Which disturbance sequence a scenario applies. `F` refers to a filter: its name as written in
/// the file, its index once resolved.
#[derive(Clone, Debug, Default, PartialEq, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum DisturbanceChoice<F = usize> {
    #[default]
    None,
    /// A random direction for every disturbance block, scaled onto its energy bound.
    Random { seed: u64 },
    /// The sequence that maximizes the named filter's error.
    WorstFor { filter: F },
}

impl<F> DisturbanceChoice<F> {
    /// The same choice with its filter reference mapped (name → index).
    pub fn map_filter<G, E>(
        self,
        f: impl FnOnce(F) -> std::result::Result<G, E>,
    ) -> std::result::Result<DisturbanceChoice<G>, E> {
        Ok(match self {
            DisturbanceChoice::None => DisturbanceChoice::None,
            DisturbanceChoice::Random { seed } => DisturbanceChoice::Random { seed },
            DisturbanceChoice::WorstFor { filter } => DisturbanceChoice::WorstFor { filter: f(filter)? },
        })
    }
}

/// Per-step mean of w: column k is the deterministic part of w[k] (zero outside disturbance blocks).
pub type WMean = Mat;

pub(crate) fn offsets(plant: &Plant) -> Vec<usize> {
    let mut o = Vec::new();
    let mut acc = 0;
    for (_, d) in &plant.noise_blocks {
        o.push(acc);
        acc += d;
    }
    o
}

/// The disturbance blocks: (index into `plant.noise_blocks`, offset in w, bound).
pub(crate) fn blocks<'a>(plant: &Plant, dist: &'a [Option<Disturbance>]) -> Vec<(usize, usize, &'a Disturbance)> {
    let off = offsets(plant);
    dist.iter().skip(1).enumerate().filter_map(|(b, d)| d.as_ref().map(|d| (b, off[b], d))).collect()
}

/// A random sequence on the energy bound of every disturbance block: Gaussian direction, then
/// scaled so that Σ_k dᵀ W d = energy exactly.
pub fn random(plant: &Plant, dist: &[Option<Disturbance>], seed: u64) -> WMean {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Mat::zeros(plant.nw(), plant.steps());
    for (b, o, d) in blocks(plant, dist) {
        let m = plant.noise_blocks[b].1;
        let mut seq = Mat::from_fn(m, plant.steps(), |_, _| StandardNormal.sample(&mut rng));
        let e: f64 = (0..plant.steps()).map(|k| (seq.column(k).transpose() * &d.weight * seq.column(k))[(0, 0)]).sum();
        seq *= (d.energy / e).sqrt();
        out.view_mut((o, 0), (m, plant.steps())).copy_from(&seq);
    }
    out
}

/// Σ_k dᵀ W d of the part of `wm` in block `b` (for checks and reports).
pub fn energy(plant: &Plant, wm: &WMean, b: usize, d: &Disturbance) -> f64 {
    let o = offsets(plant)[b];
    let m = plant.noise_blocks[b].1;
    (0..plant.steps())
        .map(|k| (wm.view((o, k), (m, 1)).transpose() * &d.weight * wm.view((o, k), (m, 1)))[(0, 0)])
        .sum()
}
