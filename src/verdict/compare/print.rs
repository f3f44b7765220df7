//! The comparison on the console (comfy-table, as the run's own table) and as JSON.

use crate::report::console::num;
use std::path::Path;

use comfy_table::{CellAlignment, ContentArrangement, Table, presets};

use super::cell::Status;
use super::outcome::Comparison;
use crate::error::{Error, Result};

/// How many changed cells the console lists below the table.
const LISTED: usize = 20;

/// One row per (table, column): its cells, how many are identical, moved within noise, changed
/// beyond noise or not tested, and the largest |z| (Monte Carlo) or relative difference; then the
/// first changed cells and the verdict.
pub fn console(c: &Comparison) -> String {
    let mut out = format!(
        "compare {} → {} (experiment `{}`): {}; α = {} over {} Monte Carlo cells (Holm), relative tolerance {:e}\n",
        c.old.display(),
        c.new.display(),
        c.experiment,
        if c.common_draws {
            "same seed and trials, so the same draws: Monte Carlo values compared like deterministic ones"
        } else {
            "independent draws: Monte Carlo means by two-sample z"
        },
        c.alpha,
        c.tested_cells,
        c.rel_tol,
    );
    let mut t = Table::new();
    t.load_preset(presets::NOTHING).set_content_arrangement(ContentArrangement::Disabled).set_header(vec![
        "table",
        "column",
        "kind",
        "cells",
        "identical",
        "within noise",
        "changed",
        "not tested",
        "largest |z| / rel. diff",
    ]);
    // A column null on both sides everywhere (another family's figures) has no cells: left out.
    for s in c.columns.iter().filter(|s| s.cells > 0) {
        let largest = match (s.max_abs_z, s.max_rel_diff) {
            (Some(z), _) => format!("|z| {}", num(z)),
            (None, Some(r)) => format!("rel {}", num(r)),
            _ => String::new(),
        };
        t.add_row(vec![
            s.table.to_string(),
            s.column.clone(),
            s.kind.map_or("", |k| k.name()).to_string(),
            s.cells.to_string(),
            s.identical.to_string(),
            s.within_noise.to_string(),
            s.changed.to_string(),
            s.not_tested.to_string(),
            largest,
        ]);
    }
    for (i, col) in t.column_iter_mut().enumerate() {
        col.set_cell_alignment(if i < 3 { CellAlignment::Left } else { CellAlignment::Right });
    }
    out.extend(t.lines().map(|l| format!(" {}\n", l.trim_end())));
    let changed: Vec<_> = c.changed_cells().collect();
    if !changed.is_empty() {
        out += &format!(
            "\nchanged beyond noise ({} cells{}):\n",
            changed.len(),
            if changed.len() > LISTED { format!(", the first {LISTED}") } else { String::new() }
        );
        for cell in changed.iter().take(LISTED) {
            let evidence = match (cell.z, cell.p, cell.rel_diff) {
                (Some(z), Some(p), _) => {
                    format!("z = {z:.2}, p = {p:.2e} ≤ Holm's {:.2e}", cell.holm_threshold.unwrap_or(f64::NAN))
                }
                (_, _, Some(r)) => format!("rel. diff {}", num(r)),
                _ => cell.kind.name().to_string(),
            };
            out += &format!(
                "  {} {} {}: {} → {} ({evidence})\n",
                cell.table,
                cell.column,
                cell.place(),
                cell.old,
                cell.new
            );
        }
    }
    out += &format!(
        "\n{}: {} identical, {} moved within noise, {} changed beyond noise, {} not tested\n",
        if c.changed() { "CHANGED" } else { "nothing changed beyond noise" },
        c.count(Status::Identical),
        c.count(Status::WithinNoise),
        c.count(Status::Changed),
        c.count(Status::NotTested),
    );
    out
}

/// Writes the comparison as JSON to `path`: the options, the column summaries and the cells.
pub fn json(c: &Comparison, path: &Path) -> Result<()> {
    let text = serde_json::to_string_pretty(c).map_err(|e| Error::output(path.display().to_string(), e))?;
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}
