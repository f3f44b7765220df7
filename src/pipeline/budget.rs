//! The memory a run needs, estimated from the experiment's sizes before anything is designed, so a
//! run that cannot fit is refused at once with the figure and the key that drives it, instead of
//! aborting after minutes with an allocation failure.

use crate::config::{Experiment, Input};
use crate::error::{Error, Result};
use crate::sim::montecarlo::{BLOCK, STEP_BYTES, WAVE, WAVE_BYTES};

/// Bytes of one step's running mean/variance accumulator in a series (mean, M2 and a bit for the
/// count, which is shared: `sim::series`).
const WELFORD: u64 = STEP_BYTES;
/// Bytes of one row of steps.parquet while it is built and written (numbers, the copy the writer
/// makes); the table is written a row group at a time.
const STEP_ROW: u64 = 256;
/// Bytes of one row of gains.parquet (one nonzero gain entry) while it is built and written, a
/// row group at a time like the steps.
const GAIN_ROW: u64 = 64;
/// Rows of a table alive at once while it is written: at most three row groups (the rows waiting,
/// the slice added and a row group's copy in one chunk; `report::parquet`'s row groups of 512²
/// rows). At N = 10⁶ writing steps.parquet was measured to add 168 MB, below these 201 MB.
const TABLE_ROWS: u64 = 3 * 512 * 512;
/// Bytes a small matrix costs beyond its entries (its header and the allocator's).
const MATRIX: u64 = 64;
/// Bytes of one step's gains beyond its sets' matrices: its pointer, the shared allocation's
/// counts and the vector of sets (`filter::realization`).
const GAINS_STEP: u64 = 72;
/// Bytes per (scenario, filter) of the recording's series, whatever the horizon: at most 4097
/// rows (longer horizons are decimated to 2049 buckets, docs/output-columns.md) of up to three
/// values, their steps and the envelope.
const RECORDED: u64 = 4097 * 10 * 8;
/// Bytes per step, scenario and filter kept until the reports: the exact error, the exact NEES
/// and NIS (a value and a bit each, `analysis::nees::PerStep`) and a guaranteed per-step promise
/// (a claimed one is the filter's, shared by every scenario).
const KEPT_STEP: u64 = 8 + 2 * (8 + 1) + 8;

/// An estimate of the peak memory of `exp`, in bytes, with the dominant terms named.
pub struct Estimate {
    pub bytes: u64,
    /// The dense matrices over the whole horizon (joint inputs, anisotropy): their side and bytes.
    pub dense_side: u64,
    pub dense_bytes: u64,
}

/// The most memory the error forms of a run's filters may take for the Monte Carlo to carry every
/// filter in error coordinates when it need not (`pipeline::evaluate`, without the plant): a form
/// holds five matrices per step and mode, which on a long horizon with time-varying gains would
/// double the gains' memory to save a few products a step.
pub(crate) const PLANT_FREE_BYTES: u64 = 64 << 20;

/// Bytes of a filter's error form (`analysis::exact::ErrorForm`): per step and mode its five
/// matrices F, E, H, G, R and their vector of factor terms.
pub(crate) fn error_form_bytes(p: &crate::model::plant::Plant, ns: usize) -> u64 {
    let (ns, nx, nz, nw) = (ns as u64, p.nx() as u64, p.nz() as u64, p.nw() as u64);
    let entries = [ns * ns, ns * nw, nz * ns, nz * nw, ns * nx].iter().fold(0u64, |a, &x| a.saturating_add(x));
    let per_step = entries.saturating_mul(8).saturating_add(5 * MATRIX + 24);
    sat(&[p.steps() as u64, p.n_modes().max(1) as u64, per_step])
}

fn sat(xs: &[u64]) -> u64 {
    xs.iter().fold(1u64, |a, &x| a.saturating_mul(x))
}

/// The peak memory of the run, from its sizes: the designed gains of every filter at every step
/// (as if no two steps were the same, so an upper bound for a filter that reaches a steady state),
/// with its NEES weights and, while they are computed, one projected copy of its gains per filter
/// (the designs run in parallel); the Monte Carlo accumulators (per step and filter, for a wave of
/// blocks cut to fit `WAVE_BYTES` on a long horizon and the reduction tree's nodes, the first of
/// which becomes the total); what every scenario keeps (per-step statistics, exact errors, NEES
/// and NIS, promises, the sample trajectories); the row groups of a table being written; the
/// recording's decimated series; and the dense matrices over the whole horizon that joint inputs,
/// anisotropic analyses and some designs build.
pub fn estimate(exp: &Experiment) -> Estimate {
    let p = &exp.plant;
    let steps = p.steps() as u64;
    let (nx, ny, nz, nw) = (p.nx() as u64, p.ny() as u64, p.nz() as u64, p.nw() as u64);
    let nf = exp.filters.len() as u64;
    let nsc = exp.scenarios.len() as u64;
    // Each family states its filter's state size and gain sets ([`crate::families::Footprint`]).
    let size = crate::families::PlantSize { nx: p.nx(), modes: p.n_modes().max(1) };
    let footprints: Vec<_> = exp.filters.iter().map(|f| f.configured.footprint(size)).collect();
    let (mut design, mut copy, mut forms) = (0u64, 0u64, 0u64);
    for fp in &footprints {
        let (ns, sets) = (fp.state as u64, fp.gain_sets as u64);
        let entries = [ns * ns, ns * ny, nz * ns, nz * ny, ns * nx].iter().fold(0u64, |a, &x| a.saturating_add(x));
        // Each of the five matrices of a step is its own allocation. Every step is counted as
        // distinct: before the design nothing tells whether the gains settle, and a steady state
        // (shared, `filter::realization`) then costs less than this.
        let per_step =
            sets.saturating_mul(entries.saturating_mul(8).saturating_add(5 * MATRIX)).saturating_add(GAINS_STEP);
        let gains = steps.saturating_mul(per_step);
        // Its NEES and NIS weights per step, and a copy of its gains to project the output on
        // (analysis::nees). The copy is temporary; while the Monte Carlo runs, the filter's stacked
        // steps (sim::stacked, the same entries in one buffer) take its place.
        let weights = sat(&[steps, (nz * nz + ny * ny) * 8 + 2 * MATRIX]);
        design = design.saturating_add(gains).saturating_add(weights);
        // Its error form, which the Monte Carlo may hold when it goes without the plant
        // ([`PLANT_FREE_BYTES`] for all filters together).
        forms = forms.saturating_add(error_form_bytes(p, fp.state));
        copy = copy.saturating_add(gains);
    }
    let design = design.saturating_add(copy).saturating_add(forms.min(PLANT_FREE_BYTES));
    // Monte Carlo accumulators alive at once per scenario: a wave of blocks and the tree's nodes
    // (one per level; the total is the first of them, `sim::tree`), each per (filter, step) for the
    // mean-square error, NEES and NIS.
    let per_block = sat(&[nf, steps, 3 * WELFORD]);
    let blocks = (exp.trials as u64).div_ceil(BLOCK);
    let threads = rayon::current_num_threads() as u64;
    let wave = (WAVE_BYTES / per_block.max(1)).max(threads).clamp(1, WAVE).min(blocks);
    let levels = 64 - u64::from(blocks.leading_zeros()) + 1;
    let live = per_block.saturating_mul(wave + levels);
    let traj = sat(&[nsc, exp.sample_trajectories as u64, (nf + 1) * nz * 8 + 4, steps]);
    let kept = sat(&[nsc, nf, steps, 3 * WELFORD + KEPT_STEP]).saturating_add(traj);
    let rows_of_gains = footprints.iter().map(|f| (f.state * (f.state + ny as usize + nz as usize) + 1) as u64);
    let table = TABLE_ROWS * STEP_ROW + rows_of_gains.max().unwrap_or(0).min(TABLE_ROWS) * GAIN_ROW;
    let recording = sat(&[nsc, nf, RECORDED]);
    let dense = exp.anisotropy.is_some()
        || footprints.iter().any(|f| f.dense_horizon)
        || exp.scenarios.iter().any(|s| s.input != Input::Independent);
    let dense_side = if dense { nx.saturating_add(nw.saturating_mul(steps)) } else { 0 };
    let dense_bytes = sat(&[3, dense_side, dense_side, 8]);
    let bytes = [design, live, kept, table, recording, dense_bytes].iter().fold(0u64, |a, &x| a.saturating_add(x));
    Estimate { bytes, dense_side, dense_bytes }
}

/// The memory available to a new allocation (Linux: MemAvailable of /proc/meminfo); None elsewhere.
pub fn available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Bytes in a short human form (1.2 GB).
pub(crate) fn human(bytes: u64) -> String {
    let b = bytes as f64;
    match b {
        _ if b >= 1e12 => format!("{:.1} TB", b / 1e12),
        _ if b >= 1e9 => format!("{:.1} GB", b / 1e9),
        _ => format!("{:.0} MB", (b / 1e6).max(1.0)),
    }
}

/// Refuses a run whose estimated memory exceeds what the machine has available, naming the figure
/// and the key that drives it (the horizon, or the string model's duration that sets it). The
/// variants of a file are run one after the other but their results are all kept until written,
/// so their estimates add up; the largest one is named.
pub fn check(exps: &[Experiment]) -> Result<()> {
    let Some(avail) = available() else { return Ok(()) };
    let estimates: Vec<Estimate> = exps.iter().map(estimate).collect();
    let total = estimates.iter().fold(0u64, |a, e| a.saturating_add(e.bytes));
    if total <= avail {
        return Ok(());
    }
    let (exp, est) = exps.iter().zip(&estimates).max_by_key(|(_, e)| e.bytes).expect("at least one variant");
    let key = if exp.string.is_some() { "string.duration" } else { "plant.horizon" };
    let why = if est.dense_bytes >= est.bytes / 2 {
        format!("(dense {0}×{0} matrices over the whole horizon for the joint input or the anisotropy)", est.dense_side)
    } else {
        format!("({} steps × {} filters × {} scenarios)", exp.plant.steps(), exp.filters.len(), exp.scenarios.len())
    };
    let variant = exp.variant.as_deref().map_or(String::new(), |v| format!(" (variant `{v}`)"));
    Err(Error::invalid(
        format!("{key}{variant}"),
        format!(
            "the run needs about {} of memory {why}, but only {} is available: lower {key}",
            human(total),
            human(avail)
        ),
    ))
}
