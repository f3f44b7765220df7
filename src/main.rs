//! Command line: `list`, `experiment NAME|FILE [--shard I/N]`, `merge SHARD_DIR…`, `bench NAME|FILE`,
//! `compare OLD NEW`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use filterbench::config::Overrides;
use filterbench::pipeline::RunOutcome;
use filterbench::pipeline::shards;
use filterbench::report::{self, manifest::CommandLine, output};
use filterbench::{Result, config, experiment_path, list_experiments, pipeline};

#[derive(Parser)]
#[command(
    name = "filterbench",
    version,
    about = "Monte Carlo benchmarking of robust state estimators: empirical vs exact vs guaranteed error"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the shipped experiments with a one-line description each.
    List,
    /// Run an experiment (a name from `list`, or the path of a TOML file) and write its results.
    Experiment {
        /// Experiment name (experiments/NAME.toml) or path to a TOML file.
        name: String,
        #[command(flatten)]
        opts: RunOpts,
        /// Output folder (default: results/NAME); replaced only when the run completes.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Do not print the progress bar or the table.
        #[arg(long)]
        quiet: bool,
        /// Run only shard I of N (0 ≤ I < N) and write a partial result for `merge`.
        #[arg(long, value_name = "I/N")]
        shard: Option<String>,
        /// Keep every trial's summed error J: trials.parquet, and the summary's median and p95.
        #[arg(long)]
        per_trial: bool,
    },
    /// Merge the partial results of every shard of a run into the output of one run.
    Merge {
        /// The shards' folders (any order).
        #[arg(required = true)]
        shards: Vec<PathBuf>,
        /// Output folder; replaced only when the merge completes.
        #[arg(long)]
        out: PathBuf,
        /// Worker threads (default: all cores). Results do not depend on it.
        #[arg(long)]
        threads: Option<usize>,
        /// Do not print the table.
        #[arg(long)]
        quiet: bool,
    },
    /// Measure throughput per scenario (trial-steps/s) and one thread's split: drawing, simulation, statistics.
    Bench {
        /// Experiment name or path to a TOML file.
        name: String,
        #[command(flatten)]
        opts: RunOpts,
    },
    /// What changed between two result folders of the same experiment: deterministic columns within
    /// a relative tolerance, Monte Carlo means by a two-sample z with Holm's procedure. Exit status 0
    /// when nothing changed beyond noise, 1 when something did, 2 for bad input.
    Compare {
        /// The earlier result folder (the baseline).
        old: PathBuf,
        /// The later result folder.
        new: PathBuf,
        /// Family-wise false-alarm rate of the Monte Carlo cells (split by Holm's procedure).
        #[arg(long, default_value_t = filterbench::verdict::compare::DEFAULT_ALPHA)]
        alpha: f64,
        /// Relative tolerance of deterministic columns (design, exact, guaranteed, gains, …).
        #[arg(long, default_value_t = filterbench::verdict::compare::DEFAULT_REL_TOL)]
        rel_tol: f64,
        /// Also write every cell that moved, with the column summaries, as JSON to this file.
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
    },
}

#[derive(clap::Args)]
struct RunOpts {
    /// Number of Monte Carlo trials per scenario (overrides the file).
    #[arg(long)]
    trials: Option<usize>,
    /// Random seed (overrides the file).
    #[arg(long)]
    seed: Option<u64>,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
}

impl RunOpts {
    /// What these options set instead of the experiment file.
    fn overrides(&self, per_trial: bool) -> Overrides {
        Overrides { trials: self.trials, seed: self.seed, per_trial }
    }
}

/// Every variant of the experiment, built from its file and the command line's `overrides`.
fn load(name: &str, overrides: &Overrides) -> Result<Vec<config::Experiment>> {
    config::load_variants(&experiment_path(name)?, overrides)
}

/// Claims the output place before any work (nothing of the user's is replaced), runs `work` into
/// its temporary folder and renames it onto `target` only when `work` succeeded.
fn publish(target: &Path, work: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    output::install_signal_cleanup()?;
    let holder: Vec<String> = std::env::args().map(|a| a.escape_debug().to_string()).collect();
    let staging = output::OutputPlace::claim(target, &holder.join(" "))?;
    work(staging.path())?;
    staging.commit()?;
    Ok(())
}

/// The tables, manifest and recording of finished runs, then (unless quiet) the console table.
fn report_runs(
    runs: &[(&config::Experiment, &RunOutcome)],
    dir: &Path,
    overrides: &CommandLine,
    quiet: bool,
) -> Result<()> {
    report::write_all(runs, dir, overrides)?;
    if !quiet {
        for (exp, outcome) in runs {
            print!("{}", report::console::table(exp, outcome));
        }
    }
    Ok(())
}

/// The most worker threads `--threads` may ask for.
const MAX_THREADS: usize = 1024;

fn pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    let mut b = rayon::ThreadPoolBuilder::new();
    if let Some(t) = threads {
        if t == 0 {
            return Err(filterbench::Error::invalid("--threads", "must be at least 1"));
        }
        // Results do not depend on the thread count; beyond this, spawning the pool alone takes minutes.
        if t > MAX_THREADS {
            return Err(filterbench::Error::invalid(
                "--threads",
                format!("{t} is more than the limit of {MAX_THREADS}"),
            ));
        }
        b = b.num_threads(t);
    }
    b.build().map_err(|e| filterbench::Error::invalid("--threads", e.to_string()))
}

fn main_inner(cli: Cli) -> Result<ExitCode> {
    match cli.command {
        Command::List => {
            let list = list_experiments();
            let w = list.iter().map(|(n, _)| n.len()).max().unwrap_or(0);
            for (name, desc) in list {
                println!("{name:w$}  {desc}");
            }
        }
        Command::Experiment { name, opts, out, quiet, shard, per_trial } => {
            let overrides = opts.overrides(per_trial);
            let exps = load(&name, &overrides)?;
            let shard = shard.as_deref().map(shards::parse_shard).transpose()?;
            let default = match shard {
                Some((i, n)) => format!("{}-shard-{i}-of-{n}", exps[0].name),
                None => exps[0].name.clone(),
            };
            let target = out.clone().unwrap_or_else(|| PathBuf::from("results").join(default));
            let pool = pool(opts.threads)?;
            filterbench::pipeline::budget::check(&exps)?;
            let command_line = CommandLine {
                trials: opts.trials,
                seed: opts.seed,
                threads: opts.threads,
                out: out.map(|p| p.display().to_string()),
            };
            publish(&target, |dir| match shard {
                Some((i, n)) => {
                    let meta = pool.install(|| shards::run_shards(&exps, n, &[i], &overrides, |_| dir.into()))?;
                    if let (Some(m), false) = (meta, quiet) {
                        println!("shard {i}/{n}: blocks {}..{} of every scenario", m.blocks[0], m.blocks[1]);
                    }
                    Ok(())
                }
                None => {
                    let outcomes =
                        exps.iter().map(|e| pool.install(|| pipeline::run(e, !quiet))).collect::<Result<Vec<_>>>()?;
                    let runs: Vec<_> = exps.iter().zip(&outcomes).collect();
                    report_runs(&runs, dir, &command_line, quiet)
                }
            })?;
            if !quiet {
                println!("\nresults: {}", target.display());
            }
        }
        Command::Merge { shards: dirs, out, threads, quiet } => {
            let pool = pool(threads)?;
            let checked = shards::check(&dirs, &out)?;
            let given = &checked.meta.overrides;
            let command_line =
                CommandLine { trials: given.trials, seed: given.seed, threads, out: Some(out.display().to_string()) };
            publish(&out, |dir| {
                let outcomes = pool.install(|| shards::merge(&checked))?;
                let runs: Vec<_> = checked.exps.iter().zip(&outcomes).collect();
                report_runs(&runs, dir, &command_line, quiet)
            })?;
            if !quiet {
                println!("\nresults: {}", out.display());
            }
        }
        Command::Bench { name, opts } => {
            let p = pool(opts.threads)?;
            let exps = load(&name, &opts.overrides(false))?;
            filterbench::pipeline::budget::check(&exps)?;
            for exp in exps {
                print!("{}", p.install(|| pipeline::bench::run(&exp))?);
            }
        }
        Command::Compare { old, new, alpha, rel_tol, json } => {
            use filterbench::verdict::compare;
            let opts = compare::CompareOptions { alpha, rel_tol, keep_identical: false };
            let c = compare::compare_folders(&old, &new, &opts)?;
            if let Some(path) = json {
                compare::json(&c, &path)?;
            }
            print!("{}", compare::console(&c));
            return Ok(if c.changed() { ExitCode::from(1) } else { ExitCode::SUCCESS });
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn main() -> ExitCode {
    match main_inner(Cli::parse()) {
        Ok(code) => code,
        Err(e) => {
            // One line, whatever a library put into its message.
            eprintln!("error: {}", e.to_string().trim().replace('\n', "; "));
            ExitCode::from(2)
        }
    }
}
