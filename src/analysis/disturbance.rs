//! A filter's exact worst case over deterministic disturbances bounded in energy (seed 000 §5,
//! eq (36)): the sequence that maximizes its summed error, and that error.

use crate::error::Result;
use crate::filter::realization::Realization;
use crate::model::disturbance::{Disturbance, WMean, blocks};
use crate::model::plant::Plant;
use crate::numerics::linalg::{Mat, psd_factor, top_eigen};

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
    if plant.random_matrices() {
        return Err(crate::error::Error::invalid(
            "disturbances",
            "the worst deterministic disturbance is computed for a plant with deterministic matrices (no dropouts, modes or multiplicative noise)",
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
    Ok(best)
}
