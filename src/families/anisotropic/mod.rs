//! The anisotropic suboptimal filters of seed 003 §4 (docs/math.md §5). The structures of §4.2 are in
//! [`structure`]; Theorem 1's LMIs, shared with the analysis check, in
//! [`crate::analysis::theorem1`]. The bound is derived here for the dropout predictor (4.31)
//!
//! ```text
//! x̂[k+1] = W(k) x̂[k] + H(k) (y[k] − p Cy x̂[k]) + r[k],   ẑ[k] = Cz x̂[k],   x̂[0] = E x0,
//! ```
//!
//! with the error system (4.32)–(4.33) on X = (x, e), e = x − x̂:
//!
//! ```text
//! A0 = [[A, 0], [A − W, W − pHCy]],  A1 = [[0, 0], [−HCy, 0]],  B = [B; B − HDy],  C = [0, Cz],  D = Dz.
//! ```
//!
//! **The bound.** For q > 0 and R(N+1) = 0, a solution of the Riccati inequality
//! R ⪰ A0ᵀR'A0 + p(1−p) A1ᵀR'A1 + qCᵀC + (A0ᵀR'B + qCᵀD) S⁻¹ (·)ᵀ, S = I − qDᵀD − BᵀR'B ≻ 0, gives
//! I − qΛ ⪰ TᵀST with T unit lower triangular (complete the square in E\[XᵀRX] and use Jensen on the
//! mean of X), so ln det(I − qΛ) ≥ Σ ln det S(k); and ln det(I − qΛ) ≥ 2a + lw ln(1 − qγ²) implies
//! |||F|||_a ≤ γ (the Gibbs variational inequality at power 1/(1 − qγ²)). This is (4.21)–(4.24).
//! With η = 1/q, P = ηR and Ψ(k) ⪯ ηS(k) it becomes the LMIs (4.34)–(4.37) (Schur complements;
//! the printed `P(k+1)A1ᵀ` is P(k+1)A1) and, with lw = mw(N+1), the determinant condition in the
//! convex form of docs/math.md §5:  η − γ² ≤ e^{−2a/lw} (∏_k det Ψ(k))^{1/lw}.
//!
//! **The change of variables.** P(k) = diag(P1(k), P2(k)) block diagonal makes (4.39)–(4.41) exact:
//! P(k+1)A0 = [[P1'A, 0], [P2'A − Q2, Q2 − pY2Cy]], P(k+1)A1 = [[0, 0], [−Y2Cy, 0]],
//! P(k+1)B = [P1'B; P2'B − Y2Dy] are linear in (P1, P2, Q2 = P2(k+1)W(k), Y2 = P2(k+1)H(k)), and
//! W = P2⁻¹Q2, H = P2⁻¹Y2 are recovered exactly (P2 ⪰ CzᵀCz ≻ 0 from the LMI at each step when Cz
//! has full column rank). A full P would leave products P12·W that no linear substitution removes.
//!
//! The H2-suboptimal filter is a = 0 and the H∞-suboptimal one a → ∞, where the determinant
//! condition forces η = γ² and drops out: minimize η subject to (4.34)–(4.35) alone. At a = 0 the
//! LMIs' infimum lies at η → ∞, and the program solved is that limit, attained at finite matrices:
//! P(k) ⪰ E\[𝒜ᵀP'𝒜 + 𝒞ᵀ𝒞], N(k) ⪰ E\[ℬᵀP'ℬ + 𝒟ᵀ𝒟], minimize Σₖ tr N(k)/lw
//! ([`crate::analysis::theorem1`]'s `Conditions::h2_limit`).

use serde::Deserialize;

use crate::analysis::theorem1;
use crate::error::{Error, Result};
use crate::filter::design::{Design, DesignInput};
use crate::filter::realization::Realization;
use crate::model::plant::Plant;
use crate::numerics::accuracy;
use crate::numerics::linalg::Mat;
use crate::numerics::solve::conic::{Failure, Solver, Tuning};

pub mod structure;

pub use crate::analysis::theorem1::Level;
pub use structure::{Structure, Synthesis, realization};

#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
enum LevelFile {
    Value(f64),
    Name(String),
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// Total anisotropy level a of the design (0: H2-suboptimal; "inf": H∞-suboptimal).
    anisotropy: LevelFile,
    /// Which filter of §4.2 ([`Structure`]); `predictor` (§4.2.3, §4.2.1 with dropouts) by default.
    #[serde(default = "default_structure")]
    structure: Structure,
    /// The SDP's solver: `clarabel` (the default, every shipped design) or `own`, the project's
    /// interior-point method (`numerics::solve::interior`), clarabel's attempts after it if it fails.
    #[serde(default)]
    solver: Solver,
}

impl Params {
    /// The design's level: a ≥ 0 finite, or ∞ for "inf".
    fn level(&self) -> std::result::Result<Level, String> {
        match &self.anisotropy {
            LevelFile::Value(a) if *a >= 0.0 && a.is_finite() => Ok(Level::Anisotropy(*a)),
            LevelFile::Name(s) if s == "inf" => Ok(Level::Hinf),
            LevelFile::Value(a) => Err(format!("must be finite and ≥ 0, or \"inf\"; got {a}")),
            LevelFile::Name(s) => Err(format!("must be a number ≥ 0 or \"inf\"; got \"{s}\"")),
        }
    }
}

fn default_structure() -> Structure {
    Structure::Predictor
}

/// The family's entry: `family = "anisotropic"`.
pub struct Anisotropic;

impl super::family::Family for Anisotropic {
    const NAME: &'static str = "anisotropic";
    type Params = Params;

    /// Seed 003's noise is independent over time: dropouts and multiplicative factors, not Markov
    /// modes. A structure that uses y(k) through G needs the filtering pattern.
    fn supports(p: &Params) -> super::family::Supports {
        super::family::Supports {
            patterns: if p.structure.filtering() { super::family::FILTERING } else { super::family::ANY_PATTERN },
            markov_modes: false,
            narrowed_by: p.structure.filtering().then(|| ("structure", p.structure.name())),
            ..super::family::Supports::ALL
        }
    }

    fn check(p: &Params) -> std::result::Result<(), (&'static str, String)> {
        p.level().map(|_| ()).map_err(|why| ("anisotropy", why))
    }

    /// Λ, the design's and the checks' operator over the whole horizon, is dense.
    fn footprint(_: &Params, plant: super::family::PlantSize) -> super::family::Footprint {
        super::family::Footprint { state: plant.nx, gain_sets: 1, dense_horizon: true }
    }

    fn design(input: &DesignInput, p: &Params) -> Result<Design> {
        let level = p.level().map_err(|why| Error::invalid(input.key("anisotropy"), why))?;
        check_setting(input, p.structure)?;
        let checked = synthesize_checked_with(input.plant, p.structure, level, p.solver).map_err(|e| Error::design(input.name, e))?;
        let syn = &checked.synthesis;
        let realization = realization(input.plant, syn);
        let mut diagnostics = serde_json::Map::new();
        diagnostics.insert("structure".into(), p.structure.name().into());
        diagnostics.insert("exact_norm_sq".into(), checked.norm_sq.into());
        diagnostics.insert("theorem1_gamma_sq".into(), checked.theorem1.gamma_sq.into());
        diagnostics.insert("theorem1_q".into(), checked.theorem1.q.into());
        diagnostics.insert("theorem1_seconds".into(), checked.theorem1.seconds.into());
        diagnostics.insert("sdp_attempt".into(), checked.attempt.into());
        diagnostics.insert("sdp_solver".into(), checked.solver.name().into());
        diagnostics.insert("gamma_sq".into(), syn.gamma_sq.into());
        diagnostics.insert("gamma_sq_objective_error".into(), syn.objective_error.into());
        diagnostics.insert("theorem1_error".into(), checked.theorem1.error.into());
        diagnostics.insert("certified_gamma_sq".into(), checked.certified_sq.into());
        // η = ∞ in the H2 limit program (a = 0), written as the level's "inf" is.
        diagnostics.insert("eta".into(), if syn.eta.is_finite() { syn.eta.into() } else { "inf".into() });
        diagnostics.insert(
            "design_anisotropy".into(),
            match level {
                Level::Anisotropy(a) => a.into(),
                Level::Hinf => "inf".into(),
            },
        );
        diagnostics.insert("sdp_variables".into(), syn.variables.into());
        diagnostics.insert("sdp_rows".into(), syn.rows.into());
        diagnostics.insert("sdp_cones".into(), serde_json::to_value(&syn.cones).unwrap_or_default());
        diagnostics.insert("sdp_iterations".into(), syn.iterations.into());
        diagnostics.insert("sdp_seconds".into(), syn.solve_seconds.into());
        Ok(Design {
            gain_bound: Some(crate::filter::design::GainBound {
                gamma_sq: checked.certified_sq,
                design_gamma_sq: syn.gamma_sq,
                anisotropy: level.value(),
                theorem1_sq: checked.theorem1.gamma_sq,
            }),
            ..Design::new(realization, diagnostics)
        })
    }
}

/// The setting of seed 003 §4 beyond the plant's features ([`Anisotropic::supports`]): x(0) known
/// (zero covariance, (4.7)), every step counted and measured, and the static filter ẑ = G y
/// (§4.2.2) cannot see x(0)'s mean or the known input.
fn check_setting(input: &DesignInput, structure: Structure) -> Result<()> {
    let name = input.name;
    let p = input.plant;
    let problem: Option<String> = if input.nominal.x0().amax() != 0.0 {
        Some("the anisotropic theory takes x(0) known (seed 003 (4.7)): set nominal.x0 to zero".into())
    } else if p.sum_from != 0 || p.first_measurement != 0 {
        Some("the anisotropic design (seed 003 §4) needs sum_from = 0 and first_measurement = 0".into())
    } else if structure == Structure::Static && (p.x0_mean.amax() != 0.0 || !p.known_input.is_empty()) {
        Some("the static filter ẑ = G y (§4.2.2, x̂ ≡ 0) cannot follow x(0)'s mean or the known input: remove plant.x0_mean and plant.known_input, or use another structure".into())
    } else {
        None
    };
    match problem {
        Some(m) => Err(Error::design(name, m)),
        None => Ok(()),
    }
}

/// The predictor (§4.2.1/§4.2.3) with clarabel's default settings. The error says whether clarabel
/// certified infeasibility or failed numerically.
pub fn synthesize(plant: &Plant, level: Level) -> std::result::Result<Synthesis, String> {
    structure::synthesize_tuned(plant, Structure::Predictor, level, &Tuning::default()).map_err(|f| failure_message(&f))
}

/// What a failed synthesis tells the user: infeasibility and numerical failure are different
/// problems with different remedies.
fn failure_message(f: &Failure) -> String {
    if f.infeasible {
        format!(
            "clarabel reports the anisotropic LMIs (4.42)–(4.43) infeasible ({f}); on a finite horizon they have \
             a solution in exact arithmetic, so the certificate says the bound needs matrices beyond the solver's \
             range: the predictor (4.31) does not see the dropouts, so on an unstable A its error grows like the \
             state over the horizon; shorten the horizon, raise the arrival probability or use a filter that sees \
             the dropouts"
        )
    } else {
        format!(
            "the anisotropic SDP (4.42)–(4.43) could not be solved accurately ({f}): a numerical failure, not \
             infeasibility (the finite-horizon LMIs always have a solution for η large enough); rescale the \
             plant's matrices towards unit size or change the horizon"
        )
    }
}

/// A design that passed its checks: the synthesis, its exact norm² and that figure's rounding
/// error, what Theorem 1 certifies for it with a full P, the certified bound, and the attempt that
/// passed.
pub struct Checked {
    pub synthesis: Synthesis,
    pub norm_sq: f64,
    pub norm_error: f64,
    pub theorem1: theorem1::Analysis,
    /// The guaranteed γ²: the solver's γ² where it is above Theorem 1's certified bound for the
    /// returned filter (then it is one too), the certified bound where the solver's value is below
    /// it (an interior-point value can sit under the optimum it approximates).
    pub certified_sq: f64,
    pub attempt: usize,
    /// The method whose design passed.
    pub solver: Solver,
}

/// Designs `structure` at `level` and checks the design three ways: its exact a-anisotropic norm
/// (from Λ, or Lemma 1 when lw is large; not from the solver) must not exceed γ, and Theorem 1's
/// analysis LMIs (4.25)–(4.29) with the filter fixed and a full P(k) must certify a γ_T1 with
/// exact ≤ γ_T1 ≤ γ (the design's own P is one of their solutions), each within the errors its two
/// routes state (the rounding bounds of the exact routes, clarabel's `objective_error` for γ). The first attempt uses clarabel's default settings (shipped designs are unchanged);
/// after a numerical failure or a design that fails a check, retries with [`Tuning::robust`], then
/// both settings in balanced state coordinates (`synthesize_balanced`).
pub fn synthesize_checked(plant: &Plant, structure: Structure, level: Level) -> std::result::Result<Checked, String> {
    synthesize_checked_with(plant, structure, level, Solver::Clarabel)
}

/// [`synthesize_checked`] with the solver of the filter's `solver` key: [`Solver::Own`] is tried
/// first and checked the same three ways, then clarabel's attempts follow if it fails (the own
/// method has no infeasibility certificate, so its failure is never reported as infeasibility).
pub fn synthesize_checked_with(
    plant: &Plant,
    structure: Structure,
    level: Level,
    solver: Solver,
) -> std::result::Result<Checked, String> {
    let mut last = String::new();
    let clarabel =
        [(Tuning::default(), false), (Tuning::robust(), false), (Tuning::default(), true), (Tuning::robust(), true)];
    let attempts: Vec<(Tuning, bool)> = match solver {
        Solver::Clarabel => clarabel.to_vec(),
        Solver::Own => std::iter::once((Tuning::own(), false)).chain(clarabel).collect(),
    };
    let describe = match level {
        Level::Anisotropy(a) => format!("a-anisotropic (a = {a})"),
        Level::Hinf => "H∞".to_string(),
    };
    for (attempt, (tuning, balance)) in attempts.iter().enumerate() {
        let solved = if *balance {
            synthesize_balanced(plant, structure, level, tuning)
        } else {
            structure::synthesize_tuned(plant, structure, level, tuning)
        };
        let syn = match solved {
            Ok(syn) => syn,
            Err(f) if f.infeasible => return Err(failure_message(&f)),
            Err(f) => {
                last = failure_message(&f);
                continue;
            }
        };
        let real = realization(plant, &syn);
        // The exact norm and Theorem 1's analysis are independent checks of the same filter: side by
        // side where a core is free (each alone is the same bits).
        let (exact, t1) =
            rayon::join(|| exact_norm_sq_with_error(plant, &real, level), || theorem1::analyze(plant, &real, level));
        let (norm_sq, norm_error) = exact.map_err(|e| e.to_string())?;
        let solver = match (tuning.solver, syn.almost) {
            (Solver::Clarabel, true) => "clarabel AlmostSolved",
            (Solver::Clarabel, false) => "clarabel Solved",
            (Solver::Own, true) => "own method, stalled near its tolerance",
            (Solver::Own, false) => "own method, solved",
        };
        if !accuracy::ordered(norm_sq, syn.gamma_sq, norm_error + syn.objective_error) {
            last = format!(
                "the SDP returned a design whose exact {describe} norm {:.9e} exceeds its bound γ = {:.9e} by {:.1e} \
                 relative ({solver}): a numerical failure, not infeasibility; rescale the plant's matrices \
                 towards unit size or change the horizon",
                norm_sq.sqrt(),
                syn.gamma_sq.sqrt(),
                norm_sq.sqrt() / syn.gamma_sq.sqrt() - 1.0,
            );
            continue;
        }
        let t1 = match t1 {
            Ok(t1) => t1,
            Err(e) => {
                last = format!(
                    "the design could not be checked by Theorem 1's analysis LMIs ({e}): a numerical failure, not \
                     infeasibility; rescale the plant's matrices towards unit size or change the horizon"
                );
                continue;
            }
        };
        // Two exact routes, then an exact route against the solver's objective: each pair within
        // the errors its routes state (numerics::accuracy).
        if accuracy::ordered(norm_sq, t1.gamma_sq, norm_error + t1.error)
            && accuracy::ordered(t1.gamma_sq, syn.gamma_sq, t1.error + syn.objective_error)
        {
            let certified_sq = syn.gamma_sq.max(t1.certified());
            return Ok(Checked {
                synthesis: syn,
                norm_sq,
                norm_error,
                theorem1: t1,
                certified_sq,
                attempt: attempt + 1,
                solver: tuning.solver,
            });
        }
        last = format!(
            "the three routes to the design's {describe} norm disagree: exact {:.9e}, Theorem 1 with the filter fixed \
             {:.9e}, the synthesis's γ {:.9e} ({solver}); they must be ordered exact ≤ Theorem 1 ≤ γ: a \
             numerical failure; rescale the plant's matrices towards unit size or change the horizon",
            norm_sq.sqrt(),
            t1.gamma_sq.sqrt(),
            syn.gamma_sq.sqrt(),
        );
    }
    Err(last)
}

/// [`structure::synthesize_tuned`] in balanced state coordinates x̃ = T x, T = diag(t_i) with
/// t_i = 1/√σ_i, σ_i the time-averaged open-loop variance of x_i under unit white noise
/// (Σ(k+1) = A(k)ΣA(k)ᵀ + B(k)B(k)ᵀ from 0). On a chain of integrators the states grow like k^{1/2},
/// k^{3/2}, …, and the blocks of the LMIs (hence P1, P2) span as many orders of magnitude as the
/// horizon makes them; in balanced coordinates they are comparable. Every matrix that multiplies
/// or produces x is transformed, the factors' too; the filter is mapped back: W = T⁻¹W̃T,
/// H = T⁻¹H̃, F = F̃T (z and w are unchanged, so γ is too).
fn synthesize_balanced(
    plant: &Plant,
    structure: Structure,
    level: Level,
    tuning: &Tuning,
) -> std::result::Result<Synthesis, Failure> {
    let n = plant.nx();
    let mut sigma = Mat::zeros(n, n);
    let mut avg = vec![0.0; n];
    for k in 0..plant.steps() {
        sigma = plant.a_at(k) * &sigma * plant.a_at(k).transpose() + plant.b_at(k) * plant.b_at(k).transpose();
        for (i, v) in avg.iter_mut().enumerate() {
            *v += sigma[(i, i)] / plant.steps() as f64;
        }
    }
    let t: Vec<f64> = avg.iter().map(|v| if *v > 0.0 && v.is_finite() { 1.0 / v.sqrt() } else { 1.0 }).collect();
    let tm = Mat::from_diagonal(&crate::numerics::linalg::Vector::from_vec(t.clone()));
    let ti = Mat::from_diagonal(&crate::numerics::linalg::Vector::from_iterator(n, t.iter().map(|v| 1.0 / v)));
    let mut scaled = plant.clone();
    let state = |m: &crate::model::plant::Steps| m.map(|a| &tm * a * &ti);
    let input = |m: &crate::model::plant::Steps| m.map(|b| &tm * b);
    let output = |m: &crate::model::plant::Steps| m.map(|c| c * &ti);
    scaled.a = state(&plant.a);
    scaled.b = input(&plant.b);
    scaled.c = output(&plant.c);
    scaled.cz = output(&plant.cz);
    scaled.x0_mean = &tm * &plant.x0_mean;
    for f in &mut scaled.factors {
        f.a = f.a.as_ref().map(state);
        f.b = f.b.as_ref().map(input);
        f.c = f.c.as_ref().map(output);
        f.cz = f.cz.as_ref().map(output);
    }
    let mut syn = structure::synthesize_tuned(&scaled, structure, level, tuning)?;
    for k in 0..syn.w.len() {
        syn.w[k] = &ti * &syn.w[k] * &tm;
        syn.h[k] = &ti * &syn.h[k];
        syn.f[k] = &syn.f[k] * &tm;
    }
    Ok(syn)
}

/// Above this many inputs lw = mw(N + 1) the exact norm comes from Lemma 1 (O(N n³)) instead of the
/// eigenvalues of the lw × lw matrix Λ (the two agree to 1e-13: tests/it/lemma1.rs).
pub(crate) const DENSE_NORM_MAX_INPUTS: usize = 1500;

/// [`exact_norm_sq`] and a bound on its rounding error: from the eigenvalues of Λ, each computed to
/// [`accuracy::eigenvalue_error`] (|||F|||²_a is a weighted mean of them, so it moves by no more to
/// first order); from Lemma 1's recursion, [`accuracy::recursion_error`].
pub(crate) fn exact_norm_sq_with_error(plant: &Plant, real: &Realization, level: Level) -> Result<(f64, f64)> {
    if plant.nw() * plant.steps() > DENSE_NORM_MAX_INPUTS {
        let value = exact_norm_sq(plant, real, level)?;
        return Ok((value, accuracy::recursion_error(plant.steps(), plant.nx() + real.ns(), value)));
    }
    // The dense route: Λ formed once, for the norm and its error bound.
    let gram = crate::analysis::anisotropy::error_gram(plant, real)?;
    let value = dense_norm_sq(&gram, level)?;
    Ok((value, accuracy::eigenvalue_error(&gram)))
}

/// |||F|||²_a from Λ's eigenvalues (seed 003 §2), a = ∞ giving λmax(Λ): the eigenvalues alone, the
/// worst input's covariance is not needed here.
fn dense_norm_sq(gram: &Mat, level: Level) -> Result<f64> {
    let values = crate::numerics::linalg::sym_eigenvalues(gram)?;
    Ok(match level {
        Level::Anisotropy(a) => {
            let mu: Vec<f64> = values.iter().map(|m| m.max(0.0)).collect();
            crate::analysis::anisotropy::anisotropic_norm_from_eigenvalues(&mu, a)?.value.powi(2)
        }
        Level::Hinf => values.into_iter().fold(0.0, f64::max),
    })
}

/// |||F|||²_a of a realization, a = ∞ giving ‖F‖∞² (seed 003 §2): the eigenvalues of Λ, or Lemma 1
/// above `DENSE_NORM_MAX_INPUTS`.
pub fn exact_norm_sq(plant: &Plant, real: &Realization, level: Level) -> Result<f64> {
    if plant.nw() * plant.steps() > DENSE_NORM_MAX_INPUTS {
        return Ok(crate::analysis::lemma1::anisotropic_norm_riccati(plant, real, level.value())?.value.powi(2));
    }
    dense_norm_sq(&crate::analysis::anisotropy::error_gram(plant, real)?, level)
}
