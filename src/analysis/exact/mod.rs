//! Exact second moments of a realization's error (docs/math.md §0, "exact" column): the augmented state
//! ξ = (x, s) obeys, in mode θ\[k] = j (one mode for a plant that does not switch),
//!
//! ```text
//! ξ[k+1] = F_j ξ[k] + E_j w[k] + c_j[k],   e[k] = z[k] − ẑ[k] = H_j ξ[k] + G_j w[k]
//! F_j = [[A_j, 0], [Bf C_j, Af]],  E_j = [B_j; Bf D_j],  H_j = [Cz − Df C_j, −Cf],  G_j = Dz − Df D_j,
//! c_j = (r, Gf r),
//! ```
//!
//! with the filter's gains those of mode j when it is mode-indexed. The exact error follows from
//! per-mode raw moments m_j = E\[ξ 1{θ = j}], Y_j = E\[ξξᵀ 1{θ = j}] (seed 001 eq (10); docs/math.md §3: "one
//! recursion per mode"), propagated with the mode's matrices and mixed by Π, since θ\[k+1] depends on
//! the past only through θ\[k]. Without modes this is the mean-plus-Lyapunov recursion
//! Σ\[k+1] = F Σ Fᵀ + E W Eᵀ; with dropouts (seed 003 (4.30)–(4.33), two independent modes) it gives
//! exactly the p(1 − p) terms of the multiplicative-noise form ("the Σ_i A_i M A_iᵀ terms").
//!
//! Inputs drawn jointly over the horizon (not white) add the cross moments Z_j = E\[ξ Jᵀ 1{θ = j}]
//! with the whole input J; for white inputs the cross moment with w\[k] is m_j μ_kᵀ.
//!
//! The error is affine in the covariances K, and the backward (adjoint) recursion
//! Λ_j\[k] = H_jᵀH_j + F_jᵀ (Σ_i Π_ji Λ_i\[k+1]) F_j gives ∂J/∂K for every block in one pass (seed 000
//! eq (27), computed as docs/math.md §2 recommends).

mod form;
mod propagate;
mod sensitivity;

pub use form::*;
use propagate::*;
pub use sensitivity::*;

use crate::error::{Error, Result};
use crate::filter::realization::{Gains, Realization};
use crate::model::plant::{Covariances, Plant};
use crate::model::uncertainty::CovSet;
use crate::numerics::linalg::{Mat, Vector, symmetrize};

/// The augmented matrices F, E, H, G of step k in one mode (module docs), the map from the
/// known input r\[k] to the state's shift c = R r (no columns when the plant has no known input),
/// and one zero-mean term per multiplicative factor ζ_i (seed 003 (4.12)–(4.13)): F = F̄ + Σ ζ_i F_i
/// and so on, which add F_i Y F_iᵀ to the second moments and nothing to the means.
#[derive(Clone, Debug)]
pub(crate) struct Augmented {
    pub f: Mat,
    pub e: Mat,
    pub h: Mat,
    pub g: Mat,
    pub r_map: Mat,
    pub terms: Vec<Augmented>,
}

impl Augmented {
    /// The mean matrices and every factor's term: what a second moment sums over.
    pub fn with_terms(&self) -> impl Iterator<Item = &Augmented> {
        std::iter::once(self).chain(&self.terms)
    }
}

/// The error system of a realization on plant matrices (a, b, c, d, cz, dz) at step k:
/// F = [[A, 0], [Bf C, Af]], E = [B; Bf D], H = [Cz − Df C, −Cf], G = Dz − Df D. A factor's term
/// is the same map of its matrices M_i with the filter's own dynamics (Af, Cf) left out, since the
/// filter's matrices carry no noise.
#[allow(clippy::too_many_arguments)]
fn error_system(n: usize, gk: &Gains, a: &Mat, b: &Mat, c: &Mat, d: &Mat, cz: &Mat, dz: &Mat, own: bool) -> Augmented {
    let (ns, nw, nz) = (gk.af.nrows(), b.ncols(), cz.nrows());
    let mut f = Mat::zeros(n + ns, n + ns);
    f.view_mut((0, 0), (n, n)).copy_from(a);
    f.view_mut((n, 0), (ns, n)).copy_from(&(&gk.bf * c));
    let mut e = Mat::zeros(n + ns, nw);
    e.view_mut((0, 0), (n, nw)).copy_from(b);
    e.view_mut((n, 0), (ns, nw)).copy_from(&(&gk.bf * d));
    let mut h = Mat::zeros(nz, n + ns);
    h.view_mut((0, 0), (nz, n)).copy_from(&(cz - &gk.df * c));
    if own {
        f.view_mut((n, n), (ns, ns)).copy_from(&gk.af);
        h.view_mut((0, n), (nz, ns)).copy_from(&(-&gk.cf));
    }
    let g = dz - &gk.df * d;
    Augmented { f, e, h, g, r_map: Mat::zeros(n + ns, 0), terms: Vec::new() }
}

pub(crate) fn augmented(plant: &Plant, real: &Realization, k: usize, mode: usize) -> Augmented {
    let (n, ns) = (plant.nx(), real.ns());
    let gk = real.gains(k, mode);
    let (a, b) = (plant.a_of(k, mode), plant.b_of(k, mode));
    let (c, d) = (&*plant.c_of(k, mode), &*plant.d_of(k, mode));
    let mut out = error_system(n, gk, a, b, c, d, plant.cz_at(k), plant.dz_at(k), true);
    let mut r_map = Mat::zeros(n + ns, if plant.known_input.is_empty() { 0 } else { n });
    if r_map.ncols() == n {
        r_map.view_mut((0, 0), (n, n)).fill_with_identity();
        r_map.view_mut((n, 0), (ns, n)).copy_from(&gk.gf);
    }
    out.r_map = r_map;
    out.terms = plant
        .factors
        .iter()
        .map(|fac| {
            let pick = |m: &Option<crate::model::plant::Steps>, like: &Mat| {
                m.as_ref().map_or_else(|| Mat::zeros(like.nrows(), like.ncols()), |s| s.at(k).clone())
            };
            // No measurement, no measurement noise: C_i and D_i vanish where C and D do.
            let measured = |m: Mat| if plant.measured(k) { m } else { m * 0.0 };
            let (ai, bi) = (pick(&fac.a, a), pick(&fac.b, b));
            let (ci, di) = (measured(pick(&fac.c, c)), measured(pick(&fac.d, d)));
            let (czi, dzi) = (pick(&fac.cz, plant.cz_at(k)), pick(&fac.dz, plant.dz_at(k)));
            error_system(n, gk, &ai, &bi, &ci, &di, &czi, &dzi, false)
        })
        .collect();
    out
}

/// The augmented matrices of every mode at step k.
fn modal(plant: &Plant, real: &Realization, k: usize) -> Vec<Augmented> {
    (0..plant.n_modes()).map(|j| augmented(plant, real, k, j)).collect()
}

/// Exact expected squared error E|z\[k] − ẑ\[k]|² per step and its sum J over the steps that count
/// (k ≥ `plant.sum_from`).
#[derive(Clone, Debug)]
pub struct ExactError {
    pub per_step: Vec<f64>,
    pub total: f64,
    /// Σ_k E[|e\[k]|² 1{θ\[k] = j}] over the counted steps, per mode j (one entry without modes).
    pub per_mode: Vec<f64>,
    /// How many digits the worst step lost to cancellation, and which step.
    pub resolution: Resolution,
    /// The coordinates the moments were carried in.
    pub coordinates: Coordinates,
    /// Why error coordinates could not be used, when they were needed and could not be.
    pub untracked: Option<String>,
}

/// The coordinates of the moment recursion: the plant's ξ = (x, s) (the reference), or the error
/// coordinates ε = s − M x alone, where M is what the filter's state tracks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coordinates {
    Plant,
    Error,
}

/// Cancellation in one step's error: E|e|² is a sum of terms of magnitude
/// Σ |H| |Y| |H|ᵀ + 2|H| |Z| |G|ᵀ + |G| |R| |G|ᵀ (absolute values entrywise, traces taken), each
/// accurate to about one rounding unit of its own size; the ratio of that magnitude to the result is
/// the factor by which rounding is amplified, and its log10 the decimal digits lost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolution {
    pub step: usize,
    pub digits_lost: f64,
}

/// A double carries about 16 significant digits. A result that lost more than this many (at least
/// ~8 left after the rounding a long recursion accumulates) is not reported: error coordinates are
/// tried, and if they cannot be used the number is refused.
pub const MAX_DIGITS_LOST: f64 = 6.0;

impl ExactError {
    /// Why the value cannot be trusted (the step and the digits lost when double precision does
    /// not resolve it), or None.
    pub fn unresolved(&self) -> Option<String> {
        let Resolution { step, digits_lost } = self.resolution;
        if digits_lost <= MAX_DIGITS_LOST {
            return None;
        }
        let lost = if digits_lost >= 16.0 && digits_lost.is_finite() {
            "all ~16 digits lost to cancellation".to_string()
        } else if digits_lost.is_finite() {
            format!("{digits_lost:.1} of ~16 digits lost to cancellation")
        } else {
            "the moments overflowed".to_string()
        };
        let why = match (&self.untracked, self.coordinates) {
            (Some(why), _) => format!("; error coordinates s − M x do not apply: {why}"),
            (None, Coordinates::Error) => " even in error coordinates s − M x".to_string(),
            (None, Coordinates::Plant) => String::new(),
        };
        Some(format!(
            "double precision cannot resolve its exact error at step {step} ({lost}{why}); the plant's state grows \
             much faster than the error: shorten the horizon or use a filter whose state tracks the plant's in every mode"
        ))
    }

    /// The value, or an error naming the filter, the step and the digits lost.
    pub fn trusted(self, filter: &str) -> Result<Self> {
        match self.unresolved() {
            None => Ok(self),
            Some(cause) => Err(Error::design(filter, cause)),
        }
    }
}

/// The exact error of `real` on `plant` when x0 and w have the covariances `cov` (any distribution).
pub fn error(plant: &Plant, real: &Realization, cov: &Covariances) -> ExactError {
    error_with_mean(plant, real, cov, None)
}

/// Σ_k |E e\[k]|² over the steps that count: the deterministic part of J, from x0's mean, the known
/// input and a deterministic sequence `w_mean` (column k is the mean of w\[k]).
pub fn mean_error(plant: &Plant, real: &Realization, w_mean: &Mat) -> f64 {
    error_with_mean(plant, real, &zero_covariances(plant), Some(w_mean)).total
}

/// As [`error`], with w\[k] having mean `w_mean` column k (deterministic disturbances, seed 000 §5).
pub fn error_with_mean(plant: &Plant, real: &Realization, cov: &Covariances, w_mean: Option<&Mat>) -> ExactError {
    let w = white(plant, cov);
    if !plant.random_matrices()
        && !plant.time_varying()
        && !cov.varies()
        && !has_mean(plant, real, w_mean)
        && plant.nx() >= MODAL_MIN_STATES
    {
        let bwb = plant.b_at(0) * &w[0] * plant.b_at(0).transpose();
        if [plant.a_at(0), cov.x0(), &bwb].into_iter().all(two_by_two_block_diagonal) {
            return propagate_modal(plant, real, cov.x0(), &w[0], &bwb);
        }
    }
    let input = Input::White { w: &w, mean: w_mean };
    resolved(plant, real, &start(plant, real, &Vector::zeros(plant.nx()), cov.x0(), &input), &input)
}

/// W\[k] for [`Input::White`]: one matrix, or one per step when some block varies.
fn white(plant: &Plant, cov: &Covariances) -> Vec<Mat> {
    if cov.varies() { (0..plant.steps()).map(|k| cov.w_at(k)).collect() } else { vec![cov.w()] }
}

/// The plant-coordinate recursion, kept as the reference wherever it resolves the error; where it
/// loses more than [`MAX_DIGITS_LOST`] digits, the same moments in error coordinates (when the
/// realization's declared M passes [`error_form`]'s check).
fn resolved(plant: &Plant, real: &Realization, start: &Start, input: &Input) -> ExactError {
    let reference = propagate(plant, start, input, &|k| modal(plant, real, k));
    if reference.resolution.digits_lost <= MAX_DIGITS_LOST {
        return reference;
    }
    match error_form(plant, real) {
        Ok(form) => {
            let mut out = propagate(plant, &start.transformed(&form.to_error), input, &|k| form.steps[k].clone());
            out.coordinates = Coordinates::Error;
            out
        }
        Err(why) => ExactError { untracked: Some(why), ..reference },
    }
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
    Covariances::new(
        std::iter::once(plant.nx()).chain(plant.noise_blocks.iter().map(|b| b.1)).map(|d| Mat::zeros(d, d)).collect(),
    )
}

/// Which step's noise w\[k] sits where in a joint input J = col(x0 − E x0, w\[0..N−1]) (w\[N] = 0) or
/// col(x0 − E x0, w\[0..N]): the offset of w\[k] in J, None when w\[k] = 0.
pub fn joint_offset(plant: &Plant, dim: usize, k: usize) -> Option<usize> {
    let (n, nw) = (plant.nx(), plant.nw());
    let with_last = dim == n + plant.steps() * nw;
    (k < plant.horizon || (k == plant.horizon && with_last)).then_some(n + k * nw)
}

/// The exact error when J = col(x0 − E x0, w\[0..N−1] or w\[0..N]) has mean `mean` and covariance
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
    let input = Input::Joint { mean, raw: &raw };
    Ok(resolved(plant, real, &start(plant, real, &x0_shift, &x0_cov, &input), &input))
}
