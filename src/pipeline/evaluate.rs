//! Stage 3: each scenario evaluated: every filter's exact error (docs/math.md §4) and exact NEES, then the
//! Monte Carlo on the same input (docs/math.md §6) from the run's one [`MonteCarlo`] source,
//! gathered into the scenario's [`ScenarioOutcome`].

use std::sync::Arc;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::analysis::exact::{self, ErrorForm, ExactError};
use crate::analysis::nees::{self, Normalized};
use crate::config::Experiment;
use crate::error::{Error, Result};
use crate::filter::realization::Realization;
use crate::model::plant::{Covariances, Plant};
use crate::model::shape::Shape;
use crate::numerics::linalg::Mat;
use crate::sim::montecarlo::{self, Partial, PlantOps, RatioCheck};
use crate::sim::noise::JointInput;
use crate::sim::stacked::Stacked;

use rayon::prelude::*;

use super::budget;
use super::design::DesignedFilter;
use super::outcome::{Evaluated, FilterOutcome, ScenarioOutcome};
use super::scenarios::Setup;

/// What the Monte Carlo engine needs of a run, the same for every scenario: the realizations, the
/// plant's operators, the per-trial ratio checks and the NEES weights.
pub struct Engine<'a> {
    pub exp: &'a Experiment,
    pub filters: &'a [DesignedFilter],
    pub reals: Vec<&'a Realization>,
    pub ops: PlantOps,
    pub ratios: Option<RatioCheck<'a>>,
    pub nees: Vec<Option<&'a [Option<Arc<Mat>>]>>,
    pub nis: Vec<Option<&'a [Option<Arc<Mat>>]>>,
    /// Every filter may be simulated in error coordinates, without the plant: no per-trial ratio
    /// check and the forms fit the memory set aside for them. Each scenario still checks that
    /// every filter has an error form.
    pub plant_free: bool,
}

/// Whether the Monte Carlo may simulate every filter in error coordinates ε = s − M x (docs/math.md
/// §0), where a trial's error e = H ε + G w needs none of the plant's x, y and z, so the engine skips
/// the plant's products ([`crate::sim::block::simulate`]): no per-trial ratio check reads x\[N], and
/// the forms fit in [`budget::PLANT_FREE_BYTES`]. The error is the same number computed in other
/// coordinates, so only its rounding changes.
fn plant_free(exp: &Experiment, reals: &[&Realization], ratios: Option<&RatioCheck>) -> bool {
    let bytes = reals.iter().fold(0u64, |a, r| a.saturating_add(budget::error_form_bytes(&exp.plant, r.ns())));
    ratios.is_none() && bytes <= budget::PLANT_FREE_BYTES
}

impl<'a> Engine<'a> {
    pub fn new(exp: &'a Experiment, filters: &'a [DesignedFilter]) -> Self {
        let reals: Vec<_> = filters.iter().map(|f| &f.design.realization).collect();
        let (ops, ratios) = (PlantOps::new(&exp.plant), ratio_check(exp, filters));
        Engine {
            exp,
            filters,
            plant_free: plant_free(exp, &reals, ratios.as_ref()),
            reals,
            ops,
            ratios,
            nees: filters.iter().map(|f| f.nees.as_ref().map(|n| &n.weights[..])).collect(),
            nis: filters.iter().map(|f| f.nis.as_ref().map(|n| &n.weights[..])).collect(),
        }
    }

    /// Scenario `index` as the engine runs it: drawn from `setup`, each filter simulated in the
    /// coordinates its exact error was resolved in (`forms`, from `exact_errors`).
    pub fn scenario<'s>(
        &'s self,
        setup: &'s Setup,
        index: usize,
        forms: &'s [Option<ErrorForm>],
        stacked: &'s [Option<Stacked>],
    ) -> montecarlo::Scenario<'s> {
        montecarlo::Scenario {
            plant: &self.exp.plant,
            ops: &self.ops,
            filters: &self.reals,
            sampler: &setup.sampler,
            seed: self.exp.seed,
            index,
            ratios: self.ratios.as_ref(),
            nees: &self.nees,
            nis: &self.nis,
            forms,
            stacked,
        }
    }

    /// Each filter's steps stacked for the Monte Carlo ([`Stacked`]) in the coordinates of `forms`.
    pub fn stacked(&self, forms: &[Option<ErrorForm>]) -> Vec<Option<Stacked>> {
        (self.reals.iter().zip(forms).zip(&self.nis))
            .map(|((r, f), nis)| Stacked::new(&self.exp.plant, r, f.as_ref(), *nis))
            .collect()
    }
}

/// A scenario ready for its Monte Carlo: its setup and every filter's exact error (docs/math.md
/// §4), with the coordinates each filter is simulated in.
pub struct Prepared {
    pub index: usize,
    pub setup: Setup,
    pub exact: Vec<ExactError>,
    pub forms: Vec<Option<ErrorForm>>,
    pub stacked: Vec<Option<Stacked>>,
}

impl Prepared {
    /// The scenario as the Monte Carlo engine runs it.
    pub fn scenario<'s>(&'s self, engine: &'s Engine) -> crate::sim::montecarlo::Scenario<'s> {
        engine.scenario(&self.setup, self.index, &self.forms, &self.stacked)
    }
}

/// The exact error of filter `r` in a scenario (docs/math.md §4): with the scenario's covariance and
/// deterministic disturbance, or the first two moments of its joint input (seed 002).
fn exact_of(p: &Plant, r: &Realization, setup: &Setup) -> Result<ExactError> {
    match &setup.joint_moments {
        None => Ok(exact::error_with_mean(p, r, &setup.covariances, setup.w_mean.as_ref())),
        Some((mean, jcov)) => exact::error_joint(p, r, mean, jcov),
    }
}

/// [`exact_of`] for pairs that differ only in their outputs (one state recursion), each refused
/// for `filter` if double precision cannot resolve it, the first in order reported.
fn trusted_exact_of(pairs: &[(&Plant, &Realization)], setup: &Setup, filter: &str) -> Result<Vec<ExactError>> {
    let errors = match &setup.joint_moments {
        None => exact::errors_with_mean(pairs, &setup.covariances, setup.w_mean.as_ref()),
        Some((mean, jcov)) => exact::errors_joint(pairs, mean, jcov)?,
    };
    errors.into_iter().map(|e| e.trusted(filter)).collect()
}

/// Every filter's exact error in a scenario, each refused if double precision cannot resolve it,
/// and the error forms the Monte Carlo simulates in: every filter's where all have one and the
/// engine may go without the plant ([`Engine::plant_free`]), else those of the filters resolved
/// only in error coordinates.
pub(crate) fn exact_errors(engine: &Engine, setup: &Setup) -> Result<(Vec<ExactError>, Vec<Option<ErrorForm>>)> {
    let exp = engine.exp;
    // One filter per task: the recursions are independent, and between two scenarios' Monte Carlo
    // they would otherwise leave every core but one idle. The first failure in file order is the
    // one reported.
    let each = engine
        .reals
        .par_iter()
        .zip(&exp.filters)
        .map(|(r, f)| {
            let e = exact_of(&exp.plant, r, setup)?.trusted(&f.name)?;
            let wanted = engine.plant_free || e.coordinates == exact::Coordinates::Error;
            Ok((e, wanted.then(|| exact::error_form(&exp.plant, r).ok()).flatten()))
        })
        .collect::<Vec<Result<_>>>();
    let (errors, forms): (Vec<ExactError>, Vec<_>) = each.into_iter().collect::<Result<Vec<_>>>()?.into_iter().unzip();
    if engine.plant_free && forms.iter().all(Option::is_some) {
        return Ok((errors, forms));
    }
    let needed = |(f, e): (Option<ErrorForm>, &ExactError)| f.filter(|_| e.coordinates == exact::Coordinates::Error);
    let forms = forms.into_iter().zip(&errors).map(needed).collect();
    Ok((errors, forms))
}

/// Where a run's Monte Carlo statistics come from, chosen once by the command.
pub enum MonteCarlo {
    /// Every block, simulated here; a progress bar per scenario when `progress`.
    /// Side by side with the other variants' bars under one `MultiProgress`, if shown.
    Run { progress: Option<indicatif::MultiProgress> },
    /// Every block, from a merge's shards (`filterbench merge`): per scenario every shard's tree
    /// nodes in block order and the per-trial J in trial order. The designs made here must have
    /// `fingerprint`, those the shards ran.
    Merged { fingerprint: String, partials: Vec<Partial> },
}

/// Refuses a merge whose shards ran other designs than those made here.
fn same_designs(expected: &str, ours: &str) -> Result<()> {
    if ours != expected {
        return Err(Error::invalid(
            "merge",
            format!("the shards' designs (fingerprint {expected}) differ from this machine's ({ours})"),
        ));
    }
    Ok(())
}

/// The Monte Carlo statistics of [`MonteCarlo`], scenario by scenario.
pub(super) enum Source {
    /// The bar, and the variant's name in front of its messages.
    Run(ProgressBar, String),
    Merged(std::vec::IntoIter<Partial>),
}

impl Source {
    /// The source `mc`; a merge's shards are refused unless they ran the designs of `ours`.
    pub(super) fn new(exp: &Experiment, mc: MonteCarlo, ours: impl FnOnce() -> String) -> Result<Self> {
        Ok(match mc {
            MonteCarlo::Run { progress } => {
                let bar = progress_bar(exp.trials as u64, progress.is_some());
                let bar = match progress {
                    Some(bars) => bars.add(bar),
                    None => bar,
                };
                let variant = exp.variant.as_ref().map_or(String::new(), |v| format!("[{v}] "));
                bar.set_message(format!("{variant}scenarios being set up"));
                Source::Run(bar, variant)
            }
            MonteCarlo::Merged { fingerprint, partials } => {
                same_designs(&fingerprint, &ours())?;
                Source::Merged(partials.into_iter())
            }
        })
    }

    /// Shows scenario `index` of `count` on the progress bar.
    pub(super) fn start(&self, index: usize, count: usize, name: &str) {
        if let Source::Run(bar, variant) = self {
            bar.reset();
            bar.set_message(format!("{variant}scenario {}/{count} {name}", index + 1));
        }
    }

    /// Every block's tree nodes and per-trial J of scenario `sc`: simulated over every block, or
    /// the merge's next scenario checked against it.
    fn statistics(&mut self, sc: &montecarlo::Scenario, exp: &Experiment) -> Result<Partial> {
        match self {
            Source::Run(bar, _) => {
                let trials = exp.trials as u64;
                Ok(montecarlo::run_range(sc, trials, 0..montecarlo::blocks(trials), exp.per_trial, &|n| bar.inc(n)))
            }
            Source::Merged(given) => check_given(sc, given.next().expect("one partial per scenario")),
        }
    }

    pub(super) fn finish(&self) {
        if let Source::Run(bar, _) = self {
            bar.finish_and_clear();
        }
    }
}

/// Scenario `p` evaluated: its Monte Carlo statistics from `source` on the input its exact errors
/// were computed for, sample trajectories with the noise-free output they scatter around, the exact
/// NEES (seed 001 §3) and the input's power and anisotropy.
pub(super) fn outcome(engine: &Engine, p: Prepared, source: &mut Source) -> Result<ScenarioOutcome> {
    let exp = engine.exp;
    let s = &exp.scenarios[p.index];
    let sc = p.scenario(engine);
    let t = Instant::now();
    let part = source.statistics(&sc, exp)?;
    let mc = montecarlo::reduce(&sc, part.nodes);
    let mc_seconds = t.elapsed().as_secs_f64();
    let trajectories = montecarlo::trajectories(&sc, exp.sample_trajectories as u64);
    let Prepared { setup, exact, .. } = p;
    // NEES and NIS from the same exact recursions, each projected output checked like the error
    // itself.
    let square = |name: &str, n: &Normalized, p: &Plant, r: &Realization| -> Result<nees::PerStep> {
        let trusted = |pairs: &[(&Plant, &Realization)]| trusted_exact_of(pairs, &setup, name);
        Ok(nees::exact(&n.weights, &nees::error_moments(p, r, &trusted)?))
    };
    let squares = engine
        .filters
        .iter()
        .zip(&exp.filters)
        .map(|(f, spec)| {
            let real = &f.design.realization;
            let nees = f.nees.as_ref().map(|n| square(&spec.name, n, &exp.plant, real)).transpose()?;
            let innovation = f.nis.as_ref().and_then(|n| Some((n, nees::innovation_system(&exp.plant, real)?)));
            // Where double precision cannot resolve E[ν νᵀ] in this scenario, nis_exact is null (the
            // Monte Carlo NIS stands on its own); the output error's exact value is never dropped.
            let nis = innovation.and_then(|(n, (p, r))| square(&spec.name, n, &p, &r).ok());
            Ok((nees, nis))
        })
        .collect::<Result<Vec<_>>>()?;
    let (input_power, input_anisotropy) =
        input_statistics(exp, &setup.covariances, &s.shape, setup.w_mean.as_ref(), setup.joint.as_ref());
    let filters = engine
        .filters
        .iter()
        .zip(squares)
        .enumerate()
        .map(|(f, (d, (nees_exact, nis_exact)))| {
            FilterOutcome::new(
                d,
                Evaluated {
                    plant: &exp.plant,
                    input_power,
                    input_anisotropy,
                    disturbed: setup.w_mean.is_some(),
                    holds: setup.holds[f],
                    exact: &exact[f],
                    mc: &mc.filters[f],
                    nees_exact,
                    nis_exact,
                },
            )
        })
        .collect();
    Ok(ScenarioOutcome {
        name: s.name.clone(),
        covariance_label: setup.covariance_label,
        shape_label: s.shape.label(),
        covariances: setup.covariances,
        disturbance_label: setup.disturbance_label,
        disturbance: setup.w_mean,
        exact,
        input_power,
        input_anisotropy,
        mc,
        mc_seconds,
        trajectories,
        noise_free: crate::analysis::noise_free::noise_free_output(&exp.plant),
        per_trial: part.per_trial,
        filters,
    })
}

/// A merge's nodes checked against the scenario: every accumulator of the right size (the
/// per-trial rows are counted where the shards are read, [`super::shards`]).
fn check_given(sc: &montecarlo::Scenario, p: Partial) -> Result<Partial> {
    let want = montecarlo::McStats::new(sc);
    if let Some(n) = p.nodes.iter().find(|n| !n.stats.same_shape(&want)) {
        let b = n.blocks();
        return Err(Error::invalid(
            "merge",
            format!(
                "scenario {}: the accumulators of blocks {}..{} do not fit this experiment",
                sc.index, b.start, b.end
            ),
        ));
    }
    Ok(p)
}

/// One bar per scenario, counting the trials the user asked for (not trials × scenarios).
pub(crate) fn progress_bar(trials: u64, show: bool) -> ProgressBar {
    let bar = if show {
        ProgressBar::new(trials)
    } else {
        ProgressBar::with_draw_target(Some(trials), ProgressDrawTarget::hidden())
    };
    bar.set_style(
        ProgressStyle::with_template("{msg} [{wide_bar}] {human_pos}/{human_len} trials, {rate}/s, eta {eta}")
            .expect("valid template")
            .with_key("rate", |st: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = w.write_str(&three_figures(st.per_sec()));
            })
            .progress_chars("=> "),
    );
    bar
}

/// The per-trial ratio checks of the filters that promise one (seed 002), weighted by the nominal
/// covariances of x0 and w (pseudo-inverses, so a singular block simply carries no weight).
fn ratio_check<'a>(exp: &Experiment, filters: &'a [DesignedFilter]) -> Option<RatioCheck<'a>> {
    let bounds: Vec<_> = filters.iter().map(|f| f.design.per_trial.as_ref()).collect();
    bounds.iter().any(Option::is_some).then(|| RatioCheck {
        x0_weight: crate::numerics::linalg::psd_pinv(exp.nominal.x0()),
        w_weight: crate::numerics::linalg::psd_pinv(&exp.nominal.w()),
        bounds,
    })
}

/// E|W|² and the Gaussian anisotropy of W = col(w\[0..N]) for a scenario's input (docs/math.md §5).
///
/// The anisotropy is exact for W = L u with L square and u i.i.d. of the scenario's shape: the
/// Gaussian formula plus lw times the shape's negentropy h_G − h(u) (seed 003 §2 with
/// h(Lu) = Σ h(u_i) + ln|det L|; [`Shape::entropy`]); infinite for a discrete shape (W has no
/// density). Where W mixes the x0 components into it (a random full covariance) the
/// non-Gaussian value has no closed form and is left out; the ellipsoid inputs keep the Gaussian
/// value of their covariance.
fn input_statistics(
    exp: &Experiment,
    cov: &Covariances,
    shape: &Shape,
    w_mean: Option<&Mat>,
    joint: Option<&JointInput>,
) -> (f64, Option<f64>) {
    let p = &exp.plant;
    let steps = p.steps();
    // A(W) − A_Gaussian(W) for W = L u, lw components; None when it has no closed form here.
    let correction = |lw: usize| -> Option<f64> {
        match (shape, shape.entropy()) {
            (Shape::Gaussian, _) => Some(0.0),
            (_, Some(h)) => Some(lw as f64 * (Shape::Gaussian.entropy().expect("a density") - h)),
            (_, None) => Some(f64::INFINITY),
        }
    };
    match joint {
        None => {
            let w = cov.w();
            let power = steps as f64 * w.trace() + w_mean.map_or(0.0, |m| m.norm_squared());
            let a = steps as f64 * crate::analysis::anisotropy::gaussian_anisotropy(&w);
            let a = (a.is_finite() && w_mean.is_none()).then_some(a);
            (power, a.and_then(|a| Some(a + correction(steps * p.nw())?)))
        }
        Some(j) => {
            let (mean, c) = j.moments();
            let n = p.nx();
            let d = c.nrows() - n;
            let cw = c.view((n, n), (d, d)).into_owned();
            let power = cw.trace() + mean.rows(n, d).norm_squared();
            let full = d == steps * p.nw() && mean.rows(n, d).norm() == 0.0;
            let a = crate::analysis::anisotropy::gaussian_anisotropy(&cw);
            let a = (full && a.is_finite()).then_some(a);
            let a = match j {
                JointInput::Correlated { factor } if *shape != Shape::Gaussian => {
                    let square = factor.view((n, 0), (d, n)).amax() == 0.0;
                    a.and_then(|a| Some(a + correction(d).filter(|_| square)?))
                }
                _ => a,
            };
            (power, a)
        }
    }
}

/// A rate with three significant figures and a k/M/G suffix (91.3k, not 91,332.6321).
pub fn three_figures(x: f64) -> String {
    if !x.is_finite() {
        return "—".into();
    }
    let (v, suffix) = match x {
        _ if x >= 1e9 => (x / 1e9, "G"),
        _ if x >= 1e6 => (x / 1e6, "M"),
        _ if x >= 1e3 => (x / 1e3, "k"),
        _ => (x, ""),
    };
    let prec = if v >= 100.0 {
        0
    } else if v >= 10.0 {
        1
    } else {
        2
    };
    format!("{v:.prec$}{suffix}")
}
