mod traits;
pub(crate) use traits::*;
mod cholesky;
pub(crate) use cholesky::*;
mod syevr;
pub(crate) use syevr::*;
mod svd;
pub(crate) use svd::*;
mod lu;
#[allow(unused_imports)]
pub(crate) use lu::*;

mod gemm;
mod gemv;
mod symv;
mod syr2k;
mod syrk;
