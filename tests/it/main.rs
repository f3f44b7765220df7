//! Integration and statistical regression tests (one test binary: every extra one would link the
//! whole dependency tree again). Statistical tests use fixed seeds; their tolerances are stated in
//! standard errors (σ) of the Monte Carlo estimate next to each assertion.

mod aniso_design;
mod aniso_dropout;
mod aniso_structures;
mod anisotropy;
mod array_files;
mod bad_input;
mod check;
mod common;
mod compare;
mod determinism;
mod disturbance;
mod double_double;
mod end_to_end;
mod exact_vs_mc;
mod family_recipe;
mod from_run;
mod galerkin;
mod galerkin_projections;
mod generators;
mod hinf;
mod hinf_sdp;
mod kalman;
mod lane_draws;
mod lemma1;
mod linear;
mod long_horizon;
mod markov_jump;
mod minimax;
mod multiplicative;
mod nees;
mod noise_free;
mod output_safety;
mod promises;
mod realization_sharing;
mod recording;
mod sdp;
mod series;
mod shards;
mod strict_files;
mod time_varying;
mod unstable;
