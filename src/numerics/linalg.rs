//! Small dense linear algebra on nalgebra matrices: the checks and factorizations that every other
//! module needs (symmetry, positive semidefiniteness, a square-root factor, a pseudo-inverse).

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use crate::error::{Error, Result};

pub type Mat = DMatrix<f64>;
pub type Vector = DVector<f64>;

/// Relative tolerance for symmetry and for the smallest admissible eigenvalue of a "PSD" matrix.
pub(crate) const PSD_TOL: f64 = 1e-10;

/// Builds a matrix from rows as written in an experiment file, checking that the rows are equally
/// long and, when given, the expected shape. `key` names the file key in the error.
pub(crate) fn from_rows(key: &str, rows: &[Vec<f64>], shape: Option<(usize, usize)>) -> Result<Mat> {
    let nr = rows.len();
    let nc = rows.first().map_or(0, Vec::len);
    if let Some(r) = rows.iter().position(|r| r.len() != nc) {
        return Err(Error::invalid(key, format!("row {} has {} entries, row 1 has {nc}", r + 1, rows[r].len())));
    }
    if let Some((er, ec)) = shape.filter(|&s| s != (nr, nc)) {
        return Err(Error::invalid(key, format!("expected a {er}×{ec} matrix, found {nr}×{nc}")));
    }
    if let Some(v) = rows.iter().flatten().find(|v| !v.is_finite()) {
        return Err(Error::invalid(key, format!("entry {v} is not finite")));
    }
    Ok(Mat::from_fn(nr, nc, |i, j| rows[i][j]))
}

fn scale(m: &Mat) -> f64 {
    m.amax().max(1e-300)
}

/// Feeds a matrix's shape and the bits of its entries (column by column) into `h`: equal digests
/// mean bit-equal matrices. The one encoding behind every fingerprint of filters and plants.
pub(crate) fn digest_mat(h: &mut impl sha2::Digest, m: &Mat) {
    h.update((m.nrows() as u64).to_le_bytes());
    h.update((m.ncols() as u64).to_le_bytes());
    for v in m.iter() {
        h.update(v.to_bits().to_le_bytes());
    }
}

/// A digest's bytes in lower-case hex, as the manifest and the fingerprints print them.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Checks that `m` is square, symmetric and positive semidefinite (to `PSD_TOL` relative to its
/// largest entry); the error names `key` and the smallest eigenvalue.
pub(crate) fn check_psd(key: &str, m: &Mat) -> Result<()> {
    if !m.is_square() {
        return Err(Error::invalid(key, format!("a covariance must be square, found {}×{}", m.nrows(), m.ncols())));
    }
    let s = scale(m);
    let asym = (m - m.transpose()).amax();
    if asym > PSD_TOL * s {
        return Err(Error::invalid(key, format!("covariance is not symmetric (max |S - Sᵀ| = {asym:.3e})")));
    }
    let min = min_eigenvalue(m);
    if min < -PSD_TOL * s * m.nrows() as f64 {
        return Err(Error::invalid(
            key,
            format!("covariance is not positive semidefinite (smallest eigenvalue {min:.6e})"),
        ));
    }
    Ok(())
}

/// ½(M + Mᵀ): the symmetric part of a square matrix.
pub fn symmetrize(m: &Mat) -> Mat {
    let mut s = m.clone();
    symmetrize_mut(&mut s);
    s
}

/// [`symmetrize`] in place, ½(M + Mᵀ) entry by entry (the same bits: halving is exact), for a
/// recursion that reuses its matrices.
pub fn symmetrize_mut(m: &mut Mat) {
    for j in 0..m.ncols() {
        for i in j + 1..m.nrows() {
            let v = 0.5 * (m[(i, j)] + m[(j, i)]);
            m[(i, j)] = v;
            m[(j, i)] = v;
        }
    }
}

pub fn min_eigenvalue(m: &Mat) -> f64 {
    if m.is_empty() {
        return 0.0;
    }
    SymmetricEigen::new(symmetrize(m)).eigenvalues.min()
}

/// A factor L with L Lᵀ = S for a symmetric PSD S, singular S included: Cholesky when it succeeds,
/// otherwise the eigen-factor V·sqrt(max(Λ, 0)). Sampling w = L u with E\[uuᵀ] = I then has
/// covariance exactly S, whatever the law of u.
pub fn psd_factor(s: &Mat) -> Mat {
    if let Some(ch) = nalgebra::Cholesky::new(symmetrize(s)) {
        return ch.l();
    }
    let eig = SymmetricEigen::new(symmetrize(s));
    let mut v = eig.eigenvectors;
    for (j, lam) in eig.eigenvalues.iter().enumerate() {
        let r = lam.max(0.0).sqrt();
        v.column_mut(j).scale_mut(r);
    }
    v
}

/// Moore–Penrose pseudo-inverse of a symmetric PSD matrix (the `⁺` of seed 000 eq (5)), with
/// eigenvalues below `PSD_TOL` times the largest treated as zero. A step without measurements
/// (C = 0, D = 0) then gets a zero gain instead of a division by zero.
pub fn psd_pinv(s: &Mat) -> Mat {
    let n = s.nrows();
    if n == 0 {
        return Mat::zeros(0, 0);
    }
    let eig = SymmetricEigen::new(symmetrize(s));
    let top = eig.eigenvalues.amax();
    let mut out = Mat::zeros(n, n);
    for (j, &lam) in eig.eigenvalues.iter().enumerate() {
        if lam > PSD_TOL * top && lam > 0.0 {
            let v = eig.eigenvectors.column(j);
            out += (v * v.transpose()) / lam;
        }
    }
    out
}

/// E_ij: the r×c matrix with a one at (i, j), zeros elsewhere.
pub fn unit(r: usize, c: usize, i: usize, j: usize) -> Mat {
    let mut e = Mat::zeros(r, c);
    e[(i, j)] = 1.0;
    e
}

/// E_ij + E_ji for i ≠ j and E_ii on the diagonal: the n×n symmetric matrix with ones at (i, j) and
/// (j, i), the coefficient of the scalar variable X_ij = X_ji in a symmetric matrix variable X.
pub(crate) fn sym_unit(n: usize, i: usize, j: usize) -> Mat {
    let mut e = unit(n, n, i, j);
    e[(j, i)] = 1.0;
    e
}

/// Σ_i w_i X_i for r×c matrices X_i, summed in the order given, starting from zero: a stationary
/// average Σ_s π_s X_s, or the mixing Σ_j Π_ji X_j of per-mode moments by a Markov chain.
pub(crate) fn weighted_sum<X: std::borrow::Borrow<Mat>>(
    r: usize,
    c: usize,
    terms: impl IntoIterator<Item = (f64, X)>,
) -> Mat {
    terms.into_iter().fold(Mat::zeros(r, c), |acc, (w, x)| acc + w * x.borrow())
}

/// Writes into m the symmetric n×n matrix of v in clarabel's PSD triangle form: the upper triangle
/// by columns, off-diagonal entries scaled by √2 so that ⟨svec A, svec B⟩ = ⟨A, B⟩.
pub fn unpack_triangle(v: &[f64], n: usize, m: &mut Mat) {
    let mut t = 0;
    for j in 0..n {
        for i in 0..=j {
            let x = if i == j { v[t] } else { v[t] / std::f64::consts::SQRT_2 };
            m[(i, j)] = x;
            m[(j, i)] = x;
            t += 1;
        }
    }
}

/// Block-diagonal matrix of the given square blocks.
pub fn block_diag(blocks: &[&Mat]) -> Mat {
    let n: usize = blocks.iter().map(|b| b.nrows()).sum();
    let mut out = Mat::zeros(n, n);
    let mut o = 0;
    for b in blocks {
        out.view_mut((o, o), (b.nrows(), b.ncols())).copy_from(b);
        o += b.nrows();
    }
    out
}

/// Frobenius inner product ⟨A, B⟩ = tr(Aᵀ B).
pub fn frob_dot(a: &Mat, b: &Mat) -> f64 {
    a.component_mul(b).sum()
}

/// Whether a symmetric matrix is PSD to `PSD_TOL` relative to its largest entry.
pub(crate) fn is_psd(m: &Mat) -> bool {
    min_eigenvalue(m) >= -PSD_TOL * m.amax().max(1.0)
}

/// Eigendecomposition of a symmetric matrix with faer (for the large ones: stacked operators over
/// the horizon): eigenvalues in nondecreasing order and the eigenvectors as columns.
pub fn sym_eigen(m: &Mat) -> Result<(Vec<f64>, Mat)> {
    let n = m.nrows();
    let s = symmetrize(m);
    // faer splits its work by the size of the rayon pool by default, so its rounding (and every
    // figure downstream of a worst-case covariance) would depend on --threads: run it sequentially.
    faer::set_global_parallelism(faer::Par::Seq);
    let fm = faer::Mat::<f64>::from_fn(n, n, |i, j| s[(i, j)]);
    let evd = fm
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|e| Error::invalid("eigendecomposition", format!("faer failed: {e:?}")))?;
    let values = (0..n).map(|i| evd.S().column_vector()[i]).collect();
    Ok((values, Mat::from_fn(n, n, |i, j| evd.U()[(i, j)])))
}

/// The eigenvalues of a symmetric matrix in nondecreasing order, by faer without the eigenvectors
/// (backward stable as [`sym_eigen`] is, so the same error bound holds; the last digits may differ
/// from [`sym_eigen`]'s).
pub fn sym_eigenvalues(m: &Mat) -> Result<Vec<f64>> {
    let n = m.nrows();
    let s = symmetrize(m);
    // Sequential for the same reason as in `sym_eigen`.
    faer::set_global_parallelism(faer::Par::Seq);
    faer::Mat::<f64>::from_fn(n, n, |i, j| s[(i, j)])
        .self_adjoint_eigenvalues(faer::Side::Lower)
        .map_err(|e| Error::invalid("eigendecomposition", format!("faer failed: {e:?}")))
}

/// The largest eigenvalue of a symmetric PSD matrix and a unit eigenvector for it ([`sym_eigen`]).
pub(crate) fn top_eigen(m: &Mat) -> Result<(f64, Vector)> {
    let (values, vectors) = sym_eigen(m)?;
    let top = values.len() - 1;
    Ok((values[top], vectors.column(top).into_owned()))
}
