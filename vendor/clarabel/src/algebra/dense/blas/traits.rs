#![cfg_attr(rustfmt, rustfmt_skip)]
#![allow(clippy::too_many_arguments)]

cfg_if::cfg_if! {
    if #[cfg(sdp_pyblas)] {
        // imports via scipy 
        use crate::python::pyblas::*;
    }
    else {
        // standard imports via blas-lapack-rs crates 
        extern crate blas_src;
        extern crate lapack_src;
        use lapack::*;
        use blas::*;
    }
}

pub trait BlasFloatT: 
    private::BlasFloatSealed 
    + XsyevrScalar 
    + XpotrfScalar 
    + XpotrsScalar 
    + XgesddScalar 
    + XgesvdScalar 
    + XgemmScalar 
    + XgemvScalar 
    + XsymvScalar 
    + XsyrkScalar
    + Xsyr2kScalar
    + XgesvScalar
{}

cfg_if::cfg_if! {
  if #[cfg(not(feature="sdp-r"))] {
	// R blas/lapack only provides double precision routines
	impl BlasFloatT for f32 {}
  }
}
impl BlasFloatT for f64 {}

mod private {
  pub trait BlasFloatSealed {}
  cfg_if::cfg_if! {
	if #[cfg(not(feature="sdp-r"))] {
	    // R blas/lapack only provides double precision routines
	    impl BlasFloatSealed for f32 {}     
	}
  }
  impl BlasFloatSealed for f64 {}
}


// --------------------------------------
// ?syevr : Symmetric eigen decomposition
// --------------------------------------

pub trait XsyevrScalar: Sized {
    fn xsyevr(
        jobz: u8, range: u8, uplo: u8, n: i32, a: &mut [Self], lda: i32, vl: Self, vu: Self, il: i32, iu: i32, 
        abstol: Self, m: &mut i32, w: &mut [Self], z: &mut [Self], ldz: i32, isuppz: &mut [i32], 
        work: &mut [Self], lwork: i32, iwork: &mut [i32], liwork: i32, info: &mut i32,
    );
}

macro_rules! impl_blas_xsyevr {
    ($T:ty, $XSYEVR:path) => {
        impl XsyevrScalar for $T {
            fn xsyevr(
                jobz: u8, range: u8, uplo: u8, n: i32, a: &mut [Self], lda: i32, vl: Self, vu: Self, il: i32, iu: i32, 
                abstol: Self, m: &mut i32, w: &mut [Self], z: &mut [Self], ldz: i32, isuppz: &mut [i32], 
                work: &mut [$T], lwork: i32, iwork: &mut [i32], liwork: i32, info: &mut i32,
            ) {
                unsafe{
                    $XSYEVR(
                        jobz, range, uplo, n, a, lda, vl, vu, il, iu, abstol, m, 
                        w, z, ldz, isuppz, work, lwork, iwork, liwork, info,
                    );
                }
            }
        }
    };
}

cfg_if::cfg_if! {
  if #[cfg(not(feature="sdp-r"))] {
      // R blas/lapack only provides double precision routines
      impl_blas_xsyevr!(f32, ssyevr);      
  }
}
impl_blas_xsyevr!(f64, dsyevr);

// --------------------------------------
// ?potrf : Cholesky decomposition
// --------------------------------------

pub trait XpotrfScalar: Sized {
    fn xpotrf(
        uplo: u8, n: i32, a: &mut [Self], lda: i32, info: &mut i32
    );
}

pub trait XpotrsScalar: Sized {
    fn xpotrs(
        uplo: u8, n: i32, nrhs: i32, a: &[Self], lda: i32,  b: &mut [Self], ldb: i32, info: &mut i32
    );
}

macro_rules! impl_blas_xpotrfs{
    ($T:ty, $XPOTRF:path, $XPOTRS:path) => {
        impl XpotrfScalar for $T {
            fn xpotrf(
                uplo: u8, n: i32, a: &mut [Self], lda: i32, info: &mut i32
            ) {
                unsafe{
                    $XPOTRF(
                        uplo, n, a, lda, info
                    );
                }
            }
        }
        impl XpotrsScalar for $T {
            fn xpotrs(
                uplo: u8, n: i32, nrhs: i32, a: &[Self], lda: i32, b: &mut [Self], ldb: i32, info: &mut i32
            ) {
                unsafe{
                    $XPOTRS(
                        uplo, n, nrhs, a, lda, b, ldb, info
                    );
                }
            }
        }
    };
}

cfg_if::cfg_if! {
  if #[cfg(not(feature="sdp-r"))] {
      // R blas/lapack only provides double precision routines
      impl_blas_xpotrfs!(f32, spotrf, spotrs);      
  }
}
impl_blas_xpotrfs!(f64, dpotrf, dpotrs);


// --------------------------------------
// ?gesdd : SVD (divide and conquer method)
// --------------------------------------

pub trait XgesddScalar: Sized {
    fn xgesdd(
        jobz: u8, m: i32, n: i32, a: &mut [Self], lda: i32, 
        s: &mut [Self], u: &mut [Self], ldu: i32, vt: &mut [Self], ldvt: i32, 
        work: &mut [Self], lwork: i32, iwork: &mut [i32], info: &mut i32
    );
}

macro_rules! impl_blas_xgesdd{
    ($T:ty, $XGESDD:path) => {
        impl XgesddScalar for $T {
            fn xgesdd(
                jobz: u8, m: i32, n: i32, a: &mut [Self], lda: i32, 
                s: &mut [Self], u: &mut [Self], ldu: i32, vt: &mut [Self], ldvt: i32, 
                work: &mut [Self], lwork: i32, iwork: &mut [i32], info: &mut i32
            ) {
                unsafe{
                    $XGESDD(
                        jobz, m, n, a, lda, s, u, ldu, vt, ldvt, work, lwork, iwork, info
                    );
                }
            }
        }
    };
}

cfg_if::cfg_if! {
  if #[cfg(not(feature="sdp-r"))] {
      // R blas/lapack only provides double precision routines
      impl_blas_xgesdd!(f32, sgesdd);
  }
}
impl_blas_xgesdd!(f64, dgesdd);


// --------------------------------------
// ?gesvd : SVD (QR method)
// --------------------------------------

pub trait XgesvdScalar: Sized {
    fn xgesvd(
        jobu: u8, jobvt: u8,m: i32, n: i32, a: &mut [Self], lda: i32, 
        s: &mut [Self], u: &mut [Self], ldu: i32, vt: &mut [Self], ldvt: i32, 
        work: &mut [Self], lwork: i32, info: &mut i32
    );
}

macro_rules! impl_blas_xgesvd{
    ($T:ty, $XGESVD:path) => {
        impl XgesvdScalar for $T {
            fn xgesvd(
                jobu: u8, jobvt: u8,m: i32, n: i32, a: &mut [Self], lda: i32, 
                s: &mut [Self], u: &mut [Self], ldu: i32, vt: &mut [Self], ldvt: i32, 
                work: &mut [Self], lwork: i32, info: &mut i32
            ) {
                unsafe{
                    $XGESVD(
                        jobu, jobvt, m, n, a, lda, s, u, ldu, vt, ldvt, work, lwork, info
                    );
                }
            }
        }
    };
}

cfg_if::cfg_if! {
  if #[cfg(not(feature="sdp-r"))] {
      // R blas/lapack only provides double precision routines
      impl_blas_xgesvd!(f32, sgesvd);
  }
}
impl_blas_xgesvd!(f64, dgesvd);


// --------------------------------------
// ?gemm : matrix matrix multiply
// --------------------------------------

pub trait XgemmScalar: Sized {
    fn xgemm(
        transa: u8, transb: u8, m: i32, n: i32, k: i32, alpha: Self, a: &[Self], 
        lda: i32, b: &[Self], ldb: i32, beta: Self, c: &mut [Self], ldc: i32
    );
}

// filterbench patch: ?gemm, ?syrk and ?syr2k through faer's matmul instead of BLAS. The PSD cones
// multiply matrices of a few rows (their blocks' sides), where OpenBLAS spends most of its time
// outside the product: every call takes a buffer from its allocator under a process-wide mutex,
// and two threads designing at once then wait on each other in the kernel. faer multiplies small
// matrices with its own kernels and no allocation; a transposed operand is a transposed view of
// the same column-major storage (FILTERBENCH.md, change 3).
mod faer_blas {
    use faer_dense::linalg::matmul::{self, triangular::BlockStructure};
    use faer_dense::traits::ComplexField;
    use faer_dense::{Accum, MatMut, MatRef, Par};

    /// op(X), `rows` × `cols`, from X stored column by column with leading dimension `ld` (X
    /// itself is `cols` × `rows` when `trans` is not `N`).
    fn op<T>(x: &[T], trans: u8, rows: usize, cols: usize, ld: i32) -> MatRef<'_, T> {
        if trans == b'N' {
            MatRef::from_column_major_slice_with_stride(x, rows, cols, ld as usize)
        } else {
            MatRef::from_column_major_slice_with_stride(x, cols, rows, ld as usize).transpose()
        }
    }

    /// C (`m` × `n`, leading dimension `ldc`) scaled by β where `uplo` says (`U`, `L`, or
    /// anything else for all of it), and how the product is then accumulated: BLAS reads C only
    /// when β ≠ 0.
    fn scaled<T: ComplexField + Copy + PartialEq + core::ops::MulAssign>(
        c: &mut [T], m: usize, n: usize, ldc: i32, beta: T, uplo: u8,
    ) -> (MatMut<'_, T>, Accum) {
        let accum = if beta == T::zero_impl() {
            Accum::Replace
        } else {
            if beta != T::one_impl() {
                let ldc = ldc as usize;
                for j in 0..n {
                    let rows = match uplo {
                        b'U' => 0..(j + 1).min(m),
                        b'L' => j.min(m)..m,
                        _ => 0..m,
                    };
                    for x in &mut c[j * ldc + rows.start..j * ldc + rows.end] {
                        *x *= beta;
                    }
                }
            }
            Accum::Add
        };
        (MatMut::from_column_major_slice_with_stride_mut(c, m, n, ldc as usize), accum)
    }

    fn triangle(uplo: u8) -> BlockStructure {
        if uplo == b'U' { BlockStructure::TriangularUpper } else { BlockStructure::TriangularLower }
    }

    /// C = α op(A) op(B) + β C.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn gemm<T: ComplexField + Copy + PartialEq + core::ops::MulAssign>(
        transa: u8, transb: u8, m: i32, n: i32, k: i32, alpha: T, a: &[T], lda: i32, b: &[T],
        ldb: i32, beta: T, c: &mut [T], ldc: i32,
    ) {
        let (m, n, k) = (m as usize, n as usize, k as usize);
        let (lhs, rhs) = (op(a, transa, m, k, lda), op(b, transb, k, n, ldb));
        let (dst, accum) = scaled(c, m, n, ldc, beta, b'A');
        matmul::matmul(dst, accum, lhs, rhs, alpha, Par::Seq);
    }

    /// The `uplo` triangle of C = α op(A) op(A)ᵀ + β C (op(A) is n × k), and with `b`, of
    /// C = α (op(A) op(B)ᵀ + op(B) op(A)ᵀ) + β C; the other triangle is not touched.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn syr2k<T: ComplexField + Copy + PartialEq + core::ops::MulAssign>(
        uplo: u8, trans: u8, n: i32, k: i32, alpha: T, a: &[T], lda: i32, b: Option<(&[T], i32)>,
        beta: T, c: &mut [T], ldc: i32,
    ) {
        let (n, k) = (n as usize, k as usize);
        let a = op(a, trans, n, k, lda);
        let (mut dst, accum) = scaled(c, n, n, ldc, beta, uplo);
        let rect = BlockStructure::Rectangular;
        let Some((b, ldb)) = b else {
            matmul::triangular::matmul(dst, triangle(uplo), accum, a, rect, a.transpose(), rect, alpha, Par::Seq);
            return;
        };
        let b = op(b, trans, n, k, ldb);
        matmul::triangular::matmul(dst.as_mut(), triangle(uplo), accum, a, rect, b.transpose(), rect, alpha, Par::Seq);
        matmul::triangular::matmul(dst, triangle(uplo), Accum::Add, b, rect, a.transpose(), rect, alpha, Par::Seq);
    }
}

macro_rules! impl_blas_gemm {
    ($T:ty) => {
        impl XgemmScalar for $T {
            fn xgemm(
                transa: u8, transb: u8, m: i32, n: i32, k: i32, alpha: Self, a: &[Self], 
                lda: i32, b: &[Self], ldb: i32, beta: Self, c: &mut [Self], ldc: i32
            ) {
                faer_blas::gemm(transa, transb, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc);
            }
        }
    };
}

cfg_if::cfg_if! {
  if #[cfg(not(feature="sdp-r"))] {
      // R blas/lapack only provides double precision routines
      impl_blas_gemm!(f32);
  }
}
impl_blas_gemm!(f64);

// --------------------------------------
// ?gemv : matrix vector multiply (general shape)
// --------------------------------------

pub trait XgemvScalar: Sized {
    fn xgemv(
        trans: u8, m: i32, n: i32, alpha: Self, a: &[Self], lda: i32, 
        x: &[Self], incx: i32, beta: Self, y: &mut [Self], incy: i32
    );
}


macro_rules! impl_blas_gemv {
    ($T:ty, $XGEMV:path) => {
        impl XgemvScalar for $T {
            fn xgemv(
                trans: u8, m: i32, n: i32, alpha: Self, a: &[Self], lda: i32, 
                x: &[Self], incx: i32, beta: Self, y: &mut [Self], incy: i32
            ) {
                unsafe{
                    $XGEMV(
                        trans, m, n, alpha, a, lda, x, incx, beta, y, incy
                    );
                }
            }
        }
    };
}

cfg_if::cfg_if! {
  if #[cfg(not(feature="sdp-r"))] {
      // R blas/lapack only provides double precision routines
      impl_blas_gemv!(f32, sgemv);
  }
}
impl_blas_gemv!(f64, dgemv);


// --------------------------------------
// ?symv : matrix vector multiply (symmetric)
// --------------------------------------

pub trait XsymvScalar: Sized {
    fn xsymv(
        uplo: u8, n: i32, alpha: Self, a: &[Self], lda: i32, 
        x: &[Self], incx: i32, beta: Self, y: &mut [Self], incy: i32
    );
}


macro_rules! impl_blas_gsymv {
    ($T:ty, $XSYMV:path) => {
        impl XsymvScalar for $T {
            fn xsymv(
                uplo: u8, n: i32, alpha: Self, a: &[Self], lda: i32, 
                x: &[Self], incx: i32, beta: Self, y: &mut [Self], incy: i32
            ) {
                unsafe{
                    $XSYMV(
                        uplo, n, alpha, a, lda, x, incx, beta, y, incy
                    );
                }
            }
        }
    };
}

cfg_if::cfg_if! {
  if #[cfg(not(feature="sdp-r"))] {
      // R blas/lapack only provides double precision routines
      impl_blas_gsymv!(f32, ssymv);
  }
}
impl_blas_gsymv!(f64, dsymv);


// --------------------------------------
// ?syrk : symmetric rank k update
// --------------------------------------

pub trait XsyrkScalar: Sized {
    fn xsyrk(
        uplo: u8, trans: u8, n: i32, k: i32, alpha: Self, 
        a: &[Self], lda: i32, beta: Self, c: &mut [Self], ldc: i32
    );
}


// filterbench patch: through faer (see ?gemm above).
macro_rules! impl_blas_gsyrk {
    ($T:ty) => {
        impl XsyrkScalar for $T {
            fn xsyrk(
                uplo: u8, trans: u8, n: i32, k: i32, alpha: Self, 
                a: &[Self], lda: i32, beta: Self, c: &mut [Self], ldc: i32
            ) {
                faer_blas::syr2k(uplo, trans, n, k, alpha, a, lda, None, beta, c, ldc);
            }
        }
    };
}

cfg_if::cfg_if! {
  if #[cfg(not(feature="sdp-r"))] {
      // R blas/lapack only provides double precision routines
      impl_blas_gsyrk!(f32);
  }
}
impl_blas_gsyrk!(f64);

// --------------------------------------
// ?syrk : symmetric rank 2k update
// --------------------------------------

pub trait Xsyr2kScalar: Sized {
    fn xsyr2k(
        uplo: u8, trans: u8, n: i32, k: i32, alpha: Self, a: &[Self], lda: i32, 
        b: &[Self], ldb: i32, beta: Self, c: &mut [Self], ldc: i32
    );
}


// filterbench patch: through faer (see ?gemm above).
macro_rules! impl_blas_gsyr2k {
    ($T:ty) => {
        impl Xsyr2kScalar for $T {
            fn xsyr2k(
                uplo: u8, trans: u8, n: i32, k: i32, alpha: Self, a: &[Self], lda: i32, 
                b: &[Self], ldb: i32, beta: Self, c: &mut [Self], ldc: i32
            ) {
                faer_blas::syr2k(uplo, trans, n, k, alpha, a, lda, Some((b, ldb)), beta, c, ldc);
            }
        }
    };
}

cfg_if::cfg_if! {
  if #[cfg(not(feature="sdp-r"))] {
      // R blas/lapack only provides double precision routines
      impl_blas_gsyr2k!(f32);
  }
}
impl_blas_gsyr2k!(f64);


// --------------------------------------
// ?gesv : Generalized (LU) linear solve, multiple right hand side
// --------------------------------------

pub trait XgesvScalar: Sized {
    fn xgesv(
        n: i32, nrhs: i32, a: &mut [Self], lda: i32, ipiv: &mut [i32], 
                b: &mut [Self], ldb: i32, info:&mut i32,
    );
}

macro_rules! impl_blas_xgesv{
    ($T:ty, $XGESV:path) => {
        impl XgesvScalar for $T {
            fn xgesv(
                n: i32, nrhs: i32, a: &mut [Self], lda: i32, ipiv: &mut [i32], 
                b: &mut [Self], ldb: i32, info:&mut i32,
            ) {
                unsafe{
                    $XGESV(
                        n, nrhs, a, lda, ipiv, b, ldb, info,
                    );
                }
            }
        }
    };
}

cfg_if::cfg_if! {
  if #[cfg(not(feature="sdp-r"))] {
      // R blas/lapack only provides double precision routines
      impl_blas_xgesv!(f32, sgesv);
  }
}
impl_blas_xgesv!(f64, dgesv);