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
use crate::filter::realization::Realization;
use crate::model::plant::{Covariances, Plant};
use crate::model::uncertainty::CovSet;
use crate::numerics::linalg::{Mat, Vector, symmetrize};

/// The augmented matrices F, E, H, G of step k in one mode (module docs), and the map from the
/// known input r[k] to the state's shift c = R r (no columns when the plant has no known input).
#[derive(Clone, Debug)]
pub(crate) struct Augmented {
    pub f: Mat,
    pub e: Mat,
    pub h: Mat,
    pub g: Mat,
    pub r_map: Mat,
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
    let mut r_map = Mat::zeros(n + ns, if plant.known_input.is_empty() { 0 } else { n });
    if r_map.ncols() == n {
        r_map.view_mut((0, 0), (n, n)).fill_with_identity();
        r_map.view_mut((n, 0), (ns, n)).copy_from(&gk.gf);
    }
    Augmented { f, e, h, g, r_map }
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
    let input = Input::White { w: &w, mean: w_mean };
    resolved(plant, real, &start(plant, real, &Vector::zeros(plant.nx()), cov.x0(), &input), &input)
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

/// [`error`] computed in error coordinates whatever the plant-coordinate recursion would give, or
/// why they do not apply (for comparing the two where both are accurate).
pub fn error_in_error_coordinates(
    plant: &Plant,
    real: &Realization,
    cov: &Covariances,
) -> std::result::Result<ExactError, String> {
    let form = error_form(plant, real)?;
    let w = cov.w();
    let input = Input::White { w: &w, mean: None };
    let start = start(plant, real, &Vector::zeros(plant.nx()), cov.x0(), &input).transformed(&form.to_error);
    let mut out = propagate(plant, &start, &input, &|k| form.steps[k].clone());
    out.coordinates = Coordinates::Error;
    Ok(out)
}

/// A realization in error coordinates ε = s − M x: with T_j = Af M + Bf C_j − M A_j = 0 and
/// Cz − Df C_j − Cf M = 0 at every step and mode (checked, not assumed),
///
///     ε[k+1] = Af ε + (Bf D_j − M B_j) w + (Gf − M) r,   e[k] = −Cf ε + (Dz − Df D_j) w,
///
/// so x drops out and neither the exact moments nor a simulated trial ever difference it.
#[derive(Clone, Debug)]
pub struct ErrorForm {
    /// M, what the state tracks.
    pub m: Mat,
    /// [−M, I]: ε = to_error · (x, s).
    pub to_error: Mat,
    /// M = I exactly (then x − s = −ε, with no x to difference).
    pub identity: bool,
    /// The ε system of each step, per mode: F = Af, E, H = −Cf, G, R = Gf − M.
    pub(crate) steps: Vec<Vec<Augmented>>,
}

/// A residual counts as zero below this fraction of the products it is made of: the rounding of
/// gains computed from the identity is ~1e-16 of them, a filter that does not satisfy it is ≳ 1e-3.
const IDENTITY_TOLERANCE: f64 = 1e-9;

/// The realization in error coordinates, or why not: no M declared, M of the wrong size, or the
/// step and mode where Af M + Bf C − M A (or Cz − Df C − Cf M) is not zero, with its size. A
/// residual within rounding of its terms is set to exactly zero: these are the coordinates of the
/// filter its family designed, whose gains satisfy the identity by construction.
pub fn error_form(plant: &Plant, real: &Realization) -> std::result::Result<ErrorForm, String> {
    let (n, ns) = (plant.nx(), real.ns());
    let m = real.tracks.as_ref().ok_or("the filter declares no M (what its state tracks)")?;
    if m.shape() != (ns, n) {
        return Err(format!("its M is {}×{}, not {ns}×{n}", m.nrows(), m.ncols()));
    }
    let fro = |a: &Mat| a.norm();
    let mut steps = Vec::with_capacity(plant.steps());
    for k in 0..plant.steps() {
        let mut here = Vec::with_capacity(plant.n_modes());
        for j in 0..plant.n_modes() {
            let g = real.gains(k, j);
            let (a, b) = (plant.a_of(j), plant.b_of(j));
            let (c, d) = (plant.c_of(k, j), plant.d_of(k, j));
            let hx = &plant.cz - &g.df * c - &g.cf * m;
            let h_scale = fro(&plant.cz) + fro(&g.df) * fro(c) + fro(&g.cf) * fro(m);
            let mut residuals = vec![("Cz − Df C − Cf M", hx.norm(), h_scale)];
            if k < plant.horizon {
                let t = &g.af * m + &g.bf * c - m * a;
                residuals.push((
                    "Af M + Bf C − M A",
                    t.norm(),
                    fro(&g.af) * fro(m) + fro(&g.bf) * fro(c) + fro(m) * fro(a),
                ));
            }
            for (what, r, scale) in residuals {
                if r > IDENTITY_TOLERANCE * scale {
                    let mode = plant.modes.as_ref().map_or(String::new(), |md| format!(", mode {}", md.names[j]));
                    return Err(format!("{what} = {r:.2e} (relative {:.1e}) at step {k}{mode}", r / scale.max(1e-300)));
                }
            }
            let r_map = if plant.known_input.is_empty() { Mat::zeros(ns, 0) } else { &g.gf - m };
            here.push(Augmented { f: g.af.clone(), e: &g.bf * d - m * b, h: -&g.cf, g: &plant.dz - &g.df * d, r_map });
        }
        steps.push(here);
    }
    let mut to_error = Mat::zeros(ns, n + ns);
    to_error.view_mut((0, 0), (ns, n)).copy_from(&(-m));
    to_error.view_mut((0, n), (ns, ns)).fill_with_identity();
    let identity = ns == n && *m == Mat::identity(n, n);
    Ok(ErrorForm { m: m.clone(), to_error, identity, steps })
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
    let input = Input::Joint { mean, raw: &raw };
    Ok(resolved(plant, real, &start(plant, real, &x0_shift, &x0_cov, &input), &input))
}

/// What drives the recursion besides x0: white noise (covariance and optional mean per step) or a
/// joint input J with mean and raw second moment over the whole horizon.
enum Input<'a> {
    White { w: &'a Mat, mean: Option<&'a Mat> },
    Joint { mean: &'a Vector, raw: &'a Mat },
}

/// The moments at k = 0 before the modes are mixed in: mean m, raw second moment Y and, for a joint
/// input, the cross moment Z = E[ξ Jᵀ].
struct Start {
    m: Vector,
    y: Mat,
    z: Option<Mat>,
}

impl Start {
    /// The moments of P ξ.
    fn transformed(&self, p: &Mat) -> Start {
        Start { m: p * &self.m, y: symmetrize(&(p * &self.y * p.transpose())), z: self.z.as_ref().map(|z| p * z) }
    }
}

/// ξ[0] = (x0, s0) in plant coordinates, with x0 = E x0 + x0_shift + δ, Cov δ = x0_cov.
fn start(plant: &Plant, real: &Realization, x0_shift: &Vector, x0_cov: &Mat, input: &Input) -> Start {
    let (n, ns) = (plant.nx(), real.ns());
    let nxi = n + ns;
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
    Start { m: m0, y: y0, z: z0 }
}

/// Σ_ab |A|_ab |B|_ab: the magnitude of ⟨A, B⟩'s terms.
fn abs_dot(a: &Mat, b: &Mat) -> f64 {
    a.iter().zip(b.iter()).map(|(x, y)| (x * y).abs()).sum()
}

/// The per-mode raw-moment recursion of the module docs, in whatever coordinates `system` gives
/// the matrices of (the state dimension is the start's).
fn propagate(plant: &Plant, start: &Start, input: &Input, system: &dyn Fn(usize) -> Vec<Augmented>) -> ExactError {
    let nw = plant.nw();
    let nxi = start.m.len();
    let probs = plant.mode_probabilities();
    let q = plant.n_modes();
    let transition = plant.modes.as_ref().map(|m| m.transition.clone()).unwrap_or_else(|| Mat::identity(1, 1));
    let mut m: Vec<Vector> = probs[0].iter().map(|p| &start.m * *p).collect();
    let mut y: Vec<Mat> = probs[0].iter().map(|p| &start.y * *p).collect();
    let mut z: Vec<Option<Mat>> = probs[0].iter().map(|p| start.z.as_ref().map(|z| z * *p)).collect();
    let mut per_step = Vec::with_capacity(plant.steps());
    let mut per_mode = vec![0.0; q];
    let mut magnitudes = Vec::with_capacity(plant.steps());
    for k in 0..plant.steps() {
        let augs = system(k);
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
        let mut magnitude = 0.0;
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
            let (habs, gabs) = (a.h.abs(), a.g.abs());
            magnitude += abs_dot(&(habs.transpose() * &habs), &y[j])
                + 2.0 * abs_dot(&(habs.transpose() * &gabs), &zk)
                + pj * abs_dot(&(gabs.transpose() * &gabs), &rkk);
            mse += ej;
            if counted {
                per_mode[j] += ej;
            }
            if k == plant.horizon {
                continue;
            }
            let c = r.map_or_else(|| Vector::zeros(nxi), |r| &a.r_map * r);
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
        magnitudes.push(magnitude);
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
    let resolution = resolution(&per_step, &magnitudes);
    ExactError { per_step, total, per_mode, resolution, coordinates: Coordinates::Plant, untracked: None }
}

/// The worst step's digits lost. Each step is measured against its own value or a millionth of
/// the largest step's, whichever is larger: a step whose error is zero up to rounding (a
/// deterministic input the filter matches exactly) need not be resolved beyond the run's scale.
fn resolution(per_step: &[f64], magnitudes: &[f64]) -> Resolution {
    let scale = per_step.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
    let mut worst = Resolution { step: 0, digits_lost: 0.0 };
    for (k, (v, mag)) in per_step.iter().zip(magnitudes).enumerate() {
        // A value that is not finite stays so (f64::max would drop a NaN).
        let against = if v.is_finite() { v.abs().max(RESOLVE_FRACTION * scale) } else { *v };
        let lost = digits_lost(against, *mag);
        if lost > worst.digits_lost {
            worst = Resolution { step: k, digits_lost: lost };
        }
    }
    worst
}

/// See [`resolution`].
const RESOLVE_FRACTION: f64 = 1e-6;

/// log10(magnitude of the terms / |result|), 0 when there is nothing to lose, capped at 17 (all
/// digits) when the result is zero but its terms are not; infinite when anything is not finite.
fn digits_lost(result: f64, magnitude: f64) -> f64 {
    if !(result.is_finite() && magnitude.is_finite()) {
        return f64::INFINITY;
    }
    if magnitude <= 0.0 {
        return 0.0;
    }
    (magnitude / result.abs().max(magnitude * 1e-17)).log10().max(0.0)
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
    // A stable modal truth (the string) is the only use: only overflow is looked for.
    let resolution = match per_step.iter().position(|v| !v.is_finite()) {
        Some(step) => Resolution { step, digits_lost: f64::INFINITY },
        None => Resolution { step: 0, digits_lost: 0.0 },
    };
    ExactError { per_step, total, per_mode: vec![total], resolution, coordinates: Coordinates::Plant, untracked: None }
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

/// ∂J/∂K for every covariance block (J = summed exact error): J(K) = J(center) + Σ_i ⟨grad_i, K_i⟩.
/// It does not depend on K, since J is affine in K.
///
/// The adjoint cancels like the forward moments on an unstable plant (F_jᵀ Λ F_j multiplies Λ's
/// rounding by |A|² per step while the response of the error stays bounded), so when some A_θ has
/// spectral radius above 1 and the realization passes [`error_form`]'s check, the pass runs in error
/// coordinates: Λ^ε[k] = HᵀH + Afᵀ Λ^ε[k+1] Af on ε alone, x0 entering as ε[0] = s0 − M x0 (x0's
/// gradient Mᵀ Λ^ε[0] M). Elsewhere the plant coordinates, as before.
pub fn gradient(plant: &Plant, real: &Realization) -> Vec<Mat> {
    let n = plant.nx();
    let unstable = || (0..plant.n_modes()).any(|j| spectral_radius(plant.a_of(j)) > 1.0 + 1e-12);
    if let Some(form) = real.tracks.as_ref().and_then(|_| unstable().then(|| error_form(plant, real).ok())?) {
        return adjoint_gradient(plant, &|k| form.steps[k].clone(), &(-&form.m));
    }
    let mut x0_map = Mat::zeros(n + real.ns(), n);
    x0_map.view_mut((0, 0), (n, n)).fill_with_identity();
    adjoint_gradient(plant, &|k| modal(plant, real, k), &x0_map)
}

/// The largest |eigenvalue| of a square matrix.
fn spectral_radius(a: &Mat) -> f64 {
    a.complex_eigenvalues().iter().map(|z| z.norm()).fold(0.0, f64::max)
}

/// The backward adjoint pass of [`gradient`] on the matrices `system` gives, x0 entering the state
/// as `x0_map` · x0.
fn adjoint_gradient(plant: &Plant, system: &dyn Fn(usize) -> Vec<Augmented>, x0_map: &Mat) -> Vec<Mat> {
    let nw = plant.nw();
    let probs = plant.mode_probabilities();
    let q = plant.n_modes();
    let transition = plant.modes.as_ref().map(|m| m.transition.clone()).unwrap_or_else(|| Mat::identity(1, 1));
    let mut lambda: Option<Vec<Mat>> = None;
    let mut gw = Mat::zeros(nw, nw);
    for k in (0..plant.steps()).rev() {
        let augs = system(k);
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
    let psd = argmax.blocks.iter().all(crate::numerics::linalg::is_psd);
    Ok(Some(WorstCase { total, argmax, psd, disturbance: None }))
}
