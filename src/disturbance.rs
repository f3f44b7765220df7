//! Deterministic disturbances bounded in energy (seed 000 §5): a noise block d of w that is not
//! random but an unknown sequence with Σ_k d[k]ᵀ W d[k] ≤ r (eq (36)). The minimax design treats it
//! as white noise with covariance r W⁻¹ (eqs (38)–(39)); this module draws such sequences for the
//! scenarios (random directions on the bound, or the worst case for a given filter) and computes a
//! filter's exact worst case over them.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use crate::error::Result;
use crate::linalg::{Mat, psd_factor, top_eigen};
use crate::plant::Plant;
use crate::realization::Realization;

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

fn offsets(plant: &Plant) -> Vec<usize> {
    let mut o = Vec::new();
    let mut acc = 0;
    for (_, d) in &plant.noise_blocks {
        o.push(acc);
        acc += d;
    }
    o
}

/// The disturbance blocks: (index into `plant.noise_blocks`, offset in w, bound).
fn blocks<'a>(plant: &Plant, dist: &'a [Option<Disturbance>]) -> Vec<(usize, usize, &'a Disturbance)> {
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

/// The map L from one block's sequence (columns: step-major, then component) to the stacked
/// deterministic errors e[k] over the steps that count: w[k0] enters e[k0] through G and the state
/// through E, then propagates through F.
fn response(plant: &Plant, real: &Realization, offset: usize, m: usize) -> Mat {
    let nz = plant.nz();
    let steps = plant.steps();
    let mut rows = vec![None; steps];
    let mut next = 0;
    for (k, r) in rows.iter_mut().enumerate() {
        if plant.counts(k) {
            *r = Some(next * nz);
            next += 1;
        }
    }
    let aug: Vec<_> = (0..steps).map(|k| crate::exact::augmented(plant, real, k, 0)).collect();
    let mut l = Mat::zeros(next * nz, steps * m);
    for k0 in 0..steps {
        for j in 0..m {
            let col = k0 * m + j;
            let unit_g = aug[k0].g.column(offset + j).into_owned();
            if let Some(r) = rows[k0] {
                l.view_mut((r, col), (nz, 1)).copy_from(&unit_g);
            }
            if k0 == plant.horizon {
                continue;
            }
            let mut xi = aug[k0].e.column(offset + j).into_owned();
            for k in k0 + 1..steps {
                if let Some(r) = rows[k] {
                    let e = &aug[k].h * &xi;
                    l.view_mut((r, col), (nz, 1)).copy_from(&e);
                }
                if k < plant.horizon {
                    xi = &aug[k].f * &xi;
                }
            }
        }
    }
    l
}

/// The filter's worst disturbance and the mean squared error it adds, Σ_k |e_mean[k]|² (the
/// deterministic part of J). One block: the top right singular vector of L (I ⊗ W^{-½}), scaled to
/// the bound (exact). Several blocks: each block's maximizer with the signs combined for the largest
/// value, which is feasible but can fall short of the joint maximum (a convex quadratic over a
/// product of ellipsoids); the minimax guarantee covers the joint maximum either way.
pub fn worst(plant: &Plant, real: &Realization, dist: &[Option<Disturbance>]) -> Result<Option<(f64, WMean)>> {
    let bl = blocks(plant, dist);
    if bl.is_empty() {
        return Ok(None);
    }
    if plant.modes.is_some() {
        return Err(crate::error::Error::invalid(
            "disturbances",
            "the worst deterministic disturbance is computed for a plant that does not switch (no dropouts, no modes)",
        ));
    }
    let steps = plant.steps();
    let mut best_parts = Vec::new();
    for &(b, o, d) in &bl {
        let m = plant.noise_blocks[b].1;
        let l = response(plant, real, o, m);
        // d[k] = W^{-½} u[k] with Σ|u|² ≤ r: maximize |L (I ⊗ W^{-½}) u|².
        let winv_half = psd_factor(&d.weight.clone().try_inverse().expect("weight checked positive definite"));
        let mut t = Mat::zeros(steps * m, steps * m);
        for k in 0..steps {
            t.view_mut((k * m, k * m), (m, m)).copy_from(&winv_half);
        }
        let lt = &l * &t;
        let (_, u) = top_eigen(&(lt.transpose() * &lt))?;
        let seq = &t * u * d.energy.sqrt();
        let mut wm = Mat::zeros(plant.nw(), steps);
        for k in 0..steps {
            wm.view_mut((o, k), (m, 1)).copy_from(&seq.rows(k * m, m));
        }
        best_parts.push(wm);
    }
    // Combine the blocks' maximizers with the signs that give the largest deterministic error.
    let value = |wm: &WMean| crate::exact::mean_error(plant, real, wm);
    let mut best: Option<(f64, WMean)> = None;
    for signs in 0..(1u32 << best_parts.len()) {
        let mut wm = Mat::zeros(plant.nw(), steps);
        for (i, p) in best_parts.iter().enumerate() {
            let s = if signs >> i & 1 == 1 { -1.0 } else { 1.0 };
            wm += p * s;
        }
        let v = value(&wm);
        if best.as_ref().is_none_or(|(bv, _)| v > *bv) {
            best = Some((v, wm));
        }
    }
    Ok(best)
}

/// Σ_k dᵀ W d of the part of `wm` in block `b` (for checks and reports).
pub fn energy(plant: &Plant, wm: &WMean, b: usize, d: &Disturbance) -> f64 {
    let o = offsets(plant)[b];
    let m = plant.noise_blocks[b].1;
    (0..plant.steps())
        .map(|k| (wm.view((o, k), (m, 1)).transpose() * &d.weight * wm.view((o, k), (m, 1)))[(0, 0)])
        .sum()
}
