//! A filter's worst case over deterministic disturbances bounded in energy (seed 000 §5, eq (36)
//! with time-varying weights W_k, and per-step bounds d[k]ᵀ W_k d[k] ≤ r_k as a set U of (33)):
//! the sequence that maximizes its summed error, that error, and an upper bound on it.
//!
//! In u[k] = W_k^{½} d[k] the error is |L T u|², T = blockdiag(W_k^{-½}). With the summed bound
//! alone the maximum is r λmax((LT)ᵀLT), attained by the top eigenvector: a closed form. Per-step
//! bounds make it a convex quadratic maximized over a product of balls (intersected with the summed
//! ball), which has no closed form (box-constrained cases are NP-hard); we take the best of a
//! monotone ascent u ← argmax_{u' ∈ U} ⟨M u, u'⟩ (the linear oracle is a water-filling in closed
//! form) from the top eigenvectors, and bound it above by the S-lemma dual solved with clarabel
//! ([`crate::numerics::solve::sdp::ball_product_bound`]). When the two meet (to 1e-9) the value is
//! the exact maximum.

use crate::error::Result;
use crate::filter::realization::Realization;
use crate::model::disturbance::{Disturbance, WMean, blocks};
use crate::model::plant::Plant;
use crate::numerics::linalg::{Mat, Vector, psd_factor, sym_eigen, top_eigen};

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
    let aug: Vec<_> = (0..steps).map(|k| crate::analysis::exact::augmented(plant, real, k, 0)).collect();
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

/// A filter's worst deterministic disturbance: the mean squared error it adds Σ_k |e_mean[k]|² (the
/// deterministic part of J), the sequence, and an upper bound on the maximum over all admissible
/// sequences (equal to `value` up to 1e-9 when the maximum is certified).
#[derive(Clone, Debug)]
pub struct Worst {
    pub value: f64,
    pub sequence: WMean,
    pub upper: f64,
}

impl Worst {
    /// Whether `value` is the maximum (the upper bound is attained to 1e-9).
    pub fn exact(&self) -> bool {
        self.value >= self.upper * (1.0 - 1e-9)
    }
}

/// One block's worst sequence in u coordinates (steps × m entries) and the bound on its value.
struct BlockWorst {
    u: Vector,
    /// The sequence is T u · scale (the closed form scales the unit eigenvector by √r).
    scale: f64,
    upper: f64,
}

/// The linear oracle of the ascent: argmax ⟨g, u⟩ over |u_k|² ≤ r_k, Σ|u_k|² ≤ total. Each u_k
/// points along g_k with length t_k = min(√r_k, c |g_k|), c the water level that spends the total
/// (all caps when Σ r_k ≤ total): exact, by sorting the breakpoints √r_k/|g_k|.
fn oracle(g: &Vector, m: usize, r: &[f64], total: f64) -> Vector {
    let a: Vec<f64> = (0..r.len()).map(|k| g.rows(k * m, m).norm()).collect();
    let mut lengths: Vec<f64> = r.iter().map(|r| r.sqrt()).collect();
    if r.iter().sum::<f64>() > total {
        let mut order: Vec<usize> = (0..r.len()).filter(|&k| a[k] > 0.0).collect();
        order.sort_by(|&i, &j| (lengths[i] / a[i]).total_cmp(&(lengths[j] / a[j])));
        let (mut capped, mut free): (f64, f64) = (0.0, order.iter().map(|&k| a[k] * a[k]).sum());
        let mut level = 0.0;
        for (i, &k) in order.iter().enumerate() {
            let c = ((total - capped).max(0.0) / free).sqrt();
            level = c;
            if c <= lengths[k] / a[k] {
                break;
            }
            capped += r[k];
            free -= a[k] * a[k];
            if i + 1 == order.len() {
                level = f64::INFINITY;
            }
        }
        for k in 0..r.len() {
            lengths[k] = if a[k] > 0.0 { lengths[k].min(level * a[k]) } else { 0.0 };
        }
    }
    let mut u = Vector::zeros(g.len());
    for k in 0..r.len() {
        if a[k] > 0.0 {
            u.rows_mut(k * m, m).copy_from(&(g.rows(k * m, m) * (lengths[k] / a[k])));
        }
    }
    u
}

/// max uᵀ M u over the block's set (module docs): closed form with the summed bound alone, else the
/// best ascent from the top eigenvectors beside the S-lemma bound.
fn block_worst(mm: &Mat, m: usize, d: &Disturbance) -> Result<BlockWorst> {
    let Some(r) = &d.step_energy else {
        let (top, u) = top_eigen(mm)?;
        return Ok(BlockWorst { u, scale: d.energy.sqrt(), upper: top * d.energy });
    };
    let value = |u: &Vector| (u.transpose() * mm * u)[(0, 0)];
    let (_, vectors) = sym_eigen(mm)?;
    let n = mm.nrows();
    let mut best: Option<(f64, Vector)> = None;
    for i in 0..n.min(STARTS) {
        let mut u = oracle(&vectors.column(n - 1 - i).into_owned(), m, r, d.energy);
        let mut f = value(&u);
        for _ in 0..MAX_ASCENT {
            let next = oracle(&(mm * &u), m, r, d.energy);
            let fn_ = value(&next);
            if fn_ <= f * (1.0 + 1e-15) {
                break;
            }
            (u, f) = (next, fn_);
        }
        if best.as_ref().is_none_or(|(bf, _)| f > *bf) {
            best = Some((f, u));
        }
    }
    let total = d.energy.is_finite().then_some(d.energy);
    let upper = crate::numerics::solve::sdp::ball_product_bound(mm, m, r, total)
        .map_err(|e| crate::error::Error::invalid("disturbances", format!("the S-lemma bound failed: {e}")))?;
    let (f, u) = best.expect("at least one start");
    Ok(BlockWorst { u, scale: 1.0, upper: upper.max(f) })
}

/// Starts of the ascent: the top eigenvectors of (LT)ᵀLT.
const STARTS: usize = 8;
/// A cap on the ascent's iterations (each one increases the value; it stops when it does not).
const MAX_ASCENT: usize = 10_000;

/// The filter's worst disturbance ([`Worst`]). One block: the block's maximizer (module docs).
/// Several blocks: each block's maximizer with the signs combined for the largest value, which is
/// feasible but can fall short of the joint maximum (a convex quadratic over a product of sets);
/// the bound is then (Σ_b √U_b)² by the triangle inequality. The minimax guarantee covers the joint
/// maximum either way.
pub fn worst(plant: &Plant, real: &Realization, dist: &[Option<Disturbance>]) -> Result<Option<Worst>> {
    let bl = blocks(plant, dist);
    if bl.is_empty() {
        return Ok(None);
    }
    if plant.random_matrices() {
        return Err(crate::error::Error::invalid(
            "disturbances",
            "the worst deterministic disturbance is computed for a plant with deterministic matrices (no dropouts, modes or multiplicative noise)",
        ));
    }
    let steps = plant.steps();
    let mut best_parts = Vec::new();
    let mut root_bound = 0.0;
    for &(b, o, d) in &bl {
        let m = plant.noise_blocks[b].1;
        let l = response(plant, real, o, m);
        // d[k] = W_k^{-½} u[k]: maximize |L T u|² over the block's set in u.
        let mut t = Mat::zeros(steps * m, steps * m);
        for k in 0..steps {
            let winv_half = psd_factor(&d.weights[k].clone().try_inverse().expect("weight checked positive definite"));
            t.view_mut((k * m, k * m), (m, m)).copy_from(&winv_half);
        }
        let lt = &l * &t;
        let bw = block_worst(&(lt.transpose() * &lt), m, d)?;
        root_bound += bw.upper.sqrt();
        let seq = &t * bw.u * bw.scale;
        let mut wm = Mat::zeros(plant.nw(), steps);
        for k in 0..steps {
            wm.view_mut((o, k), (m, 1)).copy_from(&seq.rows(k * m, m));
        }
        best_parts.push(wm);
    }
    // Combine the blocks' maximizers with the signs that give the largest deterministic error.
    let value = |wm: &WMean| crate::analysis::exact::mean_error(plant, real, wm);
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
    Ok(best.map(|(value, sequence)| Worst { value, sequence, upper: (root_bound * root_bound).max(value) }))
}
