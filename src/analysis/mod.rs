//! Layer 4, analysis of a realization on a plant: exact error moments, worst cases over sets,
//! operator norms (H∞, generalized H2), anisotropy (eigenvalues of Λ, or seed 003's Lemma 1), NEES, and
//! the plant's noise-free output.

pub mod anisotropy;
pub mod disturbance;
pub mod exact;
pub mod hinf;
pub mod lemma1;
pub mod nees;
pub mod noise_free;
pub mod theorem1;
