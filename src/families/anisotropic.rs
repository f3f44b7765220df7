//! The anisotropic suboptimal filter for measurement dropouts (seed 003 §4.2.1, SPEC §5): the
//! predictor (4.31)
//!
//!     x̂[k+1] = W(k) x̂[k] + H(k) (y[k] − p Cy x̂[k]) + r[k],   ẑ[k] = Cz x̂[k],   x̂[0] = E x0,
//!
//! with the error system (4.32)–(4.33) on X = (x, e), e = x − x̂:
//!
//!     A0 = [[A, 0], [A − W, W − pHCy]],  A1 = [[0, 0], [−HCy, 0]],  B = [B; B − HDy],  C = [0, Cz],  D = Dz.
//!
//! **The bound.** For q > 0 and R(N+1) = 0, a solution of the Riccati inequality
//! R ⪰ A0ᵀR'A0 + p(1−p) A1ᵀR'A1 + qCᵀC + (A0ᵀR'B + qCᵀD) S⁻¹ (·)ᵀ, S = I − qDᵀD − BᵀR'B ≻ 0, gives
//! I − qΛ ⪰ TᵀST with T unit lower triangular (complete the square in E[XᵀRX] and use Jensen on the
//! mean of X), so ln det(I − qΛ) ≥ Σ ln det S(k); and ln det(I − qΛ) ≥ 2a + lw ln(1 − qγ²) implies
//! |||F|||_a ≤ γ (the Gibbs variational inequality at power 1/(1 − qγ²)). This is (4.21)–(4.24).
//! With η = 1/q, P = ηR and Ψ(k) ⪯ ηS(k) it becomes the LMIs (4.34)–(4.37) (Schur complements;
//! the printed `P(k+1)A1ᵀ` is P(k+1)A1) and, with lw = mw(N+1), the determinant condition in the
//! convex form of SPEC §5:  η − γ² ≤ e^{−2a/lw} (∏_k det Ψ(k))^{1/lw}.
//!
//! **The change of variables.** P(k) = diag(P1(k), P2(k)) block diagonal makes (4.39)–(4.41) exact:
//! P(k+1)A0 = [[P1'A, 0], [P2'A − Q2, Q2 − pY2Cy]], P(k+1)A1 = [[0, 0], [−Y2Cy, 0]],
//! P(k+1)B = [P1'B; P2'B − Y2Dy] are linear in (P1, P2, Q2 = P2(k+1)W(k), Y2 = P2(k+1)H(k)), and
//! W = P2⁻¹Q2, H = P2⁻¹Y2 are recovered exactly (P2 ⪰ CzᵀCz ≻ 0 from the LMI at each step when Cz
//! has full column rank). A full P would leave products P12·W that no linear substitution removes.
//!
//! **The determinant condition in clarabel.** det Ψ ≥ ∏ Z_ii for every lower-triangular Z with
//! [[Ψ, Z], [Zᵀ, Diag Z]] ⪰ 0 (PSD cone), and the geometric mean of the lw diagonal entries is
//! bounded below by a binary tree of rotated second-order cones u² ≤ ab (power cones of exponent
//! ½), padded with copies of the bound itself to a power of two.
//!
//! The H2-suboptimal filter is a = 0 and the H∞-suboptimal one a → ∞, where the determinant
//! condition forces η = γ² and drops out: minimize η subject to (4.34)–(4.35) alone.

use serde::Deserialize;

use crate::filter::design::{Design, DesignInput};
use crate::error::{Error, Result};
use crate::numerics::linalg::Mat;
use crate::model::plant::Plant;
use crate::filter::realization::{Gains, Realization};
use crate::numerics::solve::affine::{AffMat, Vars};
use crate::numerics::solve::conic::{Conic, Failure, Tuning};
use crate::model::plant::Pattern;

/// The design level: a total anisotropy a ≥ 0 (over lw = mw(N+1)), or `"inf"` for H∞.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Level {
    Anisotropy(f64),
    Hinf,
}

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
}

/// The solved synthesis.
#[derive(Clone, Debug)]
pub struct Synthesis {
    pub w: Vec<Mat>,
    pub h: Vec<Mat>,
    /// The guaranteed bound γ² and η = 1/q.
    pub gamma_sq: f64,
    pub eta: f64,
    pub variables: usize,
    pub rows: usize,
    pub cones: std::collections::BTreeMap<String, usize>,
    pub iterations: u32,
    pub solve_seconds: f64,
    /// clarabel stopped at its reduced tolerances.
    pub almost: bool,
}

/// The family's entry: `family = "anisotropic"`.
pub struct Anisotropic;

impl super::Family for Anisotropic {
    const NAME: &'static str = "anisotropic";
    type Params = Params;

    fn design(input: &DesignInput, p: &Params) -> Result<Design> {
        let key = format!("filters.{}.anisotropy", input.name);
        let level = match p.anisotropy.clone() {
            LevelFile::Value(a) if a >= 0.0 && a.is_finite() => Level::Anisotropy(a),
            LevelFile::Name(s) if s == "inf" => Level::Hinf,
            LevelFile::Value(a) => return Err(Error::invalid(key, format!("must be finite and ≥ 0, or \"inf\"; got {a}"))),
            LevelFile::Name(s) => return Err(Error::invalid(key, format!("must be a number ≥ 0 or \"inf\"; got \"{s}\""))),
        };
        check_setting(input)?;
        let (syn, norm_sq, attempts) = synthesize_checked(input.plant, level).map_err(|e| Error::design(input.name, e))?;
        let realization = realization(input.plant, &syn);
        let mut diagnostics = serde_json::Map::new();
        diagnostics.insert("exact_norm_sq".into(), norm_sq.into());
        diagnostics.insert("clarabel_attempts".into(), attempts.into());
        diagnostics.insert("gamma_sq".into(), syn.gamma_sq.into());
        diagnostics.insert("eta".into(), syn.eta.into());
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
        diagnostics.insert("clarabel_iterations".into(), syn.iterations.into());
        diagnostics.insert("clarabel_seconds".into(), syn.solve_seconds.into());
        Ok(Design {
            gain_bound: Some(crate::filter::design::GainBound {
                gamma_sq: syn.gamma_sq,
                anisotropy: match level {
                    Level::Anisotropy(a) => a,
                    Level::Hinf => f64::INFINITY,
                },
            }),
            ..Design::new(realization, diagnostics)
        })
    }
}

/// The setting of seed 003 §4.2.1: prediction, x(0) known (zero covariance), every step counted and
/// measured, a constant measurement matrix.
fn check_setting(input: &DesignInput) -> Result<()> {
    let name = input.name;
    let p = input.plant;
    let problem = if input.pattern != Pattern::Prediction {
        Some("the anisotropic filter (4.31) is a predictor: set pattern = \"prediction\"")
    } else if input.nominal.x0().amax() != 0.0 {
        Some("the anisotropic theory takes x(0) known (seed 003 (4.7)): set nominal.x0 to zero")
    } else if p.sum_from != 0 || p.first_measurement != 0 || p.time_varying() {
        Some("the anisotropic design (§4.2.1) needs sum_from = 0, first_measurement = 0 and constant matrices (no plant.*_steps)")
    } else if !p.factors.is_empty() {
        Some("the anisotropic design is §4.2.1 (dropouts); multiplicative noise on the other matrices (§4.2.2–§4.2.5) is not built yet")
    } else if p.switches() && p.arrival().is_none() {
        Some("the anisotropic design covers measurement dropouts (plant.arrival), not general Markov modes")
    } else {
        None
    };
    match problem {
        Some(m) => Err(Error::design(name, m)),
        None => Ok(()),
    }
}

/// The predictor (4.31) as a realization: s[k+1] = (W − pHCy) s + H y + r, ẑ = Cz s.
pub fn realization(plant: &Plant, syn: &Synthesis) -> Realization {
    let p = plant.arrival_mean();
    let steps = (0..plant.steps())
        .map(|k| Gains::predicting(&syn.w[k] - p * &syn.h[k] * plant.c.at(k), syn.h[k].clone(), plant.cz_at(k)))
        .collect();
    Realization::state_estimator(plant.x0_mean.clone(), steps)
}

/// Solves the LMIs (4.42)–(4.43) with the terminal conditions and the convex determinant
/// condition (module docs), minimizing γ² at `level`, with clarabel's default settings. The error
/// says whether clarabel certified infeasibility or failed numerically.
pub fn synthesize(plant: &Plant, level: Level) -> std::result::Result<Synthesis, String> {
    synthesize_tuned(plant, level, &Tuning::default()).map_err(|f| failure_message(&f))
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

/// Designs at `level` and checks the design: its exact a-anisotropic norm (from Λ, not from the
/// solver) must not exceed γ by more than 1e-6 relative. The first attempt uses clarabel's default
/// settings (shipped designs are unchanged); after a numerical failure or a design that fails the
/// check, retries with [`Tuning::robust`], then both settings in balanced state coordinates
/// ([`synthesize_balanced`]). Returns the synthesis, its exact norm² and the attempt that passed.
pub fn synthesize_checked(plant: &Plant, level: Level) -> std::result::Result<(Synthesis, f64, usize), String> {
    let mut last = String::new();
    let attempts =
        [(Tuning::default(), false), (Tuning::robust(), false), (Tuning::default(), true), (Tuning::robust(), true)];
    for (attempt, (tuning, balance)) in attempts.iter().enumerate() {
        let solved =
            if *balance { synthesize_balanced(plant, level, tuning) } else { synthesize_tuned(plant, level, tuning) };
        let syn = match solved {
            Ok(syn) => syn,
            Err(f) if f.infeasible => return Err(failure_message(&f)),
            Err(f) => {
                last = failure_message(&f);
                continue;
            }
        };
        let real = realization(plant, &syn);
        let norm_sq = exact_norm_sq(plant, &real, level).map_err(|e| e.to_string())?;
        if norm_sq.sqrt() <= syn.gamma_sq.sqrt() * (1.0 + NORM_TOLERANCE) {
            return Ok((syn, norm_sq, attempt + 1));
        }
        last = format!(
            "the SDP returned a design whose exact {} norm {:.9e} exceeds its bound γ = {:.9e} by {:.1e} relative \
             (clarabel {}): a numerical failure, not infeasibility; rescale the plant's matrices towards unit size \
             or change the horizon",
            match level {
                Level::Anisotropy(a) => format!("a-anisotropic (a = {a})"),
                Level::Hinf => "H∞".to_string(),
            },
            norm_sq.sqrt(),
            syn.gamma_sq.sqrt(),
            norm_sq.sqrt() / syn.gamma_sq.sqrt() - 1.0,
            if syn.almost { "AlmostSolved" } else { "Solved" },
        );
    }
    Err(last)
}

/// P2(k) ⪰ P2_FLOOR · λmax(CzᵀCz) I when Cz is column-rank deficient (see [`synthesize_tuned`]).
pub const P2_FLOOR: f64 = 1e-6;

/// [`synthesize_tuned`] in balanced state coordinates x̃ = T x, T = diag(t_i) with t_i = 1/√σ_i,
/// σ_i the time-averaged open-loop variance of x_i under unit white noise (Σ' = AΣAᵀ + BBᵀ from 0).
/// On a chain of integrators the states grow like k^{1/2}, k^{3/2}, …, and the blocks of the LMIs
/// (hence P1, P2) span as many orders of magnitude as the horizon makes them; in balanced
/// coordinates they are comparable. The filter is mapped back: W = T⁻¹W̃T, H = T⁻¹H̃ (z and w are
/// unchanged, so γ is too).
fn synthesize_balanced(plant: &Plant, level: Level, tuning: &Tuning) -> std::result::Result<Synthesis, Failure> {
    let n = plant.nx();
    let bb = plant.b_at(0) * plant.b_at(0).transpose();
    let mut sigma = Mat::zeros(n, n);
    let mut avg = vec![0.0; n];
    for _ in 0..plant.steps() {
        sigma = plant.a_at(0) * &sigma * plant.a_at(0).transpose() + &bb;
        for (i, v) in avg.iter_mut().enumerate() {
            *v += sigma[(i, i)] / plant.steps() as f64;
        }
    }
    let t: Vec<f64> = avg.iter().map(|v| if *v > 0.0 && v.is_finite() { 1.0 / v.sqrt() } else { 1.0 }).collect();
    let tm = Mat::from_diagonal(&crate::numerics::linalg::Vector::from_vec(t.clone()));
    let ti = Mat::from_diagonal(&crate::numerics::linalg::Vector::from_iterator(n, t.iter().map(|v| 1.0 / v)));
    let mut scaled = plant.clone();
    scaled.a = plant.a.map(|a| &tm * a * &ti);
    scaled.b = plant.b.map(|b| &tm * b);
    scaled.c = plant.c.map(|c| c * &ti);
    scaled.cz = plant.cz.map(|cz| cz * &ti);
    if let Some(p) = plant.arrival() {
        scaled.set_arrival(p);
    }
    let mut syn = synthesize_tuned(&scaled, level, tuning)?;
    for (w, h) in syn.w.iter_mut().zip(syn.h.iter_mut()) {
        *w = &ti * &*w * &tm;
        *h = &ti * &*h;
    }
    Ok(syn)
}

/// A design's exact norm may exceed γ by this much (relative): solver tolerance, not a broken bound.
pub const NORM_TOLERANCE: f64 = 1e-6;

/// |||F|||²_a of a realization from Λ (seed 003 §2); λmax(Λ) = ‖F‖∞² for a = ∞.
pub fn exact_norm_sq(plant: &Plant, real: &Realization, level: Level) -> Result<f64> {
    Ok(match level {
        Level::Anisotropy(a) => crate::analysis::anisotropy::realization_norm(plant, real, a)?.0.value.powi(2),
        Level::Hinf => {
            crate::numerics::linalg::sym_eigen(&crate::analysis::anisotropy::error_gram(plant, real)?)?.0.into_iter().fold(0.0, f64::max)
        }
    })
}

/// [`synthesize`] with the given clarabel settings.
pub fn synthesize_tuned(plant: &Plant, level: Level, tuning: &Tuning) -> std::result::Result<Synthesis, Failure> {
    debug_assert!(!plant.time_varying(), "§4.2.1 is written for constant matrices: check_setting refuses the rest");
    let (nx, mw, pz, ny) = (plant.nx(), plant.nw(), plant.nz(), plant.ny());
    let (p, v) = (plant.arrival_mean(), plant.dropout_variance());
    let (a, b, cy, dy) = (plant.a_at(0), plant.b_at(0), plant.c.at(0), plant.d.at(0));
    let steps = plant.steps();
    let nn = plant.horizon;
    let mut vars = Vars::default();
    let eta = vars.scalar();
    let gsq = match level {
        Level::Anisotropy(_) => vars.scalar(),
        Level::Hinf => eta,
    };
    let p1: Vec<AffMat> = (0..steps).map(|_| vars.symmetric(nx)).collect();
    let p2: Vec<AffMat> = (0..steps).map(|_| vars.symmetric(nx)).collect();
    let q2: Vec<AffMat> = (0..nn).map(|_| vars.matrix(nx, nx, false)).collect();
    let y2: Vec<AffMat> = (0..nn).map(|_| vars.matrix(nx, ny, false)).collect();
    let aniso = matches!(level, Level::Anisotropy(_));
    let psi: Vec<AffMat> = if aniso { (0..steps).map(|_| vars.symmetric(mw)).collect() } else { Vec::new() };
    let zl: Vec<AffMat> = if aniso { (0..steps).map(|_| vars.matrix(mw, mw, true)).collect() } else { Vec::new() };

    let zero = |r: usize, c: usize| AffMat::zeros(r, c);
    let diag2 = |x: &AffMat, y: &AffMat| {
        AffMat::symmetric_blocks(&[nx, nx], &[vec![Some(x.clone())], vec![None, Some(y.clone())]])
    };
    let eta_i = |d: usize| AffMat::scalar_times(eta, Mat::identity(d, d));
    let c_err = AffMat::constant({
        let mut c = Mat::zeros(pz, 2 * nx);
        c.view_mut((0, nx), (pz, nx)).copy_from(plant.cz_at(0));
        c
    });
    let d_err = AffMat::constant(plant.dz_at(0).clone());
    let ident = |d: usize| AffMat::constant(Mat::identity(d, d));

    let mut conic = Conic::default();
    // W = P2⁻¹Q2 and H = P2⁻¹Y2 need P2 ≻ 0. With Cz of full column rank the LMIs give it
    // (P2(k) ⪰ CzᵀCz from the C row of every LMI); otherwise P2(k) ⪰ εI with
    // ε = P2_FLOOR · λmax(CzᵀCz) is added: a restriction of the feasible set, so the bound still
    // holds, and small enough to cost nothing measurable in γ.
    let floor = (plant.cz_at(0).rank(1e-12) < nx).then(|| {
        let czz = plant.cz_at(0).transpose() * plant.cz_at(0);
        P2_FLOOR * czz.symmetric_eigenvalues().max().max(f64::MIN_POSITIVE)
    });
    for k in 0..steps {
        if let Some(eps) = floor {
            p2[k].sub(&AffMat::constant(Mat::identity(nx, nx) * eps)).psd_into(&mut conic);
        }
        let pk = diag2(&p1[k], &p2[k]);
        if k < nn {
            let pn = diag2(&p1[k + 1], &p2[k + 1]);
            // P(k+1)A0, P(k+1)A1 and P(k+1)B after the change of variables (4.39)–(4.41).
            let top = AffMat::hstack(&p1[k + 1].rmul(a), &zero(nx, nx));
            let bottom = AffMat::hstack(&p2[k + 1].rmul(a).sub(&q2[k]), &q2[k].sub(&y2[k].rmul(cy).scale(p)));
            let pa0 = AffMat::vstack(&top, &bottom);
            let pa1 = AffMat::vstack(&zero(nx, 2 * nx), &AffMat::hstack(&y2[k].rmul(cy).scale(-1.0), &zero(nx, nx)));
            let pb = AffMat::vstack(&p1[k + 1].rmul(b), &p2[k + 1].rmul(b).sub(&y2[k].rmul(dy)));
            // (4.42): [[P, ·, ·, ·, ·], [0, ηI, ·, ·, ·], [P'A0, P'B, P', ·, ·], [√v P'A1, 0, 0, P', ·], [C, D, 0, 0, I]].
            let (sizes, lower) = if v > 0.0 {
                (
                    vec![2 * nx, mw, 2 * nx, 2 * nx, pz],
                    vec![
                        vec![Some(pk.clone())],
                        vec![None, Some(eta_i(mw))],
                        vec![Some(pa0), Some(pb.clone()), Some(pn.clone())],
                        vec![Some(pa1.scale(v.sqrt())), None, None, Some(pn.clone())],
                        vec![Some(c_err.clone()), Some(d_err.clone()), None, None, Some(ident(pz))],
                    ],
                )
            } else {
                (
                    vec![2 * nx, mw, 2 * nx, pz],
                    vec![
                        vec![Some(pk.clone())],
                        vec![None, Some(eta_i(mw))],
                        vec![Some(pa0), Some(pb.clone()), Some(pn.clone())],
                        vec![Some(c_err.clone()), Some(d_err.clone()), None, Some(ident(pz))],
                    ],
                )
            };
            AffMat::symmetric_blocks(&sizes, &lower).psd_into(&mut conic);
            if aniso {
                // (4.43): [[ηI − Ψ, ·, ·], [P'B, P', ·], [D, 0, I]].
                AffMat::symmetric_blocks(
                    &[mw, 2 * nx, pz],
                    &[
                        vec![Some(eta_i(mw).sub(&psi[k]))],
                        vec![Some(pb), Some(pn)],
                        vec![Some(d_err.clone()), None, Some(ident(pz))],
                    ],
                )
                .psd_into(&mut conic);
            }
        } else {
            // Terminal conditions (P(N+1) = 0): [[P(N), ·, ·], [0, ηI, ·], [C, D, I]] and [[ηI − Ψ(N), ·], [D, I]].
            AffMat::symmetric_blocks(
                &[2 * nx, mw, pz],
                &[
                    vec![Some(pk)],
                    vec![None, Some(eta_i(mw))],
                    vec![Some(c_err.clone()), Some(d_err.clone()), Some(ident(pz))],
                ],
            )
            .psd_into(&mut conic);
            if aniso {
                AffMat::symmetric_blocks(
                    &[mw, pz],
                    &[vec![Some(eta_i(mw).sub(&psi[k]))], vec![Some(d_err.clone()), Some(ident(pz))]],
                )
                .psd_into(&mut conic);
            }
        }
        if aniso {
            // det Ψ(k) ≥ ∏ Z_ii:  [[Ψ, Z], [Zᵀ, Diag Z]] ⪰ 0.
            AffMat::symmetric_blocks(
                &[mw, mw],
                &[vec![Some(psi[k].clone())], vec![Some(zl[k].transpose()), Some(zl[k].diagonal())]],
            )
            .psd_into(&mut conic);
        }
    }

    if let Level::Anisotropy(alevel) = level {
        let lw = (mw * steps) as f64;
        // t = e^{2a/lw} (η − γ²) ≥ 0 must not exceed the geometric mean of the Z_ii.
        let s = (2.0 * alevel / lw).exp();
        let t: Scalar = (0.0, vec![(eta, s), (gsq, -s)]);
        conic.nonnegative(vec![t.clone()]);
        let mut level_nodes: Vec<Scalar> = Vec::new();
        for z in &zl {
            for i in 0..mw {
                let idx = z.terms.iter().find(|(_, m)| m[(i, i)] == 1.0).map(|(k, _)| *k).expect("diagonal variable");
                level_nodes.push((0.0, vec![(idx, 1.0)]));
            }
        }
        while !level_nodes.len().is_power_of_two() {
            level_nodes.push(t.clone());
        }
        while level_nodes.len() > 1 {
            let mut next = Vec::with_capacity(level_nodes.len() / 2);
            for pair in level_nodes.chunks(2) {
                let u = vars.scalar();
                rotated_cone(&mut conic, &pair[0], &pair[1], u);
                next.push((0.0, vec![(u, 1.0)]));
            }
            level_nodes = next;
        }
        // root ≥ t
        let root = &level_nodes[0];
        let mut terms = root.1.clone();
        terms.extend(t.1.iter().map(|(k, c)| (*k, -c)));
        conic.nonnegative(vec![(root.0 - t.0, terms)]);
    }

    let nvars = vars.count;
    let mut cost = vec![0.0; nvars];
    cost[gsq] = 1.0;
    let (rows, cones) = conic.size();
    let sol = conic.minimize_tuned(&cost, tuning)?;
    let singular =
        || Failure { status: "solved, but P2(k+1) is singular: W, H cannot be recovered".into(), infeasible: false };
    let x = &sol.x;
    let mut w = Vec::with_capacity(steps);
    let mut h = Vec::with_capacity(steps);
    for k in 0..steps {
        if k < nn {
            let p2n = p2[k + 1].value(x);
            let lu = p2n.clone().lu();
            let wk = lu.solve(&q2[k].value(x)).ok_or_else(singular)?;
            let hk = lu.solve(&y2[k].value(x)).ok_or_else(singular)?;
            w.push(wk);
            h.push(hk);
        } else {
            // The gains of step N are never used (the predictor's last output needs s[N] only).
            w.push(a.clone());
            h.push(Mat::zeros(nx, ny));
        }
    }
    Ok(Synthesis {
        w,
        h,
        gamma_sq: x[gsq],
        eta: x[eta],
        variables: nvars,
        rows,
        cones,
        iterations: sol.iterations,
        solve_seconds: sol.seconds,
        almost: sol.almost,
    })
}

/// An affine scalar: constant + Σ coef·x.
type Scalar = (f64, Vec<(usize, f64)>);

/// u² ≤ a·b with a, b ≥ 0, as the second-order cone ‖(2u, a − b)‖ ≤ a + b.
fn rotated_cone(conic: &mut Conic, a: &Scalar, b: &Scalar, u: usize) {
    let comb = |sa: f64, sb: f64| -> Scalar {
        let mut t: Vec<(usize, f64)> = a.1.iter().map(|(k, c)| (*k, sa * c)).collect();
        t.extend(b.1.iter().map(|(k, c)| (*k, sb * c)));
        (sa * a.0 + sb * b.0, t)
    };
    conic.second_order(vec![comb(1.0, 1.0), (0.0, vec![(u, 2.0)]), comb(1.0, -1.0)]);
}
