//! Exact second moments of a realization's error (SPEC §0, "exact" column): the augmented state
//! ξ = (x, s) obeys
//!
//!     ξ[k+1] = F[k] ξ[k] + E[k] w[k] + (r[k], Gf r[k]),   e[k] = z[k] − ẑ[k] = H[k] ξ[k] + G[k] w[k]
//!     F = [[A, 0], [Bf C, Af]],  E = [B; Bf D],  H = [Cz − Df C, −Cf],  G = Dz − Df D,
//!
//! so the mean follows a linear recursion and the covariance the Lyapunov recursion
//! Σ[k+1] = F Σ Fᵀ + E W Eᵀ, Σ[0] = diag(S_x0, 0). The error is affine in the covariances K, and the
//! backward (adjoint) recursion Λ[k] = HᵀH + Fᵀ Λ[k+1] F gives ∂J/∂K for every block in one pass
//! (seed 000 eq (27), computed as SPEC §2 recommends).

use crate::linalg::{Mat, Vector, symmetrize};
use crate::plant::{Covariances, Plant};
use crate::realization::Realization;
use crate::uncertainty::CovSet;

/// The augmented matrices F, E, H, G of step k (module docs).
pub(crate) struct Augmented {
    pub f: Mat,
    pub e: Mat,
    pub h: Mat,
    pub g: Mat,
}

pub(crate) fn augmented(plant: &Plant, real: &Realization, k: usize) -> Augmented {
    let (n, ns) = (plant.nx(), real.ns());
    let gk = &real.steps[k];
    let (c, d) = (plant.c_at(k), plant.d_at(k));
    let mut f = Mat::zeros(n + ns, n + ns);
    f.view_mut((0, 0), (n, n)).copy_from(&plant.a);
    f.view_mut((n, 0), (ns, n)).copy_from(&(&gk.bf * c));
    f.view_mut((n, n), (ns, ns)).copy_from(&gk.af);
    let mut e = Mat::zeros(n + ns, plant.nw());
    e.view_mut((0, 0), (n, plant.nw())).copy_from(&plant.b);
    e.view_mut((n, 0), (ns, plant.nw())).copy_from(&(&gk.bf * d));
    let mut h = Mat::zeros(plant.nz(), n + ns);
    h.view_mut((0, 0), (plant.nz(), n)).copy_from(&(&plant.cz - &gk.df * c));
    h.view_mut((0, n), (plant.nz(), ns)).copy_from(&(-&gk.cf));
    let g = &plant.dz - &gk.df * d;
    Augmented { f, e, h, g }
}

/// Exact expected squared error E|z[k] − ẑ[k]|² per step and its sum J over the steps that count
/// (k ≥ `plant.sum_from`).
#[derive(Clone, Debug)]
pub struct ExactError {
    pub per_step: Vec<f64>,
    pub total: f64,
}

/// The exact error of `real` on `plant` when x0 and w have the covariances `cov` (any distribution).
pub fn error(plant: &Plant, real: &Realization, cov: &Covariances) -> ExactError {
    error_with_mean(plant, real, cov, None)
}

/// Σ_k |E e[k]|² over the steps that count: the deterministic part of J, from x0's mean, the known
/// input and a deterministic sequence `w_mean` (column k is the mean of w[k]).
pub fn mean_error(plant: &Plant, real: &Realization, w_mean: &Mat) -> f64 {
    error_with_mean(plant, real, &zero_covariances(plant), Some(w_mean)).total
}

/// As [`error`], with w[k] having mean `w_mean` column k (deterministic disturbances, seed 000 §5).
pub fn error_with_mean(plant: &Plant, real: &Realization, cov: &Covariances, w_mean: Option<&Mat>) -> ExactError {
    moments(plant, real, cov, w_mean).0
}

/// The mean error E e[k] at every step when w has zero mean (from x0's mean and the known input).
pub fn mean_errors(plant: &Plant, real: &Realization) -> Vec<Vector> {
    moments(plant, real, &zero_covariances(plant), None).1
}

fn zero_covariances(plant: &Plant) -> Covariances {
    Covariances {
        blocks: std::iter::once(plant.nx())
            .chain(plant.noise_blocks.iter().map(|b| b.1))
            .map(|d| Mat::zeros(d, d))
            .collect(),
    }
}

/// The exact error and the mean error vector of every step.
fn moments(plant: &Plant, real: &Realization, cov: &Covariances, w_mean: Option<&Mat>) -> (ExactError, Vec<Vector>) {
    let (n, ns) = (plant.nx(), real.ns());
    let w = cov.w();
    let mut mean = Vector::zeros(n + ns);
    mean.rows_mut(0, n).copy_from(&plant.x0_mean);
    mean.rows_mut(n, ns).copy_from(&real.s0);
    let mut sigma = Mat::zeros(n + ns, n + ns);
    sigma.view_mut((0, 0), (n, n)).copy_from(cov.x0());
    let mut per_step = Vec::with_capacity(plant.steps());
    let mut means = Vec::with_capacity(plant.steps());
    for k in 0..plant.steps() {
        let aug = augmented(plant, real, k);
        let mut em = &aug.h * &mean;
        if let Some(wm) = w_mean {
            em += &aug.g * wm.column(k);
        }
        let mse = em.norm_squared()
            + (&aug.h * &sigma * aug.h.transpose()).trace()
            + (&aug.g * &w * aug.g.transpose()).trace();
        per_step.push(mse);
        means.push(em);
        if k < plant.horizon {
            sigma = symmetrize(&(&aug.f * &sigma * aug.f.transpose() + &aug.e * &w * aug.e.transpose()));
            let mut next = &aug.f * &mean;
            if let Some(wm) = w_mean {
                next += &aug.e * wm.column(k);
            }
            if let Some(r) = plant.r_at(k) {
                next.rows_mut(0, n).axpy(1.0, r, 1.0);
                let gr = &real.steps[k].gf * r;
                next.rows_mut(n, ns).axpy(1.0, &gr, 1.0);
            }
            mean = next;
        }
    }
    let total = per_step.iter().enumerate().filter(|(k, _)| plant.counts(*k)).map(|(_, v)| v).sum();
    (ExactError { per_step, total }, means)
}

/// The exact error when ξ = col(x0 − E x0, w[0..N−1]) has mean `mean` and covariance `cov` jointly
/// over the horizon (not white) and w[N] = 0: e[k] = c[k] + Ψ_k ξ, so
/// E|e[k]|² = |c[k] + Ψ_k mean|² + tr(Ψ_k cov Ψ_kᵀ).
pub fn error_joint(plant: &Plant, real: &Realization, mean: &Vector, cov: &Mat) -> crate::error::Result<ExactError> {
    let psi = crate::hinf::operator_with(plant, real, crate::hinf::Terminal::Output)?;
    let c = mean_errors(plant, real);
    let nz = plant.nz();
    let per_step: Vec<f64> = (0..plant.steps())
        .map(|k| {
            let pk = psi.rows(k * nz, nz);
            let m = &c[k] + pk * mean;
            m.norm_squared() + (pk * cov * pk.transpose()).trace()
        })
        .collect();
    let total = per_step.iter().enumerate().filter(|(k, _)| plant.counts(*k)).map(|(_, v)| v).sum();
    Ok(ExactError { per_step, total })
}

/// ∂J/∂K for every covariance block (J = summed exact error): J(K) = J(0) + Σ_i ⟨grad_i, K_i⟩.
/// It does not depend on K, since J is affine in K.
pub fn gradient(plant: &Plant, real: &Realization) -> Vec<Mat> {
    let n = plant.nx();
    let nw = plant.nw();
    let mut lambda: Option<Mat> = None;
    let mut gw = Mat::zeros(nw, nw);
    for k in (0..plant.steps()).rev() {
        let aug = augmented(plant, real, k);
        let mut l = Mat::zeros(aug.f.nrows(), aug.f.ncols());
        if plant.counts(k) {
            gw += aug.g.transpose() * &aug.g;
            l += aug.h.transpose() * &aug.h;
        }
        if let Some(next) = &lambda {
            gw += aug.e.transpose() * next * &aug.e;
            l += aug.f.transpose() * next * &aug.f;
        }
        lambda = Some(symmetrize(&l));
    }
    let lambda0 = lambda.expect("at least one step");
    let mut out = vec![lambda0.view((0, 0), (n, n)).into_owned()];
    let mut o = 0;
    for (_, d) in &plant.noise_blocks {
        out.push(symmetrize(&gw.view((o, o), (*d, *d)).into_owned()));
        o += d;
    }
    out
}

/// A realization's worst case over the uncertainty sets (blocks without a set stay at `center`).
#[derive(Clone, Debug)]
pub struct WorstCase {
    pub total: f64,
    pub argmax: Covariances,
    /// Whether every block of the maximizer is PSD (a box corner need not be; then the value is the
    /// maximum over the box as the seed defines it, not over covariances).
    pub psd: bool,
    /// The worst deterministic disturbance sequence (column k adds to w[k]), when there is one.
    pub disturbance: Option<Mat>,
}

/// max over the sets of J(K) = J(center) + Σ_i max_{K_i ∈ set_i} ⟨∂J/∂K_i, K_i − center_i⟩ (J is
/// affine in K, so this is exact; seed 000 eq (26)).
pub fn worst_case(
    plant: &Plant,
    real: &Realization,
    center: &Covariances,
    sets: &[Option<CovSet>],
) -> crate::error::Result<Option<WorstCase>> {
    if sets.iter().all(Option::is_none) {
        return Ok(None);
    }
    let grad = gradient(plant, real);
    let mut total = error(plant, real, center).total;
    let mut argmax = center.clone();
    for (i, set) in sets.iter().enumerate() {
        if let Some(set) = set {
            let (gain, s) = set.linear_gain(&grad[i], &center.blocks[i])?;
            total += gain;
            argmax.blocks[i] = s;
        }
    }
    let psd = argmax.blocks.iter().all(crate::linalg::is_psd);
    Ok(Some(WorstCase { total, argmax, psd, disturbance: None }))
}
