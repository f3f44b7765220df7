//! Layer 6, simulation: noise sampling and the Monte Carlo engine with its streaming statistics.

pub mod block;
mod checks;
pub mod lanes;
pub mod mc_stats;
pub mod montecarlo;
pub mod noise;
mod plant_ops;
pub mod scenario;
pub mod series;
pub mod stacked;
pub mod stats;
pub mod tree;
