//! The generalized H∞ norm of a realization's error system (seed 002 §§2–4; formulas and misprints
//! in docs/seed002_notes.md). The error system maps ξ = col(x0 − E x0, w\[0..N−1]) to
//! η = col(e_z\[0..N−1], S^½ e\[N]), with e = x − s the state error of a state-estimate realization
//! (ns = n) and e_z = z − ẑ; the input is weighted by K = blockdiag(R, G, …, G), R the covariance of
//! x0 and G that of w. Theorem 2.1: the worst deterministic gain over the ellipsoid ξᵀK⁻¹ξ ≤ 1 and
//! the worst mean-square gain over unknown input covariances are both λmax(Ψ K Ψᵀ).

use crate::analysis::exact::{Augmented, augmented};
use crate::error::{Error, Result};
use crate::filter::realization::Realization;
use crate::model::plant::{Covariances, Plant};
use crate::numerics::linalg::{Mat, Vector, block_diag, psd_factor, sym_unit, top_eigen};
use crate::numerics::solve::conic::Conic;

/// What the last block of rows of Ψ holds.
pub enum Terminal<'a> {
    /// S^½ e\[N], the weighted terminal state error (seed 002; needs ns = n).
    State(&'a Mat),
    /// e_z\[N], so that Ψ gives the error at every step k = 0..N (with w\[N] = 0).
    Output,
}

/// Adds to column `col` of Ψ the response to the augmented state `xi` at step `k`.
fn respond(
    aug: &[Augmented],
    psi: &mut Mat,
    col: usize,
    mut k: usize,
    mut xi: Vector,
    s_half: Option<&Mat>,
    nz: usize,
) {
    let nn = aug.len() - 1;
    while k < nn {
        let e = &aug[k].h * &xi;
        let mut v = psi.view_mut((k * nz, col), (nz, 1));
        v += &e;
        xi = &aug[k].f * &xi;
        k += 1;
    }
    match s_half {
        Some(sh) => {
            let n = sh.nrows();
            let e = xi.rows(0, n) - xi.rows(n, n);
            let mut v = psi.view_mut((nn * nz, col), (n, 1));
            v += sh * e;
        }
        None => {
            let e = &aug[nn].h * &xi;
            let mut v = psi.view_mut((nn * nz, col), (nz, 1));
            v += &e;
        }
    }
}

/// The stacked operator Ψ of seed 002 (rows: e_z\[0..N−1], then S^½ e\[N]; columns: x0, then
/// w\[0..N−1]).
pub fn operator(plant: &Plant, real: &Realization, s: &Mat) -> Result<Mat> {
    operator_with(plant, real, Terminal::State(s))
}

/// Ψ with the chosen last block of rows (see [`Terminal`]).
pub fn operator_with(plant: &Plant, real: &Realization, terminal: Terminal) -> Result<Mat> {
    let (n, nz, nw, nn) = (plant.nx(), plant.nz(), plant.nw(), plant.horizon);
    if plant.random_matrices() {
        return Err(Error::invalid(
            "plant",
            "the generalized H∞ operator Ψ is deterministic only for a plant with deterministic matrices (no dropouts, modes or multiplicative noise); with those use the anisotropic analysis (Λ = E[𝓕ᵀ𝓕])",
        ));
    }
    let s_half = match terminal {
        Terminal::State(s) => {
            if real.ns() != n {
                return Err(Error::invalid("hinf", "the H∞ analysis needs a state-estimate realization (ns = n)"));
            }
            Some(psd_factor(s).transpose())
        }
        Terminal::Output => None,
    };
    let last_rows = if s_half.is_some() { n } else { nz };
    let ns = real.ns();
    let aug: Vec<Augmented> = (0..plant.steps()).map(|k| augmented(plant, real, k, 0)).collect();
    let mut psi = Mat::zeros(nn * nz + last_rows, n + nn * nw);
    for j in 0..n {
        let mut xi = Vector::zeros(n + ns);
        xi[j] = 1.0;
        respond(&aug, &mut psi, j, 0, xi, s_half.as_ref(), nz);
    }
    for k0 in 0..nn {
        for j in 0..nw {
            let col = n + k0 * nw + j;
            let mut v = psi.view_mut((k0 * nz, col), (nz, 1));
            v += aug[k0].g.column(j);
            respond(&aug, &mut psi, col, k0 + 1, aug[k0].e.column(j).into_owned(), s_half.as_ref(), nz);
        }
    }
    Ok(psi)
}

/// The generalized H2 norm² of a realization's error system (seed 002 Theorem 3.1, Corollary 3.1):
/// the largest gain from input energy ξᵀK⁻¹ξ ≤ 1 to the error at a single step,
/// max_t λmax(Ψ_t K Ψ_tᵀ), with Ψ_t the rows of e_z\[t] in Ψ (the SDP (3.8) has this value).
pub fn generalized_h2_norm_sq(plant: &Plant, real: &Realization, weights: &Covariances) -> Result<f64> {
    let psi = operator_with(plant, real, Terminal::Output)?;
    let a = &psi * psd_factor(&input_weight(plant, weights));
    let nz = plant.nz();
    let mut top: f64 = 0.0;
    for t in 0..plant.steps() {
        let at = a.rows(t * nz, nz);
        let g = crate::numerics::linalg::symmetrize(&(at * at.transpose()));
        top = top.max(g.symmetric_eigenvalues().max());
    }
    Ok(top)
}

/// The input weight K = blockdiag(R, G, …, G) of the ellipsoid.
pub fn input_weight(plant: &Plant, weights: &Covariances) -> Mat {
    let w = weights.w();
    let mut blocks = vec![weights.x0()];
    blocks.extend(std::iter::repeat_n(&w, plant.horizon));
    block_diag(&blocks)
}

/// The generalized H∞ norm² λmax(Ψ K Ψᵀ) and the worst input on the ellipsoid boundary,
/// ξ* = K^½ v with v the top eigenvector of K^½ᵀ Ψᵀ Ψ K^½ (faer), so ξ*ᵀ K⁻¹ ξ* = 1 when K ≻ 0.
pub fn norm(plant: &Plant, real: &Realization, weights: &Covariances, s: &Mat) -> Result<(f64, Vector)> {
    norm_with_error(plant, real, weights, s).map(|(top, _, xi)| (top, xi))
}

/// [`norm`] with the rounding bound of the computed λmax ([`crate::numerics::accuracy::eigenvalue_error`]),
/// so that a per-trial bound λ is promised only when λmax + error < λ.
pub fn norm_with_error(
    plant: &Plant,
    real: &Realization,
    weights: &Covariances,
    s: &Mat,
) -> Result<(f64, f64, Vector)> {
    let psi = operator(plant, real, s)?;
    let k_half = psd_factor(&input_weight(plant, weights));
    let a = &psi * &k_half;
    let gram = a.transpose() * &a;
    let (top, v) = top_eigen(&gram)?;
    Ok((top, crate::numerics::accuracy::eigenvalue_error(&gram), k_half * v))
}

/// The generalized H∞ norm² of a predictor realization (s\[t+1] = (A − ΘC) s + Θ y + r, ẑ = Cz s)
/// by the SDP (4.7) of seed 002, solved with clarabel: minimize λ over symmetric X\[1..N] with
/// X\[0] = R⁻¹ and, for t = 0..N−1 (Ac = A − ΘC, Bc = B − ΘD, X⁺ = X\[t+1]),
///
/// ```text
/// [[AcᵀX⁺Ac − X, AcᵀX⁺Bc, Czᵀ], [BcᵀX⁺Ac, BcᵀX⁺Bc − G⁻¹, 0], [Cz, 0, −λI]] ⪯ 0,
/// [[X[N], S^½], [S^½, λI]] ⪰ 0.
/// ```
///
/// Independent of [`norm`]: no operator is formed. Returns (λ*, clarabel's objective_error, its iterations, seconds).
pub fn norm_sdp(plant: &Plant, real: &Realization, weights: &Covariances, s: &Mat) -> Result<(f64, f64, u32, f64)> {
    let (n, nw, nz, nn) = (plant.nx(), plant.nw(), plant.nz(), plant.horizon);
    for (t, g) in real.gains.iter().map(|g| &g[0]).enumerate() {
        let predictor = (&g.af - (plant.a_at(t) - &g.bf * &*plant.c_at(t))).amax() < 1e-12
            && g.df.amax() == 0.0
            && (&g.cf - plant.cz_at(t)).amax() == 0.0
            && real.ns() == n;
        if !predictor {
            return Err(Error::invalid(
                "hinf",
                format!("the SDP (4.7) needs a predictor realization; step {t} is not one"),
            ));
        }
    }
    let r_inv = weights.x0().clone().try_inverse().ok_or_else(|| Error::invalid("hinf", "R must be invertible"))?;
    let g_inv = crate::numerics::linalg::psd_pinv(&weights.w());
    let s_half = psd_factor(s).transpose();
    let tri = n * (n + 1) / 2;
    let lam = nn * tri;
    // Variable (t, i, j), t = 1..N: X[t]_{ij} = X[t]_{ji}.
    let var = |t: usize, i: usize, j: usize| (t - 1) * tri + j * (j + 1) / 2 + i;
    let mut program = Conic::default();
    let d = n + nw + nz;
    for t in 0..nn {
        let th = &real.step(t).bf;
        let ac = plant.a_at(t) - th * &*plant.c_at(t);
        let bc = plant.b_at(t) - th * &*plant.d_at(t);
        // −(LMI) ⪰ 0: its constant part and the coefficient of every variable.
        let mut c = Mat::zeros(d, d);
        c.view_mut((n, n), (nw, nw)).copy_from(&g_inv);
        c.view_mut((0, n + nw), (n, nz)).copy_from(&(-plant.cz_at(t).transpose()));
        c.view_mut((n + nw, 0), (nz, n)).copy_from(&(-plant.cz_at(t)));
        if t == 0 {
            c.view_mut((0, 0), (n, n)).copy_from(&r_inv);
        }
        let mut terms = Vec::new();
        for j in 0..n {
            for i in 0..=j {
                let e = sym_unit(n, i, j);
                let mut m = Mat::zeros(d, d);
                m.view_mut((0, 0), (n, n)).copy_from(&(-(ac.transpose() * &e * &ac)));
                m.view_mut((0, n), (n, nw)).copy_from(&(-(ac.transpose() * &e * &bc)));
                m.view_mut((n, 0), (nw, n)).copy_from(&(-(bc.transpose() * &e * &ac)));
                m.view_mut((n, n), (nw, nw)).copy_from(&(-(bc.transpose() * &e * &bc)));
                terms.push((var(t + 1, i, j), m));
                if t > 0 {
                    let mut m = Mat::zeros(d, d);
                    m.view_mut((0, 0), (n, n)).copy_from(&e);
                    terms.push((var(t, i, j), m));
                }
            }
        }
        let mut m = Mat::zeros(d, d);
        m.view_mut((n + nw, n + nw), (nz, nz)).fill_with_identity();
        terms.push((lam, m));
        program.psd(&c, &terms);
    }
    // Terminal: [[X[N], S^½], [S^½ᵀ, λI]] ⪰ 0.
    let mut c = Mat::zeros(2 * n, 2 * n);
    c.view_mut((0, n), (n, n)).copy_from(&s_half.transpose());
    c.view_mut((n, 0), (n, n)).copy_from(&s_half);
    let mut terms = Vec::new();
    for j in 0..n {
        for i in 0..=j {
            let mut m = Mat::zeros(2 * n, 2 * n);
            m.view_mut((0, 0), (n, n)).copy_from(&sym_unit(n, i, j));
            terms.push((var(nn, i, j), m));
        }
    }
    let mut m = Mat::zeros(2 * n, 2 * n);
    m.view_mut((n, n), (n, n)).fill_with_identity();
    terms.push((lam, m));
    program.psd(&c, &terms);

    let mut cost = vec![0.0; lam + 1];
    cost[lam] = 1.0;
    let sol =
        program.minimize(&cost).map_err(|e| Error::invalid("hinf", format!("the SDP (4.7) was not solved: {e}")))?;
    Ok((sol.x[lam], sol.objective_error, sol.iterations, sol.seconds))
}
