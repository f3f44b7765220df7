mod quasidef;
pub use quasidef::*;
