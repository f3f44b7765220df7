//! The error as a function of the covariances: its gradient by the adjoint recursion (seed 000 eq
//! (27)), the second-moment operator, and the worst case over an uncertainty set (docs/math.md §2).

use super::augmented::{Augmented, modal};
use super::form::error_form;
use super::moments::error;
use crate::error::{Error, Result};
use crate::filter::realization::Realization;
use crate::model::plant::{Covariances, Plant};
use crate::model::uncertainty::CovSet;
use crate::numerics::linalg::weighted_sum;
use crate::numerics::linalg::{Mat, symmetrize};

/// Λ = E\[𝓕ᵀ𝓕] of the operator 𝓕 from J = col(x0 − E x0, w\[0..N]) to col(e\[k], k counted), the
/// known input and x0's mean set aside (seed 003 §2, docs/math.md §5: "Λ for multiplicative noise is exact
/// from second-moment recursions"), for modes independent over time with probabilities p_j (the
/// dropout plant). With the backward second moment R_t = Σ_j p_j (H_jᵀH_j + F_jᵀ R_{t+1} F_j)
/// (counted steps only for the H term), the means F̄ = Σ p_j F_j, Ē = Σ p_j E_j, and
/// L_j = Σ_i p_i (G_iᵀ H_i + E_iᵀ R_{j+1} F_i) (θ\[j] is independent of everything before):
///
/// ```text
/// Λ_{w_j w_j} = Σ_i p_i (G_iᵀ G_i + E_iᵀ R_{j+1} E_i),   Λ_{w_j w_i} = L_j F̄_{j−1} ⋯ F̄_{i+1} Ē_i   (i < j),
/// ```
///
/// and x0 enters like a w_{−1} with E_{−1} = [I; 0]. So E|e|² summed = tr(Λ E\[JJᵀ]) for any input.
/// A chain with memory would need the modes carried along; it is refused.
pub fn second_moment_operator(plant: &Plant, real: &Realization) -> Result<Mat> {
    if !plant.independent_modes() {
        return Err(Error::invalid(
            "modes",
            "Λ = E[𝓕ᵀ𝓕] is computed for modes independent over time (dropouts); this chain has memory",
        ));
    }
    let (n, nw, steps) = (plant.nx(), plant.nw(), plant.steps());
    let p = plant.mode_probabilities()[0].clone();
    let augs: Vec<Vec<Augmented>> = (0..steps).map(|k| modal(plant, real, k)).collect();
    let mean = |k: usize, pick: &dyn Fn(&Augmented) -> &Mat| {
        let (r, c) = pick(&augs[k][0]).shape();
        weighted_sum(r, c, augs[k].iter().zip(&p).map(|(a, pj)| (*pj, pick(a))))
    };
    let nxi = augs[0][0].f.nrows();
    // r[t] = R_t for t = 0..=N+1 (R_{N+1} = 0).
    let mut r = vec![Mat::zeros(nxi, nxi); steps + 1];
    for t in (0..steps).rev() {
        let counted = if plant.counts(t) { 1.0 } else { 0.0 };
        let v = augs[t]
            .iter()
            .zip(&p)
            .flat_map(|(a, pj)| a.with_terms().map(move |a| (a, pj)))
            .fold(Mat::zeros(nxi, nxi), |acc, (a, pj)| {
                acc + *pj * (counted * a.h.transpose() * &a.h + a.f.transpose() * &r[t + 1] * &a.f)
            });
        r[t] = symmetrize(&v);
    }
    let dim = n + steps * nw;
    let mut lambda = Mat::zeros(dim, dim);
    let mut e_x0 = Mat::zeros(nxi, n);
    e_x0.view_mut((0, 0), (n, n)).fill_with_identity();
    lambda.view_mut((0, 0), (n, n)).copy_from(&(e_x0.transpose() * &r[0] * &e_x0));
    for j in 0..steps {
        let counted = if plant.counts(j) { 1.0 } else { 0.0 };
        let oj = n + j * nw;
        let (diag, mut l) = augs[j].iter().zip(&p).flat_map(|(a, pj)| a.with_terms().map(move |a| (a, pj))).fold(
            (Mat::zeros(nw, nw), Mat::zeros(nw, nxi)),
            |(d, l), (a, pj)| {
                (
                    d + *pj * (counted * a.g.transpose() * &a.g + a.e.transpose() * &r[j + 1] * &a.e),
                    l + *pj * (counted * a.g.transpose() * &a.h + a.e.transpose() * &r[j + 1] * &a.f),
                )
            },
        );
        lambda.view_mut((oj, oj), (nw, nw)).copy_from(&diag);
        for i in (0..j).rev() {
            let oi = n + i * nw;
            let block = &l * mean(i, &|a| &a.e);
            lambda.view_mut((oj, oi), (nw, nw)).copy_from(&block);
            lambda.view_mut((oi, oj), (nw, nw)).copy_from(&block.transpose());
            l = l * mean(i, &|a| &a.f);
        }
        let block = &l * &e_x0;
        lambda.view_mut((oj, 0), (nw, n)).copy_from(&block);
        lambda.view_mut((0, oj), (n, nw)).copy_from(&block.transpose());
    }
    Ok(symmetrize(&lambda))
}

/// ∂J/∂K for every covariance block (J = summed exact error): J(K) = J(center) + Σ_i ⟨grad_i, K_i⟩.
/// It does not depend on K, since J is affine in K.
///
/// The adjoint cancels like the forward moments on an unstable plant (F_jᵀ Λ F_j multiplies Λ's
/// rounding by |A|² per step while the response of the error stays bounded), so when some A_θ has
/// spectral radius above 1 and the realization passes [`error_form`]'s check, the pass runs in error
/// coordinates: Λ^ε\[k] = HᵀH + Afᵀ Λ^ε\[k+1] Af on ε alone, x0 entering as ε\[0] = s0 − M x0 (x0's
/// gradient Mᵀ Λ^ε\[0] M). Elsewhere the plant coordinates, as before.
pub fn gradient(plant: &Plant, real: &Realization) -> Vec<Mat> {
    let n = plant.nx();
    let unstable =
        || (0..plant.horizon).any(|k| (0..plant.n_modes()).any(|j| spectral_radius(plant.a_of(k, j)) > 1.0 + 1e-12));
    if let Some(form) = real.tracks.as_ref().and_then(|_| unstable().then(|| error_form(plant, real).ok())?) {
        return adjoint_gradient(plant, &|k| form.steps[k].clone(), &(-&form.m));
    }
    let mut x0_map = Mat::zeros(n + real.ns(), n);
    x0_map.view_mut((0, 0), (n, n)).fill_with_identity();
    adjoint_gradient(plant, &|k| modal(plant, real, k), &x0_map)
}

/// The largest |eigenvalue| of a square matrix.
pub(super) fn spectral_radius(a: &Mat) -> f64 {
    a.complex_eigenvalues().iter().map(|z| z.norm()).fold(0.0, f64::max)
}

/// The backward adjoint pass of [`gradient`] on the matrices `system` gives, x0 entering the state
/// as `x0_map` · x0.
pub(super) fn adjoint_gradient(plant: &Plant, system: &dyn Fn(usize) -> Vec<Augmented>, x0_map: &Mat) -> Vec<Mat> {
    let nw = plant.nw();
    let probs = plant.mode_probabilities();
    let q = plant.n_modes();
    let transition = plant.transition();
    let mut lambda: Option<Vec<Mat>> = None;
    let mut gw = Mat::zeros(nw, nw);
    for k in (0..plant.steps()).rev() {
        let augs = system(k);
        let nxi = augs[0].f.nrows();
        let mut here = Vec::with_capacity(q);
        for (j, a) in augs.iter().enumerate() {
            let mut l = Mat::zeros(nxi, nxi);
            let mut g = Mat::zeros(nw, nw);
            let ahead =
                lambda.as_ref().map(|next| weighted_sum(nxi, nxi, (0..q).map(|i| (transition[(j, i)], &next[i]))));
            for t in a.with_terms() {
                if plant.counts(k) {
                    g += t.g.transpose() * &t.g;
                    l += t.h.transpose() * &t.h;
                }
                if let Some(ahead) = &ahead {
                    g += t.e.transpose() * ahead * &t.e;
                    l += t.f.transpose() * ahead * &t.f;
                }
            }
            gw += probs[k][j] * g;
            here.push(symmetrize(&l));
        }
        lambda = Some(here);
    }
    let lambda0 = lambda.expect("at least one step");
    let lx = (0..q).fold(Mat::zeros(x0_map.ncols(), x0_map.ncols()), |acc, j| {
        acc + probs[0][j] * (x0_map.transpose() * &lambda0[j] * x0_map)
    });
    let mut out = vec![symmetrize(&lx)];
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
    /// The worst deterministic disturbance sequence (column k adds to w\[k]), when there is one.
    pub disturbance: Option<Mat>,
    /// The deterministic error that sequence adds and an upper bound on the maximum over all
    /// admissible sequences ([`crate::analysis::disturbance::Worst`]; equal when certified exact).
    pub disturbance_bound: Option<(f64, f64)>,
    /// With deterministic disturbances: a certified upper bound on the maximum of E J over the sets
    /// and the disturbances jointly, the sets' exact maximum plus the disturbances' certified
    /// increase ([`crate::analysis::disturbance::Worst::increase`]); None without disturbances,
    /// where `total` is itself the maximum.
    pub certified: Option<f64>,
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
    let psd = argmax.blocks.iter().all(crate::numerics::linalg::is_psd);
    Ok(Some(WorstCase { total, argmax, psd, disturbance: None, disturbance_bound: None, certified: None }))
}
