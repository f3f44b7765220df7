//! `manifest.json`: the resolved experiment, seed, trials, threads, library versions and timings.

use std::path::Path;

use rayon::prelude::*;
use serde::Serialize;

use crate::config::Experiment;
use crate::error::{Error, Result};
use crate::pipeline::RunOutcome;

/// The command line as the manifest records it: the values that replaced the file's (`--trials`,
/// `--seed`) and how the run was made (`--threads`, `--out`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct CommandLine {
    pub trials: Option<usize>,
    pub seed: Option<u64>,
    pub threads: Option<usize>,
    pub out: Option<String>,
}

/// Versions of the libraries as pinned in this crate's Cargo.toml.
pub(crate) fn library_versions() -> serde_json::Map<String, serde_json::Value> {
    let manifest: toml::Table = toml::from_str(include_str!("../../Cargo.toml")).unwrap_or_default();
    let mut out = serde_json::Map::new();
    if let Some(deps) = manifest.get("dependencies").and_then(|d| d.as_table()) {
        for (name, v) in deps {
            let ver = v.as_str().or_else(|| v.get("version").and_then(|x| x.as_str())).unwrap_or("?");
            out.insert(name.clone(), serde_json::Value::String(ver.to_string()));
        }
    }
    out
}

fn matrix(m: &nalgebra::DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows()).map(|i| m.row(i).iter().copied().collect()).collect()
}

/// The scenarios and filters of one run, as JSON.
fn run_json(exp: &Experiment, out: &RunOutcome) -> (Vec<serde_json::Value>, Vec<serde_json::Value>) {
    let names = exp.plant.block_names();
    let cov_json = |c: &crate::model::plant::Covariances| -> serde_json::Map<String, serde_json::Value> {
        names.iter().zip(&c.blocks).map(|(n, m)| (n.to_string(), serde_json::json!(matrix(m)))).collect()
    };
    let scenarios: Vec<_> = out
        .scenarios
        .iter()
        .map(|s| {
            let blocks = cov_json(&s.covariances);
            serde_json::json!({
                "name": s.name, "covariance": s.covariance_label, "shape": s.shape_label,
                "disturbance": s.disturbance_label,
                "covariances": blocks, "mc_seconds": s.mc_seconds,
            })
        })
        .collect();
    let filters: Vec<_> = exp
        .filters
        .iter()
        .zip(&out.filters)
        .map(|(f, d)| {
            serde_json::json!({
                "name": f.name, "family": f.family, "params": f.params, "design_seconds": d.seconds,
                "guarantee": d.design.guarantee.as_ref().map(|g| serde_json::json!({"kind": g.kind.name(), "total": g.total})),
                "claimed": d.claimed.as_ref().map(|c| c.total),
                "worst_case": d.worst.as_ref().map(|w| w.total),
                "certified_worst_case": d.worst.as_ref().and_then(|w| w.certified),
                "worst_disturbance": d.worst.as_ref().and_then(|w| w.disturbance_bound).map(|(value, upper)| serde_json::json!({
                    "value": value, "upper_bound": upper, "exact": value >= upper * (1.0 - 1e-9)})),
                "design_covariance": d.design.design_covariance.as_ref().map(cov_json),
                "diagnostics": d.design.manifest_diagnostics(),
                "anisotropic": d.anisotropic.map(|x| serde_json::json!({"norm_sq": x.norm_sq, "h2_sq": x.h2_sq, "hinf_sq": x.hinf_sq})),
                "realization": realization_json(&d.design.realization),
                "gain_bound": d.design.gain_bound.map(|g| serde_json::json!({"gamma_sq": g.gamma_sq, "design_gamma_sq": g.design_gamma_sq, "anisotropy": g.anisotropy, "theorem1_sq": g.theorem1_sq})),
            })
        })
        .collect();
    (scenarios, filters)
}

/// What an earlier run's filter is read back with (`from_run`, docs/experiment-files.md "A filter
/// from an earlier run"): the sizes gains.parquet leaves out with its zeros, and the digest of the
/// realization it holds.
fn realization_json(r: &crate::filter::realization::Realization) -> serde_json::Value {
    use sha2::Digest;
    let mut h = sha2::Sha256::new();
    r.digest(&mut h);
    let g = r.gains(0, 0);
    serde_json::json!({
        "states": r.ns(),
        "modes": if r.is_mode_indexed() { r.gains[0].len() } else { 1 },
        "known_input_columns": g.gf.ncols(),
        "sha256": crate::numerics::linalg::hex(&h.finalize()),
    })
}

/// The plant a run's filters were designed on: its sizes and the digest of its model.
fn plant_json(exp: &Experiment) -> serde_json::Value {
    let p = &exp.plant;
    serde_json::json!({
        "states": p.nx(), "measurements": p.ny(), "outputs": p.nz(), "steps": p.steps(),
        "modes": p.n_modes(), "sha256": p.model_digest(),
    })
}

/// What the families found on the run ([`crate::families::Finding`]), per family.
fn findings_json(out: &RunOutcome) -> serde_json::Map<String, serde_json::Value> {
    out.findings.iter().map(|f| (f.family.to_string(), f.record.json())).collect()
}

/// Writes the manifest of the runs of one experiment: the first run's scenarios and filters at the
/// top level, and with variants one entry per variant under `variants`.
pub fn write(runs: &[(&Experiment, &RunOutcome)], overrides: &CommandLine, path: &Path) -> Result<()> {
    let (exp, out) = runs[0];
    let (scenarios, filters) = run_json(exp, out);
    // Each plant's digest hashes its model at every step (galerkin_string: about 0.4 s a variant):
    // once per run, the runs side by side.
    let plants: Vec<_> = runs.par_iter().map(|(e, _)| plant_json(e)).collect();
    let variants: Vec<_> = runs
        .iter()
        .zip(&plants)
        .filter(|((e, _), _)| e.variant.is_some())
        .map(|((e, o), plant)| {
            let (scenarios, filters) = run_json(e, o);
            serde_json::json!({
                "variant": e.variant, "plant": plant, "arrival": e.plant.arrival(), "anisotropy": e.anisotropy,
                "design_seconds": o.design_seconds, "total_seconds": o.total_seconds,
                "scenarios": scenarios, "filters": filters, "findings": findings_json(o),
            })
        })
        .collect();
    let doc = serde_json::json!({
        "experiment": exp.name,
        "description": exp.description,
        "seed": exp.seed,
        "trials": exp.trials,
        "sample_trajectories": exp.sample_trajectories,
        "threads": out.threads,
        "pattern": exp.pattern,
        "horizon": exp.plant.horizon,
        "plant": plants[0],
        "overrides": overrides,
        "filterbench_version": env!("CARGO_PKG_VERSION"),
        "libraries": library_versions(),
        "anisotropy": exp.anisotropy,
        "design_seconds": out.design_seconds,
        "total_seconds": runs.iter().map(|(_, o)| o.total_seconds).sum::<f64>(),
        "scenarios": scenarios,
        "filters": filters,
        "findings": findings_json(out),
        "variants": variants,
        "experiment_file": exp.source,
        "files": exp.inputs,
    });
    let text = serde_json::to_string_pretty(&doc).map_err(|e| Error::output("manifest.json", e))?;
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}
