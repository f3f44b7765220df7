mod cholesky;
mod core;
mod eigen;
mod svd;

pub(crate) use self::core::*;
