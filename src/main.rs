//! Command line: `list`, `experiment NAME|FILE [--shard I/N]`, `merge SHARD_DIR…`, `bench NAME|FILE`,
//! `compare OLD NEW`, `check NAME|FILE`.

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
    /// Run an experiment (or read a result folder) and test its `[[expect]]` entries at a designed
    /// false-alarm rate: exit 0 when every one holds, 1 when one fails, 2 for bad input.
    Check(CheckArgs),
    /// Measure throughput per scenario (trial-steps/s) and one thread's split: drawing, simulation, statistics.
    Bench {
        /// Experiment name or path to a TOML file.
        name: String,
        /// The lane kernels' build to time: the best this processor has (default), or a lower one
        /// to compare with (every build gives the same bits).
        #[arg(long, value_enum, default_value_t = BuildArg::Best)]
        build: BuildArg,
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
struct CheckArgs {
    /// Experiment name or path to a TOML file (its `[[expect]]` entries); with --results, optional.
    name: Option<String>,
    /// Evaluate an existing result folder instead of running (its manifest names the experiment).
    #[arg(long)]
    results: Option<PathBuf>,
    /// Family-wise false-alarm rate, split over every tested cell by Holm's procedure (default 1e-3).
    #[arg(long)]
    alpha: Option<f64>,
    /// Miss rate at which each test's power is stated (default 0.05).
    #[arg(long)]
    beta: Option<f64>,
    /// Choose the trial count so every cell detects this relative discrepancy with probability 1 − β.
    #[arg(long)]
    min_detectable: Option<f64>,
    /// The most trials --min-detectable may choose (default 10⁸).
    #[arg(long)]
    max_trials: Option<usize>,
    /// Write a JUnit XML report (one test case per cell) to this file.
    #[arg(long)]
    junit: Option<PathBuf>,
    /// The stored result folder `matches_baseline` expectations compare the run with.
    #[arg(long)]
    baseline: Option<PathBuf>,
    #[command(flatten)]
    opts: RunOpts,
    /// Output folder (default: results/NAME); replaced only when the run completes.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Do not print the progress bar or the table.
    #[arg(long)]
    quiet: bool,
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
            filterbench::verdict::evaluate::configure(&exps[0])?;
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
                    let outcomes = pool.install(|| pipeline::run_variants(&exps, !quiet))?;
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
        Command::Check(args) => return check(args),
        Command::Bench { name, build, opts } => {
            use filterbench::sim::lanes::{Build, force_build};
            force_build(match build {
                BuildArg::Best => None,
                BuildArg::Avx2 => Some(Build::Avx2),
                BuildArg::Baseline => Some(Build::Baseline),
            });
            let p = pool(opts.threads)?;
            let exps = load(&name, &opts.overrides(false))?;
            filterbench::pipeline::budget::check(&exps)?;
            for exp in exps {
                print!("{}", p.install(|| pipeline::bench::run(&exp))?);
            }
        }
        Command::Compare { old, new, alpha, rel_tol, json } => {
            use filterbench::verdict::compare;
            let opts = compare::CompareOptions { alpha, rel_tol, ..Default::default() };
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

/// The most trials `--min-detectable` chooses without `--max-trials` or `[check] max_trials`.
const DEFAULT_MAX_TRIALS: usize = 100_000_000;

/// Trials of the pilot run `--min-detectable` estimates the per-trial spread from (unless --trials).
const PILOT_TRIALS: usize = 1000;

/// `filterbench check`: run the experiment (or read `--results`), evaluate every expectation on the
/// written tables, write check.parquet beside them (and the JUnit report), print the table.
fn check(a: CheckArgs) -> Result<ExitCode> {
    use filterbench::Error;
    use filterbench::verdict::{output, run};
    if let Some(dir) = &a.results {
        for (flag, given) in [
            ("--trials", a.opts.trials.is_some()),
            ("--seed", a.opts.seed.is_some()),
            ("--out", a.out.is_some()),
            ("--min-detectable", a.min_detectable.is_some()),
        ] {
            if given {
                return Err(Error::invalid(
                    flag,
                    "does not apply with --results (the folder's run is checked as it is)",
                ));
            }
        }
        let mut exps = run::experiments_of(dir)?;
        if let Some(name) = &a.name {
            // The expectations of the file given, against the experiment the folder ran.
            let file = load(name, &Overrides::default())?;
            if file[0].name != exps[0].name {
                return Err(Error::invalid(
                    "--results",
                    format!("{} holds a result of `{}`, not of `{}`", dir.display(), exps[0].name, file[0].name),
                ));
            }
            for e in &mut exps {
                (e.expectations, e.check) = (file[0].expectations.clone(), file[0].check.clone());
            }
        }
        let rates = run::rates(a.alpha, a.beta, &exps[0].check)?;
        let result = run::evaluate_folder(dir, &exps, rates, a.baseline.as_deref())?;
        output::write_parquet(&result, &exps[0].name, &dir.join(output::CHECK_FILE))?;
        return finish(&a, &result, &exps[0].name, dir);
    }
    let name = a.name.as_deref().ok_or_else(|| Error::invalid("check", "name an experiment or give --results DIR"))?;
    let mut exps = load(name, &a.opts.overrides(false))?;
    let configured = filterbench::verdict::evaluate::configure(&exps[0])?;
    if configured.is_empty() {
        return Err(Error::invalid("expect", format!("`{name}` has no [[expect]] entries: nothing to check")));
    }
    let rates = run::rates(a.alpha, a.beta, &exps[0].check)?;
    let pool = pool(a.opts.threads)?;
    let min_detectable = a.min_detectable.or(exps[0].check.min_detectable);
    if let Some(delta) = min_detectable {
        config::check_min_detectable("--min-detectable", delta)?;
        let cap = a.max_trials.or(exps[0].check.max_trials).unwrap_or(DEFAULT_MAX_TRIALS);
        config::check_max_trials("--max-trials", cap)?;
        let pilot_trials = a.opts.trials.unwrap_or(exps[0].trials.min(PILOT_TRIALS));
        let pilot = load(name, &Overrides { trials: Some(pilot_trials), ..a.opts.overrides(false) })?;
        filterbench::pipeline::budget::check(&pilot)?;
        let dir = std::env::temp_dir().join(format!("filterbench-pilot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
        let piloted = (|| {
            let outcomes = pool.install(|| pipeline::run_variants(&pilot, false))?;
            let runs: Vec<_> = pilot.iter().zip(&outcomes).collect();
            report::parquet::write_tables(&runs, &dir)?;
            run::evaluate_folder(&dir, &pilot, rates, a.baseline.as_deref())
        })();
        let _ = std::fs::remove_dir_all(&dir);
        let n = filterbench::verdict::evaluate::trials_for(&piloted?, pilot_trials, delta).ok_or_else(|| {
            Error::invalid("--min-detectable", "no tested cell has an exact value or bound to be relative to")
        })?;
        if n > cap as f64 {
            return Err(Error::invalid(
                "--min-detectable",
                format!(
                    "detecting {delta} (relative) needs {n:.0} trials, more than the limit of {cap} (--max-trials)"
                ),
            ));
        }
        let n = (n as usize).max(2);
        if !a.quiet {
            println!("min_detectable {delta}: the pilot run of {pilot_trials} trials asks for {n} trials");
        }
        exps = load(name, &Overrides { trials: Some(n), ..a.opts.overrides(false) })?;
    }
    filterbench::pipeline::budget::check(&exps)?;
    let target = a.out.clone().unwrap_or_else(|| PathBuf::from("results").join(&exps[0].name));
    let command_line = CommandLine {
        trials: if min_detectable.is_some() { Some(exps[0].trials) } else { a.opts.trials },
        seed: a.opts.seed,
        threads: a.opts.threads,
        out: a.out.as_ref().map(|p| p.display().to_string()),
    };
    let mut result = None;
    publish(&target, |dir| {
        let outcomes = pool.install(|| pipeline::run_variants(&exps, !a.quiet))?;
        let runs: Vec<_> = exps.iter().zip(&outcomes).collect();
        report_runs(&runs, dir, &command_line, true)?;
        let r = run::evaluate_folder(dir, &exps, rates, a.baseline.as_deref())?;
        output::write_parquet(&r, &exps[0].name, &dir.join(output::CHECK_FILE))?;
        result = Some(r);
        Ok(())
    })?;
    let result = result.expect("publish ran the check");
    finish(&a, &result, &exps[0].name, &target)
}

/// The JUnit report and the table of a finished check, and its exit code: 1 when an expectation fails.
fn finish(a: &CheckArgs, result: &filterbench::verdict::evaluate::Check, name: &str, dir: &Path) -> Result<ExitCode> {
    use filterbench::verdict::output;
    if let Some(path) = &a.junit {
        output::write_junit(result, name, path)?;
    }
    if !a.quiet {
        print!("{}", output::table(result));
        println!("\nresults: {} (check: {})", dir.display(), output::CHECK_FILE);
    }
    Ok(if result.fails() { ExitCode::from(1) } else { ExitCode::SUCCESS })
}

/// `bench --build`: which build of the lane kernels to time.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum BuildArg {
    /// The best build this processor runs (AVX-512, AVX2 or the x86-64 baseline).
    Best,
    /// AVX2, or the baseline where the processor has no AVX2.
    Avx2,
    /// The x86-64 baseline (SSE2).
    Baseline,
}

fn main() -> ExitCode {
    filterbench::numerics::solve::conic::single_threaded_blas();
    match main_inner(Cli::parse()) {
        Ok(code) => code,
        Err(e) => {
            // One line, whatever a library put into its message.
            eprintln!("error: {}", e.to_string().trim().replace('\n', "; "));
            ExitCode::from(2)
        }
    }
}
