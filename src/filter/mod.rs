//! Layer 3, the filter: the one linear realization every family compiles to, and what a design
//! hands on (its realization, its promise, its trace).

pub mod design;
pub mod realization;
