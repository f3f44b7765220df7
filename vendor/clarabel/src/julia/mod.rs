//! Clarabel.rs Julia interface.
//!
//! This module implements a Julia wrapper for the Rust version of Clarabel.   
//! This module is intended for developer benchmarking and testing purposes.
//! Most Julia users should instead using the native Julia implementation of
//! this solver, available [here](https://github.com/oxfordcontrol/Clarabel.jl).

pub(crate) mod interface;
pub(crate) mod types;
