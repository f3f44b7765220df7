//! The augmented error system ξ = (x, s) of the module docs: its matrices F, E, H, G per step and
//! mode, with one term per multiplicative factor.

use crate::filter::realization::{Gains, Realization};
use crate::model::plant::Plant;
use crate::numerics::linalg::Mat;

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
    pub(crate) fn with_terms(&self) -> impl Iterator<Item = &Augmented> {
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
pub(super) fn modal(plant: &Plant, real: &Realization, k: usize) -> Vec<Augmented> {
    (0..plant.n_modes()).map(|j| augmented(plant, real, k, j)).collect()
}
