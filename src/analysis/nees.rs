//! Consistency of a filter with its own belief: the normalized estimation error squared
//! NEES\[k] = E[e\[k]ᵀ P_z\[k]⁺ e\[k]] / rank P_z\[k] of the output error e = z − ẑ, where P_z\[k] is
//! the filter's claimed error covariance, E\[e eᵀ] at its design covariance (Kalman: Cz P\[k] Czᵀ
//! with P its Riccati solution; minimax at K̂). A consistent filter has NEES = 1; above 1 it
//! believes itself better than it is.
//!
//! The output error, not the state error: z is what every family estimates and what the tables
//! score, and not every realization's state is an estimate of x. Second moments, not covariances:
//! a known mean (x0, a deterministic disturbance) is an error the filter should have removed.
//!
//! E\[e eᵀ] per step comes from the exact per-step mean-square error (the moment recursions of
//! [`crate::analysis::exact`], unchanged) of scalar outputs uᵀz: of e_i for every i and of e_i + e_j for
//! i < j, by polarization. That is nz(nz+1)/2 exact evaluations, cheap for the few outputs these
//! filters estimate.

use crate::analysis::exact::ExactError;
use crate::error::Result;
use crate::filter::realization::Realization;
use crate::model::plant::Plant;
use crate::numerics::linalg::{Mat, PSD_TOL};

/// The plant and filter seen through the output uᵀz (one row).
fn project(plant: &Plant, real: &Realization, u: &Mat) -> (Plant, Realization) {
    let mut p = plant.clone();
    p.cz = plant.cz.map(|m| u * m);
    p.dz = plant.dz.map(|m| u * m);
    // The clone shares the gains; `map_gains` copies each distinct step once.
    let mut r = real.clone();
    r.map_gains(|g| {
        g.cf = u * &g.cf;
        g.df = u * &g.df;
    });
    (p, r)
}

/// E[e\[k] e\[k]ᵀ] for every step k, where `exact` evaluates the per-step mean-square error of a
/// plant and filter under the input of interest.
pub fn error_moments(
    plant: &Plant,
    real: &Realization,
    exact: &dyn Fn(&Plant, &Realization) -> Result<ExactError>,
) -> Result<Vec<Mat>> {
    let nz = plant.nz();
    let unit = |i: usize| Mat::from_fn(1, nz, |_, c| (c == i) as u8 as f64);
    let mut diag: Vec<Vec<f64>> = Vec::with_capacity(nz);
    for i in 0..nz {
        let (p, r) = project(plant, real, &unit(i));
        diag.push(exact(&p, &r)?.per_step);
    }
    let steps = plant.steps();
    let mut m: Vec<Mat> =
        (0..steps).map(|k| Mat::from_fn(nz, nz, |i, j| if i == j { diag[i][k] } else { 0.0 })).collect();
    for i in 0..nz {
        for j in i + 1..nz {
            let (p, r) = project(plant, real, &(unit(i) + unit(j)));
            let sum = exact(&p, &r)?.per_step;
            for (k, mk) in m.iter_mut().enumerate() {
                let c = 0.5 * (sum[k] - diag[i][k] - diag[j][k]);
                mk[(i, j)] = c;
                mk[(j, i)] = c;
            }
        }
    }
    Ok(m)
}

/// The rank of a claimed error second moment P_z\[k], counted as [`weights`] and
/// [`crate::numerics::linalg::psd_pinv`] count it (eigenvalues above `PSD_TOL` of the largest):
/// the degrees of freedom r of e\[k]ᵀ P_z⁺ e\[k], χ²(r) for a Gaussian error of that covariance
/// (docs/checks.md, `consistent`).
pub fn rank(p: &Mat) -> usize {
    let eig = nalgebra::SymmetricEigen::new(crate::numerics::linalg::symmetrize(p));
    let top = eig.eigenvalues.amax();
    eig.eigenvalues.iter().filter(|l| **l > PSD_TOL * top && **l > 0.0).count()
}

/// The NEES weight of each step, P_z⁺ / rank P_z, from the claimed moments; None where the filter
/// claims no error at all (then the ratio means nothing).
pub fn weights(claimed: &[Mat]) -> Vec<Option<Mat>> {
    claimed
        .iter()
        .map(|p| {
            let rank = rank(p);
            (rank > 0).then(|| crate::numerics::linalg::psd_pinv(p) / rank as f64)
        })
        .collect()
}

/// The exact NEES per step: tr(W\[k] E\[e eᵀ]) with W the [`weights`].
pub fn exact(weights: &[Option<Mat>], moments: &[Mat]) -> Vec<Option<f64>> {
    weights.iter().zip(moments).map(|(w, m)| w.as_ref().map(|w| (w * m).trace())).collect()
}
