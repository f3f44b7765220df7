#![allow(non_snake_case)]

mod core;
pub use self::core::*;
mod block_concatenate;
mod matrix_math;
mod utils;
