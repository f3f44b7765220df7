//! Layer 6, simulation: noise sampling and the Monte Carlo engine with its streaming statistics.

pub mod montecarlo;
pub mod noise;
mod plant_ops;
pub mod stats;
