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
//!
//! NIS, the normalized innovation squared, is the same statistic for the innovation
//! ν\[k] = y\[k] − C\[k] s\[k] of a filter whose state estimates x (M = I): s\[k] depends on
//! y\[0..k−1] only, so ν is the measurement's surprise to the filter and its claimed covariance
//! S\[k] = E[ν νᵀ] at the design covariance is C P⁻ Cᵀ + D W Dᵀ for the Kalman filter (seed 002
//! (5.6)–(5.7)). ν is the output error of the [`innovation_system`], so both moments come from the
//! same exact recursions.

use std::sync::Arc;

use crate::analysis::exact::ExactError;
use crate::error::Result;
use crate::filter::realization::Realization;
use crate::model::plant::{Plant, Steps};
use crate::numerics::linalg::{Mat, PSD_TOL};

/// A claimed second moment per step made into the weights of a normalized square (NEES or NIS):
/// P⁺ / rank P and the rank r, the degrees of freedom of the square (χ²(r) for a Gaussian vector of
/// that covariance).
#[derive(Clone, Debug)]
pub struct Normalized {
    /// None at a step where the filter claims nothing (then the ratio means nothing).
    pub weights: Vec<Option<Arc<Mat>>>,
    pub ranks: Vec<usize>,
}

impl Normalized {
    pub fn of(claimed: &[Mat]) -> Self {
        Normalized { weights: weights(claimed), ranks: claimed.iter().map(rank).collect() }
    }
}

/// The plant and filter whose output error is the filter's innovation: z' = y (Cz' = C\[k],
/// Dz' = D, zero before the first measurement) and ẑ' = C\[k] s (Cf' = C\[k], Df' = 0), so that
/// e' = y − C s = ν. Defined for a filter whose state estimates x (M = I), which reads no mode,
/// on a plant with one measurement model and no multiplicative noise in y; None elsewhere: a
/// filter whose state is not an estimate of x has no innovation to speak of, and with modes or
/// random matrices E[ν νᵀ] would mix measurement models the filter does not tell apart.
pub fn innovation_system(plant: &Plant, real: &Realization) -> Option<(Plant, Realization)> {
    let (n, ny) = (plant.nx(), plant.ny());
    let tracks_x = real.tracks.as_ref().is_some_and(|m| m.shape() == (n, n) && *m == Mat::identity(n, n));
    if !tracks_x || real.is_mode_indexed() || plant.n_modes() != 1 || !plant.factors.is_empty() {
        return None;
    }
    let steps = plant.steps();
    let constant = plant.first_measurement == 0 && (1..steps).all(|k| plant.c.at(k) == plant.c.at(0));
    let c: Vec<Mat> =
        if constant { vec![plant.c.at(0).clone()] } else { (0..steps).map(|k| plant.c_at(k).into_owned()).collect() };
    let mut p = plant.clone();
    if plant.first_measurement == 0 {
        p.cz = plant.c.clone();
        p.dz = plant.d.clone();
    } else {
        p.cz = Steps::per_step(c.clone());
        p.dz = Steps::per_step((0..steps).map(|k| plant.d_at(k).into_owned()).collect());
    }
    let mut r = real.clone();
    if constant {
        // One C: settled steps keep sharing their gains (`Realization::map_gains`).
        r.map_gains(|g| {
            g.cf = c[0].clone();
            g.df = Mat::zeros(ny, ny);
        });
    } else {
        for (k, ck) in c.iter().enumerate() {
            for g in r.gains_mut(k).iter_mut() {
                g.cf = ck.clone();
                g.df = Mat::zeros(ny, ny);
            }
        }
    }
    Some((p, r))
}

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

/// E[e\[k] e\[k]ᵀ] for every step k, where `exact` evaluates the per-step mean-square error of
/// pairs of a plant and filter under the input of interest: the error's projections on every unit
/// vector and every sum of two, which differ only in their outputs, so `exact` can run them as one
/// state recursion (`exact::errors`).
pub fn error_moments(
    plant: &Plant,
    real: &Realization,
    exact: &dyn Fn(&[(&Plant, &Realization)]) -> Result<Vec<ExactError>>,
) -> Result<Vec<Mat>> {
    let nz = plant.nz();
    let unit = |i: usize| Mat::from_fn(1, nz, |_, c| (c == i) as u8 as f64);
    let pairs: Vec<(usize, usize)> =
        (0..nz).map(|i| (i, i)).chain((0..nz).flat_map(|i| (i + 1..nz).map(move |j| (i, j)))).collect();
    let projected: Vec<(Plant, Realization)> =
        pairs.iter().map(|&(i, j)| project(plant, real, &if i == j { unit(i) } else { unit(i) + unit(j) })).collect();
    let refs: Vec<(&Plant, &Realization)> = projected.iter().map(|(p, r)| (p, r)).collect();
    let per_step: Vec<Vec<f64>> = exact(&refs)?.into_iter().map(|e| e.per_step).collect();
    let diag = &per_step[..nz];
    let steps = plant.steps();
    let mut m: Vec<Mat> =
        (0..steps).map(|k| Mat::from_fn(nz, nz, |i, j| if i == j { diag[i][k] } else { 0.0 })).collect();
    for (&(i, j), sum) in pairs.iter().zip(&per_step).skip(nz) {
        for (k, mk) in m.iter_mut().enumerate() {
            let c = 0.5 * (sum[k] - diag[i][k] - diag[j][k]);
            mk[(i, j)] = c;
            mk[(j, i)] = c;
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
/// claims no error at all (then the ratio means nothing). A step whose claim is the same bits as
/// the step before's shares its weight: a settled filter on a long horizon costs a pointer per step.
pub fn weights(claimed: &[Mat]) -> Vec<Option<Arc<Mat>>> {
    let mut out: Vec<Option<Arc<Mat>>> = Vec::with_capacity(claimed.len());
    for (k, p) in claimed.iter().enumerate() {
        if k > 0 && claimed[k - 1] == *p {
            out.push(out[k - 1].clone());
            continue;
        }
        let rank = rank(p);
        out.push((rank > 0).then(|| Arc::new(crate::numerics::linalg::psd_pinv(p) / rank as f64)));
    }
    out
}

/// The exact NEES per step: tr(W\[k] E\[e eᵀ]) with W the [`weights`].
pub fn exact(weights: &[Option<Arc<Mat>>], moments: &[Mat]) -> PerStep {
    weights.iter().zip(moments).map(|(w, m)| w.as_ref().map(|w| (&**w * m).trace())).collect()
}

/// An exact NEES or NIS per step, None at a step where the filter claims nothing: the values and
/// one bit a step for whether there is one, 8 bytes and a bit a step where a `Vec<Option<f64>>`
/// takes 16 (every scenario keeps two per filter until the reports: 10⁷ steps at N = 10⁶ with
/// 5 scenarios and 2 filters).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PerStep {
    /// 0 where there is no value.
    values: Vec<f64>,
    /// Bit k: step k has a value.
    present: bit_vec::BitVec,
}

impl PerStep {
    pub fn len(&self) -> usize {
        self.values.len()
    }

    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The value at step k (None where the filter claims nothing, or beyond the horizon).
    pub fn get(&self, k: usize) -> Option<f64> {
        let v = *self.values.get(k)?;
        self.present[k].then_some(v)
    }

    pub fn iter(&self) -> impl Iterator<Item = Option<f64>> + '_ {
        (0..self.len()).map(|k| self.get(k))
    }
}

impl FromIterator<Option<f64>> for PerStep {
    fn from_iter<I: IntoIterator<Item = Option<f64>>>(iter: I) -> Self {
        let iter = iter.into_iter();
        let n = iter.size_hint().0;
        let mut out = PerStep { values: Vec::with_capacity(n), present: bit_vec::BitVec::with_capacity(n) };
        for v in iter {
            out.present.push(v.is_some());
            out.values.push(v.unwrap_or(0.0));
        }
        out
    }
}
