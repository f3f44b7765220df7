//! Deterministic disturbances bounded in energy (seed 000 §5): a noise block d of w that is not
//! random but an unknown sequence with Σ_k d\[k]ᵀ W_k d\[k] ≤ r (eq (36), time-varying weights W_k)
//! and, optionally, d\[k]ᵀ W_k d\[k] ≤ r_k at every step (a convex set U of (33)–(35) that is not one
//! ellipsoid). The minimax design treats it as white noise with covariance s W_k⁻¹ at step k
//! (eqs (38)–(39); s = r without per-step bounds, see [`Disturbance::surrogate_scale`]); this module
//! draws such sequences for the scenarios (random directions on the bound, or the worst case for a
//! given filter).

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use crate::model::plant::Plant;
use crate::numerics::linalg::Mat;

/// Energy bounds on one noise block: Σ_k d\[k]ᵀ W_k d\[k] ≤ energy and, if given,
/// d\[k]ᵀ W_k d\[k] ≤ step_energy\[k] for every step k = 0..N.
#[derive(Clone, Debug)]
pub struct Disturbance {
    /// W_k for k = 0..N (the one `weight` of the file repeated when it gives no `weights`).
    pub weights: Vec<Mat>,
    /// r of the summed bound; ∞ when the file gives only per-step bounds.
    pub energy: f64,
    /// r_k of the per-step bounds, if any.
    pub step_energy: Option<Vec<f64>>,
}

impl Disturbance {
    /// Whether the weights differ between steps.
    pub fn varies(&self) -> bool {
        self.weights.iter().any(|w| w != &self.weights[0])
    }
    /// s of the surrogate s W_k⁻¹ (seed 000 eqs (38)–(39)). The surrogate is honest when every
    /// admissible sequence has d dᵀ ⪯ blockdiag(s W_k⁻¹) (then the design's error at it bounds the
    /// error at d, Theorem 3). By Cauchy–Schwarz that holds iff Σ_k e_k / s ≤ 1 for every admissible
    /// energy profile e_k = d\[k]ᵀ W_k d\[k], i.e. s ≥ max Σ e_k = min(r, Σ_k r_k): the paper's r
    /// without per-step bounds, and the smaller Σ r_k when the per-step bounds are the tighter ones.
    /// (Step-dependent s_k with max_e Σ e_k/s_k ≤ 1 are honest too; we keep the constant one.)
    pub fn surrogate_scale(&self) -> f64 {
        self.step_energy.as_ref().map_or(self.energy, |r| self.energy.min(r.iter().sum()))
    }
    /// The surrogate covariance s W_k⁻¹ at step k (seed 000 eq (39)).
    pub(crate) fn surrogate_at(&self, k: usize) -> Mat {
        self.weights[k].clone().try_inverse().expect("weight checked positive definite") * self.surrogate_scale()
    }
    /// The constant surrogate s W⁻¹ (step 0's; the design covariance block of a disturbance).
    pub(crate) fn surrogate_covariance(&self) -> Mat {
        self.surrogate_at(0)
    }
    /// The surrogate per step when the weights vary, else None.
    pub(crate) fn surrogate_steps(&self) -> Option<Vec<Mat>> {
        self.varies().then(|| (0..self.weights.len()).map(|k| self.surrogate_at(k)).collect())
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
    pub(crate) fn map_filter<G, E>(
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

/// Per-step mean of w: column k is the deterministic part of w\[k] (zero outside disturbance blocks).
pub(crate) type WMean = Mat;

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

/// d\[k]ᵀ W_k d\[k] for a block's sequence (columns are steps).
fn step_energies(seq: &Mat, d: &Disturbance) -> Vec<f64> {
    (0..seq.ncols()).map(|k| (seq.column(k).transpose() * &d.weights[k] * seq.column(k))[(0, 0)]).collect()
}

/// A random sequence on the boundary of every disturbance block's set: Gaussian direction; each
/// step scaled onto its own bound r_k when there are per-step bounds; then the whole scaled so that
/// Σ_k dᵀ W_k d = r exactly (without per-step bounds) or at most r (with them).
pub fn random(plant: &Plant, dist: &[Option<Disturbance>], seed: u64) -> WMean {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Mat::zeros(plant.nw(), plant.steps());
    for (b, o, d) in blocks(plant, dist) {
        let m = plant.noise_blocks[b].1;
        let mut seq = Mat::from_fn(m, plant.steps(), |_, _| StandardNormal.sample(&mut rng));
        if let Some(r) = &d.step_energy {
            for (k, e) in step_energies(&seq, d).into_iter().enumerate() {
                seq.column_mut(k).scale_mut((r[k] / e).sqrt());
            }
            let e: f64 = step_energies(&seq, d).iter().sum();
            seq *= (d.energy / e).sqrt().min(1.0);
        } else {
            let e: f64 = step_energies(&seq, d).iter().sum();
            seq *= (d.energy / e).sqrt();
        }
        out.view_mut((o, 0), (m, plant.steps())).copy_from(&seq);
    }
    out
}

/// d\[k]ᵀ W_k d\[k] of the part of `wm` in block `b`, per step (for checks and reports).
pub fn energies(plant: &Plant, wm: &WMean, b: usize, d: &Disturbance) -> Vec<f64> {
    let o = offsets(plant)[b];
    let m = plant.noise_blocks[b].1;
    step_energies(&wm.view((o, 0), (m, plant.steps())).into_owned(), d)
}

/// Σ_k dᵀ W_k d of the part of `wm` in block `b` (for checks and reports).
pub fn energy(plant: &Plant, wm: &WMean, b: usize, d: &Disturbance) -> f64 {
    energies(plant, wm, b, d).iter().sum()
}
