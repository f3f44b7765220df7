//! The output contract (docs/output-columns.md): `summary.parquet`, `steps.parquet`, `gains.parquet`,
//! `paired.parquet`, `design_trace.parquet`, `manifest.json` and `recording.rrd` in one folder, plus
//! the console table.
//!
//! Everything is written into a temporary sibling folder that is renamed onto the target only when
//! every file is complete, so a failed run leaves the previous results untouched ([`output`]).

pub mod console;
pub mod manifest;
pub mod output;
pub mod parquet;
pub mod recording;
mod rows;
pub mod trials;

use std::path::Path;

use crate::config::Experiment;
use crate::error::Result;
use crate::pipeline::RunOutcome;

/// Writes every file of the output contract into `dir`, for the runs of one experiment (one per
/// variant; a file without variants is one run).
pub fn write_all(runs: &[(&Experiment, &RunOutcome)], dir: &Path, overrides: &manifest::CommandLine) -> Result<()> {
    // Three independent writers, each serial inside: side by side they take the longest one's
    // time instead of the sum (galerkin_string's model digest and gains table). The first failure
    // in this order is the one reported.
    let ((tables, rrd), man) = rayon::join(
        || rayon::join(|| parquet::write_tables(runs, dir), || recording::write(runs, &dir.join("recording.rrd"))),
        || manifest::write(runs, overrides, &dir.join("manifest.json")),
    );
    tables.and(rrd).and(man)
}
