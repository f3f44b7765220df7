//! Fixed matrices applied in the trial loop. A large matrix that is mostly zero — the modal truth of
//! seed 004's string (2×2 blocks on the diagonal of a 256 × 256 A, B = [I 0], sensors that see only
//! displacements) — is stored as CSR (nalgebra-sparse) and applied in O(nonzeros); every other matrix
//! stays dense and goes through nalgebra's gemv, so small plants give bit-for-bit the results they
//! gave before sparse storage existed.

use nalgebra::storage::{Storage, StorageMut};
use nalgebra::{DMatrixView, DMatrixViewMut, Dyn, Matrix, U1};
use nalgebra_sparse::CsrMatrix;
use nalgebra_sparse::ops::Op;
use nalgebra_sparse::ops::serial::spmm_csr_dense;

use crate::numerics::linalg::Mat;

/// Matrices with fewer entries than this stay dense whatever their sparsity.
const SPARSE_MIN_ENTRIES: usize = 1024;
/// …and so do those with more than this share of nonzeros.
const SPARSE_MAX_DENSITY: f64 = 0.25;

#[derive(Clone, Debug)]
pub enum LinOp {
    Dense(Mat),
    Sparse(CsrMatrix<f64>),
}

impl LinOp {
    pub fn new(m: &Mat) -> Self {
        let entries = m.nrows() * m.ncols();
        let nonzeros = m.iter().filter(|v| **v != 0.0).count();
        if entries >= SPARSE_MIN_ENTRIES && (nonzeros as f64) <= SPARSE_MAX_DENSITY * entries as f64 {
            LinOp::Sparse(CsrMatrix::from(m))
        } else {
            LinOp::Dense(m.clone())
        }
    }

    /// y ← alpha·M x + beta·y, allocating nothing; x and y are vectors or columns of matrices.
    pub fn apply<S, SM>(&self, alpha: f64, x: &Matrix<f64, Dyn, U1, S>, beta: f64, y: &mut Matrix<f64, Dyn, U1, SM>)
    where
        S: Storage<f64, Dyn, U1, RStride = U1, CStride = Dyn>,
        SM: StorageMut<f64, Dyn, U1, RStride = U1, CStride = Dyn>,
    {
        match self {
            LinOp::Dense(m) => y.gemv(alpha, m, x, beta),
            LinOp::Sparse(m) => {
                let (nx, ny) = (x.nrows(), y.nrows());
                let xs: DMatrixView<'_, f64> = x.generic_view((0, 0), (Dyn(nx), Dyn(1)));
                let ys: DMatrixViewMut<'_, f64> = y.generic_view_mut((0, 0), (Dyn(ny), Dyn(1)));
                spmm_csr_dense(beta, ys, alpha, Op::NoOp(m), Op::NoOp(xs));
            }
        }
    }

    pub fn nrows(&self) -> usize {
        match self {
            LinOp::Dense(m) => m.nrows(),
            LinOp::Sparse(m) => m.nrows(),
        }
    }

    pub fn ncols(&self) -> usize {
        match self {
            LinOp::Dense(m) => m.ncols(),
            LinOp::Sparse(m) => m.ncols(),
        }
    }
}
