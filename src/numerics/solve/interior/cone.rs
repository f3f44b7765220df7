//! The cones of [`super`]: their Nesterov–Todd scalings, Jordan products and step lengths, and the
//! svec conventions of clarabel's PSD triangle (upper triangle, column-major, off-diagonals × √2).

use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, DimDiff, DimSub, Dyn, OMatrix, U1};

use super::sandwich::sandwich;
pub(super) use super::sandwich::{SQ2, Scratch};
use crate::numerics::linalg::Mat;
pub(super) use crate::numerics::linalg::unpack_triangle as smat;

/// A second-order cone up to this size forms λ = W z on the stack (seed 003's tree is SOC(3)).
const SOC_ON_STACK: usize = 16;

#[derive(Clone, Copy, Debug)]
pub(super) enum Kind {
    Nonnegative,
    SecondOrder,
    Psd(usize),
}

/// One cone's rows, and for a PSD cone each variable's coefficient matrix as its upper-triangle
/// entries (p ≤ q, value of the unscaled matrix).
pub(super) struct Cone {
    pub(super) kind: Kind,
    pub(super) rows: std::ops::Range<usize>,
    pub(super) coefs: Vec<(usize, Vec<(usize, usize, f64)>)>,
}

/// A cone's Nesterov–Todd scaling.
pub(super) enum Scaling {
    /// W = diag(d).
    Nonnegative(Vec<f64>),
    /// W⁻¹ (W is symmetric, so W⁻ᵀ = W⁻¹).
    SecondOrder(Mat),
    /// W: Z ↦ RᵀZR, kept as the three matrices B of the sandwiches V ↦ B V Bᵀ it needs: R⁻¹ (W⁻ᵀ),
    /// R⁻ᵀ (W⁻¹) and M = R⁻ᵀR⁻¹ (W⁻¹W⁻ᵀ).
    Psd { rinv: Mat, rinv_t: Mat, m: Mat },
}

/// What the scaling does to a vector: W⁻ᵀ, W⁻¹ and W⁻¹W⁻ᵀ (W itself is not needed: the primal
/// step is formed in the original coordinates).
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Op {
    InvTranspose,
    Inverse,
    Normal,
}

pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

pub(super) fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// The identity e of the cone's Jordan algebra.
pub(super) fn identity(kind: Kind, out: &mut [f64]) {
    out.iter_mut().for_each(|v| *v = 0.0);
    match kind {
        Kind::Nonnegative => out.iter_mut().for_each(|v| *v = 1.0),
        Kind::SecondOrder => out[0] = 1.0,
        Kind::Psd(n) => {
            let mut k = 0;
            for j in 0..n {
                out[k + j] = 1.0;
                k += j + 1;
            }
        }
    }
}

/// The largest α ≤ cap with x + α d in the cone, x in its interior. In scaled coordinates x = λ,
/// diagonal for a PSD cone.
pub(super) fn max_step(kind: Kind, x: &[f64], d: &[f64], cap: f64, w: &mut Scratch) -> f64 {
    match kind {
        Kind::Nonnegative => x.iter().zip(d).filter(|(_, d)| **d < 0.0).fold(cap, |a, (x, d)| a.min(-x / d)),
        Kind::SecondOrder => {
            let qa = d[0] * d[0] - dot(&d[1..], &d[1..]);
            let qb = 2.0 * (x[0] * d[0] - dot(&x[1..], &d[1..]));
            let qc = x[0] * x[0] - dot(&x[1..], &x[1..]);
            let mut a = cap;
            if d[0] < 0.0 {
                a = a.min(-x[0] / d[0]);
            }
            let disc = qb * qb - 4.0 * qa * qc;
            if qa < 0.0 || (disc >= 0.0 && qb < 0.0) {
                let t = (-qb - disc.max(0.0).sqrt()) / (2.0 * qa);
                if t > 0.0 {
                    a = a.min(t);
                }
            } else if qa == 0.0 && qb < 0.0 {
                a = a.min(-qc / qb);
            }
            a
        }
        Kind::Psd(n) => {
            // Λ + αD ⪰ 0 ⇔ I + α Λ^{-1/2} D Λ^{-1/2} ⪰ 0.
            let (isq, a) = (&mut w.o[..n], &mut w.v[..n * n]);
            let mut k = 0;
            for (j, v) in isq.iter_mut().enumerate() {
                *v = 1.0 / x[k + j].sqrt();
                k += j + 1;
            }
            // Cheap first: if I + cap·T factors with a margin the cone does not limit the step.
            let isq = &*isq;
            if factors(n, |i, j, v| f64::from(u8::from(i == j)) * (1.0 - 1e-12) + cap * v * isq[i] * isq[j], d, a) {
                return cap;
            }
            let mut t = Mat::zeros(n, n);
            smat(d, n, &mut t);
            let mut k = 0;
            let isq: Vec<f64> = (0..n)
                .map(|j| {
                    let v = 1.0 / x[k + j].sqrt();
                    k += j + 1;
                    v
                })
                .collect();
            for j in 0..n {
                for i in 0..n {
                    t[(i, j)] *= isq[i] * isq[j];
                }
            }
            let lmin = t.symmetric_eigenvalues().min();
            if lmin < 0.0 { cap.min(-1.0 / lmin) } else { cap }
        }
    }
}

/// An upper bound on [`max_step`] without a factorization: the same for the nonnegative and
/// second-order cones; for a PSD cone the diagonal's (λ_i + α d_ii ≥ 0 is necessary for
/// Λ + αD ⪰ 0).
pub(super) fn step_bound(kind: Kind, x: &[f64], d: &[f64], cap: f64, w: &mut Scratch) -> f64 {
    match kind {
        Kind::Psd(n) => {
            let mut k = 0;
            (0..n).fold(cap, |a, j| {
                let i = k + j;
                k += j + 1;
                if d[i] < 0.0 { a.min(-x[i] / d[i]) } else { a }
            })
        }
        _ => max_step(kind, x, d, cap, w),
    }
}

/// Whether the symmetric matrix with upper-triangle entries entry(i, j, v), v the triangle's
/// unscaled value of d, has a Cholesky factor (is positive definite), in the scratch a.
fn factors(n: usize, entry: impl Fn(usize, usize, f64) -> f64, d: &[f64], a: &mut [f64]) -> bool {
    let mut k = 0;
    for j in 0..n {
        for i in 0..=j {
            let v = if i == j { d[k] } else { d[k] / SQ2 };
            a[i + j * n] = entry(i, j, v);
            k += 1;
        }
    }
    // Upper Cholesky A = RᵀR by columns: R_ij = (A_ij − Σ_{k<i} R_ki R_kj)/R_ii.
    for j in 0..n {
        for i in 0..=j {
            let mut v = a[i + j * n];
            for k in 0..i {
                v -= a[k + i * n] * a[k + j * n];
            }
            if i == j {
                if v <= 0.0 || !v.is_finite() {
                    return false;
                }
                a[j + j * n] = v.sqrt();
            } else {
                a[i + j * n] = v / a[i + i * n];
            }
        }
    }
    true
}

/// The Jordan product u∘v.
pub(super) fn jprod(kind: Kind, u: &[f64], v: &[f64], out: &mut [f64], w: &mut Scratch) {
    match kind {
        Kind::Nonnegative => out.iter_mut().zip(u.iter().zip(v)).for_each(|(o, (a, b))| *o = a * b),
        Kind::SecondOrder => {
            out[0] = dot(u, v);
            for i in 1..u.len() {
                out[i] = u[0] * v[i] + v[0] * u[i];
            }
        }
        Kind::Psd(n) => {
            // (UV + VU)/2 on the upper triangle, U and V unpacked into the scratch.
            let (um, vm) = (&mut w.v[..n * n], &mut w.t[..n * n]);
            let mut k = 0;
            for j in 0..n {
                for i in 0..=j {
                    let s = if i == j { 1.0 } else { 1.0 / SQ2 };
                    (um[i + j * n], vm[i + j * n]) = (u[k] * s, v[k] * s);
                    (um[j + i * n], vm[j + i * n]) = (u[k] * s, v[k] * s);
                    k += 1;
                }
            }
            let mut k = 0;
            for j in 0..n {
                for i in 0..=j {
                    let (ui, uj) = (&um[i * n..(i + 1) * n], &um[j * n..(j + 1) * n]);
                    let (vi, vj) = (&vm[i * n..(i + 1) * n], &vm[j * n..(j + 1) * n]);
                    let x = 0.5 * (dot(ui, vj) + dot(vi, uj));
                    out[k] = if i == j { x } else { x * SQ2 };
                    k += 1;
                }
            }
        }
    }
}

/// λ∘λ, for λ = W z as [`scaling`] leaves it: diagonal for a PSD cone, so the product is the
/// squares of the diagonal (the same bits as [`jprod`], without its n³ work).
pub(super) fn jsquare(kind: Kind, lam: &[f64], out: &mut [f64], w: &mut Scratch) {
    match kind {
        Kind::Psd(n) => {
            out.iter_mut().for_each(|v| *v = 0.0);
            let mut k = 0;
            for j in 0..n {
                out[k + j] = lam[k + j] * lam[k + j];
                k += j + 1;
            }
        }
        _ => jprod(kind, lam, lam, out, w),
    }
}

/// The u with λ∘u = r (λ diagonal for a PSD cone, so u_ij = 2 r_ij/(λ_i + λ_j)).
pub(super) fn jdiv(kind: Kind, lam: &[f64], r: &[f64], out: &mut [f64]) {
    match kind {
        Kind::Nonnegative => out.iter_mut().zip(r.iter().zip(lam)).for_each(|(o, (r, l))| *o = r / l),
        Kind::SecondOrder => {
            let l0 = lam[0];
            let det = l0 * l0 - dot(&lam[1..], &lam[1..]);
            let u0 = (l0 * r[0] - dot(&lam[1..], &r[1..])) / det;
            out[0] = u0;
            for i in 1..r.len() {
                out[i] = (r[i] - u0 * lam[i]) / l0;
            }
        }
        Kind::Psd(n) => {
            let mut diag = vec![0.0; n];
            let mut k = 0;
            for (j, d) in diag.iter_mut().enumerate() {
                *d = lam[k + j];
                k += j + 1;
            }
            let mut k = 0;
            for j in 0..n {
                for i in 0..=j {
                    out[k] = 2.0 * r[k] / (diag[i] + diag[j]);
                    k += 1;
                }
            }
        }
    }
}

pub(super) fn apply(sc: &Scaling, op: Op, v: &[f64], out: &mut [f64], w: &mut Scratch) {
    match sc {
        Scaling::Nonnegative(d) => {
            for i in 0..v.len() {
                out[i] = if op == Op::Normal { v[i] / (d[i] * d[i]) } else { v[i] / d[i] };
            }
        }
        Scaling::SecondOrder(m) => {
            for (i, o) in out.iter_mut().enumerate() {
                *o = (0..v.len()).map(|j| m[(i, j)] * v[j]).sum();
            }
            if op == Op::Normal {
                let first = &mut w.v[..v.len()];
                first.copy_from_slice(out);
                for (i, o) in out.iter_mut().enumerate() {
                    *o = (0..v.len()).map(|j| m[(i, j)] * first[j]).sum();
                }
            }
        }
        Scaling::Psd { rinv, rinv_t, m } => {
            let b = match op {
                Op::InvTranspose => rinv,
                Op::Inverse => rinv_t,
                Op::Normal => m,
            };
            sandwich(b.as_slice(), b.nrows(), v, out, w);
        }
    }
}

/// The Nesterov–Todd scaling of one cone at (s, z) into `out` (the cone's previous scaling, whose
/// storage is reused: the iterations allocate nothing per cone), and λ = W z; false if s or z has
/// left the cone's interior numerically.
pub(super) fn scaling(s: &[f64], z: &[f64], lam: &mut [f64], out: &mut Scaling) -> bool {
    match out {
        Scaling::Nonnegative(d) => {
            if s.iter().chain(z).any(|v| *v <= 0.0) {
                return false;
            }
            for i in 0..s.len() {
                lam[i] = (s[i] * z[i]).sqrt();
                d[i] = (s[i] / z[i]).sqrt();
            }
            true
        }
        Scaling::SecondOrder(winv) => {
            let n = s.len();
            let jn = |x: &[f64]| x[0] * x[0] - dot(&x[1..], &x[1..]);
            let (sn, zn) = (jn(s), jn(z));
            if sn <= 0.0 || zn <= 0.0 || s[0] <= 0.0 || z[0] <= 0.0 {
                return false;
            }
            let (sn, zn) = (sn.sqrt(), zn.sqrt());
            let g = ((1.0 + dot(s, z) / (sn * zn)) / 2.0).sqrt();
            // w̄ = (s̄ + J z̄)/(2γ); W = β [w̄0, w̄1ᵀ; w̄1, I + w̄1 w̄1ᵀ/(1 + w̄0)], W⁻¹ = J W J / β².
            // w̄ goes into λ's rows until λ = W z is formed; W's entries are formed where read.
            let wb = &mut *lam;
            for i in 0..n {
                wb[i] = if i == 0 { s[0] / sn + z[0] / zn } else { s[i] / sn - z[i] / zn } / (2.0 * g);
            }
            let beta = (sn / zn).sqrt();
            let v = |wb: &[f64], i: usize, j: usize| {
                if i == 0 || j == 0 {
                    wb[i.max(j)]
                } else {
                    f64::from(u8::from(i == j)) + wb[i] * wb[j] / (1.0 + wb[0])
                }
            };
            for i in 0..n {
                for j in 0..n {
                    let sign = if (i == 0) != (j == 0) { -1.0 } else { 1.0 };
                    winv[(i, j)] = sign * v(wb, i, j) / beta;
                }
            }
            // λ = W z with W = β v: z's weights are formed from w̄ before λ overwrites it.
            let mut wz = [0.0; SOC_ON_STACK];
            let mut heap = Vec::new();
            let wz: &mut [f64] = if n <= SOC_ON_STACK {
                &mut wz[..n]
            } else {
                heap.resize(n, 0.0);
                &mut heap
            };
            for (i, o) in wz.iter_mut().enumerate() {
                *o = (0..n).map(|j| beta * v(wb, i, j) * z[j]).sum();
            }
            lam.copy_from_slice(wz);
            true
        }
        Scaling::Psd { rinv, rinv_t, m } => {
            let n = rinv.nrows();
            // The block sizes of seed 003's programs after the chordal decomposition (2 to 10; 16
            // undecomposed): at a size known to the compiler nalgebra keeps the matrices on the
            // stack and multiplies them in plain loops.
            let inside = match n {
                2 => psd_scaling(Const::<2>, s, z, rinv, m, lam),
                3 => psd_scaling(Const::<3>, s, z, rinv, m, lam),
                4 => psd_scaling(Const::<4>, s, z, rinv, m, lam),
                5 => psd_scaling(Const::<5>, s, z, rinv, m, lam),
                6 => psd_scaling(Const::<6>, s, z, rinv, m, lam),
                7 => psd_scaling(Const::<7>, s, z, rinv, m, lam),
                8 => psd_scaling(Const::<8>, s, z, rinv, m, lam),
                9 => psd_scaling(Const::<9>, s, z, rinv, m, lam),
                10 => psd_scaling(Const::<10>, s, z, rinv, m, lam),
                12 => psd_scaling(Const::<12>, s, z, rinv, m, lam),
                16 => psd_scaling(Const::<16>, s, z, rinv, m, lam),
                _ => psd_scaling(Dyn(n), s, z, rinv, m, lam),
            };
            if !inside {
                return false;
            }
            for j in 0..n {
                for i in 0..n {
                    rinv_t[(i, j)] = rinv[(j, i)];
                }
            }
            true
        }
    }
}

/// A PSD cone's Nesterov–Todd scaling (Vandenberghe's CVXOPT paper §4.4): with Cholesky factors
/// S = L_s L_sᵀ, Z = L_z L_zᵀ and L_zᵀ L_s = U Σ Vᵀ, R = L_s V Σ^{-1/2}; returns R⁻¹ = Σ^{-1/2} Uᵀ L_zᵀ,
/// into `rinv_out`, M = R⁻ᵀR⁻¹ into `m_out` and λ = Σ (diagonal, in svec form) into `lam`; false if
/// s or z has left the cone's interior numerically.
fn psd_scaling<D>(dim: D, s: &[f64], z: &[f64], rinv_out: &mut Mat, m_out: &mut Mat, lam: &mut [f64]) -> bool
where
    D: DimSub<U1>,
    DefaultAllocator: Allocator<D, D> + Allocator<D> + Allocator<DimDiff<D, U1>>,
{
    let n = dim.value();
    let unpack = |v: &[f64]| {
        OMatrix::<f64, D, D>::from_fn_generic(dim, dim, |i, j| {
            let (i, j) = (i.min(j), i.max(j));
            let x = v[j * (j + 1) / 2 + i];
            if i == j { x } else { x / SQ2 }
        })
    };
    let (Some(ls), Some(lz)) = (unpack(s).cholesky(), unpack(z).cholesky()) else {
        return false;
    };
    let (ls, lz) = (ls.l(), lz.l());
    // G = L_zᵀ L_s = U Σ Vᵀ. Its singular vectors from the symmetric eigenproblem GᵀG = V Σ² Vᵀ
    // (about half an SVD's work), U = G V Σ⁻¹; that squares G's condition number, so where
    // σ_max/σ_min > 10⁴ (a relative error above 10⁻⁸ in σ_min²) the SVD itself is taken.
    let g = lz.tr_mul(&ls);
    let eig = g.tr_mul(&g).symmetric_eigen();
    let mut sig = eig.eigenvalues.map(|e| e.max(0.0).sqrt());
    let (smin, smax) = sig.iter().fold((f64::INFINITY, 0.0_f64), |(a, b), v| (a.min(*v), b.max(*v)));
    let rinv = if smin > 0.0 && smax < 1e4 * smin {
        // R⁻¹ = Σ^{-3/2} Vᵀ Gᵀ L_zᵀ, with P = Vᵀ Gᵀ.
        let p = eig.eigenvectors.tr_mul(&g.transpose());
        let h = p.transpose().tr_mul(&lz.transpose());
        OMatrix::<f64, D, D>::from_fn_generic(dim, dim, |i, j| h[(i, j)] / (sig[i] * sig[i].sqrt()))
    } else {
        let svd = Mat::from_iterator(n, n, g.iter().copied()).svd(true, true);
        let Some(u) = svd.u else {
            return false;
        };
        if svd.singular_values.iter().any(|v| *v <= 0.0 || !v.is_finite()) {
            return false;
        }
        sig.iter_mut().zip(svd.singular_values.iter()).for_each(|(a, b)| *a = *b);
        OMatrix::<f64, D, D>::from_fn_generic(dim, dim, |i, j| {
            (0..n).map(|k| u[(k, i)] * lz[(j, k)]).sum::<f64>() / sig[i].sqrt()
        })
    };
    // Every product is nalgebra's dot-based Aᵀ B: a general product of a dynamic size would go
    // through matrixmultiply, whose kernel (and rounding) depends on the processor.
    let m = rinv.tr_mul(&rinv);
    rinv_out.as_mut_slice().copy_from_slice(rinv.as_slice());
    m_out.as_mut_slice().copy_from_slice(m.as_slice());
    lam.iter_mut().for_each(|v| *v = 0.0);
    let mut k = 0;
    for (j, v) in sig.iter().enumerate() {
        lam[k + j] = *v;
        k += j + 1;
    }
    true
}
