mod block_concatenate;
mod core;
mod types;
pub(crate) use self::types::*;

// fixed sized types required for pow/exp cones
mod fixed;
pub(crate) use self::fixed::*;

// these only required for sdps
cfg_if::cfg_if! {
    if #[cfg(feature = "sdp")] {
        mod traits;
        pub(crate) use traits::*;
        mod blas;
        pub(crate) use self::blas::*;
        mod matrix_math;
        pub(crate) use self::matrix_math::*;
    }
}
