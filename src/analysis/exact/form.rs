//! The error coordinates ε = s − M x of a realization that tracks M x (docs/math.md §0): where they keep
//! ε independent of x, the exact analysis and the Monte Carlo carry ε instead of s.

use super::augmented::Augmented;
use super::exact_error::{Coordinates, ExactError};
use super::propagate::{Input, propagate, start, white};
use crate::filter::realization::Realization;
use crate::model::plant::{Covariances, Plant};
use crate::numerics::linalg::{Mat, Vector};

/// [`error`](super::error) computed in error coordinates whatever the plant-coordinate recursion would give, or
/// why they do not apply (for comparing the two where both are accurate).
pub fn error_in_error_coordinates(
    plant: &Plant,
    real: &Realization,
    cov: &Covariances,
) -> std::result::Result<ExactError, String> {
    let form = error_form(plant, real)?;
    let w = white(plant, cov);
    let input = Input::White { w: &w, mean: None };
    let start = start(plant, real, &Vector::zeros(plant.nx()), cov.x0(), &input).transformed(&form.to_error);
    let mut out = propagate(plant, &start, &input, &|k| form.steps[k].clone());
    out.coordinates = Coordinates::Error;
    Ok(out)
}

/// A realization in error coordinates ε = s − M x: with T_j = Af M + Bf C_j − M A_j = 0 and
/// Cz − Df C_j − Cf M = 0 at every step and mode (checked, not assumed),
///
/// ```text
/// ε[k+1] = Af ε + (Bf D_j − M B_j) w + (Gf − M) r,   e[k] = −Cf ε + (Dz − Df D_j) w,
/// ```
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
pub(super) const IDENTITY_TOLERANCE: f64 = 1e-9;

/// The realization in error coordinates, or why not: no M declared, M of the wrong size, or the
/// step and mode where Af M + Bf C − M A (or Cz − Df C − Cf M) is not zero, with its size. A
/// residual within rounding of its terms is set to exactly zero: these are the coordinates of the
/// filter its family designed, whose gains satisfy the identity by construction.
pub fn error_form(plant: &Plant, real: &Realization) -> std::result::Result<ErrorForm, String> {
    let (n, ns) = (plant.nx(), real.ns());
    if !plant.factors.is_empty() {
        // ζ_i A_i x enters x but not the filter: ε = s − M x would carry x along.
        return Err("the plant has multiplicative noise (ε = s − M x would depend on x)".into());
    }
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
            let (a, b) = (plant.a_of(k, j), plant.b_of(k, j));
            let (c, d) = (&*plant.c_of(k, j), &*plant.d_of(k, j));
            let hx = plant.cz_at(k) - &g.df * c - &g.cf * m;
            let h_scale = fro(plant.cz_at(k)) + fro(&g.df) * fro(c) + fro(&g.cf) * fro(m);
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
                    let mode = plant.modes().map_or(String::new(), |md| format!(", mode {}", md.names[j]));
                    return Err(format!("{what} = {r:.2e} (relative {:.1e}) at step {k}{mode}", r / scale.max(1e-300)));
                }
            }
            let r_map = if plant.known_input.is_empty() { Mat::zeros(ns, 0) } else { &g.gf - m };
            here.push(Augmented {
                f: g.af.clone(),
                e: &g.bf * d - m * b,
                h: -&g.cf,
                g: plant.dz_at(k) - &g.df * d,
                r_map,
                terms: Vec::new(),
            });
        }
        steps.push(here);
    }
    let mut to_error = Mat::zeros(ns, n + ns);
    to_error.view_mut((0, 0), (ns, n)).copy_from(&(-m));
    to_error.view_mut((0, n), (ns, ns)).fill_with_identity();
    let identity = ns == n && *m == Mat::identity(n, n);
    Ok(ErrorForm { m: m.clone(), to_error, identity, steps })
}
