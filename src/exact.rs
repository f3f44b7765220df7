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
//!
//! With measurement dropouts (seed 003 (4.30)–(4.33)) F and H are random: F = F̄ + (λ − p) F1,
//! H = H̄ + (λ − p) H1 with F̄, H̄ built on p C and F1 = [[0, 0], [Bf C, 0]], H1 = [−Df C, 0]. Since λ[k]
//! is independent of ξ[k], the second moments pick up p(1 − p) F1 E[ξξᵀ] F1ᵀ (SPEC §0: "the
//! Σ_i A_i M A_iᵀ terms"), with the raw moment E[ξξᵀ] = Σ + m mᵀ because the mean is multiplied too.

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
    /// The parts multiplied by λ − p, and Var λ = p(1 − p); zero without dropouts.
    pub f1: Mat,
    pub h1: Mat,
    pub var: f64,
}

impl Augmented {
    /// E[Fᵀ M F] = F̄ᵀ M F̄ + p(1 − p) F1ᵀ M F1.
    pub fn second_moment_t(&self, m: &Mat) -> Mat {
        let mut out = self.f.transpose() * m * &self.f;
        if self.var > 0.0 {
            out += self.var * (self.f1.transpose() * m * &self.f1);
        }
        out
    }
    /// E[Hᵀ H] = H̄ᵀ H̄ + p(1 − p) H1ᵀ H1.
    pub fn output_gram(&self) -> Mat {
        let mut out = self.h.transpose() * &self.h;
        if self.var > 0.0 {
            out += self.var * (self.h1.transpose() * &self.h1);
        }
        out
    }
    /// E|H ξ|² for E[ξξᵀ] = y (raw moment).
    fn output_power(&self, y: &Mat) -> f64 {
        let mut v = (&self.h * y * self.h.transpose()).trace();
        if self.var > 0.0 {
            v += self.var * (&self.h1 * y * self.h1.transpose()).trace();
        }
        v
    }
}

pub(crate) fn augmented(plant: &Plant, real: &Realization, k: usize) -> Augmented {
    let (n, ns) = (plant.nx(), real.ns());
    let gk = &real.steps[k];
    let (c, d) = (plant.c_at(k), plant.d_at(k));
    let pc = plant.arrival_mean() * c;
    let mut f = Mat::zeros(n + ns, n + ns);
    f.view_mut((0, 0), (n, n)).copy_from(&plant.a);
    f.view_mut((n, 0), (ns, n)).copy_from(&(&gk.bf * &pc));
    f.view_mut((n, n), (ns, ns)).copy_from(&gk.af);
    let mut e = Mat::zeros(n + ns, plant.nw());
    e.view_mut((0, 0), (n, plant.nw())).copy_from(&plant.b);
    e.view_mut((n, 0), (ns, plant.nw())).copy_from(&(&gk.bf * d));
    let mut h = Mat::zeros(plant.nz(), n + ns);
    h.view_mut((0, 0), (plant.nz(), n)).copy_from(&(&plant.cz - &gk.df * &pc));
    h.view_mut((0, n), (plant.nz(), ns)).copy_from(&(-&gk.cf));
    let g = &plant.dz - &gk.df * d;
    let mut f1 = Mat::zeros(n + ns, n + ns);
    let mut h1 = Mat::zeros(plant.nz(), n + ns);
    let var = plant.dropout_variance();
    if var > 0.0 {
        f1.view_mut((n, 0), (ns, n)).copy_from(&(&gk.bf * c));
        h1.view_mut((0, 0), (plant.nz(), n)).copy_from(&(-&gk.df * c));
    }
    Augmented { f, e, h, g, f1, h1, var }
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
    moments(plant, real, cov, w_mean)
}

/// The summed error with no noise at all: what x0's mean and the known input alone cost (with
/// dropouts the known input's trajectory is multiplied by λ − p, so this is not zero).
pub fn deterministic_error(plant: &Plant, real: &Realization) -> f64 {
    moments(plant, real, &zero_covariances(plant), None).total
}

fn zero_covariances(plant: &Plant) -> Covariances {
    Covariances {
        blocks: std::iter::once(plant.nx())
            .chain(plant.noise_blocks.iter().map(|b| b.1))
            .map(|d| Mat::zeros(d, d))
            .collect(),
    }
}

/// The exact error of every step from the mean and covariance recursions (module docs).
fn moments(plant: &Plant, real: &Realization, cov: &Covariances, w_mean: Option<&Mat>) -> ExactError {
    let (n, ns) = (plant.nx(), real.ns());
    let w = cov.w();
    let mut mean = Vector::zeros(n + ns);
    mean.rows_mut(0, n).copy_from(&plant.x0_mean);
    mean.rows_mut(n, ns).copy_from(&real.s0);
    let mut sigma = Mat::zeros(n + ns, n + ns);
    sigma.view_mut((0, 0), (n, n)).copy_from(cov.x0());
    let mut per_step = Vec::with_capacity(plant.steps());
    for k in 0..plant.steps() {
        let aug = augmented(plant, real, k);
        let mut em = &aug.h * &mean;
        if let Some(wm) = w_mean {
            em += &aug.g * wm.column(k);
        }
        let mut mse = em.norm_squared()
            + (&aug.h * &sigma * aug.h.transpose()).trace()
            + (&aug.g * &w * aug.g.transpose()).trace();
        // The dropout term acts on the raw moment: the mean of ξ is multiplied by λ − p as well.
        let raw = (aug.var > 0.0).then(|| &sigma + &mean * mean.transpose());
        if let Some(raw) = &raw {
            mse += aug.var * (&aug.h1 * raw * aug.h1.transpose()).trace();
        }
        per_step.push(mse);
        if k < plant.horizon {
            let mut next = &aug.f * &sigma * aug.f.transpose() + &aug.e * &w * aug.e.transpose();
            if let Some(raw) = &raw {
                next += aug.var * (&aug.f1 * raw * aug.f1.transpose());
            }
            sigma = symmetrize(&next);
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
    ExactError { per_step, total }
}

/// Which step's noise w[k] sits where in a joint input J = col(x0 − E x0, w[0..N−1]) (w[N] = 0) or
/// col(x0 − E x0, w[0..N]): the offset of w[k] in J, None when w[k] = 0.
pub fn joint_offset(plant: &Plant, dim: usize, k: usize) -> Option<usize> {
    let (n, nw) = (plant.nx(), plant.nw());
    let with_last = dim == n + plant.steps() * nw;
    (k < plant.horizon || (k == plant.horizon && with_last)).then_some(n + k * nw)
}

/// The exact error when J = col(x0 − E x0, w[0..N−1] or w[0..N]) has mean `mean` and covariance
/// `cov` jointly over the horizon (not white): a forward recursion on the raw moments
/// m = E ξ, Y = E[ξξᵀ] and the cross moment Z = E[ξ Jᵀ] (ξ = (x, s)),
///
///     m' = F̄ m + E μ_k + c,   Z' = F̄ Z + E R[k, :] + c μᵀ,
///     Y' = F̄ Y F̄ᵀ + p(1−p) F1 Y F1ᵀ + F̄ Z_k Eᵀ + E Z_kᵀ F̄ᵀ + E R_kk Eᵀ + c uᵀ + u cᵀ + c cᵀ,
///
/// with R = cov + μμᵀ, c = (r, Gf r) the known input, u = F̄ m + E μ_k, Z_k = Z[:, w[k]]; then
/// E|e[k]|² = tr(H̄ Y H̄ᵀ) + p(1−p) tr(H1 Y H1ᵀ) + 2 tr(H̄ Z_k Gᵀ) + tr(G R_kk Gᵀ). Exact for dropouts
/// because λ[k] is independent of (ξ[k], J).
pub fn error_joint(plant: &Plant, real: &Realization, mean: &Vector, cov: &Mat) -> crate::error::Result<ExactError> {
    let (n, ns, nw) = (plant.nx(), real.ns(), plant.nw());
    let dj = mean.len();
    if cov.shape() != (dj, dj) || (dj != n + plant.horizon * nw && dj != n + plant.steps() * nw) {
        return Err(crate::error::Error::invalid(
            "input",
            format!("a joint input of dimension {dj} does not fit the plant"),
        ));
    }
    let raw = cov + mean * mean.transpose();
    let mut m = Vector::zeros(n + ns);
    m.rows_mut(0, n).copy_from(&(&plant.x0_mean + mean.rows(0, n)));
    m.rows_mut(n, ns).copy_from(&real.s0);
    let mut y = &m * m.transpose();
    let mut y0 = y.view_mut((0, 0), (n, n));
    y0 += cov.view((0, 0), (n, n));
    let mut z = Mat::zeros(n + ns, dj);
    z.view_mut((0, 0), (n, dj)).copy_from(&(&plant.x0_mean * mean.transpose() + raw.rows(0, n)));
    z.view_mut((n, 0), (ns, dj)).copy_from(&(&real.s0 * mean.transpose()));
    let mut per_step = Vec::with_capacity(plant.steps());
    for k in 0..plant.steps() {
        let aug = augmented(plant, real, k);
        let off = joint_offset(plant, dj, k);
        let mut mse = aug.output_power(&y);
        if let Some(o) = off {
            let zk = z.columns(o, nw);
            mse += 2.0 * (&aug.h * zk * aug.g.transpose()).trace();
            mse += (&aug.g * raw.view((o, o), (nw, nw)) * aug.g.transpose()).trace();
        }
        per_step.push(mse);
        if k == plant.horizon {
            break;
        }
        let mut c = Vector::zeros(n + ns);
        if let Some(r) = plant.r_at(k) {
            c.rows_mut(0, n).copy_from(r);
            c.rows_mut(n, ns).copy_from(&(&real.steps[k].gf * r));
        }
        let mut u = &aug.f * &m;
        let mut y_next = &aug.f * &y * aug.f.transpose();
        if aug.var > 0.0 {
            y_next += aug.var * (&aug.f1 * &y * aug.f1.transpose());
        }
        let mut z_next = &aug.f * &z + &c * mean.transpose();
        if let Some(o) = off {
            let fze = &aug.f * z.columns(o, nw) * aug.e.transpose();
            y_next += &fze + fze.transpose() + &aug.e * raw.view((o, o), (nw, nw)) * aug.e.transpose();
            u += &aug.e * mean.rows(o, nw);
            z_next += &aug.e * raw.rows(o, nw);
        }
        y_next += &c * u.transpose() + &u * c.transpose() + &c * c.transpose();
        m = u + &c;
        y = symmetrize(&y_next);
        z = z_next;
    }
    let total = per_step.iter().enumerate().filter(|(k, _)| plant.counts(*k)).map(|(_, v)| v).sum();
    Ok(ExactError { per_step, total })
}

/// Λ = E[𝓕ᵀ𝓕] of the operator 𝓕 from J = col(x0 − E x0, w[0..N]) to col(e[k], k counted), the
/// known input and x0's mean set aside (seed 003 §2, SPEC §5: "Λ for multiplicative noise is exact
/// from second-moment recursions"). With the backward second moment R_t = E[Hᵀ H] + E[Fᵀ R_{t+1} F]
/// (counted steps only) and L_j = Gᵀ H̄ + Eᵀ R_{j+1} F̄ (λ[j] is independent of everything before):
///
///     Λ_{w_j w_j} = Gᵀ G + Eᵀ R_{j+1} E,   Λ_{w_j w_i} = L_j F̄_{j−1} ⋯ F̄_{i+1} E_i   (i < j),
///
/// and x0 enters like a w_{−1} with E_{−1} = [I; 0]. So E|e|² summed = tr(Λ E[JJᵀ]) for any input.
pub fn second_moment_operator(plant: &Plant, real: &Realization) -> Mat {
    let (n, nw, steps) = (plant.nx(), plant.nw(), plant.steps());
    let augs: Vec<Augmented> = (0..steps).map(|k| augmented(plant, real, k)).collect();
    let nxi = augs[0].f.nrows();
    // r[t] = R_t for t = 0..=N+1 (R_{N+1} = 0).
    let mut r = vec![Mat::zeros(nxi, nxi); steps + 1];
    for t in (0..steps).rev() {
        let mut v = augs[t].second_moment_t(&r[t + 1]);
        if plant.counts(t) {
            v += augs[t].output_gram();
        }
        r[t] = symmetrize(&v);
    }
    let dim = n + steps * nw;
    let mut lambda = Mat::zeros(dim, dim);
    let mut e_x0 = Mat::zeros(nxi, n);
    e_x0.view_mut((0, 0), (n, n)).fill_with_identity();
    lambda.view_mut((0, 0), (n, n)).copy_from(&(e_x0.transpose() * &r[0] * &e_x0));
    for j in 0..steps {
        let a = &augs[j];
        let counted = if plant.counts(j) { 1.0 } else { 0.0 };
        let oj = n + j * nw;
        let diag = counted * a.g.transpose() * &a.g + a.e.transpose() * &r[j + 1] * &a.e;
        lambda.view_mut((oj, oj), (nw, nw)).copy_from(&diag);
        let mut l = counted * a.g.transpose() * &a.h + a.e.transpose() * &r[j + 1] * &a.f;
        for i in (0..j).rev() {
            let oi = n + i * nw;
            let block = &l * &augs[i].e;
            lambda.view_mut((oj, oi), (nw, nw)).copy_from(&block);
            lambda.view_mut((oi, oj), (nw, nw)).copy_from(&block.transpose());
            l = l * &augs[i].f;
        }
        let block = &l * &e_x0;
        lambda.view_mut((oj, 0), (nw, n)).copy_from(&block);
        lambda.view_mut((0, oj), (n, nw)).copy_from(&block.transpose());
    }
    symmetrize(&lambda)
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
            l += aug.output_gram();
        }
        if let Some(next) = &lambda {
            gw += aug.e.transpose() * next * &aug.e;
            l += aug.second_moment_t(next);
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
