//! What a comparison of two result folders returns: one summary per (table, column) and the cells.

use std::path::PathBuf;

use super::cell::{Cell, Kind, Status};

/// Counts of one (table, column).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ColumnSummary {
    pub table: &'static str,
    pub column: String,
    pub kind: Option<Kind>,
    pub cells: usize,
    pub identical: usize,
    pub within_noise: usize,
    pub changed: usize,
    pub not_tested: usize,
    /// The largest |z| of its Monte Carlo cells.
    pub max_abs_z: Option<f64>,
    /// The largest relative difference of its deterministic cells (∞ for a value against null).
    pub max_rel_diff: Option<f64>,
}

impl ColumnSummary {
    pub(crate) fn count(&mut self, status: Status) {
        self.cells += 1;
        match status {
            Status::Identical => self.identical += 1,
            Status::WithinNoise => self.within_noise += 1,
            Status::Changed => self.changed += 1,
            Status::NotTested => self.not_tested += 1,
        }
    }
}

/// The comparison of two result folders: one summary per (table, column) counting every cell, and
/// the cells themselves (only those that moved, unless [`super::CompareOptions::keep_identical`]).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Comparison {
    pub old: PathBuf,
    pub new: PathBuf,
    pub experiment: String,
    pub alpha: f64,
    pub rel_tol: f64,
    /// Both manifests have the same seed and trial count, so both runs drew the same numbers.
    pub common_draws: bool,
    /// The Monte Carlo cells tested together by Holm's procedure.
    pub tested_cells: usize,
    pub columns: Vec<ColumnSummary>,
    pub cells: Vec<Cell>,
}

impl Comparison {
    /// Whether any cell changed beyond noise (the command's exit status 1).
    pub fn changed(&self) -> bool {
        self.columns.iter().any(|c| c.changed > 0)
    }

    /// The cells that changed beyond noise.
    pub fn changed_cells(&self) -> impl Iterator<Item = &Cell> {
        self.cells.iter().filter(|c| c.status == Status::Changed)
    }

    /// Every cell of that status, over all columns.
    pub fn count(&self, status: Status) -> usize {
        self.columns
            .iter()
            .map(|c| match status {
                Status::Identical => c.identical,
                Status::WithinNoise => c.within_noise,
                Status::Changed => c.changed,
                Status::NotTested => c.not_tested,
            })
            .sum()
    }
}
