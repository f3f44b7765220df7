//! Exact second moments of a realization's error (SPEC §0, "exact" column): the augmented state
//! ξ = (x, s) obeys, in mode θ[k] = j (one mode for a plant that does not switch),
//!
//!     ξ[k+1] = F_j ξ[k] + E_j w[k] + c_j[k],   e[k] = z[k] − ẑ[k] = H_j ξ[k] + G_j w[k]
//!     F_j = [[A_j, 0], [Bf C_j, Af]],  E_j = [B_j; Bf D_j],  H_j = [Cz − Df C_j, −Cf],  G_j = Dz − Df D_j,
//!     c_j = (r, Gf r),
//!
//! with the filter's gains those of mode j when it is mode-indexed. The exact error follows from
//! per-mode raw moments m_j = E[ξ 1{θ = j}], Y_j = E[ξξᵀ 1{θ = j}] (seed 001 eq (10); SPEC §3: "one
//! recursion per mode"), propagated with the mode's matrices and mixed by Π, since θ[k+1] depends on
//! the past only through θ[k]. Without modes this is the mean-plus-Lyapunov recursion
//! Σ[k+1] = F Σ Fᵀ + E W Eᵀ; with dropouts (seed 003 (4.30)–(4.33), two independent modes) it gives
//! exactly the p(1 − p) terms of the multiplicative-noise form ("the Σ_i A_i M A_iᵀ terms").
//!
//! Inputs drawn jointly over the horizon (not white) add the cross moments Z_j = E[ξ Jᵀ 1{θ = j}]
//! with the whole input J; for white inputs the cross moment with w[k] is m_j μ_kᵀ.
//!
//! The error is affine in the covariances K, and the backward (adjoint) recursion
//! Λ_j[k] = H_jᵀH_j + F_jᵀ (Σ_i Π_ji Λ_i[k+1]) F_j gives ∂J/∂K for every block in one pass (seed 000
//! eq (27), computed as SPEC §2 recommends).

use crate::error::{Error, Result};
use crate::linalg::{Mat, Vector, symmetrize};
use crate::plant::{Covariances, Plant};
use crate::realization::Realization;
use crate::uncertainty::CovSet;

/// The augmented matrices F, E, H, G of step k in one mode (module docs), and c's Gf.
pub(crate) struct Augmented {
    pub f: Mat,
    pub e: Mat,
    pub h: Mat,
    pub g: Mat,
    pub gf: Mat,
}

pub(crate) fn augmented(plant: &Plant, real: &Realization, k: usize, mode: usize) -> Augmented {
    let (n, ns) = (plant.nx(), real.ns());
    let gk = real.gains(k, mode);
    let (a, b) = (plant.a_of(mode), plant.b_of(mode));
    let (c, d) = (plant.c_of(k, mode), plant.d_of(k, mode));
    let mut f = Mat::zeros(n + ns, n + ns);
    f.view_mut((0, 0), (n, n)).copy_from(a);
    f.view_mut((n, 0), (ns, n)).copy_from(&(&gk.bf * c));
    f.view_mut((n, n), (ns, ns)).copy_from(&gk.af);
    let mut e = Mat::zeros(n + ns, plant.nw());
    e.view_mut((0, 0), (n, plant.nw())).copy_from(b);
    e.view_mut((n, 0), (ns, plant.nw())).copy_from(&(&gk.bf * d));
    let mut h = Mat::zeros(plant.nz(), n + ns);
    h.view_mut((0, 0), (plant.nz(), n)).copy_from(&(&plant.cz - &gk.df * c));
    h.view_mut((0, n), (plant.nz(), ns)).copy_from(&(-&gk.cf));
    let g = &plant.dz - &gk.df * d;
    Augmented { f, e, h, g, gf: gk.gf.clone() }
}

/// The augmented matrices of every mode at step k.
fn modal(plant: &Plant, real: &Realization, k: usize) -> Vec<Augmented> {
    (0..plant.n_modes()).map(|j| augmented(plant, real, k, j)).collect()
}

/// Exact expected squared error E|z[k] − ẑ[k]|² per step and its sum J over the steps that count
/// (k ≥ `plant.sum_from`).
#[derive(Clone, Debug)]
pub struct ExactError {
    pub per_step: Vec<f64>,
    pub total: f64,
    /// Σ_k E[|e[k]|² 1{θ[k] = j}] over the counted steps, per mode j (one entry without modes).
    pub per_mode: Vec<f64>,
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
    let w = cov.w();
    if plant.modes.is_none() && !has_mean(plant, real, w_mean) && plant.nx() >= MODAL_MIN_STATES {
        let bwb = &plant.b * &w * plant.b.transpose();
        if [&plant.a, cov.x0(), &bwb].into_iter().all(two_by_two_block_diagonal) {
            return propagate_modal(plant, real, cov.x0(), &w, &bwb);
        }
    }
    propagate(plant, real, &Vector::zeros(plant.nx()), cov.x0(), &Input::White { w: &w, mean: w_mean })
}

/// The summed error with no noise at all: what x0's mean and the known input alone cost (with
/// dropouts the known input's trajectory is multiplied by λ − p, so this is not zero).
pub fn deterministic_error(plant: &Plant, real: &Realization) -> f64 {
    if !has_mean(plant, real, None) {
        return 0.0;
    }
    error(plant, real, &zero_covariances(plant)).total
}

/// Whether anything in the augmented state has a nonzero mean: x0's, the filter's start s0, the
/// known input or a deterministic sequence in w.
fn has_mean(plant: &Plant, real: &Realization, w_mean: Option<&Mat>) -> bool {
    w_mean.is_some() || !plant.known_input.is_empty() || plant.x0_mean.amax() != 0.0 || real.s0.amax() != 0.0
}

fn zero_covariances(plant: &Plant) -> Covariances {
    Covariances {
        blocks: std::iter::once(plant.nx())
            .chain(plant.noise_blocks.iter().map(|b| b.1))
            .map(|d| Mat::zeros(d, d))
            .collect(),
    }
}

/// Which step's noise w[k] sits where in a joint input J = col(x0 − E x0, w[0..N−1]) (w[N] = 0) or
/// col(x0 − E x0, w[0..N]): the offset of w[k] in J, None when w[k] = 0.
pub fn joint_offset(plant: &Plant, dim: usize, k: usize) -> Option<usize> {
    let (n, nw) = (plant.nx(), plant.nw());
    let with_last = dim == n + plant.steps() * nw;
    (k < plant.horizon || (k == plant.horizon && with_last)).then_some(n + k * nw)
}

/// The exact error when J = col(x0 − E x0, w[0..N−1] or w[0..N]) has mean `mean` and covariance
/// `cov` jointly over the horizon (not white).
pub fn error_joint(plant: &Plant, real: &Realization, mean: &Vector, cov: &Mat) -> Result<ExactError> {
    let (n, nw) = (plant.nx(), plant.nw());
    let dj = mean.len();
    if cov.shape() != (dj, dj) || (dj != n + plant.horizon * nw && dj != n + plant.steps() * nw) {
        return Err(Error::invalid("input", format!("a joint input of dimension {dj} does not fit the plant")));
    }
    let raw = cov + mean * mean.transpose();
    let x0_cov = cov.view((0, 0), (n, n)).into_owned();
    let x0_shift = mean.rows(0, n).into_owned();
    Ok(propagate(plant, real, &x0_shift, &x0_cov, &Input::Joint { mean, raw: &raw }))
}

/// What drives the recursion besides x0: white noise (covariance and optional mean per step) or a
/// joint input J with mean and raw second moment over the whole horizon.
enum Input<'a> {
    White { w: &'a Mat, mean: Option<&'a Mat> },
    Joint { mean: &'a Vector, raw: &'a Mat },
}

/// The per-mode raw-moment recursion of the module docs; x0 = E x0 + x0_shift + δ with Cov δ = x0_cov.
fn propagate(plant: &Plant, real: &Realization, x0_shift: &Vector, x0_cov: &Mat, input: &Input) -> ExactError {
    let (n, ns, nw) = (plant.nx(), real.ns(), plant.nw());
    let nxi = n + ns;
    let probs = plant.mode_probabilities();
    let q = plant.n_modes();
    let transition = plant.modes.as_ref().map(|m| m.transition.clone()).unwrap_or_else(|| Mat::identity(1, 1));
    let mut m0 = Vector::zeros(nxi);
    m0.rows_mut(0, n).copy_from(&(&plant.x0_mean + x0_shift));
    m0.rows_mut(n, ns).copy_from(&real.s0);
    let mut y0 = &m0 * m0.transpose();
    let mut top = y0.view_mut((0, 0), (n, n));
    top += x0_cov;
    let z0 = match input {
        Input::White { .. } => None,
        Input::Joint { mean, raw } => {
            let dj = mean.len();
            let mut z = Mat::zeros(nxi, dj);
            z.view_mut((0, 0), (n, dj)).copy_from(&(&plant.x0_mean * mean.transpose() + raw.rows(0, n)));
            z.view_mut((n, 0), (ns, dj)).copy_from(&(&real.s0 * mean.transpose()));
            Some(z)
        }
    };
    let mut m: Vec<Vector> = probs[0].iter().map(|p| &m0 * *p).collect();
    let mut y: Vec<Mat> = probs[0].iter().map(|p| &y0 * *p).collect();
    let mut z: Vec<Option<Mat>> = probs[0].iter().map(|p| z0.as_ref().map(|z| z * *p)).collect();
    let mut per_step = Vec::with_capacity(plant.steps());
    let mut per_mode = vec![0.0; q];
    for k in 0..plant.steps() {
        let augs = modal(plant, real, k);
        // The moments of w[k]: mean μ and raw second moment R (zero when w[k] is not drawn).
        let (mu, rkk, off) = match input {
            Input::White { w, mean } => {
                let mu = mean.map_or_else(|| Vector::zeros(nw), |m| m.column(k).into_owned());
                let r = *w + &mu * mu.transpose();
                (mu, r, None)
            }
            Input::Joint { mean, raw } => match joint_offset(plant, mean.len(), k) {
                Some(o) => (mean.rows(o, nw).into_owned(), raw.view((o, o), (nw, nw)).into_owned(), Some(o)),
                None => (Vector::zeros(nw), Mat::zeros(nw, nw), None),
            },
        };
        let r = plant.r_at(k);
        let mut mse = 0.0;
        let mut next: Vec<(Vector, Mat, Option<Mat>)> = Vec::with_capacity(q);
        let counted = plant.counts(k);
        for (j, a) in augs.iter().enumerate() {
            let pj = probs[k][j];
            // E[ξ w[k]ᵀ 1{θ = j}]: from the cross moment, or m_j μᵀ when w[k] is independent of ξ.
            let zk = match (&z[j], off) {
                (Some(zj), Some(o)) => zj.columns(o, nw).into_owned(),
                (Some(_), None) => Mat::zeros(nxi, nw),
                (None, _) => &m[j] * mu.transpose(),
            };
            let ej = (&a.h * &y[j] * a.h.transpose()).trace()
                + 2.0 * (&a.h * &zk * a.g.transpose()).trace()
                + pj * (&a.g * &rkk * a.g.transpose()).trace();
            mse += ej;
            if counted {
                per_mode[j] += ej;
            }
            if k == plant.horizon {
                continue;
            }
            let mut c = Vector::zeros(nxi);
            if let Some(r) = r {
                c.rows_mut(0, n).copy_from(r);
                c.rows_mut(n, ns).copy_from(&(&a.gf * r));
            }
            let v = &a.f * &m[j] + pj * (&a.e * &mu);
            let fze = &a.f * &zk * a.e.transpose();
            let yn = &a.f * &y[j] * a.f.transpose()
                + &fze
                + fze.transpose()
                + pj * (&a.e * &rkk * a.e.transpose())
                + &c * v.transpose()
                + &v * c.transpose()
                + pj * (&c * c.transpose());
            let zn = match (&z[j], input) {
                (Some(zj), Input::Joint { mean, raw }) => {
                    let mut zn = &a.f * zj + pj * (&c * mean.transpose());
                    if let Some(o) = off {
                        zn += pj * (&a.e * raw.rows(o, nw));
                    }
                    Some(zn)
                }
                _ => None,
            };
            next.push((v + pj * c, yn, zn));
        }
        per_step.push(mse);
        if k == plant.horizon {
            break;
        }
        // Mix by the chain: moments of θ[k+1] = i collect Π_ji times those of θ[k] = j.
        for i in 0..q {
            m[i] = (0..q).fold(Vector::zeros(nxi), |acc, j| acc + transition[(j, i)] * &next[j].0);
            y[i] = symmetrize(&(0..q).fold(Mat::zeros(nxi, nxi), |acc, j| acc + transition[(j, i)] * &next[j].1));
            z[i] = next[0].2.as_ref().map(|z0| {
                (0..q).fold(Mat::zeros(z0.nrows(), z0.ncols()), |acc, j| {
                    acc + transition[(j, i)] * next[j].2.as_ref().expect("every mode carries Z")
                })
            });
        }
    }
    let total = per_step.iter().enumerate().filter(|(k, _)| plant.counts(*k)).map(|(_, v)| v).sum();
    ExactError { per_step, total, per_mode }
}

/// Below this many states the dense recursion costs nothing and the structure is not looked for.
const MODAL_MIN_STATES: usize = 32;

/// Whether `m` is zero outside 2×2 blocks on its diagonal (a modal truth: independent oscillators).
fn two_by_two_block_diagonal(m: &Mat) -> bool {
    m.nrows() % 2 == 0
        && m.iter().enumerate().all(|(idx, v)| *v == 0.0 || (idx % m.nrows()) / 2 == (idx / m.nrows()) / 2)
}

/// The recursion of [`propagate`] when A, cov x0 and B W Bᵀ are block diagonal in 2×2 blocks and
/// there are no modes and no means (a modal truth, seed 004's string): the state covariance stays
/// block diagonal, so only its blocks P_b, the cross covariance X = E[x sᵀ] and the filter's
/// S = E[s sᵀ] are carried:
///
///     P_b' = A_b P_b A_bᵀ + (B W Bᵀ)_b,   X' = A X Afᵀ + A P (Bf C)ᵀ + B W Dᵀ Bfᵀ,
///     S' = Af S Afᵀ + Af Xᵀ (Bf C)ᵀ + (Bf C) X Afᵀ + (Bf C) P (Bf C)ᵀ + Bf D W Dᵀ Bfᵀ,
///
/// E|e|² = Σ_b tr(H_x,b P_b H_x,bᵀ) + 2 tr(H_x X H_sᵀ) + tr(H_s S H_sᵀ) + tr(G W Gᵀ), with
/// H_x = Cz − Df C, H_s = −Cf, G = Dz − Df D. The cost per step is linear in the number of modes
/// instead of cubic.
fn propagate_modal(plant: &Plant, real: &Realization, x0_cov: &Mat, w: &Mat, bwb_full: &Mat) -> ExactError {
    let (nx, ns) = (plant.nx(), real.ns());
    let nb = nx / 2;
    let blk = |m: &Mat, b: usize| m.view((2 * b, 2 * b), (2, 2)).into_owned();
    let a: Vec<Mat> = (0..nb).map(|b| blk(&plant.a, b)).collect();
    let bwb: Vec<Mat> = (0..nb).map(|b| blk(bwb_full, b)).collect();
    let mut p: Vec<Mat> = (0..nb).map(|b| blk(x0_cov, b)).collect();
    let mut x = Mat::zeros(nx, ns);
    let mut sm = Mat::zeros(ns, ns);
    // Block-diagonal products: A·M and P·M for M with nx rows.
    let bd_mul = |d: &[Mat], m: &Mat| {
        let mut out = Mat::zeros(m.nrows(), m.ncols());
        for (b, db) in d.iter().enumerate() {
            out.rows_mut(2 * b, 2).copy_from(&(db * m.rows(2 * b, 2)));
        }
        out
    };
    let bw = &plant.b * w;
    let mut per_step = Vec::with_capacity(plant.steps());
    for k in 0..plant.steps() {
        let g = real.gains(k, 0);
        let (c, d) = (plant.c_at(k), plant.d_at(k));
        let hx = &plant.cz - &g.df * c;
        let hs = -&g.cf;
        let gw = &plant.dz - &g.df * d;
        let mut mse = 2.0 * (&hx * &x * hs.transpose()).trace()
            + (&hs * &sm * hs.transpose()).trace()
            + (&gw * w * gw.transpose()).trace();
        for (b, pb) in p.iter().enumerate() {
            let h = hx.columns(2 * b, 2);
            mse += (h * pb * h.transpose()).trace();
        }
        per_step.push(mse);
        if k == plant.horizon {
            break;
        }
        let gc = &g.bf * c;
        let pgc = bd_mul(&p, &gc.transpose());
        let bwd = &bw * d.transpose() * g.bf.transpose();
        let dwd = &g.bf * d * w * d.transpose() * g.bf.transpose();
        let x_next = bd_mul(&a, &(&x * g.af.transpose() + &pgc)) + bwd;
        let xg = x.transpose() * gc.transpose();
        let s_next =
            &g.af * &sm * g.af.transpose() + &g.af * &xg + xg.transpose() * g.af.transpose() + &gc * &pgc + dwd;
        for b in 0..nb {
            p[b] = symmetrize(&(&a[b] * &p[b] * a[b].transpose() + &bwb[b]));
        }
        x = x_next;
        sm = symmetrize(&s_next);
    }
    let total: f64 = per_step.iter().enumerate().filter(|(k, _)| plant.counts(*k)).map(|(_, v)| v).sum();
    ExactError { per_step, total, per_mode: vec![total] }
}

/// Λ = E[𝓕ᵀ𝓕] of the operator 𝓕 from J = col(x0 − E x0, w[0..N]) to col(e[k], k counted), the
/// known input and x0's mean set aside (seed 003 §2, SPEC §5: "Λ for multiplicative noise is exact
/// from second-moment recursions"), for modes independent over time with probabilities p_j (the
/// dropout plant). With the backward second moment R_t = Σ_j p_j (H_jᵀH_j + F_jᵀ R_{t+1} F_j)
/// (counted steps only for the H term), the means F̄ = Σ p_j F_j, Ē = Σ p_j E_j, and
/// L_j = Σ_i p_i (G_iᵀ H_i + E_iᵀ R_{j+1} F_i) (θ[j] is independent of everything before):
///
///     Λ_{w_j w_j} = Σ_i p_i (G_iᵀ G_i + E_iᵀ R_{j+1} E_i),   Λ_{w_j w_i} = L_j F̄_{j−1} ⋯ F̄_{i+1} Ē_i   (i < j),
///
/// and x0 enters like a w_{−1} with E_{−1} = [I; 0]. So E|e|² summed = tr(Λ E[JJᵀ]) for any input.
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
        augs[k]
            .iter()
            .zip(&p)
            .fold(Mat::zeros(pick(&augs[k][0]).nrows(), pick(&augs[k][0]).ncols()), |acc, (a, pj)| acc + *pj * pick(a))
    };
    let nxi = augs[0][0].f.nrows();
    // r[t] = R_t for t = 0..=N+1 (R_{N+1} = 0).
    let mut r = vec![Mat::zeros(nxi, nxi); steps + 1];
    for t in (0..steps).rev() {
        let counted = if plant.counts(t) { 1.0 } else { 0.0 };
        let v = augs[t].iter().zip(&p).fold(Mat::zeros(nxi, nxi), |acc, (a, pj)| {
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
        let (diag, mut l) =
            augs[j].iter().zip(&p).fold((Mat::zeros(nw, nw), Mat::zeros(nw, nxi)), |(d, l), (a, pj)| {
                (
                    d + *pj * (counted * a.g.transpose() * &a.g + a.e.transpose() * &r[j + 1] * &a.e),
                    l + *pj * (counted * a.g.transpose() * &a.h + a.e.transpose() * &r[j + 1] * &a.f),
                )
            });
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

/// ∂J/∂K for every covariance block (J = summed exact error): J(K) = J(0) + Σ_i ⟨grad_i, K_i⟩.
/// It does not depend on K, since J is affine in K.
pub fn gradient(plant: &Plant, real: &Realization) -> Vec<Mat> {
    let n = plant.nx();
    let nw = plant.nw();
    let probs = plant.mode_probabilities();
    let q = plant.n_modes();
    let transition = plant.modes.as_ref().map(|m| m.transition.clone()).unwrap_or_else(|| Mat::identity(1, 1));
    let mut lambda: Option<Vec<Mat>> = None;
    let mut gw = Mat::zeros(nw, nw);
    for k in (0..plant.steps()).rev() {
        let augs = modal(plant, real, k);
        let nxi = augs[0].f.nrows();
        let mut here = Vec::with_capacity(q);
        for (j, a) in augs.iter().enumerate() {
            let mut l = Mat::zeros(nxi, nxi);
            let mut g = Mat::zeros(nw, nw);
            if plant.counts(k) {
                g += a.g.transpose() * &a.g;
                l += a.h.transpose() * &a.h;
            }
            if let Some(next) = &lambda {
                let ahead = (0..q).fold(Mat::zeros(nxi, nxi), |acc, i| acc + transition[(j, i)] * &next[i]);
                g += a.e.transpose() * &ahead * &a.e;
                l += a.f.transpose() * &ahead * &a.f;
            }
            gw += probs[k][j] * g;
            here.push(symmetrize(&l));
        }
        lambda = Some(here);
    }
    let lambda0 = lambda.expect("at least one step");
    let lx = (0..q).fold(Mat::zeros(n, n), |acc, j| acc + probs[0][j] * lambda0[j].view((0, 0), (n, n)));
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
