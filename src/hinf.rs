//! The generalized H∞ norm of a realization's error system (seed 002 §§2–4; formulas and misprints
//! in docs/seed002_notes.md). The error system maps ξ = col(x0 − E x0, w[0..N−1]) to
//! η = col(e_z[0..N−1], S^½ e[N]), with e = x − s the state error of a state-estimate realization
//! (ns = n) and e_z = z − ẑ; the input is weighted by K = blockdiag(R, G, …, G), R the covariance of
//! x0 and G that of w. Theorem 2.1: the worst deterministic gain over the ellipsoid ξᵀK⁻¹ξ ≤ 1 and
//! the worst mean-square gain over unknown input covariances are both λmax(Ψ K Ψᵀ).

use crate::error::{Error, Result};
use crate::exact::{Augmented, augmented};
use crate::linalg::{Mat, Vector, block_diag, psd_factor};
use crate::plant::{Covariances, Plant};
use crate::realization::Realization;

/// What the last block of rows of Ψ holds.
pub enum Terminal<'a> {
    /// S^½ e[N], the weighted terminal state error (seed 002; needs ns = n).
    State(&'a Mat),
    /// e_z[N], so that Ψ gives the error at every step k = 0..N (with w[N] = 0).
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

/// The stacked operator Ψ of seed 002 (rows: e_z[0..N−1], then S^½ e[N]; columns: x0, then
/// w[0..N−1]).
pub fn operator(plant: &Plant, real: &Realization, s: &Mat) -> Result<Mat> {
    operator_with(plant, real, Terminal::State(s))
}

/// Ψ with the chosen last block of rows (see [`Terminal`]).
pub fn operator_with(plant: &Plant, real: &Realization, terminal: Terminal) -> Result<Mat> {
    let (n, nz, nw, nn) = (plant.nx(), plant.nz(), plant.nw(), plant.horizon);
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
    let aug: Vec<Augmented> = (0..plant.steps()).map(|k| augmented(plant, real, k)).collect();
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
    let psi = operator(plant, real, s)?;
    let k_half = psd_factor(&input_weight(plant, weights));
    let a = &psi * &k_half;
    let gram = a.transpose() * &a;
    let m = gram.nrows();
    let fm = faer::Mat::<f64>::from_fn(m, m, |i, j| gram[(i, j)]);
    let evd = fm
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|e| Error::invalid("hinf", format!("eigendecomposition failed: {e:?}")))?;
    let top = evd.S().column_vector()[m - 1];
    let v = Vector::from_fn(m, |i, _| evd.U()[(i, m - 1)]);
    Ok((top, k_half * v))
}
