//! The result tables `check` evaluates, read back from a result folder (summary.parquet,
//! steps.parquet, paired.parquet; docs/output-columns.md): whether the experiment was just run or
//! ran earlier, the expectations see the same numbers, as written.

use std::path::Path;

use crate::error::Result;
use crate::pipeline::table::Table;

/// One row of summary.parquet: the summed error of one (variant, scenario, filter).
#[derive(Clone, Debug)]
pub struct SummaryRow {
    pub variant: Option<String>,
    pub scenario: String,
    pub filter: String,
    pub n_trials: u64,
    pub mean: f64,
    pub std_error: f64,
    pub exact: Option<f64>,
    pub guaranteed: Option<f64>,
    pub violations: Option<u64>,
    pub deterministic_error: Option<f64>,
    pub input_power: Option<f64>,
    pub gain_exact_noise: Option<f64>,
    pub anisotropic_norm_sq: Option<f64>,
    pub guaranteed_gain: Option<f64>,
    pub guarantee_anisotropy: Option<f64>,
    pub guarantee_applies: Option<bool>,
}

/// One row of steps.parquet.
#[derive(Clone, Debug)]
pub struct StepRow {
    pub variant: Option<String>,
    pub scenario: String,
    pub filter: String,
    pub step: u32,
    pub mse_mean: f64,
    pub mse_std_error: f64,
    pub exact: Option<f64>,
    pub nees: Square,
    pub nis: Square,
}

/// A normalized square's columns at one step (NEES or NIS, docs/output-columns.md): None where the
/// filter claims nothing, or in a result written before the columns existed.
#[derive(Clone, Debug, Default)]
pub struct Square {
    pub mean: Option<f64>,
    pub std_error: Option<f64>,
    /// None also in a result written before `_rank` existed: then no χ² test.
    pub rank: Option<u32>,
}

/// One row of paired.parquet: J_a − J_b on the same draws.
#[derive(Clone, Debug)]
pub struct PairedRow {
    pub variant: Option<String>,
    pub scenario: String,
    pub filter_a: String,
    pub filter_b: String,
    pub mean_diff: f64,
    pub std_error: f64,
}

/// The three tables of one result folder.
#[derive(Clone, Debug)]
pub struct Tables {
    /// The result folder the tables were read from.
    pub dir: std::path::PathBuf,
    pub summary: Vec<SummaryRow>,
    pub steps: Vec<StepRow>,
    pub paired: Vec<PairedRow>,
}

/// z of the 95 % interval the tables were written with (docs/output-columns.md): the standard
/// error of a result written before `mse_std_error` existed is the interval's half-width over it.
const Z95: f64 = 1.959_963_984_540_054;

fn nonnull(v: Vec<Option<f64>>, t: &Table, name: &str) -> Result<Vec<f64>> {
    v.into_iter().enumerate().map(|(i, x)| x.ok_or_else(|| t.bad(format!("row {i}: `{name}` is null")))).collect()
}

impl Tables {
    /// Reads the tables of the result folder `dir`.
    pub fn read(dir: &Path) -> Result<Tables> {
        Ok(Tables { dir: dir.to_path_buf(), summary: summary(dir)?, steps: steps(dir)?, paired: paired(dir)? })
    }
}

fn summary(dir: &Path) -> Result<Vec<SummaryRow>> {
    let t = Table::read(dir, "summary.parquet")?;
    let (variant, scenario, filter) = (t.strs("variant")?, t.required("scenario")?, t.required("filter")?);
    let n = t.opt_u64s("n_trials")?;
    let (mean, se) = (nonnull(t.opt_f64s("empirical_mean")?, &t, "empirical_mean")?, t.opt_f64s("std_error")?);
    let (exact, guaranteed, violations) = (t.opt_f64s("exact")?, t.opt_f64s("guaranteed")?, t.opt_u64s("violations")?);
    let (det, power) = (t.opt_f64s("deterministic_error")?, t.opt_f64s("input_power")?);
    let (noise, norm, gamma) =
        (t.opt_f64s("gain_exact_noise")?, t.opt_f64s("anisotropic_norm_sq")?, t.opt_f64s("guaranteed_gain")?);
    let (level, applies) = (t.opt_f64s("guarantee_anisotropy")?, t.bools("guarantee_applies")?);
    Ok((0..t.height())
        .map(|i| SummaryRow {
            variant: variant[i].clone(),
            scenario: scenario[i].clone(),
            filter: filter[i].clone(),
            n_trials: n[i].unwrap_or(0),
            mean: mean[i],
            std_error: se[i].unwrap_or(f64::NAN),
            exact: exact[i],
            guaranteed: guaranteed[i],
            violations: violations[i],
            deterministic_error: det[i],
            input_power: power[i],
            gain_exact_noise: noise[i],
            anisotropic_norm_sq: norm[i],
            guaranteed_gain: gamma[i],
            guarantee_anisotropy: level[i],
            guarantee_applies: applies[i],
        })
        .collect())
}

fn steps(dir: &Path) -> Result<Vec<StepRow>> {
    let t = Table::read(dir, "steps.parquet")?;
    let (variant, scenario, filter) = (t.strs("variant")?, t.required("scenario")?, t.required("filter")?);
    let step = t.opt_u64s("step")?;
    let mean = nonnull(t.opt_f64s("mse_mean")?, &t, "mse_mean")?;
    let se = if t.has("mse_std_error") {
        t.opt_f64s("mse_std_error")?
    } else {
        from_interval(t.opt_f64s("mse_ci_low")?, t.opt_f64s("mse_ci_high")?)
    };
    let exact = t.opt_f64s("exact_mse")?;
    let (mut nees, mut nis) = (square(&t, "nees")?.into_iter(), square(&t, "nis")?.into_iter());
    Ok((0..t.height())
        .map(|i| StepRow {
            variant: variant[i].clone(),
            scenario: scenario[i].clone(),
            filter: filter[i].clone(),
            step: step[i].unwrap_or(0) as u32,
            mse_mean: mean[i],
            mse_std_error: se[i].unwrap_or(f64::NAN),
            exact: exact[i],
            nees: nees.next().unwrap_or_default(),
            nis: nis.next().unwrap_or_default(),
        })
        .collect())
}

/// The `{name}_mean`, `_std_error` (or the 95 % interval) and `_rank` columns of a normalized
/// square, all None where the table has no such columns.
fn square(t: &Table, name: &str) -> Result<Vec<Square>> {
    let col = |c: &str| format!("{name}_{c}");
    if !t.has(&col("mean")) {
        return Ok(vec![Square::default(); t.height()]);
    }
    let mean = t.opt_f64s(&col("mean"))?;
    let se = if t.has(&col("std_error")) {
        t.opt_f64s(&col("std_error"))?
    } else {
        from_interval(t.opt_f64s(&col("ci_low"))?, t.opt_f64s(&col("ci_high"))?)
    };
    let rank = if t.has(&col("rank")) { t.opt_u64s(&col("rank"))? } else { vec![None; t.height()] };
    Ok((0..t.height()).map(|i| Square { mean: mean[i], std_error: se[i], rank: rank[i].map(|r| r as u32) }).collect())
}

fn paired(dir: &Path) -> Result<Vec<PairedRow>> {
    let t = Table::read(dir, "paired.parquet")?;
    let (variant, scenario) = (t.strs("variant")?, t.required("scenario")?);
    let (a, b) = (t.required("filter_a")?, t.required("filter_b")?);
    let (d, se) = (nonnull(t.opt_f64s("mean_diff")?, &t, "mean_diff")?, t.opt_f64s("std_error")?);
    Ok((0..t.height())
        .map(|i| PairedRow {
            variant: variant[i].clone(),
            scenario: scenario[i].clone(),
            filter_a: a[i].clone(),
            filter_b: b[i].clone(),
            mean_diff: d[i],
            std_error: se[i].unwrap_or(f64::NAN),
        })
        .collect())
}

/// The standard errors of a 95 % interval's bounds: its half-width over z₀.₉₇₅.
fn from_interval(lo: Vec<Option<f64>>, hi: Vec<Option<f64>>) -> Vec<Option<f64>> {
    lo.iter().zip(&hi).map(|(l, h)| Some(((*h)? - (*l)?) / (2.0 * Z95))).collect()
}
